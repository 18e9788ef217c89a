#!/usr/bin/env bash
# Issue 55's speed aim, side by side: 2 processes x 1 thread against 1 process x 2 threads on the
# 2D column (1,036,800 points) and the 3D slab (921,600 points), the two in turn within a round,
# ROUNDS rounds (default 3), so a drifting background load hits both alike. Each figure is
# `skred bench ... --repeats 3`'s median, in M particle-updates/s; the load average is printed with
# every round (repeat when it was high), and the exchange per step of the distributed runs.
#   [ROUNDS=5] [SKRED=build/skred] bash scripts/processes_speed.sh
set -euo pipefail
rounds=${ROUNDS:-3}
skred=${SKRED:-build/skred}
problems=("--problem column --refine 9 --steps 20"
          "--problem column --dim 3 --refine 3 --steps 10")
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
for args in "${problems[@]}"; do
  echo "== skred bench $args --repeats 3"
  mpi=() omp=()
  for ((r = 1; r <= rounds; r++)); do
    # shellcheck disable=SC2086
    out=$(OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np 2 "$skred" bench $args --repeats 3 --threads 1)
    m=$(sed -nE 's/^median: ([0-9.]+) M.*/\1/p' <<< "$out")
    sent=$(sed -nE 's/^exchanged per step by each process: (.*)/\1/p' <<< "$out")
    # shellcheck disable=SC2086
    o=$("$skred" bench $args --repeats 3 --threads 2 | sed -nE 's/^median: ([0-9.]+) M.*/\1/p')
    echo "  round $r (load $(cut -d' ' -f1 /proc/loadavg)): 2 x 1: $m, 1 x 2: $o (exchanged per step: $sent)"
    mpi+=("$m") omp+=("$o")
  done
  a=$(printf '%s\n' "${mpi[@]}" | median)
  b=$(printf '%s\n' "${omp[@]}" | median)
  echo "  median 2 processes x 1 thread: $a, 1 process x 2 threads: $b, ratio $(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", a / b}')"
done
