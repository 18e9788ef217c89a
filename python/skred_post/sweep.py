"""The picture of a parameter sweep (OUTDIR/sweep.csv of `skred sweep`): every slide measure
of the last stage against the first swept key with more than one value, one line per value
of the other swept keys (for a 2-key grid: one line per value of the second key)."""
import os

import numpy as np

from .data import PostError, read_csv_columns

TEXT_COLUMNS = ("status", "folder", "stage", "ended_by")

# Measures drawn: (column, label with symbol, unit in 2D, unit in 3D).
MEASURES = [("runout", "runout", "m", "m"),
            ("max_displacement", "largest displacement $|u|_\\mathrm{max}$", "m", "m"),
            ("height_end", "deposit height", "m", "m"),
            ("peak_mean_speed", "peak mean speed $\\bar v_\\mathrm{max}$", "m/s", "m/s"),
            ("final_mean_speed", "final mean speed", "m/s", "m/s"),
            ("stop_time", "stop time (stage time)", "s", "s"),
            ("gravity_work", "gravity work $W_g$", "J/m", "J"),
            ("kinetic_energy_change", "kinetic energy change $\\Delta K$", "J/m", "J"),
            ("strain_energy", "stored elastic energy change", "J/m", "J"),
            ("plastic_dissipation", "plastic dissipation $D_p$", "J/m", "J"),
            ("plastic_volume", "plastified volume", "m³/m", "m³"),
            ("plastic_points", "plastified points", "-", "-")]


def read_sweep(outdir):
    """(keys, table) of OUTDIR/sweep.csv: the swept keys (the columns before `status`) and
    {column: NumPy array}: int64 for integer columns, float for numbers (NaN where the table
    says nan), str for the text columns (status, folder, stage, ended_by):
    pandas.DataFrame(table) takes it."""
    path = os.path.join(outdir, "sweep.csv")
    if not os.path.isfile(path):
        raise PostError(f"{path} not found: is {outdir} the output folder of `skred sweep`?")
    header, table = read_csv_columns(path, TEXT_COLUMNS)
    if "status" not in header:
        raise PostError(f"{path}: no header with a status column")
    return header[:header.index("status")], table


def plot_sweep(outdir, dpi=100):
    keys, table = read_sweep(outdir)
    n = len(table["status"])
    if n == 0:
        raise PostError(f"{outdir}/sweep.csv has no rows")
    varying = [k for k in keys if len(np.unique(table[k])) > 1]
    x_key = varying[0] if varying else keys[0]
    others = [k for k in keys if k != x_key]
    three_d = "runout_z_min" in table
    # A measure that is zero (or unset) in every run says nothing: left out, and named.
    shown = [m for m in MEASURES if m[0] in table and np.any(np.isfinite(table[m[0]]) & (table[m[0]] != 0))]
    zero = [m[0] for m in MEASURES if m[0] in table and m not in shown]
    measures = shown
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    plt.rcParams["axes.formatter.useoffset"] = False
    cols = 3
    cols = min(cols, max(1, len(measures)))
    nrows = max(1, -(-len(measures) // cols))
    fig, axes = plt.subplots(nrows, cols, figsize=(4.0 * cols, 2.9 * nrows + 0.6), dpi=dpi,
                             constrained_layout=True, squeeze=False)
    groups = sorted({tuple(table[k][i] for k in others) for i in range(n)})
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, max(1, len(groups))))
    failed = table["status"] != "completed"
    for ax in axes.flat[len(measures):]:
        ax.set_visible(False)
    for ax, (col, label, unit2, unit3) in zip(axes.flat, measures):
        for colour, g in zip(colours, groups):
            rows = [i for i in range(n) if tuple(table[k][i] for k in others) == g]
            rows.sort(key=lambda i: table[x_key][i])
            x, y = table[x_key][rows], table[col][rows]
            name = ", ".join(f"{k} = {v:g}" for k, v in zip(others, g))
            ax.plot(x, y, "o-", color=colour, ms=4, lw=1.2, label=name or None)
            bad = failed[rows]
            if bad.any():
                ax.plot(x[bad], y[bad], "x", color="#d62728", ms=8, mew=1.5)
        ax.set_ylabel(f"{label} [{unit3 if three_d else unit2}]", fontsize="small")
        ax.set_xlabel(x_key, fontsize="small")
        ax.grid(alpha=0.3)
    if others:
        axes.flat[0].legend(fontsize="x-small")
    title = f"sweep of {x_key}" + (f", one line per {', '.join(others)}" if others else "")
    if failed.any():
        title += " (red x: run did not complete)"
    title += ": the last stage's measures (sweep.csv)"
    if zero:
        title += "\nzero or unset in every run: " + ", ".join(zero)
    fig.suptitle(title, fontsize="medium")
    return fig
