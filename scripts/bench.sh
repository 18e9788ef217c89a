#!/usr/bin/env bash
# The throughput figures of issues 2 and 3, each the median of 5 runs: the GIMP/averaged
# elastic block at 1e5 and 1e6 points and the Mohr-Coulomb column collapse (12,800 points,
# and 10x and 100x refined), on 1 and 2 threads. Run on an idle machine:
#   bash scripts/bench.sh [path/to/skred]   (default build/skred)
#
# With --busy, the OpenMP wait policy table instead (issue 13): the 10^5-point block at 1 and
# 2 threads on an idle machine and beside a competing `yes` pinned to core 0, for skred's
# default (no OMP variable set: a short spin), libgomp's own default (GOMP_SPINCOUNT=300000)
# and OMP_WAIT_POLICY=passive, in ROUNDS interleaved rounds (default 3):
#   [ROUNDS=5] bash scripts/bench.sh --busy [path/to/skred]
set -euo pipefail
busy_mode=0
if [ "${1:-}" = "--busy" ]; then busy_mode=1; shift; fi
skred=${1:-build/skred}
median() { grep -E '^median' | sed -E 's/median: ([0-9.]+) M.*/\1/'; }
if [ "$busy_mode" = 1 ]; then
  # policy label, then the environment it runs with (env -u clears the user's own settings)
  policies=("skred default|env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT"
            "libgomp default|env -u OMP_WAIT_POLICY GOMP_SPINCOUNT=300000"
            "passive|env -u GOMP_SPINCOUNT OMP_WAIT_POLICY=passive")
  rounds=${ROUNDS:-3}
  yes_pid=
  trap '[ -n "$yes_pid" ] && kill "$yes_pid" 2>/dev/null || true' EXIT
  raw=$(mktemp)
  echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
  # Interleaved rounds (a drifting background load hits every policy alike); each figure is
  # the median over the rounds of a median of 3 repeats of 20 steps.
  for ((r = 1; r <= rounds; r++)); do
    for load in idle busy; do
      for p in "${policies[@]}"; do
        read -ra envcmd <<< "${p#*|}"
        for t in 1 2; do
          if [ "$load" = busy ]; then
            timeout 60 taskset -c 0 yes > /dev/null &
            yes_pid=$!
          fi
          m=$("${envcmd[@]}" "$skred" bench --problem block --particles 100000 --steps 20 \
                --repeats 3 --threads "$t" | median)
          if [ -n "$yes_pid" ]; then kill "$yes_pid" 2>/dev/null || true; wait "$yes_pid" 2>/dev/null || true; yes_pid=; fi
          echo "${p%%|*}|$load|$t|$m" >> "$raw"
        done
      done
    done
  done
  echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "policy            machine  threads  M updates/s (median of $rounds rounds: each round)"
  for load in idle busy; do
    for p in "${policies[@]}"; do
      for t in 1 2; do
        vals=$(awk -F'|' -v p="${p%%|*}" -v l="$load" -v t="$t" '$1 == p && $2 == l && $3 == t {print $4}' "$raw")
        med=$(echo "$vals" | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}')
        printf "%-17s %-8s %7s  %11s  (%s)\n" "${p%%|*}" "$load" "$t" "$med" "$(echo $vals)"
      done
    done
  done
  rm -f "$raw"
  exit 0
fi
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
