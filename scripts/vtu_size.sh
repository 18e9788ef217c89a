#!/usr/bin/env bash
# Particle frame sizes and write times (issue 13, "Output that scales"):
#  1. runs examples/slope_collapse.toml with the default fields and with fields = "all" and
#     prints the bytes per point of its frames (mean, and the last frame);
#  2. times the writing of one frame of 10^6 points (default and all fields, zlib and raw)
#     with the disabled test IoTest.DISABLED_WriteTimeAtAMillionPoints.
#   bash scripts/vtu_size.sh [BUILD_DIR] [THREADS]     (default: build 2)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
threads=${2:-2}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for fields in default all; do
  # the example with `fields = "..."` in its [output] table
  sed "s/^\[output\]\$/[output]\nfields = \"$fields\"/" examples/slope_collapse.toml > "$tmp/$fields.toml"
  grep -q "fields = \"$fields\"" "$tmp/$fields.toml"
  "$build/skred" run "$tmp/$fields.toml" -o "$tmp/$fields" --threads "$threads" > "$tmp/$fields.log" 2>&1
  python3 - "$tmp/$fields" "$fields" <<'PY'
import glob, os, re, sys
sizes, cells = [], []
for f in sorted(glob.glob(os.path.join(sys.argv[1], "particles_*.vtu"))):
    with open(f, "rb") as h:
        head = h.read(2000).decode("latin-1")
    cells.append(int(re.search(r'NumberOfCells="(\d+)"', head).group(1)))
    sizes.append(os.path.getsize(f))
grid = sum(os.path.getsize(f) for f in glob.glob(os.path.join(sys.argv[1], "grid_*.vtr")))
print(f"slope_collapse, fields {sys.argv[2]}: {len(sizes)} frames of {cells[-1]} points, "
      f"{sum(sizes) / sum(cells):.1f} B/point on average, {sizes[-1] / cells[-1]:.1f} B/point in the last "
      f"frame; grid files {grid / len(sizes) / 1e3:.0f} kB per frame")
PY
done
"$build/tests/skred_tests" --gtest_also_run_disabled_tests --gtest_filter='IoTest.DISABLED_WriteTimeAtAMillionPoints' \
  | grep '^write'
