#!/bin/sh
# The strength at which the slope of examples/slope_collapse.toml starts to fail, at cell size H
# (docs/method.md, "The slope's strength under refinement"): `skred fos` on a copy of the
# example with the cell size H and a 2 s slide stage. It divides the slide's c and tan(phi) by
# a factor F, runs LO (must stand) and HI (must fail), then bisects STEPS times. "Fails" means a
# point moved more than 5 cm in those 2 s (--moved 0.05 m over the material's 14 m). Prints each
# run, the bracket and Bishop's F; OUT/fos.csv and OUT/pictures/fos.png hold them.
#   scripts/strength_onset.sh [build/skred] H LO HI [STEPS]    e.g.  scripts/strength_onset.sh build/skred 0.5 0.8 0.9
# One thread; at H = 0.25 m a run takes about a minute.
set -e
skred=${1:-build/skred}
h=$2
lo=$3
hi=$4
steps=${5:-4}
out=${OUT:-out/strength_onset}/h_$h
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
/usr/bin/python3 - "$here/examples/slope_collapse.toml" "$h" > "$out.toml" << 'EOF2'
import re, sys
s = open(sys.argv[1]).read()
s = re.sub(r'(?m)^cell_size = .*$', 'cell_size = %g' % float(sys.argv[2]), s)
i = s.index('name = "slide"')
s = s[:i] + re.sub(r'(?m)^duration = .*$', 'duration = 2.0', s[i:], count=1)
print(s)
EOF2
OMP_WAIT_POLICY=PASSIVE "$skred" fos "$out.toml" -o "$out" --range "$lo" "$hi" --steps "$steps" \
  --moved "$(awk 'BEGIN { print 0.05 / 14 }')" --threads 1 --overwrite
