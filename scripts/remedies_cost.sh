#!/usr/bin/env bash
# The cost of Acosta's remedies in an implicit step (docs/studies/2026-12-03-acosta-remedies.md):
# an elastic block 10 m x 10 m on 0.1 m cells (40,000 points) settling under gravity in 3 load
# steps, at the points (linear, GIMP) and with DM / DM-G, each ROUNDS times on one thread; prints
# the assembly, factorisation and whole-run seconds from summary.json.
# Usage: scripts/remedies_cost.sh [build/skred]   (ROUNDS=3 by default)
set -euo pipefail
skred=${1:-build/skred}
rounds=${ROUNDS:-3}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
scenario() {  # interpolation integration
  cat <<TOML
[grid]
size = [12.0, 12.0]
cell_size = 0.1
[[material]]
name = "m"
model = "linear-elastic"
density = 2000.0
young = 1e7
poisson = 0.3
[[body]]
name = "block"
material = "m"
shape = "rectangle"
min = [0.0, 0.0]
max = [10.0, 10.0]
[boundary]
x_min = "roller"
x_max = "roller"
y_min = "fixed"
[gravity]
acceleration = [0, -9.81]
[solver]
end_time = 1.0
integrator = "implicit"
interpolation = "$1"
[implicit]
load_steps = 3
integration = "$2"
[output]
interval = 10.0
TOML
}
cases="linear:points linear:double-mapping gimp:points gimp:double-mapping-gimp"
for c in $cases; do scenario "${c%%:*}" "${c##*:}" > "$dir/${c/:/_}.toml"; done
for r in $(seq "$rounds"); do
  for c in $cases; do
    name=${c/:/_}
    rm -rf "$dir/out_$name"
    "$skred" run "$dir/$name.toml" -o "$dir/out_$name" --threads 1 > /dev/null
    /usr/bin/python3 - "$dir/out_$name/summary.json" "$name" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
ph = s["phase_seconds"]
d = dict(ph) if isinstance(ph, dict) else {k: v for k, v in ph}
print(f"{sys.argv[2]:32s} assembly {d.get('implicit_assembly', 0):6.3f} s  factorisation "
      f"{d.get('implicit_factorisation', 0):6.3f} s  run {s['wall_seconds']:6.3f} s  {s['status']}")
PY
  done
done
