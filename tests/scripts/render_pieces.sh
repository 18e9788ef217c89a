#!/bin/bash
# `skred render` of a run split among 2 processes (issue 55): each frame there is a
# particles_NNNNNN.pvtu over one piece per process. The picture of the soil column's last frame
# must be the one-process run's: the points agree within 1e-12 (tests/mpi), so the pixels may
# differ only where rounding puts an edge on the other side of a pixel's sampling (measured: 11
# of 284,000 pixels by one level of 255). Skips (77) without Python's VTK.
#   render_pieces.sh SKRED MPIRUN SOURCE_DIR
set -euo pipefail
skred=$1 mpirun=$2 src=$3
/usr/bin/python3 -c "import vtk, matplotlib" 2> /dev/null || exit 77
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$skred" run "$src/examples/soil_column.toml" -o "$out/one" --threads 1 > /dev/null
OMP_NUM_THREADS=1 "$mpirun" --allow-run-as-root --oversubscribe -np 2 \
  "$skred" run "$src/examples/soil_column.toml" -o "$out/two" --threads 1 > /dev/null
ls "$out/two"/particles_*.pvtu > /dev/null  # (the frames are in pieces)
for run in one two; do "$skred" render "$out/$run" --field speed -o "$out/$run.png" > /dev/null; done
/usr/bin/python3 - "$out/one.png" "$out/two.png" << 'PY'
import sys
import matplotlib.image as image
import numpy as np
a, b = image.imread(sys.argv[1]), image.imread(sys.argv[2])
assert a.shape == b.shape, f"the pictures' sizes differ: {a.shape} and {b.shape}"
d = np.abs(a - b).max(axis=-1)
off = int((d > 0).sum())
print(f"{off} of {d.size} pixels differ, by up to {d.max() * 255:.0f} of 255")
assert off <= d.size // 1000 and d.max() <= 2.5 / 255, "the picture of the pieces is not the one-process run's"
assert (a[..., :3].std(axis=(0, 1)) > 0.01).any(), "a blank picture"
PY
