"""check_series_stages.py SOURCE_PYTHON_DIR RUN_DIR
The series plot of a two-stage run (series.csv and summary.json written by
test_post_render.cpp: stage 0 "settle" rows at t = 0, 0.5, 1; stage 1 "slide" rows at
t = 1.5, 2) marks the boundary at t = 1.5 with a vertical line in each of its three panels
and names the stages above the first. Exits 1 on any failure."""
import sys

sys.path.insert(0, sys.argv[1])
from skred_post.series import plot_series, stage_starts  # noqa: E402

failures = []


def expect(cond, what):
    print(("ok " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


run = sys.argv[2]
starts = stage_starts(run, __import__("skred_post").read_series(run))
expect(starts == [(0.0, "settle"), (1.5, "slide")], f"stage starts {starts}")
fig = plot_series(run)
panels = [a for a in fig.axes if a.get_ylabel()]
expect(len(panels) == 3, f"{len(panels)} panels")
for a in panels:
    vertical = [ln for ln in a.get_lines() if list(ln.get_xdata()) == [1.5, 1.5]]
    expect(len(vertical) == 1, f"boundary line at t = 1.5 in '{a.get_ylabel()}'")
fig.canvas.draw()
every = list(fig.axes) + [c for a in fig.axes for c in a.child_axes]  # the top axis is a child
names = [t.get_text() for a in every for t in a.get_xticklabels() if t.get_text() in ("settle", "slide")]
expect(sorted(names) == ["settle", "slide"], f"stage names shown: {names}")
if failures:
    print("failed: " + "; ".join(failures))
    sys.exit(1)
