#!/usr/bin/env bash
# Acosta fig. 20-21 (reference R7): the stiffness K_mag per node of a field of points turned 20
# degrees against the grid, one material (examples/rotated_field.toml) and two
# (examples/rotated_field_two_materials.toml), with regular MPM, W*, GM, DM, GIMP and DM-G; then
# table 1's spread per method and the two pictures (scripts/rotated_field.py). A few seconds.
#   scripts/rotated_field.sh [build/skred] [OUTDIR]
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/rotated_field}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
variant() {  # name, interpolation, integration
  for case in one two; do
    local example="$here/examples/rotated_field.toml"
    [ "$case" = two ] && example="$here/examples/rotated_field_two_materials.toml"
    sed -e "s/^interpolation = \"linear\"/interpolation = \"$2\"/" \
        -e "s/^integration = \"double-mapping\"/integration = \"$3\"/" "$example" > "$out/$1_$case.toml"
    rm -rf "${out:?}/$1_$case"
    "$skred" run "$out/$1_$case.toml" -o "$out/$1_$case" --threads 1 > "$out/$1_$case.log" 2>&1 ||
      { cat "$out/$1_$case.log"; exit 1; }
  done
}
variant mpm linear points
variant wstar linear modified-weights
variant gm linear gauss-mapping
variant dm linear double-mapping
variant gimp gimp points
variant dmg gimp double-mapping-gimp
/usr/bin/python3 "$here/scripts/rotated_field.py" "$out" --png-mpm "$out/rotated_field_mpm.png" \
  --png-gimp "$out/rotated_field_gimp.png"
