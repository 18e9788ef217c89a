#!/usr/bin/python3
"""Acosta fig. 26-29 for the vertical cut (§7.2): the elastic stiffness K_mag and the internal force
|F_int| per grid node (eq. 25-26, the grid frames' `stiffness_magnitude` and
`internal_force_magnitude`), and the points' deviatoric stress q and mean stress p, for two runs
(regular MPM and DM-GC) at the frames where the toe (the front) has moved 0.1, 0.3, 0.5 and 1.0 m.

  /usr/bin/python3 scripts/vertical_cut_fields.py OUT_MPM OUT_DMGC [--labels MPM DM-GC]
      [--png-grid F26_27.png] [--png-stress F28_29.png]

Prints, per run and toe displacement, over the full nodes (mass within 5 % of rho h^2): K_mag's mean
against FEM's (bilinear cells, 2 x 2 Gauss points: 4/3 sqrt(2) (D11 + G)) and its spread (standard
deviation over mean), and the roughness of |F_int|: the RMS of its five-point Laplacian h^2 lap|F| over rho g h^2. Write a frame every
step (scripts/vertical_cut_remedies.sh does)."""
import argparse
import math
import os
import re

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

TOES = (0.1, 0.3, 0.5, 1.0)


def pvd(out, name):
    text = open(os.path.join(out, name)).read()
    return [(float(t), os.path.join(out, f)) for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', text)]


def particles(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    o = r.GetOutput()
    cd = o.GetCellData()
    pts = vtk_to_numpy(o.GetPoints().GetData())
    n = cd.GetArray("mean_stress_p").GetNumberOfTuples()
    return {"x": pts.reshape(n, -1, 3).mean(axis=1)[:, :2], "u": vtk_to_numpy(cd.GetArray("displacement"))[:, :2],
            "p": vtk_to_numpy(cd.GetArray("mean_stress_p")) / 1e3,
            "q": vtk_to_numpy(cd.GetArray("deviatoric_stress_q")) / 1e3}


def grid(path):
    r = vtk.vtkXMLRectilinearGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    x, y = vtk_to_numpy(g.GetXCoordinates()), vtk_to_numpy(g.GetYCoordinates())
    field = lambda name: vtk_to_numpy(g.GetPointData().GetArray(name)).reshape(len(y), len(x))
    return {"x": x, "y": y, "mass": field("mass"), "K": field("stiffness_magnitude") / 1e3,
            "F": field("internal_force_magnitude")}


def toe_frames(out):
    """The frames at which the front of the cut (its points' largest x) first moved each of TOES."""
    frames = pvd(out, "particles.pvd")
    x0 = particles(frames[0][1])["x"][:, 0].max()
    chosen, k = [], 0
    for i, (t, f) in enumerate(frames):
        while k < len(TOES) and particles(f)["x"][:, 0].max() - x0 >= TOES[k]:
            chosen.append(i)
            k += 1
    return chosen + [None] * (len(TOES) - len(chosen))


def measures(g, rho, E, nu, gravity):
    h = g["x"][1] - g["x"][0]
    full = np.abs(g["mass"] / (rho * h * h) - 1.0) < 0.05
    full[0, :] = full[-1, :] = full[:, 0] = full[:, -1] = False
    fem = 4.0 / 3.0 * math.sqrt(2.0) * (E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) + E / (2 * (1 + nu))) / 1e3
    k = g["K"][full]
    k_err = (100.0 * (k.mean() / fem - 1.0), 100.0 * k.std() / k.mean())
    F = g["F"]
    lap = np.zeros_like(F)
    lap[1:-1, 1:-1] = F[2:, 1:-1] + F[:-2, 1:-1] + F[1:-1, 2:] + F[1:-1, :-2] - 4 * F[1:-1, 1:-1]
    inner = full.copy()
    inner[1:-1, 1:-1] &= full[2:, 1:-1] & full[:-2, 1:-1] & full[1:-1, 2:] & full[1:-1, :-2]
    f_rough = math.sqrt(np.mean(lap[inner] ** 2)) / (rho * gravity * h * h)
    return k_err, f_rough, int(full.sum())


def draw_panels(runs, labels, png, source, fields, paint, title, dpi):
    """Rows: each field for each run; columns: the toe positions. `paint(ax, frame, field, lim)`
    draws one panel from run[source][column] and returns its mappable."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(4, len(TOES), figsize=(3.3 * len(TOES), 9.0), squeeze=False)
    for r, (field, unit, lim) in enumerate(fields):
        for s, (run, label) in enumerate(zip(runs, labels)):
            row = 2 * r + s
            for c, toe in enumerate(TOES):
                ax = axes[row][c]
                frame = run[source][c]
                if frame is None:
                    ax.set_axis_off()
                    continue
                mappable = paint(ax, frame, field, lim)
                ax.set_aspect("equal")
                ax.set_xlim(0, 5)
                ax.set_ylim(0, 3.2)
                ax.set_title(f"{label}, toe {toe} m", fontsize=9)
            fig.colorbar(mappable, ax=axes[row].tolist(), fraction=0.02, pad=0.01).set_label(unit, fontsize=8)
    fig.suptitle(title, fontsize=10)
    tmp = png + ".tmp.png"
    fig.savefig(tmp, dpi=dpi)
    os.replace(tmp, png)


def draw_grid(runs, labels, png):
    def paint(ax, g, field, lim):
        v = np.where(g["mass"] > 0, g[field], np.nan)
        return ax.pcolormesh(g["x"], g["y"], v, shading="nearest", cmap="viridis", vmin=lim[0], vmax=lim[1])

    draw_panels(runs, labels, png, "grids", (("K", "K_mag [kN/m²]", (2500, 4500)), ("F", "|F_int| [N/m]", (0, 600))),
                paint, "Vertical cut: K_mag (eq. 25) and |F_int| (eq. 26) per node (Acosta fig. 26-27)", 80)


def draw_stress(runs, labels, png):
    def paint(ax, P, field, lim):
        return ax.scatter(P["x"][:, 0], P["x"][:, 1], c=P[field], s=3.5, marker="s", cmap="viridis", vmin=lim[0],
                          vmax=lim[1], linewidths=0)

    draw_panels(runs, labels, png, "points", (("q", "q [kPa]", (0, 25)), ("p", "p [kPa]", (-60, 10))), paint,
                "Vertical cut: the points' q and p (Acosta fig. 28-29)", 110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs=2)
    ap.add_argument("--labels", nargs=2, default=["MPM", "DM-GC"])
    ap.add_argument("--density", type=float, default=2000.0)
    ap.add_argument("--young", type=float, default=1e6)
    ap.add_argument("--poisson", type=float, default=0.35)
    ap.add_argument("--png-grid")
    ap.add_argument("--png-stress")
    a = ap.parse_args()
    runs = []
    print("run      toe [m]  frame  t [s]  K_mag mean vs FEM [%]  K_mag spread [%]  |F_int| roughness  full nodes")
    for out, label in zip(a.runs, a.labels):
        chosen = toe_frames(out)
        times, gfiles = zip(*pvd(out, "grid.pvd"))
        pfiles = [f for _, f in pvd(out, "particles.pvd")]
        run = {"grids": [], "points": []}
        for toe, i in zip(TOES, chosen):
            if i is None:
                print(f"{label:8} {toe:7.1f}  not reached")
                run["grids"].append(None)
                run["points"].append(None)
                continue
            g = grid(gfiles[i])
            k_err, f_rough, n = measures(g, a.density, a.young, a.poisson, 9.81)
            print(f"{label:8} {toe:7.1f} {i:6d} {times[i]:6.3f} {k_err[0]:21.2f} {k_err[1]:17.2f} {f_rough:18.2f} {n:11d}")
            run["grids"].append(g)
            run["points"].append(particles(pfiles[i]))
        runs.append(run)
    if a.png_grid:
        draw_grid(runs, a.labels, a.png_grid)
    if a.png_stress:
        draw_stress(runs, a.labels, a.png_stress)


if __name__ == "__main__":
    main()
