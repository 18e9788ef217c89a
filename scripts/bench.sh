#!/usr/bin/env bash
# The throughput figures of issues 2 and 3, each the median of 5 runs: the GIMP/averaged
# elastic block at 1e5 and 1e6 points and the Mohr-Coulomb column collapse (12,800 points,
# and 10x and 100x refined), on 1 and 2 threads. Run on an idle machine:
#   bash scripts/bench.sh [path/to/skred]   (default build/skred)
set -euo pipefail
skred=${1:-build/skred}
median() { grep -E '^median' | sed -E 's/median: ([0-9.]+) M.*/\1/'; }
memory() { grep -E '^peak memory' | sed -E 's/.*, ([0-9]+) bytes per particle/\1/'; }

echo "problem                         threads  M updates/s  per thread  bytes/point"
block() {  # particles steps threads
  local out
  out=$("$skred" bench --problem block --particles "$1" --steps "$2" --repeats 5 --threads "$3")
  local m
  m=$(echo "$out" | median)
  printf "block gimp/averaged %-10s  %7s  %11s  %10.2f  %11s\n" "$1" "$3" "$m" \
    "$(awk -v m="$m" -v t="$3" 'BEGIN{print m/t}')" "$(echo "$out" | memory)"
}
column() {  # interpolation refine steps threads
  local out
  out=$("$skred" bench --problem column --interpolation "$1" --refine "$2" --steps "$3" --repeats 5 --threads "$4")
  local m
  m=$(echo "$out" | median)
  printf "column %-7s x%-3s (%8s)  %7s  %11s  %10.2f  %11s\n" "$1" "$(( $2 * $2 ))" \
    "$(echo "$out" | head -1 | sed -E 's/.*column: ([0-9]+) particles.*/\1/')" "$4" "$m" \
    "$(awk -v m="$m" -v t="$4" 'BEGIN{print m/t}')" "$(echo "$out" | memory)"
}
for t in 1 2; do
  block 100000 100 "$t"
  block 1000000 20 "$t"
done
for interp in linear gimp; do
  for t in 1 2; do
    column "$interp" 1 2000 "$t"
    column "$interp" 3 500 "$t"
    column "$interp" 10 50 "$t"
  done
done
