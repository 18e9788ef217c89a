#!/usr/bin/env bash
# The implicit integrator split among processes (issue 55): the vertical cut (examples/
# vertical_cut_implicit.toml: von Mises with softening, dynamic, the cell-averaged volumetric
# strain) and an elastic block of n x n cells under its own weight (E = 1 GPa: the top settles
# 0.5 m at n = 224, under the one-cell limit of a step; quasi-static, one load
# step, MUMPS), each run `repeats` times as 1 process x 2 threads, 2 processes x 1 thread and
# 4 processes x 1 thread (oversubscribed on 2 cores), interleaved. Prints per run the Newton
# iterations, the unknowns, the phase times and the wall time; the iterations must agree
# (docs/studies/2026-12-06-implicit-across-processes.md).
#   bash scripts/implicit_processes.sh [build/skred] [OUTDIR] [repeats] [n]
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/implicit_processes}
repeats=${3:-3}
n=${4:-224}
mkdir -p "$out"
block="$out/block_$n.toml"
cat > "$block" <<TOML
title = "elastic block, $n x $n cells, quasi-static"
[grid]
size = [$n.0, $n.0]
cell_size = 1.0
[[material]]
name = "soil"
model = "linear-elastic"
density = 2000.0
young = 1e9
poisson = 0.3
[[body]]
name = "block"
material = "soil"
particles_per_cell = 1
shape = "rectangle"
min = [0.0, 0.0]
max = [$n.0, $n.0]
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
[solver]
end_time = 1.0
integrator = "implicit"
[output]
interval = 1.0
fields = ["displacement"]
TOML
run() {  # name scenario processes threads
  local dir="$out/$1_$3x$4"
  if [ "$3" -eq 1 ]; then
    "$skred" run "$2" -o "$dir" --overwrite --threads "$4" 2> /dev/null
  else
    OMP_NUM_THREADS=$4 mpirun --allow-run-as-root --oversubscribe -np "$3" "$skred" run "$2" -o "$dir" \
      --overwrite --threads "$4" 2> /dev/null
  fi
  /usr/bin/python3 - "$dir/summary.json" "$1" "$3x$4" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); p = s["phase_seconds"]; im = s["implicit"]
print("%-14s %5s %6d %6d %9d %8.2f %8.2f %8.2f %8.2f %8.2f" % (sys.argv[2], sys.argv[3], im["steps"],
      im["iterations"], im["max_unknowns"], p.get("implicit_map", 0), p.get("implicit_assembly", 0) +
      p.get("implicit_stress_update", 0), p.get("implicit_factorisation", 0), p.get("implicit_solve", 0),
      s["wall_seconds"]))
PY
}
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-14s %5s %6s %6s %9s %8s %8s %8s %8s %8s\n' run pxt steps iters unknowns map asm+law factor solve wall
for r in $(seq "$repeats"); do
  for pt in "1 2" "2 1" "4 1"; do
    set -- $pt
    run vertical_cut examples/vertical_cut_implicit.toml "$1" "$2"
    run "block_$n" "$block" "$1" "$2"
  done
done
