#!/usr/bin/python3
"""The p-q paths of three points of a vertical cut (Acosta et al. 2020 §7.2, fig. 30-31), from
the particle frames of one or more runs, and a measure of their oscillation.

  /usr/bin/python3 scripts/pq_paths.py OUT_MPM OUT_DMGC --labels MPM DM-GC --cohesion 12000 \
      --png pq.png

Points are chosen on the first run and followed by their index (the runs must start from the
same points, without splitting): A at the toe, B in the shear band at mid-height (the point of
the largest final plastic shear strain among those starting at y = H/2), C in the centre of the
sliding block (the point nearest the start centroid of the points that moved more than half the
largest displacement). The oscillation of a path is the RMS of its second difference,
sqrt(mean((p[k+1] - 2 p[k] + p[k-1])^2 + (q ...)^2)) in kPa, over the path resampled linearly
at a common interval (--sample, default 0.02 s; runs whose steps were cut write more frames): a
smooth path, rising or falling, scores little; a path that zig-zags from step to step scores its
zig-zag. It is given over the whole path and over the large-deformation window from --after
(0.15 s: the toe has moved 0.1 m), apart from the start, where the release of the cut rings the
same in every run before any point crosses a cell. Write a frame every step (output interval
below the time step).
"""
import argparse
import glob
import json
import os
import re
import sys

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


def frames(out):
    pvd = os.path.join(out, "particles.pvd")
    if not os.path.exists(pvd):
        sys.exit(f"{out}: no particles.pvd")
    entries = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', open(pvd).read())
    result = []
    for time, name in entries:
        f = os.path.join(out, name)
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(f)
        r.Update()
        cd = r.GetOutput().GetCellData()
        get = lambda name: vtk_to_numpy(cd.GetArray(name))
        # The point's centre: the mean of its voxel's corners.
        pts = vtk_to_numpy(r.GetOutput().GetPoints().GetData())
        corners = pts.shape[0] // get("mean_stress_p").shape[0]
        centre = pts.reshape(-1, corners, 3).mean(axis=1)[:, :2]
        result.append({
            "t": float(time),
            "x": centre,
            "u": get("displacement")[:, :2],
            "p": get("mean_stress_p"),
            "q": get("deviatoric_stress_q"),
            "eps": get("plastic_shear_strain"),
        })
    return result


def choose_points(run, height, toe):
    first, last = run[0], run[-1]
    x0 = first["x"]
    a = int(np.argmin(np.hypot(x0[:, 0] - toe[0], x0[:, 1] - toe[1])))
    dy = np.abs(x0[:, 1] - 0.5 * height)
    row = np.where(dy < dy.min() + 1e-6)[0]  # the row of points nearest mid-height
    b = int(row[np.argmax(last["eps"][row])])
    moved = np.linalg.norm(last["u"], axis=1)
    block = moved > 0.5 * moved.max()
    centre = x0[block].mean(axis=0)
    c = int(np.argmin(np.hypot(x0[:, 0] - centre[0], x0[:, 1] - centre[1])))
    return {"A": a, "B": b, "C": c}


def oscillation(t, p, q, dt, start=None):
    ts = np.arange(t[0] if start is None else start, t[-1] + 1e-9, dt)
    if len(ts) < 3:
        return float("nan")
    p, q = np.interp(ts, t, p), np.interp(ts, t, q)
    d2 = np.diff(p, 2) ** 2 + np.diff(q, 2) ** 2
    return float(np.sqrt(d2.mean())) / 1e3


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--labels", nargs="+")
    ap.add_argument("--height", type=float, default=3.0)
    ap.add_argument("--toe", type=float, nargs=2, default=[3.0, 0.0])
    ap.add_argument("--cohesion", type=float, default=12000.0, help="peak cohesion c_p (Pa)")
    ap.add_argument("--sample", type=float, default=0.02, help="resampling interval of the paths (s)")
    ap.add_argument("--after", type=float, default=0.15,
                    help="start of the large-deformation window (s), measured apart from the whole path")
    ap.add_argument("--png")
    ap.add_argument("--json")
    args = ap.parse_args()
    labels = args.labels or [os.path.basename(r.rstrip("/")) for r in args.runs]
    runs = [frames(r) for r in args.runs]
    chosen = choose_points(runs[0], args.height, args.toe)
    table = {}
    for label, run in zip(labels, runs):
        table[label] = {}
        for name, i in chosen.items():
            t = np.array([f["t"] for f in run])
            p = np.array([f["p"][i] for f in run])
            q = np.array([f["q"][i] for f in run])
            table[label][name] = {"oscillation_kPa": oscillation(t, p, q, args.sample),
                                  "late_oscillation_kPa": oscillation(t, p, q, args.sample, args.after),
                                  "t": t.tolist(), "p": p.tolist(), "q": q.tolist()}
    x0 = runs[0][0]["x"]
    print("points (start):", ", ".join(f"{n} ({x0[i][0]:.3f}, {x0[i][1]:.3f})" for n, i in chosen.items()))
    print(f"oscillation (RMS second difference of p and q, kPa), the whole path / from t = {args.after} s:")
    print("run".ljust(12) + "".join(n.rjust(15) for n in chosen))
    for label in labels:
        print(label.ljust(12) + "".join(
            f"{table[label][n]['oscillation_kPa']:7.2f} / {table[label][n]['late_oscillation_kPa']:5.2f}" for n in chosen))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"points": {n: [float(x0[i][0]), float(x0[i][1])] for n, i in chosen.items()},
                       "runs": table}, f)
    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
        q_yield = np.sqrt(3.0) * args.cohesion / 1e3  # von Mises in p-q: q = sqrt(3) c
        for ax, name in zip(axes, chosen):
            for label in labels:
                t = table[label][name]
                ax.plot(np.array(t["p"]) / 1e3, np.array(t["q"]) / 1e3, ".-", lw=1, ms=3,
                        label=f"{label} ({t['oscillation_kPa']:.1f} / {t['late_oscillation_kPa']:.1f} kPa)")
            ax.axhline(q_yield, color="k", ls="--", lw=0.8, label="F_VM at c_p")
            ax.set_title(f"point {name}")
            ax.set_xlabel("p (kPa)")
            ax.set_ylabel("q (kPa)")
            ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.png, dpi=110)
        print("wrote", args.png)


if __name__ == "__main__":
    main()
