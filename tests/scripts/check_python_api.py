"""check_python_api.py TARGET RUN_DIR
Imports skred_post from TARGET (where `pip install --target` put it, not the source tree)
and reads the run in RUN_DIR (the colliding discs of test_post_python.cpp: two discs of
radius 0.2 m, 2 x 2 points per 0.05 m cell, velocities +-(0.1, 0.1) m/s, density 1000).
Checks what it reads against what the run wrote, read here without skred_post: summary.json
with json, series.csv with csv, particles.pvd with ElementTree; and against the scenario.
Prints one line per check; exits 1 if any fails."""
import csv
import json
import math
import os
import sys
import xml.etree.ElementTree as ET

target, run = sys.argv[1], sys.argv[2]
sys.path.insert(0, target)
import numpy as np  # noqa: E402

import skred_post as sp  # noqa: E402

failures = []


def expect(cond, what):
    print(("ok " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


expect(os.path.realpath(sp.__file__).startswith(os.path.realpath(target)),
       f"skred_post imported from the installed copy ({sp.__file__})")
for name in ("load_frame", "read_series", "read_summary", "read_sweep", "list_frames"):
    expect(callable(getattr(sp, name, None)) and getattr(sp, name).__doc__, f"{name} is documented")

# summary.json
summary = sp.read_summary(run)
with open(os.path.join(run, "summary.json")) as f:
    raw = json.load(f)
expect(summary == raw, "read_summary is summary.json")
expect(summary["status"] == "completed", "status completed")
expect(isinstance(summary["stages"], list) and summary["stages"][0]["steps"] == summary["steps"],
       "stages are a list of dicts")

# series.csv: every column, every row, as csv reads it
series = sp.read_series(run)
with open(os.path.join(run, "series.csv"), newline="") as f:
    rows = list(csv.DictReader(f))
expect(list(series) == list(rows[0]), "read_series has series.csv's columns in order")
expect(all(isinstance(v, np.ndarray) and v.shape == (len(rows),) for v in series.values()),
       f"each column a 1-D array of {len(rows)} rows (a pandas.DataFrame's columns)")
expect(all(np.array_equal(series[k], np.array([float(r[k]) for r in rows]), equal_nan=True) for k in series),
       "every value as written")
expect(series["step"].dtype.kind == "i" and series["time"].dtype.kind == "f", "step int64, time float")
expect(int(series["step"][-1]) == summary["steps"], "last row is the last step")
expect(math.isclose(series["time"][-1], summary["simulated_time"], rel_tol=1e-12), "last row's time")
expect(np.all(series["num_particles"] == summary["particles"]), "num_particles = summary's particles")

# frames: the index, and the first and last frame against the scenario
pvd = ET.parse(os.path.join(run, "particles.pvd")).getroot()
times = [float(d.get("timestep")) for d in pvd.iter("DataSet")]
index = sp.list_frames(run)
expect([t for _, t, _ in index] == times, f"list_frames gives the {len(times)} frames of particles.pvd")
first, last = sp.load_frame(run, 0), sp.load_frame(run)
n = summary["particles"]
expect(first.time == times[0] and last.time == times[-1] and last.step == len(times) - 1,
       "frame times and steps")
expect(first.dim == 2 and first.corners.shape == (n, 4, 3), f"{n} quadrilateral voxels")
x = first.positions()
expect(x.shape == (n, 2), "positions (n, 2)")
# Points fill the two discs: centres within a disc of radius 0.2 m (+ half a point spacing).
d = np.minimum(np.linalg.norm(x - [0.2, 0.2], axis=1), np.linalg.norm(x - [0.8, 0.8], axis=1))
expect(d.max() <= 0.2 + 0.0125, f"points inside the discs (farthest {d.max():.4f} m)")
# Each point is 1/4 of a 0.05 m cell: the volume column sums to n (0.025 m)^2 per metre.
expect(math.isclose(first.arrays["volume"].sum(), n * 0.025**2, rel_tol=1e-6), "volume = n (h/2)^2")
v = first.arrays["velocity"]
expect(v.shape == (n, 3) and np.allclose(np.abs(v[:, :2]), 0.1, rtol=1e-6), "|v_x| = |v_y| = 0.1 m/s")
expect(np.allclose(first.arrays["displacement"], 0.0), "no displacement in the first frame")
# Free flight until the contact (t ~ 1.59 s): every point moved by v t.
u = last.arrays["displacement"][:, :2]
expect(np.allclose(np.abs(u), 0.1 * last.time, rtol=1e-3, atol=1e-9),
       f"displacement = v t in free flight ({0.1 * last.time:.4f} m)")
stress = last.arrays["stress"]
expect(stress.shape == (n, 6) and last.components["stress"][:2] == ["xx", "yy"], "stress Voigt xx, yy, ...")
table = last.table()
expect(set(table) >= {"x", "y", "stress_xx", "stress_xy", "speed"} and
       all(len(c) == n for c in table.values()), "Frame.table(): flat columns for pandas")
if failures:
    print("failed: " + "; ".join(failures))
    sys.exit(1)
