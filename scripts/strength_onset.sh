#!/bin/sh
# The strength at which the slope of examples/slope_collapse.toml starts to fail, at cell size H
# (docs/method.md, "The slope's strength under refinement"): its slide stage is run for 2 s
# with c and tan(phi) divided by a factor F (F < 1: a stronger soil, as [[stage.material]]
# overrides), and F is bisected between LO (stands) and HI (fails). "Fails" means a point
# moved more than 5 cm in those 2 s. Prints each run (H, F, largest displacement [m], gravity
# work [kJ/m], status) and the bracket.
#   scripts/strength_onset.sh [build/skred] H LO HI [STEPS]    e.g.  scripts/strength_onset.sh build/skred 0.5 0.8 0.9
# One thread per run; at H = 0.25 m a run takes about a minute.
set -e
skred=${1:-build/skred}
h=$2
lo=$3
hi=$4
steps=${5:-4}
out=${OUT:-out/strength_onset}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"

run() {  # run F: one 2 s slide at strength factor F
  f=$out/slope_${h}_$1
  /usr/bin/python3 - "$here/examples/slope_collapse.toml" "$h" "$1" > "$f.toml" << 'EOF'
import math, re, sys
s = open(sys.argv[1]).read()
h, F = float(sys.argv[2]), float(sys.argv[3])
s = re.sub(r'(?m)^cell_size = .*$', 'cell_size = %g' % h, s)
phi = math.degrees(math.atan(math.tan(math.radians(18.0)) / F))
i, j = s.index('name = "slide"'), s.index('[output]')
s = s[:i] + ('name = "slide"\nduration = 2.0\n[[stage.material]]\nname = "soil"\n'
             'friction = %.6f\ncohesion = %.3f\n\n' % (phi, 5000.0 / F)) + s[j:]
print(s)
EOF
  OMP_WAIT_POLICY=PASSIVE "$skred" run "$f.toml" -o "$f" --overwrite --threads 1 > "$f.log" 2>&1 || true
  /usr/bin/python3 - "$f/summary.json" "$h" "$1" << 'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
st = s["stages"][-1]
print(sys.argv[2], sys.argv[3], "%.3f" % st["max_displacement"], "%.1f" % (st["gravity_work"] / 1e3), s["status"])
EOF
}

k=0
while [ "$k" -lt "$steps" ]; do
  F=$(awk -v a="$lo" -v b="$hi" 'BEGIN { printf "%.4f", (a + b) / 2 }')
  line=$(run "$F")
  echo "$line"
  if echo "$line" | awk '{ exit !($3 > 0.05) }'; then hi=$F; else lo=$F; fi
  k=$((k + 1))
done
echo "h = $h m: the slope stands at F = $lo and fails at F = $hi"
