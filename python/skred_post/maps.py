"""`skred render OUT --view top --map NAME`: a hazard map of a 3D run (docs/scenario.md,
"Hazard maps (3D)") over a hillshade of the terrain at the start (maps/terrain.asc), with a
scale bar and the runout outline: the edge of the columns the flow reached (arrival_time)."""
import os

import numpy as np

from .data import PostError
from .scenario_info import read_scenario

LABELS = {
    "deposit_thickness": ("deposit thickness", "m", "viridis"),
    "height_change": ("change of height", "m", "RdBu_r"),
    "max_speed": ("largest speed", "m/s", "magma_r"),
    "max_displacement": ("largest displacement", "m", "plasma_r"),
    "arrival_time": ("time of arrival", "s", "viridis_r"),
    "terrain": ("terrain", "m", "terrain"),
}


def read_asc(path):
    """An ESRI ASCII grid: (values with NaN for no data, rows first from the top; [x_min,
    x_max, y_min, y_max]; cell size)."""
    if not os.path.isfile(path):
        raise PostError(f"{path}: no such map (a 3D run with output.maps writes maps/)")
    header = {}
    with open(path) as f:
        for _ in range(6):
            key, value = f.readline().split()
            header[key.lower()] = float(value)
        values = np.loadtxt(f, ndmin=2)
    nodata = header.get("nodata_value")
    if nodata is not None:
        values[values == nodata] = np.nan
    cell, cols, rows = header["cellsize"], int(header["ncols"]), int(header["nrows"])
    x0, y0 = header["xllcorner"], header["yllcorner"]
    if values.shape != (rows, cols):
        raise PostError(f"{path}: {values.shape} values, not {rows} x {cols}")
    return values, [x0, x0 + cols * cell, y0, y0 + rows * cell], cell


def hillshade(z, cell, azimuth=315.0, altitude=45.0):
    """The cosine between the ground's normal and the light, from `azimuth` (clockwise from
    north) at `altitude` degrees; rows run from the north."""
    d_row, d_col = np.gradient(z, cell)
    de, dn = d_col, -d_row  # d/deasting, d/dnorthing
    a, h = np.radians(azimuth), np.radians(altitude)
    lit = (-de * np.sin(a) * np.cos(h) - dn * np.cos(a) * np.cos(h) + np.sin(h)) / np.sqrt(1 + de**2 + dn**2)
    return np.clip(lit, 0.0, 1.0)


def nice_length(width):
    """A round length near a fifth of `width`: 1, 2 or 5 times a power of ten."""
    target = width / 5.0
    power = 10.0 ** np.floor(np.log10(target))
    return max(m * power for m in (1, 2, 5) if m * power <= target)


def plot_map(outdir, name, dpi=100, cmap=None, vrange=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    maps = os.path.join(outdir, "maps")
    values, extent, cell = read_asc(os.path.join(maps, name + ".asc"))
    terrain, _, _ = read_asc(os.path.join(maps, "terrain.asc"))
    arrival, _, _ = read_asc(os.path.join(maps, "arrival_time.asc"))
    label, unit, default_cmap = LABELS[name]
    width, height = extent[1] - extent[0], extent[3] - extent[2]
    fig, ax = plt.subplots(figsize=(8, max(4.0, min(10.0, 8 * height / width))), dpi=dpi)
    ax.imshow(hillshade(np.nan_to_num(terrain), cell), cmap="gray", extent=extent, vmin=0, vmax=1)
    shown = values.copy()
    if name in ("deposit_thickness", "max_speed", "max_displacement"):
        shown[shown == 0] = np.nan  # where nothing moved: the hillshade
    vmin, vmax = vrange if vrange else (None, None)
    image = ax.imshow(np.ma.masked_invalid(shown), cmap=cmap or default_cmap, alpha=0.75, extent=extent,
                      vmin=vmin, vmax=vmax)
    fig.colorbar(image, ax=ax, label=f"{label} [{unit}]", shrink=0.8)
    reached = np.isfinite(arrival).astype(float)
    if reached.any() and not reached.all():
        xs = extent[0] + cell * (np.arange(reached.shape[1]) + 0.5)
        ys = extent[3] - cell * (np.arange(reached.shape[0]) + 0.5)
        ax.contour(xs, ys, reached, levels=[0.5], colors="red", linewidths=1.2)
    length = nice_length(width)
    x0, y0 = extent[0] + 0.05 * width, extent[2] + 0.06 * height
    ax.plot([x0, x0 + length], [y0, y0], color="black", linewidth=4, solid_capstyle="butt")
    ax.text(x0 + length / 2, y0 + 0.02 * height, f"{length:g} m", ha="center", va="bottom")
    scenario = read_scenario(outdir)[1] or {}
    if scenario.get("ground", {}).get("rotation", 0.0) % 360.0 != 0.0:
        # an ESRI grid cannot turn: a rotated scenario's .asc lies in its local frame
        ax.set_xlabel("scenario x [m]")
        ax.set_ylabel("scenario -z [m]")
        ax.set_title(f"{label}, in the scenario's frame (the GeoTIFF lies on the map); red: runout")
    else:
        ax.set_xlabel("easting [m]")
        ax.set_ylabel("northing [m]")
        ax.set_title(f"{label}, seen from above; red: the runout outline")
    ax.set_aspect("equal")
    return fig
