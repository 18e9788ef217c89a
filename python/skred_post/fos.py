"""The picture of a strength-reduction study (OUTDIR/fos.csv of `skred fos`): how far the slope
moved in the slide stage, and how long the stage ran (a failing run stops once it has failed,
so its time to fail), against the factor f that divided c, tan(phi) and tan(psi); the
threshold that counts a run as failing, the bracket found (per cell size, with --levels), and
Bishop's limit-equilibrium F where the study has it."""
import os

import numpy as np

from .data import PostError, read_csv_columns

TEXT_COLUMNS = ("status", "folder", "fails", "ended_by")


def read_fos(outdir):
    """{column: NumPy array} of OUTDIR/fos.csv, rows sorted by the factor: numbers as float
    (NaN where the table says nan), the text columns (status, folder, fails, ended_by) as str."""
    path = os.path.join(outdir, "fos.csv")
    if not os.path.isfile(path):
        raise PostError(f"{path} not found: is {outdir} the output folder of `skred fos`?")
    header, table = read_csv_columns(path, TEXT_COLUMNS)
    for column in ("factor", "fails", "max_displacement", "threshold", "stage_time"):
        if column not in header:
            raise PostError(f"{path}: no {column} column")
    if len(table["factor"]) == 0:
        raise PostError(f"{path} has no rows")
    order = np.argsort(table["factor"], kind="stable")
    return {name: values[order] for name, values in table.items()}


def fos_bracket(t):
    """(stands, fails): the largest factor that stood below the smallest that failed, or None
    where the runs do not bracket the onset (the runs of one cell size)."""
    fails = t["fails"] == "true"
    if not fails.any() or fails.all():
        return None
    first = t["factor"][fails].min()
    below = t["factor"][~fails & (t["factor"] < first)]
    return (below.max(), first) if below.size else None


def level_rows(t):
    """[(cell_size or None, {column: array})]: the runs of each cell size, coarsest first (one
    entry, cell size None, for a table of one level or without the cell_size column)."""
    if "cell_size" not in t or len(np.unique(t["cell_size"])) < 2:
        return [(None, t)]
    return [(h, {name: values[t["cell_size"] == h] for name, values in t.items()})
            for h in sorted(np.unique(t["cell_size"]), reverse=True)]


def plot_fos(outdir, dpi=100):
    t = read_fos(outdir)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bishop = t["limit_equilibrium"][0] if "limit_equilibrium" in t else np.nan
    levels = level_rows(t)
    several = len(levels) > 1
    shades = plt.get_cmap("viridis")(np.linspace(0.0, 0.8, len(levels)))
    fig, axes = plt.subplots(1, 2, figsize=(9.5, 3.8), dpi=dpi, constrained_layout=True, sharex=True)
    panels = [("max_displacement", "largest displacement in the stage [m]", True),
              ("stage_time", "time the stage ran [s] (failed: time to fail)", False)]
    for ax, (column, label, log) in zip(axes, panels):
        if log:
            ax.set_yscale("log")
            ax.axhline(t["threshold"][0], color="0.3", ls=":", lw=1.2, label="fails above")
        for shade, (h, rows) in zip(shades, levels):
            f, fails = rows["factor"], rows["fails"] == "true"
            y = np.maximum(rows[column], 1e-6) if log else rows[column]  # a slope that did not move
            at = f", h = {h:g} m" if several else ""
            ax.plot(f, y, "-", color=shade if several else "0.6", lw=1.0)
            ax.plot(f[~fails], y[~fails], "o", color="#2ca02c", mec=shade if several else "none", mew=1.5,
                    ms=6, label="stands" + at)
            ax.plot(f[fails], y[fails], "s", color="#d62728", mec=shade if several else "none", mew=1.5,
                    ms=6, label="fails" + at)
            bracket = fos_bracket(rows)
            if bracket:
                ax.axvspan(*bracket, color=shade if several else "#ff7f0e", alpha=0.2, lw=0,
                           label="the MPM's factor of safety" + at)
        if np.isfinite(bishop):
            ax.axvline(bishop, color="#1f77b4", ls="--", lw=1.3, label=f"Bishop's F = {bishop:.3f}")
        ax.set_xlabel("strength reduction factor f (c, tan φ, tan ψ divided by f)", fontsize="small")
        ax.set_ylabel(label, fontsize="small")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize="x-small")
    title = "strength reduction (fos.csv): the slide stage at each factor"
    bracket = fos_bracket(levels[-1][1])
    if bracket:
        title += f"; the slope fails between f = {bracket[0]:g} and {bracket[1]:g}"
        if several:
            title += f" at h = {levels[-1][0]:g} m"
    fig.suptitle(title, fontsize="medium")
    return fig
