#!/usr/bin/python3
"""Acosta fig. 20-21 (R7): K_mag per node of a field of points turned 20 degrees against the grid,
one material and two, per integration, from the grid frames of scripts/rotated_field.sh's runs.

  /usr/bin/python3 scripts/rotated_field.py OUT [--png-mpm F20.png] [--png-gimp F21.png]

Prints each method's largest increase and decrease of K_mag against FEM's 3263.57 kN/m^2 over the
5 x 5 cells around C (table 1) and, in the two-material field over the 13 x 13 cells around C, the
RMS departure from each material's FEM value at the nodes more than two cells from A-A' (below,
above), and from FEM's own two-material field at every node (all). FEM is computed here: bilinear
elements, 2 x 2 Gauss points, each of the material on its side of A-A'."""
import argparse
import math
import os

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

FEM = {"one": 3263.57, "below": 4525.48, "above": 3263.57}  # kN/m^2, 2 x 2 Gauss points
C = 12.5
TAN = math.tan(math.radians(20.0))
METHODS = [("mpm", "regular MPM"), ("wstar", "W*"), ("gm", "GM"), ("dm", "DM"), ("gimp", "GIMP"), ("dmg", "DM-G")]


def k_mag(run):
    r = vtk.vtkXMLRectilinearGridReader()
    r.SetFileName(os.path.join(run, "grid_000001.vtr"))
    r.Update()
    g = r.GetOutput()
    x = vtk_to_numpy(g.GetXCoordinates())
    y = vtk_to_numpy(g.GetYCoordinates())
    k = vtk_to_numpy(g.GetPointData().GetArray("stiffness_magnitude")).reshape(len(y), len(x)) / 1e3
    return x, y, k


def fem(x, y, case):
    """K_mag per node of bilinear elements over the field's cells [1, 23]^2 with 2 x 2 Gauss points,
    each Gauss point of the material on its side of A-A' (eq. 25; 3263.57 kN/m^2 inside one material)."""
    kxx = np.zeros((len(y), len(x)))
    kyy = np.zeros_like(kxx)
    g = (0.5 - 0.5 / math.sqrt(3.0), 0.5 + 0.5 / math.sqrt(3.0))
    for i in range(1, 23):
        for j in range(1, 23):
            for xi in g:
                for eta in g:
                    below = case == "two" and (j + eta - C) < TAN * (i + xi - C)
                    E, nu = (1500.0, 0.25) if below else (1000.0, 0.3)
                    d11, d33 = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
                    for a in (0, 1):
                        for b in (0, 1):
                            nx = (1 if a else -1) * (eta if b else 1 - eta)
                            ny = (1 if b else -1) * (xi if a else 1 - xi)
                            kxx[j + b, i + a] += 0.25 * (d11 * nx * nx + d33 * ny * ny)
                            kyy[j + b, i + a] += 0.25 * (d33 * nx * nx + d11 * ny * ny)
    return np.hypot(kxx, kyy)


def spread(x, y, k):
    X, Y = np.meshgrid(x, y)
    m = (abs(X - C) <= 2.5 + 1e-9) & (abs(Y - C) <= 2.5 + 1e-9)
    v = 100.0 * (k[m] / FEM["one"] - 1.0)
    return v.max(), v.min()


def two_material_error(x, y, k):
    X, Y = np.meshgrid(x, y)
    d = (Y - C - TAN * (X - C)) * math.cos(math.radians(20.0))  # signed distance from A-A'
    out = []
    for side, sel in (("below", d < -2.0), ("above", d > 2.0)):
        m = sel & (abs(X - C) <= 6.5) & (abs(Y - C) <= 6.5)
        out.append(100.0 * math.sqrt(np.mean((k[m] / FEM[side] - 1.0) ** 2)))
    m = (abs(X - C) <= 6.5) & (abs(Y - C) <= 6.5)  # every node, A-A' too, against FEM's two materials
    out.append(100.0 * math.sqrt(np.mean((k[m] / fem(x, y, "two")[m] - 1.0) ** 2)))
    return out


def draw(out, methods, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, len(methods), figsize=(3.0 * len(methods), 5.6), squeeze=False)
    for col, (key, label) in enumerate(methods):
        for row, case in enumerate(("one", "two")):
            x, y, k = k_mag(os.path.join(out, f"{'mpm' if key == 'fem' else key}_{case}"))
            if key == "fem":
                k = fem(x, y, case)
            s = (x >= C - 6.5) & (x <= C + 6.5)
            t = (y >= C - 6.5) & (y <= C + 6.5)
            ax = axes[row][col]
            if case == "one":
                lim = 40.0 if key == "gimp" else 10.0
                im = ax.pcolormesh(x[s], y[t], 100.0 * (k[np.ix_(t, s)] / FEM["one"] - 1.0), shading="gouraud",
                                   cmap="RdBu_r", vmin=-lim, vmax=lim)
                unit = "K_mag / FEM − 1 [%]"
            else:
                lo, hi = (1800.0, 4800.0) if key == "gimp" else (3000.0, 4800.0)
                im = ax.pcolormesh(x[s], y[t], k[np.ix_(t, s)], shading="gouraud", cmap="viridis", vmin=lo, vmax=hi)
                xs = np.array([C - 6.5, C + 6.5])
                ax.plot(xs, C + TAN * (xs - C), "w--", lw=1)
                unit = "K_mag [kN/m²]"
            ax.plot([C], [C], "k+")
            ax.set_aspect("equal")
            ax.set_xlim(C - 6.5, C + 6.5)
            ax.set_ylim(C - 6.5, C + 6.5)
            ax.set_title(f"{label}, {'one material' if case == 'one' else 'two materials'}", fontsize=9)
            fig.colorbar(im, ax=ax, fraction=0.046, pad=0.03).set_label(unit, fontsize=8)
    fig.suptitle("K_mag per node, field of points turned 20° (Acosta fig. 19-21); + : C, dashed: A–A'", fontsize=10)
    fig.tight_layout()
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=90)
    os.replace(tmp, png)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--png-mpm", help="fig. 20: FEM, regular MPM, W*, GM, DM")
    ap.add_argument("--png-gimp", help="fig. 21: GIMP, DM-G")
    a = ap.parse_args()
    print(f"{'method':12} {'increase %':>11} {'decrease %':>11} {'two: below %':>13} {'above %':>8} {'all %':>7}")
    x, y, _ = k_mag(os.path.join(a.out, "mpm_one"))
    rows = [("FEM", spread(x, y, fem(x, y, "one")), two_material_error(x, y, fem(x, y, "two")))]
    for key, label in METHODS:
        rows.append((label, spread(*k_mag(os.path.join(a.out, f"{key}_one"))),
                     two_material_error(*k_mag(os.path.join(a.out, f"{key}_two")))))
    for label, (hi, lo), (below, above, whole) in rows:
        print(f"{label:12} {hi:11.2f} {lo:11.2f} {below:13.2f} {above:8.2f} {whole:7.2f}")
    if a.png_mpm:
        draw(a.out, [("fem", "FEM, 2 x 2 Gauss points")] + METHODS[:4], a.png_mpm)
    if a.png_gimp:
        draw(a.out, METHODS[4:], a.png_gimp)


if __name__ == "__main__":
    main()
