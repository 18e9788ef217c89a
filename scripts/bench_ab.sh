#!/usr/bin/env bash
# Side-by-side throughput of two (or more) builds, for a "no regression" claim: every bench of
# scripts/bench.sh plus the 3D column slab, each build in turn within a round, ROUNDS rounds
# (default 3), so a drifting background load hits every build alike. Each figure is the median
# over the rounds of `skred bench ... --repeats 3`'s median, in M particle-updates/s. The load
# average is printed with every round: repeat when it was high.
#   [ROUNDS=5] [ONLY=3d] bash scripts/bench_ab.sh path/to/old/skred path/to/new/skred
# ONLY=3d runs only the 3D slab (1 and 2 threads); ONLY=2d only the 2D benches.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 OLD_SKRED NEW_SKRED [MORE...]" >&2; exit 2; }
rounds=${ROUNDS:-3}
benches3=("--problem column --dim 3 --threads 1"
          "--problem column --dim 3 --threads 2")
benches2=("--problem block --particles 100000 --steps 20 --threads 1"
          "--problem block --particles 100000 --steps 20 --threads 2"
          "--problem block --particles 1000000 --steps 10 --threads 1"
          "--problem block --particles 1000000 --steps 10 --threads 2"
          "--problem column --interpolation linear --threads 1"
          "--problem column --threads 1"
          "--problem column --threads 2")
case "${ONLY:-}" in
  3d) benches=("${benches3[@]}") ;;
  2d) benches=("${benches2[@]}") ;;
  *) benches=("${benches3[@]}" "${benches2[@]}") ;;
esac
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
for args in "${benches[@]}"; do
  echo "== skred bench $args --repeats 3"
  declare -A runs=()
  for ((r = 1; r <= rounds; r++)); do
    line="round $r (load $(cut -d' ' -f1 /proc/loadavg)):"
    for b in "$@"; do
      # shellcheck disable=SC2086
      m=$("$b" bench $args --repeats 3 | sed -nE 's/^median: ([0-9.]+) M.*/\1/p')
      runs[$b]="${runs[$b]:-} $m"
      line="$line $m"
    done
    echo "  $line"
  done
  for b in "$@"; do
    echo "  $(echo "${runs[$b]}" | tr ' ' '\n' | grep . | median)  $b"
  done
  unset runs
done
