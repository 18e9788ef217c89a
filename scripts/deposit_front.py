#!/usr/bin/python3
"""Front of a slide's deposit at fixed thicknesses, for the runout study (scripts/convergence.sh).

The runout in summary.json takes the front where the deposit has raised the surface by more than
half a cell, a threshold that shrinks with the cell. This script takes it at thicknesses that do
not: for each t, the front is the outermost +x edge x_p + l_p (l_p = l0 det(F)^(1/2), as GIMP
uses) of the points that stand more than t above the far-field original surface, walking outward
column by column (one cell wide) from the toe while the columns stay that high; the toe is the
outermost original edge x0 + l0 of the points that stood that high. Runout_t = front - toe.
It also prints the gravity work (the fall of the centre of mass) and the share of it the
velocity transfer took, from series.csv.

  /usr/bin/python3 scripts/deposit_front.py H0 OUTDIR...   (H0: the initial height; thicknesses
                                                            0.02, 0.04, 0.1 and 0.2 H0)
"""
import csv
import glob
import sys
import tomllib

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

FRACTIONS = (0.02, 0.04, 0.1, 0.2)


def last_points(outdir):
    """Centres, original centres and det F of the points in the run's last particles file."""
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(sorted(glob.glob(outdir + "/particles_*.vtu"))[-1])
    reader.Update()
    grid = reader.GetOutput()
    centres = vtk.vtkCellCenters()
    centres.SetInputData(grid)
    centres.Update()
    x = vtk_to_numpy(centres.GetOutput().GetPoints().GetData())[:, :2]
    cells = grid.GetCellData()
    u = vtk_to_numpy(cells.GetArray("displacement"))[:, :2]
    return x, x - u, vtk_to_numpy(cells.GetArray("det_F"))


def runout_at(x, x0, l, l0, h, level):
    """Front - toe (see above) at the surface level `level`."""
    high0 = x0[:, 1] + l0 > level
    if not high0.any():
        return 0.0
    toe = (x0[high0, 0] + l0[high0]).max()
    high = x[:, 1] + l > level
    col = np.floor(x[:, 0] / h).astype(int)
    front, c = toe, int(np.floor(toe / h))
    while True:
        here = high & (col == c)
        if not here.any():
            break
        front = max(front, (x[here, 0] + l[here]).max())
        c += 1
    return front - toe


def main():
    height = float(sys.argv[1])
    print("%-28s %9s %9s %9s %9s %11s %9s" % (("run",) + tuple("t=%.2fH0" % f for f in FRACTIONS) +
                                                ("W_gravity_kJ", "transfer")))
    for outdir in sys.argv[2:]:
        scenario = tomllib.load(open(outdir + "/scenario.toml", "rb"))
        h = scenario["grid"]["cell_size"]
        x, x0, det_f = last_points(outdir)
        l0 = np.full(len(x), h / (2 * scenario["body"][0]["particles_per_cell"]))
        l = l0 * np.sqrt(np.abs(det_f))
        # the far-field original surface: the top of the original material in the outermost
        # column if it reaches the grid's +x side (a base layer), else 0 (an empty base)
        edge = x0[:, 0].max()
        outer = x0[:, 0] > edge - h / 2
        base = (x0[outer, 1] + l0[outer]).max() if edge > scenario["grid"]["size"][0] - h else 0.0
        rows = list(csv.DictReader(open(outdir + "/series.csv")))
        work = float(rows[-1]["gravity_work"])
        lost = float(rows[-1]["transfer_dissipation"])
        fronts = [runout_at(x, x0, l, l0, h, base + f * height) for f in FRACTIONS]
        print("%-28s %9.3f %9.3f %9.3f %9.3f %11.1f %8.1f%%" % ((outdir.rstrip("/").split("/")[-1],) +
                                                              tuple(fronts) + (work / 1e3, 100 * lost / work)))



if __name__ == "__main__":
    main()
