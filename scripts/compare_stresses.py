#!/usr/bin/env python3
"""The stresses of the last frames of two runs of the same points, matched by their reference
positions (x - displacement): the RMS and largest difference of each component relative to
rho g H.  Usage: compare_stresses.py RUN_A RUN_B RHO G H"""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkCellCenters
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader


def last_frame(run):
    files = [d.get("file") for d in ET.parse(Path(run) / "particles.pvd").getroot().iter("DataSet")]
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(str(Path(run) / files[-1]))
    r.Update()
    g = r.GetOutput()
    c = vtkCellCenters()
    c.SetInputData(g)
    c.Update()
    x = vtk_to_numpy(c.GetOutput().GetPoints().GetData())[:, :2]
    cd = g.GetCellData()
    u = vtk_to_numpy(cd.GetArray("displacement"))[:, :2]
    s = vtk_to_numpy(cd.GetArray("stress"))
    ref = x - u
    order = np.lexsort((np.round(ref[:, 0], 3), np.round(ref[:, 1], 3)))
    return ref[order], s[order]


a_ref, a = last_frame(sys.argv[1])
b_ref, b = last_frame(sys.argv[2])
scale = float(sys.argv[3]) * float(sys.argv[4]) * float(sys.argv[5])
assert len(a) == len(b), "the runs have different points"
assert np.abs(a_ref - b_ref).max() < 1e-3, "the points do not match"
for c, name in enumerate(["xx", "yy", "zz", "xy"]):
    d = (a[:, c] - b[:, c]) / scale
    print(f"sigma_{name}: RMS difference {np.sqrt(np.mean(d * d)):.4%} of rho g H, largest {np.abs(d).max():.3%}")
