#!/usr/bin/python3
"""The angle of a deposit's flank, from a run's last particles frame.

The surface is the highest voxel corner in each column of width --bin (default: the median
voxel width); the flank is where that surface stands between --low and --high of the
deposit's height (default 0.2 and 0.8), to the right of its highest column (and to the left,
with --both); its angle is that of the least-squares line through it. With --phi and --psi
it prints Davis's (1968) angle of a non-associated Mohr-Coulomb soil in plane strain,
tan(delta) = sin(phi) cos(psi) / (1 - sin(phi) sin(psi)).

  /usr/bin/python3 scripts/deposit_angle.py OUT [OUT ...] [--phi 30 --psi 0] [--both]
"""
import argparse
import math
import os
import re
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def last_voxels(out):
    """The corners of the last particles frame's voxels, (points, corners, 2)."""
    pvd = os.path.join(out, "particles.pvd")
    if not os.path.exists(pvd):
        sys.exit(f"{out}: no particles.pvd")
    entries = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', open(pvd).read())
    if not entries:
        sys.exit(f"{pvd}: no frames")
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(os.path.join(out, entries[-1][1]))
    r.Update()
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData())
    corners = pts.shape[0] // g.GetNumberOfCells()
    return float(entries[-1][0]), pts.reshape(-1, corners, 3)[:, :, :2]


def davis(phi, psi):
    s, p = math.sin(math.radians(phi)), math.radians(psi)
    return math.degrees(math.atan(s * math.cos(p) / (1.0 - s * math.sin(p))))


def flank_angles(vox, bin_width=None, low=0.2, high=0.8, both=False):
    """The flank's angle(s) in degrees, right (and left), and the deposit's height."""
    centre = vox.mean(axis=1)
    top = vox[:, :, 1].max(axis=1)
    if bin_width is None:
        bin_width = float(np.median(vox[:, :, 0].max(axis=1) - vox[:, :, 0].min(axis=1)))
    x0 = vox[:, :, 0].min()
    col = np.floor((centre[:, 0] - x0) / bin_width).astype(int)
    n = col.max() + 1
    surface = np.full(n, -np.inf)
    np.maximum.at(surface, col, top)
    xs = x0 + (np.arange(n) + 0.5) * bin_width
    base = vox[:, :, 1].min()
    height = surface - base
    h = height[np.isfinite(height)].max()
    peak = int(np.argmax(height))
    angles = []
    sides = [(peak, n, 1.0)] + ([(0, peak + 1, -1.0)] if both else [])
    for a, b, sign in sides:
        sel = np.arange(a, b)
        sel = sel[np.isfinite(height[sel]) & (height[sel] >= low * h) & (height[sel] <= high * h)]
        if len(sel) < 3:
            angles.append(float("nan"))
            continue
        slope = np.polyfit(xs[sel], height[sel], 1)[0]
        angles.append(math.degrees(math.atan(-sign * slope)))
    return angles, h


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--phi", type=float)
    ap.add_argument("--psi", type=float, default=0.0)
    ap.add_argument("--bin", type=float)
    ap.add_argument("--low", type=float, default=0.2)
    ap.add_argument("--high", type=float, default=0.8)
    ap.add_argument("--both", action="store_true", help="the left flank too (a whole pile)")
    args = ap.parse_args()
    if args.phi is not None:
        print(f"Davis: phi {args.phi:g}, psi {args.psi:g} -> delta {davis(args.phi, args.psi):.2f} deg")
    print(f"{'run':40s} {'t [s]':>7s} {'height':>8s} {'right [deg]':>12s}" + (f" {'left [deg]':>11s}" if args.both else ""))
    for out in args.runs:
        t, vox = last_voxels(out)
        angles, h = flank_angles(vox, args.bin, args.low, args.high, args.both)
        print(f"{os.path.basename(os.path.normpath(out)):40s} {t:7.2f} {h:8.3f} " + " ".join(f"{a:12.2f}" for a in angles))


if __name__ == "__main__":
    main()
