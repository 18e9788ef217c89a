#!/usr/bin/env bash
# The equilibrium stage of examples/slope_50m.toml (elastic, gravity ramped over 12.5 s, 15 s),
# explicit with local damping against implicit (quasi-static, one load step): the RMS over the
# points of the stress difference relative to rho g H, and the wall time of each
# (docs/studies/2026-12-02-implicit-equilibrium.md).
#   bash scripts/implicit_equilibrium.sh [build/skred] [OUTDIR] [threads]
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/implicit_equilibrium}
threads=${3:-2}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$out"
# The example's equilibrium stage alone (its slide stage cut off), as each integrator runs it.
base=$(sed '/^\[\[stage\]\]$/,$d' "$here/../examples/slope_50m.toml")
stage='[[stage]]
name = "equilibrium"
duration = 15.0
gravity_ramp_time = 12.5
elastic = true'
printf '%s\n%s\nlocal_damping = 0.3\n[output]\ninterval = 15.0\nseries_interval = 0.5\n' "$base" "$stage" \
  > "$out/explicit.toml"
printf '%s\n%s\nintegrator = "implicit"\n[implicit]\nload_steps = 1\n[output]\ninterval = 15.0\n' "$base" \
  "$stage" > "$out/implicit.toml"
for k in explicit implicit; do
  "$skred" run "$out/$k.toml" -o "$out/$k" --overwrite --threads "$threads"
done
/usr/bin/python3 "$here/compare_stresses.py" "$out/explicit" "$out/implicit" 2000 9.81 70
for k in explicit implicit; do
  /usr/bin/python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(sys.argv[2], 'wall', round(s['wall_seconds'], 3), 's, steps', s['steps'], ', phases', {k: round(v, 3) for k, v in s['phase_seconds'].items()})" "$out/$k/summary.json" "$k"
done
