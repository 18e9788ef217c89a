"""The picture of a refinement study (OUTDIR/refine.csv of `skred refine`): the last stage's
runout, its change per halving of the cell, the largest displacement and the gravity work
against the cell size, one line per velocity transfer, with the 5 % band of issue 12 around
each transfer's finest runout, and, where extrapolation.csv has one, the runout and gravity work
extrapolated to h -> 0 (Richardson, Celik et al. 2008)."""
import os

import numpy as np

from .data import PostError, read_csv_columns

TEXT_COLUMNS = ("transfer", "status", "folder", "stage", "ended_by")


def read_refine(outdir):
    """{column: NumPy array} of OUTDIR/refine.csv: numbers as int64 or float (NaN where the
    table says nan), the text columns (transfer, status, folder, stage, ended_by) as str."""
    path = os.path.join(outdir, "refine.csv")
    if not os.path.isfile(path):
        raise PostError(f"{path} not found: is {outdir} the output folder of `skred refine`?")
    header, table = read_csv_columns(path, TEXT_COLUMNS)
    if "transfer" not in header or "runout" not in header:
        raise PostError(f"{path}: no header with transfer and runout columns")
    if len(table["transfer"]) == 0:
        raise PostError(f"{path} has no rows")
    return table


def read_extrapolation(outdir):
    """{column: NumPy array} of OUTDIR/extrapolation.csv (Richardson's extrapolation of the last
    three sizes per transfer: transfer, quantity, kind as str), or None if there is none."""
    path = os.path.join(outdir, "extrapolation.csv")
    if not os.path.isfile(path):
        return None
    header, table = read_csv_columns(path, ("transfer", "quantity", "kind"))
    return table if "extrapolated" in header and len(table["transfer"]) else None


def plot_refine(outdir, dpi=100):
    t = read_refine(outdir)
    ex = read_extrapolation(outdir)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    transfers = list(dict.fromkeys(t["transfer"]))  # in the table's order
    colours = plt.get_cmap("tab10")(np.arange(len(transfers)) % 10)
    panels = [("runout", "runout [m]"), ("runout_change", "change per halving [%]"),
              ("max_displacement", "largest displacement [m]"), ("gravity_work", "gravity work $W_g$")]
    fig, axes = plt.subplots(2, 2, figsize=(9.0, 6.4), dpi=dpi, constrained_layout=True, sharex=True)
    failed = t["status"] != "completed"
    for colour, name in zip(colours, transfers):
        rows = np.flatnonzero(t["transfer"] == name)
        h = t["cell_size"][rows]
        for ax, (col, label) in zip(axes.flat, panels):
            y = t[col][rows] * (100.0 if col == "runout_change" else 1.0)
            ax.plot(h, y, "o-", color=colour, ms=5, lw=1.3, label=name)
            if failed[rows].any():
                ax.plot(h[failed[rows]], y[failed[rows]], "x", color="#d62728", ms=9, mew=1.6)
        if ex is not None:  # the value as h -> 0, where Richardson's extrapolation gives one
            for ax, col in ((axes[0, 0], "runout"), (axes[1, 1], "gravity_work")):
                k = np.flatnonzero((ex["transfer"] == name) & (ex["quantity"] == col))
                if len(k) and np.isfinite(ex["extrapolated"][k[0]]):
                    ax.axhline(ex["extrapolated"][k[0]], color=colour, ls="--", lw=1.0)
        finest = t["runout"][rows[-1]]
        if np.isfinite(finest) and finest > 0:  # issue 12's 5 % around the finest runout
            axes[0, 0].axhspan(0.95 * finest, 1.05 * finest, color=colour, alpha=0.12, lw=0)
    axes[0, 1].axhspan(-5.0, 5.0, color="0.5", alpha=0.15, lw=0)
    sizes = np.unique(t["cell_size"])
    for ax, (col, label) in zip(axes.flat, panels):
        ax.set_xscale("log", base=2)
        ax.set_xticks(sizes, [f"{h:g}" for h in sizes])
        ax.minorticks_off()
        ax.set_xlim(sizes.max() * 2 ** 0.3, sizes.min() / 2 ** 0.3)  # finer cells to the right
        ax.set_xlabel("cell size h [m]", fontsize="small")
        ax.set_ylabel(label, fontsize="small")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize="x-small", title="transfer", title_fontsize="x-small")
    title = "refinement study (refine.csv): the last stage's measures against the cell size;"
    title += "\nshaded: 5 % around each transfer's finest runout, and ±5 % change per halving"
    if ex is not None and np.isfinite(ex["extrapolated"]).any():
        title += ";\ndashed: Richardson's extrapolation to h → 0 of the last three sizes (extrapolation.csv)"
    if failed.any():
        title += " (red x: run did not complete)"
    fig.suptitle(title, fontsize="medium")
    return fig
