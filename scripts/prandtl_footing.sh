#!/usr/bin/env bash
# examples/footing_prandtl.toml (a smooth strip footing on weightless Tresca clay) refined:
# h = B/16, B/32, B/64 with the cell-averaged volumetric strain, B/16 and B/32 with each point's
# own (locking), and at B/16 Acosta's iteration (the elastic matrix) beside Newton's. Prints
# per run the peak and final footing pressure over s_u against 2 + pi, Newton iterations per
# step and the wall time (docs/studies/2026-12-02-prandtl-footing.md).
#   bash scripts/prandtl_footing.sh [build/skred] [OUTDIR] [threads]
set -euo pipefail
skred=${1:-build/skred}
out=${2:-out/prandtl_footing}
threads=${3:-2}
here=$(cd "$(dirname "$0")" && pwd)
example="$here/../examples/footing_prandtl.toml"
mkdir -p "$out"
# name h volumetric_strain iteration [max_iterations]
runs=(
  "avg-16 0.0625 cell-average newton 25"
  "avg-32 0.03125 cell-average newton 25"
  "avg-64 0.015625 cell-average newton 25"
  "point-16 0.0625 point newton 25"
  "point-32 0.03125 point newton 25"
  "elastic-16 0.0625 cell-average elastic 1000"
)
printf '%-11s %9s %9s %9s %9s %9s %8s\n' run "h" "peak q/su" "end q/su" "end err%" "its/step" "wall s"
for r in "${runs[@]}"; do
  read -r name h vol iter maxit <<< "$r"
  sed -e "s/^cell_size = .*/cell_size = $h/" \
      -e "s/^volumetric_strain = .*/volumetric_strain = \"$vol\"/" \
      -e "s/^load_steps = .*/load_steps = 10\niteration = \"$iter\"\nmax_iterations = $maxit/" \
      "$example" > "$out/$name.toml"
  "$skred" run "$out/$name.toml" -o "$out/$name" --overwrite --threads "$threads" > /dev/null 2>&1 || true
  /usr/bin/python3 - "$out/$name" "$name" "$h" <<'PY'
import csv, json, math, sys
rows = list(csv.DictReader(open(sys.argv[1] + "/series.csv")))
q = [-float(r["force_footing_y"]) / 0.5 / 1e4 for r in rows]
its = [int(r["iterations"]) for r in rows[1:]]
s = json.load(open(sys.argv[1] + "/summary.json"))
p = 2 + math.pi
print(f"{sys.argv[2]:<11} {float(sys.argv[3]):9.5f} {max(q):9.4f} {q[-1]:9.4f} {100 * (q[-1] / p - 1):+9.2f} "
      f"{sum(its) / max(1, len(its)):9.1f} {s['wall_seconds']:8.2f}  {s['status']}")
PY
done
