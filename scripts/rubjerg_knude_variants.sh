#!/usr/bin/env bash
# What sets the length of examples/rubjerg_knude.toml's slide (issue 56): the example, the rain
# trigger (none, sudden, 20 % heavier), the clay without its toe on the beach, and the section 7.5 m
# deeper (the paper's point count); then how long each slide lasts and where the clay ends
# (scripts/slide_duration.py). Study: docs/studies/2026-12-04-rubjerg-knude-slide-duration.md.
# About 10 min on two threads.
#   scripts/rubjerg_knude_variants.sh [build/skred] [OUTDIR]
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/rubjerg_knude_variants}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out/notoe" "$out/deep"
out=$(cd "$out" && pwd)  # the scenarios name their profiles by absolute paths
example="$here/examples/rubjerg_knude.toml"
cp "$here"/examples/rubjerg_knude/*.csv "$out/notoe/"
# No toe: the clay's base crops out at the cliff's foot (80, 6.8) and rises at 35 deg.
printf 'x,z\n0,10.0\n78,9.0\n80,6.8\n165,66.3\n200,70.0\n' > "$out/notoe/clay_base.csv"
# Deeper: every profile 7.5 m (three cells) higher over the same floor.
for f in surface clay_base; do
  awk -F, '/^[0-9]/ { printf "%s,%g\n", $1, $2 + 7.5; next } { print }' \
    "$here/examples/rubjerg_knude/$f.csv" > "$out/deep/$f.csv"
done
variant() {  # name, sed expressions
  local name=$1
  shift
  sed "$@" -e "s|\"rubjerg_knude/|\"$here/examples/rubjerg_knude/|" -e 's/^interval = 0.5$/interval = 100.0/' \
    "$example" > "$out/$name.toml"
  rm -rf "${out:?}/$name"
  "$skred" run "$out/$name.toml" -o "$out/$name" --threads "${THREADS:-2}" | tail -1
}
variant example -e ''
variant no_trigger -e 's/^density = 2090$/density = 1900/'
variant sudden -e 's/^density_ramp_time = 2.0$/density_ramp_time = 0.01/'
variant heavier_20pct -e 's/^density = 2090$/density = 2280/'
variant no_toe -e "s|\"rubjerg_knude/clay_base|\"$out/notoe/clay_base|"
variant deeper -e "s|\"rubjerg_knude/|\"$out/deep/|" -e 's/^size = \[200.0, 80.0\]/size = [200.0, 87.5]/'
/usr/bin/python3 "$here/scripts/slide_duration.py" "$out"/{example,no_trigger,sudden,heavier_20pct,no_toe,deeper} --body 1
