"""Time-series plots from series.csv: energies with the gravity work, speeds, momentum."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .data import read_series  # noqa: E402

ENERGIES = [("kinetic_energy", "kinetic"), ("strain_energy", "strain"),
            ("plastic_dissipation", "plastic dissipation"), ("friction_work", "friction work"),
            ("transfer_dissipation", "transfer dissipation"), ("contact_work", "contact work"),
            ("damping_work", "damping work"), ("gravity_work", "gravity work"),
            ("total_energy", "total = kinetic + strain + dissipated - gravity work")]


def plot_series(outdir, width=8.0, height=8.0, dpi=100):
    s = read_series(outdir)
    t = s["time"]
    three_d = "momentum_z" in s  # 3D runs: totals, not per metre of thickness
    fig, axes = plt.subplots(3, 1, figsize=(width, height), dpi=dpi, sharex=True,
                             constrained_layout=True)
    for key, label in ENERGIES:
        if key in s:
            axes[0].plot(t, s[key], label=label, lw=2.0 if key == "total_energy" else 1.2,
                         ls="--" if key == "total_energy" else "-")
    axes[0].set_ylabel("energy [J]" if three_d else "energy [J/m]")
    axes[0].set_title("energies and gravity work (series.csv)", fontsize="medium")
    axes[0].legend(fontsize="small")
    for key, label in (("mean_speed", "mean speed (mass-weighted)"), ("max_speed", "max speed")):
        if key in s:
            axes[1].plot(t, s[key], label=label)
    axes[1].set_ylabel("speed [m/s]")
    axes[1].legend(fontsize="small")
    for key, label in (("momentum_x", "momentum x"), ("momentum_y", "momentum y"),
                       ("momentum_z", "momentum z")):
        if key in s:
            axes[2].plot(t, s[key], label=label)
    axes[2].set_ylabel("momentum [kg m/s]" if three_d else "momentum [kg m/s per m]")
    axes[2].set_xlabel("time [s]")
    axes[2].legend(fontsize="small")
    for a in axes:
        a.grid(alpha=0.3)
    return fig
