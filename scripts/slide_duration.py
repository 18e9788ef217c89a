#!/usr/bin/python3
"""How long a slide lasts, from a run's series.csv: over the rows of one stage (default: the
last), the time of the kinetic energy's peak, when it falls below --ke (default 1 %) of that
peak for good, and when the gravity work and the runout have done --share (default 95 %) of
their change over the stage; times from the stage's start. With --body ID, the x extent of that
body's points in the first and the last particles frame.

  /usr/bin/python3 scripts/slide_duration.py OUT [OUT ...] [--stage N] [--ke 0.01] [--share 0.95] [--body 1]
"""
import argparse
import csv
import os
import re


def measure(out, stage=None, ke_share=0.01, share=0.95):
    rows = list(csv.DictReader(open(os.path.join(out, "series.csv"))))
    if stage is None:
        stage = max(int(r["stage"]) for r in rows)
    rows = [r for r in rows if int(r["stage"]) == stage]
    t = [float(r["time"]) for r in rows]
    t0 = t[0]
    ke = [float(r["kinetic_energy"]) for r in rows]
    peak = max(ke)
    i_peak = ke.index(peak)
    above = [i for i, k in enumerate(ke) if k > ke_share * peak]
    over = t[above[-1] + 1] if above and above[-1] + 1 < len(t) else float("nan")

    def done(column):
        v = [float(r[column]) for r in rows]
        goal = v[0] + share * (v[-1] - v[0])
        sign = 1.0 if v[-1] >= v[0] else -1.0
        return next(ti for ti, x in zip(t, v) if sign * (x - goal) >= 0) - t0, v[-1] - v[0]

    work_t, work = done("gravity_work")
    run_t, run = done("runout")
    return {"end": t[-1] - t0, "peak": t[i_peak] - t0, "ke_over": over - t0, "work_t": work_t, "work": work,
            "runout_t": run_t, "runout": run}


def body_extent(out, body):
    """(time, x min, x max) of the body's point centres in the first and the last frame."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    entries = re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', open(os.path.join(out, "particles.pvd")).read())
    result = []
    for time, name in (entries[0], entries[-1]):
        r = vtk.vtkXMLUnstructuredGridReader()
        r.SetFileName(os.path.join(out, name))
        r.Update()
        g = r.GetOutput()
        centres = vtk_to_numpy(g.GetPoints().GetData()).reshape(g.GetNumberOfCells(), -1, 3).mean(axis=1)
        x = centres[vtk_to_numpy(g.GetCellData().GetArray("body_id")) == body, 0]
        result.append((float(time), float(x.min()), float(x.max())))
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--stage", type=int)
    ap.add_argument("--ke", type=float, default=0.01)
    ap.add_argument("--share", type=float, default=0.95)
    ap.add_argument("--body", type=int)
    a = ap.parse_args()
    print(f"{'run':28s} {'stage [s]':>9s} {'KE peak':>8s} {'KE over':>8s} {'work done':>9s} "
          f"{'work [MJ]':>9s} {'runout done':>11s} {'runout [m]':>10s}")
    for out in a.runs:
        m = measure(out, a.stage, a.ke, a.share)
        print(f"{os.path.basename(os.path.normpath(out)):28s} {m['end']:9.2f} {m['peak']:8.2f} {m['ke_over']:8.2f} "
              f"{m['work_t']:9.2f} {m['work'] / 1e6:9.2f} {m['runout_t']:11.2f} {m['runout']:10.2f}")
        if a.body is not None:
            print("    body %d: " % a.body + ", ".join(f"x {lo:.1f} to {hi:.1f} m at t = {t:.1f} s"
                                                   for t, lo, hi in body_extent(out, a.body)))


if __name__ == "__main__":
    main()
