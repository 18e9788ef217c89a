"""Time-series plots from series.csv: energies with the gravity work, speeds, momentum, with
the stage boundaries marked (energies and gravity work restart from zero at each)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

plt.rcParams["axes.formatter.useoffset"] = False  # the values themselves, never "1e-13 + 0.1414"
import numpy as np  # noqa: E402

from .data import read_series, read_summary  # noqa: E402

ENERGIES = [("kinetic_energy", "kinetic"), ("strain_energy", "strain"),
            ("plastic_dissipation", "plastic dissipation"), ("friction_work", "friction work"),
            ("transfer_dissipation", "transfer dissipation"), ("contact_work", "contact work"),
            ("damping_work", "damping work"), ("gravity_work", "gravity work"),
            ("total_energy", "total = kinetic + strain + dissipated - gravity work")]


def stage_starts(outdir, s):
    """[(time, name)] of the stages' starts: the rows where the stage column changes, named
    after summary.json's stages when it has them."""
    if "stage" not in s or len(s["stage"]) == 0:
        return []
    stage = s["stage"]
    first = [0] + [int(i) + 1 for i in np.nonzero(np.diff(stage))[0]]
    names = [st.get("name") for st in ((read_summary(outdir) or {}).get("stages") or [])]
    out = []
    for i in first:
        k = int(stage[i])
        name = names[k] if 0 <= k < len(names) and names[k] else f"stage {k}"
        out.append((float(s["time"][i]), name))
    return out


def mark_stages(axes, starts, t_end):
    """Dotted lines at the stage boundaries; the stage names above the first plot, each over
    the middle of its stage."""
    for t0, _ in starts[1:]:
        for a in axes:
            a.axvline(t0, color="0.4", ls=":", lw=1.0, zorder=0)
    if len(starts) > 1:
        ends = [t for t, _ in starts[1:]] + [t_end]
        top = axes[0].secondary_xaxis("top")
        top.set_xticks([0.5 * (t0 + t1) for (t0, _), t1 in zip(starts, ends)])
        top.set_xticklabels([name for _, name in starts], fontsize="small", color="0.3")
        top.tick_params(length=0)


def plot_series(outdir, width=8.0, height=8.0, dpi=100):
    s = read_series(outdir)
    t = s["time"]
    three_d = "momentum_z" in s  # 3D runs: totals, not per metre of thickness
    fig, axes = plt.subplots(3, 1, figsize=(width, height), dpi=dpi, sharex=True,
                             constrained_layout=True)
    big = max((float(np.nanmax(np.abs(s[k]))) for k, _ in ENERGIES if k in s and len(s[k])), default=0.0)
    scale, prefix = (1e-3, "k") if big >= 1e4 else (1.0, "")  # kJ rather than a 1e6 multiplier
    for key, label in ENERGIES:
        if key in s:
            axes[0].plot(t, s[key] * scale, label=label, lw=2.0 if key == "total_energy" else 1.2,
                         ls="--" if key == "total_energy" else "-")
    axes[0].set_ylabel(f"energy [{prefix}J]" if three_d else f"energy [{prefix}J/m]")
    axes[0].set_title("energies and gravity work, from the start of each stage (series.csv)",
                      fontsize="medium")
    axes[0].legend(fontsize="small")
    for key, label in (("mean_speed", "mean speed (mass-weighted)"), ("max_speed", "max speed"),
                       ("material_speed", "the material's mean speed (rest test)")):
        if key in s:
            axes[1].plot(t, s[key], label=label)
    axes[1].set_ylabel("speed [m/s]")
    axes[1].legend(fontsize="small")
    for key, label in (("momentum_x", "momentum x"), ("momentum_y", "momentum y"),
                       ("momentum_z", "momentum z")):
        if key in s:
            axes[2].plot(t, s[key], label=label)
    axes[2].set_ylabel("momentum [kg m/s]" if three_d else "momentum [kg m/s per m]")
    axes[2].legend(fontsize="small")
    axes[2].set_xlabel("time $t$ [s]")
    for a in axes:
        a.grid(alpha=0.3)
    mark_stages(axes, stage_starts(outdir, s), float(t[-1]))
    return fig
