#!/usr/bin/env bash
# Side-by-side throughput of two (or more) builds across processes, for a "no regression" claim
# on the exchange between processes: the 3D slab and the 2D column at 10^6 points on NPS
# processes (default "2 4") of 1 thread each, each build in turn within a round, ROUNDS rounds
# (default 5), so a drifting background load hits every build alike. Each figure is the median
# over the rounds of `skred bench`'s median (5 repeats), in M particle-updates/s. The load average
# is printed with every run (repeat when it was high), and the exchange per step.
#   [ROUNDS=5] [NPS="2 4"] bash scripts/processes_ab.sh path/to/old/skred path/to/new/skred
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 OLD_SKRED NEW_SKRED [MORE...]" >&2; exit 2; }
rounds=${ROUNDS:-5}
problems=("--problem column --dim 3 --refine 3 --steps 10"
          "--problem column --refine 9 --steps 20")
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
for args in "${problems[@]}"; do
  for np in ${NPS:-2 4}; do
    echo "== mpirun -np $np skred bench $args --threads 1"
    declare -A runs=()
    for ((r = 1; r <= rounds; r++)); do
      for b in "$@"; do
        # shellcheck disable=SC2086
        out=$(OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$np" "$b" bench $args --threads 1)
        m=$(sed -nE 's/^median: ([0-9.]+) M.*/\1/p' <<< "$out")
        sent=$(sed -nE 's/^exchanged per step by each process: (.*)/\1/p' <<< "$out")
        runs[$b]="${runs[$b]:-} $m"
        echo "  round $r (load $(cut -d' ' -f1 /proc/loadavg)): $m  $b  ($sent)"
      done
    done
    for b in "$@"; do
      echo "  median $(echo "${runs[$b]}" | tr ' ' '\n' | grep . | median)  $b"
    done
    unset runs
  done
done
