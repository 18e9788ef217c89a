#!/usr/bin/env bash
# The vertical cut of Acosta §3.2 (examples/vertical_cut_implicit.toml) with regular MPM, GIMP and
# DM-GC under Newton, a frame per step; then the p-q paths of points A, B, C with their
# oscillation (scripts/pq_paths.py), the slip circle against DM-GC's bands, and fig. 26-29: K_mag,
# |F_int|, q and p of MPM and DM-GC as the toe moves (scripts/vertical_cut_fields.py).
# Studies: docs/studies/2026-12-03-vertical-cut-slivers.md, 2026-12-04-vertical-cut-fields.md.
# About 3 min on one thread at the default step, 1 min with DT=0.01.
#   [DT=0.01] [THREADS=1] scripts/vertical_cut_remedies.sh [build/skred] [OUTDIR]
# DT sets the implicit time step (default: 10 times the explicit stable step, 0.035 s).
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/vertical_cut_remedies}
here=$(cd "$(dirname "$0")/.." && pwd)
example="$here/examples/vertical_cut_implicit.toml"
mkdir -p "$out"
variant() {  # name, interpolation, [solver] lines, [implicit] lines
  sed -e "s/^interpolation = \"gimp\"/interpolation = \"$2\"/" \
      -e "s/^integrator = \"implicit\"/integrator = \"implicit\"\n$3/" \
      -e "s/^analysis = \"dynamic\"/analysis = \"dynamic\"\n${DT:+time_step = $DT\\n}$4/" \
      -e 's/^interval = 0.05$/interval = 0.005/' "$example" > "$out/$1.toml"
  rm -rf "${out:?}/$1"
  "$skred" run "$out/$1.toml" -o "$out/$1" --threads "${THREADS:-1}" | tail -1
}
variant mpm linear 'volumetric_strain = "point"' ''
variant gimp gimp 'volumetric_strain = "point"' ''
variant dmgc gimp '' 'integration = "double-mapping-gimp"\nstress_recovery = "cmpm"\niteration = "newton"\nmax_iterations = 100'
/usr/bin/python3 "$here/scripts/pq_paths.py" "$out/mpm" "$out/gimp" "$out/dmgc" --labels MPM GIMP DM-GC \
  --png "$out/pq_paths.png"
"$skred" render "$out/dmgc" --field plastic_shear_strain --slip-circle --range 0 1 -o "$out/dmgc_slip_circle.png"
/usr/bin/python3 "$here/scripts/vertical_cut_fields.py" "$out/mpm" "$out/dmgc" --png-grid "$out/grid_fields.png" \
  --png-stress "$out/stress_fields.png"
