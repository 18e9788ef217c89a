#!/usr/bin/env bash
# Deposits of dry cohesionless Mohr-Coulomb columns against Davis's angle (issue 56): a 1 m high
# half-column (roller at x = 0, its mirror) of aspect H/L on a base of friction tan(phi), each
# run to rest, then the flank's angle (scripts/deposit_angle.py).
# Study: docs/studies/2026-12-04-deposit-angles.md. About 10 min on one thread.
#   scripts/deposit_angles.sh [build/skred] [OUTDIR]
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/deposit_angles}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
# run NAME PHI PSI ASPECT CELL TRANSFER VOLUMETRIC_STRAIN DAMPING (the run ends at rest, or at 8 s
# undamped and 25 s damped)
run() {
  local name=$1 phi=$2 psi=$3 a=$4 h=$5 tr=$6 vs=$7 damping=$8 duration=8.0
  [ "$damping" = 0 ] || duration=25.0
  read -r L W Y mu < <(/usr/bin/python3 -c "import math; L = 1 / $a; \
print(L, math.ceil((L + 4) / $h) * $h, math.ceil(1.25 / $h) * $h, round(math.tan(math.radians($phi)), 4))")
  cat > "$out/$name.toml" <<EOF
title = "deposit $name"
[grid]
size = [$W, $Y]
cell_size = $h
[[material]]
name = "sand"
model = "mohr-coulomb"
density = 1600.0
young = 2.0e6
poisson = 0.3
friction = $phi
cohesion = 0.0
dilation = $psi
[[body]]
name = "column"
material = "sand"
particles_per_cell = 2
shape = "rectangle"
min = [0.0, 0.0]
max = [$L, 1.0]
[initial_stress]
k0 = "poisson"
[gravity]
acceleration = [0.0, -9.81]
[boundary]
x_min = "roller"
y_min = { type = "friction", friction = $mu }
[solver]
interpolation = "gimp"
velocity_transfer = "$tr"
volumetric_strain = "$vs"
[[stage]]
name = "collapse"
duration = $duration
rest_speed = 0.002
rest_time = 0.5
local_damping = $damping
[output]
interval = 5.0
series_interval = 0.05
EOF
  rm -rf "${out:?}/$name"
  "$skred" run "$out/$name.toml" -o "$out/$name" --threads "${THREADS:-1}" | tail -1
  /usr/bin/python3 "$here/scripts/deposit_angle.py" "$out/$name" --phi "$phi" --psi "$psi" | sed -n '1p;3p'
}
# The slide default (velocity_transfer and volumetric_strain "auto"), undamped, by phi and psi.
for phi in 20 30 40; do run "default_phi$phi" "$phi" 0 1 0.05 auto auto 0; done
run default_phi30_psi10 30 10 1 0.05 auto auto 0
# By transfer (each point's own volumetric strain), aspect and cell, phi = 30.
for tr in xpic apic; do run "${tr}_phi30" 30 0 1 0.05 "$tr" point 0; done
run default_phi30_a05 30 0 0.5 0.05 auto auto 0
run default_phi30_a2 30 0 2 0.05 auto auto 0
run default_phi30_h0025 30 0 1 0.025 auto auto 0
# Quasi-static: local damping 0.7, to rest.
for phi in 20 30 40; do run "damped_phi$phi" "$phi" 0 1 0.05 auto auto 0.7; done
