#!/usr/bin/env bash
# How the implicit step's time grows with the number of unknowns: an elastic block under its own
# weight (fixed base, rollers at the sides, one point per cell, GIMP), quasi-static in one load
# step, on n x n cells for about 10^3 ... 10^6 unknowns, with the direct solver (MUMPS
# Cholesky) and the iterative one (CG + GAMG). Prints the unknowns and summary.json's phase
# times (docs/studies/2026-12-02-implicit-equilibrium.md).
#   bash scripts/implicit_scaling.sh [build/skred] [OUTDIR] [threads] [largest n]
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/implicit_scaling}
threads=${3:-2}
largest=${4:-707}
mkdir -p "$out"
printf '%8s %9s %10s %8s %8s %8s %8s %8s\n' n unknowns solver map assembly factor solve wall
for n in 22 70 224 707; do
  [ "$n" -le "$largest" ] || continue
  for solver in direct iterative; do
    f="$out/block_${n}_$solver.toml"
    cat > "$f" <<TOML
title = "implicit scaling, $n x $n cells, $solver"
[grid]
size = [$n.0, $n.0]
cell_size = 1.0
[[material]]
name = "soil"
model = "linear-elastic"
density = 2000.0
young = 1e8
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
[implicit]
linear_solver = "$solver"
[output]
interval = 1.0
fields = ["displacement"]
TOML
    "$skred" run "$f" -o "$out/block_${n}_$solver" --overwrite --threads "$threads" 2> /dev/null
    /usr/bin/python3 - "$out/block_${n}_$solver/summary.json" "$n" "$solver" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); p = s["phase_seconds"]
print("%8s %9d %10s %8.3f %8.3f %8.3f %8.3f %8.3f" % (sys.argv[2], s["implicit"]["max_unknowns"], sys.argv[3],
      p.get("implicit_map", 0), p.get("implicit_assembly", 0), p.get("implicit_factorisation", 0),
      p.get("implicit_solve", 0), s["wall_seconds"]))
PY
  done
done
