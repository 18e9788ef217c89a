"""Pictures of one particle frame with matplotlib (Agg): the deformed voxels as polygons
(Post §5.1), coloured by a field with a colour bar (§5.3), or by body with stripes or a
checkerboard laid out in the reference configuration (§5.2, thesis fig. C.4); velocity
arrows (§6, fig. 9) and principal-stress crosses (§7.2, fig. 12) as overlays."""
import json
import math
import os
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import colors as mcolors  # noqa: E402
from matplotlib.cm import ScalarMappable  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from .data import PostError, reference_centres, select, voxel_size  # noqa: E402

BACKGROUND = "white"
BAD_COLOUR = "#c8c8c8"  # NaN or infinite values (e.g. relative yield of an elastic material)


DEFAULT_FIELDS = ("displacement", "speed")  # the first a frame has is drawn by default


@dataclass
class Style:
    field: str = None             # NAME or NAME:COMPONENT; None: the first of DEFAULT_FIELDS
    cmap: str = "viridis"
    vrange: tuple = None          # (vmin, vmax) or None for the data's range
    pattern: str = None           # None, "stripes" or "checkerboard"
    pattern_width: float = None   # stripe width [m]; default 4 voxels
    pattern_angle: float = 0.0    # stripe direction [degrees from x]
    arrows: bool = False
    crosses: bool = False
    sample: int = 4               # overlays: one particle per sample x sample voxels
    width: float = 8.0            # figure width [inch]; the height follows the domain
    max_height: float = 9.0       # the tallest figure [inch] (a tall domain narrows it)
    dpi: int = 100
    body_names: dict = None       # body id -> name, for the pattern legend
    slip_circle: tuple = None     # (xc, yc, radius, x_from, x_to, F): Bishop's critical circle


def data_range(values_list):
    """(min, max) over the finite values of several arrays; None if there is none. Merge
    these (merge_ranges) before widening a flat range (finite_range)."""
    lo, hi = math.inf, -math.inf
    for v in values_list:
        v = v[np.isfinite(v)]
        if v.size:
            lo, hi = min(lo, float(v.min())), max(hi, float(v.max()))
    return (lo, hi) if lo <= hi else None


def merge_ranges(ranges):
    """The range holding every range of a list (None entries: no finite value)."""
    ranges = [r for r in ranges if r is not None]
    if not ranges:
        return None
    return min(r[0] for r in ranges), max(r[1] for r in ranges)


def widened(r):
    """A colour range that can be drawn: (0, 1) without data; a flat range x is widened to
    (0, 1) for x = 0 (a field that is zero everywhere, such as the displacement at the start),
    else by 0.1 % of |x| on each side; a range narrower than 1e-9 |x| counts as flat."""
    if r is None:
        return 0.0, 1.0
    lo, hi = r
    if hi - lo <= 1e-9 * max(abs(lo), abs(hi)):  # flat up to rounding (a rigid translation)
        lo = hi = 0.5 * (lo + hi)
        if lo == 0.0:
            return 0.0, 1.0
        pad = abs(lo) * 1e-3
        return lo - pad, hi + pad
    return lo, hi


def finite_range(values_list):
    """(min, max) over the finite values of several arrays, widened if empty or flat."""
    return widened(data_range(values_list))


def default_field(frame):
    """The field drawn when none is asked for: the displacement magnitude (the speed is zero
    at the final state of a slide), else the speed."""
    for name in DEFAULT_FIELDS:
        if name in frame.arrays:
            return name
    raise PostError("the frame has neither displacement nor speed; choose a field with --field: "
                    + ", ".join(sorted(frame.arrays)))


def resolve_field(frame, style):
    """Fills style.field with the default field if it is unset."""
    if not style.pattern and not style.field:
        style.field = default_field(frame)


def bounds(frames, margin=0.05):
    """Axis limits holding every voxel of every frame, with a margin."""
    pts = [f.quads.reshape(-1, 2) for f in frames if f.size]
    if not pts:
        return (0.0, 1.0), (0.0, 1.0)
    p = np.concatenate(pts)
    lo, hi = p.min(axis=0), p.max(axis=0)
    span = max(float((hi - lo).max()), 1e-12)
    lo, hi = lo - margin * span, hi + margin * span
    return (float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))


def subsample(centres, spacing):
    """Indices of one particle per square bin of side `spacing`, the one nearest its centre."""
    if len(centres) == 0:
        return np.zeros(0, dtype=int)
    keys = np.floor(centres / spacing).astype(np.int64)
    dist = np.linalg.norm(centres - (keys + 0.5) * spacing, axis=1)
    order = np.lexsort((dist, keys[:, 1], keys[:, 0]))
    k = keys[order]
    first = np.ones(len(order), dtype=bool)
    first[1:] = np.any(k[1:] != k[:-1], axis=1)
    return np.sort(order[first])


def pattern_colours(frame, style):
    """Body colour in two shades, alternating by stripe or checkerboard square of the voxel's
    reference position x_ref (Post §5.2)."""
    width = style.pattern_width or 4.0 * voxel_size(frame)
    a = math.radians(style.pattern_angle)
    x = reference_centres(frame)
    along = x[:, 0] * math.cos(a) + x[:, 1] * math.sin(a)
    across = -x[:, 0] * math.sin(a) + x[:, 1] * math.cos(a)
    band = np.floor(across / width).astype(np.int64)
    if style.pattern == "checkerboard":
        band = band + np.floor(along / width).astype(np.int64)
    dark = (band % 2) == 1
    bodies = frame.arrays.get("body_id", np.zeros(frame.size)).astype(int)
    palette = plt.get_cmap("tab10")
    base = np.array([palette(b % 10) for b in bodies]).reshape(-1, 4)
    light = base.copy()
    light[:, :3] = 0.45 * base[:, :3] + 0.55  # mixed with white
    return np.where(dark[:, None], base, light), sorted(set(bodies.tolist())), palette


def in_plane_principal(stress):
    """Larger and smaller in-plane principal stress and the direction of the larger one
    (Post eq. 59-60), from Voigt stresses (n, 6)."""
    xx, yy, xy = stress[:, 0], stress[:, 1], stress[:, 3]
    c, r = 0.5 * (xx + yy), np.hypot(0.5 * (xx - yy), xy)
    return c + r, c - r, 0.5 * np.arctan2(2.0 * xy, xx - yy)


def draw_crosses(ax, frame, idx, spacing):
    """Principal-stress crosses (Post fig. 12): black for compression, red for tension, arm
    length proportional to |sigma| (the largest magnitude shown gets 0.45 spacing)."""
    name = "smoothed_stress" if "smoothed_stress" in frame.arrays else "stress"
    s_major, s_minor, theta = in_plane_principal(frame.arrays[name][idx])
    scale = max(float(np.max(np.abs(np.concatenate([s_major, s_minor])), initial=0.0)), 1e-300)
    centres = frame.centres()[idx]
    segments, colours = [], []
    for sig, ang in ((s_major, theta), (s_minor, theta + 0.5 * math.pi)):
        half = 0.45 * spacing * np.abs(sig) / scale
        d = np.stack([np.cos(ang), np.sin(ang)], axis=1) * half[:, None]
        segments += list(np.stack([centres - d, centres + d], axis=1))
        colours += ["#d62728" if s > 0 else "black" for s in sig]
    ax.add_collection(LineCollection(segments, colors=colours, linewidths=1.0, zorder=4))
    return name


def draw_arrows(ax, frame, idx, spacing):
    """Velocity arrows on a subsample (Post fig. 9b); the fastest shown is 0.8 spacing long."""
    v = frame.arrays["velocity"][idx, :2]
    vmax = float(np.max(np.linalg.norm(v, axis=1), initial=0.0))
    if vmax == 0.0:
        return
    c = frame.centres()[idx]
    ax.quiver(c[:, 0], c[:, 1], v[:, 0], v[:, 1], angles="xy", scale_units="xy",
              scale=vmax / (0.8 * spacing), width=0.003, color="black", zorder=5)


# Margins around the plot [inch]: room for the tick labels, axis labels, the two-line title
# and, on the right, the colour bar (or the body legend) with its label.
MARGIN = {"left": 0.85, "bottom": 0.65, "top": 0.75, "right": 1.45}
BAR_GAP, BAR_WIDTH = 0.2, 0.22  # [inch]
MIN_PLOT_HEIGHT = 1.2           # [inch]; a flatter domain gets more room above and below
MIN_PLOT_WIDTH = 2.6            # [inch]; a narrower domain gets room beside it (for the title)


def draw_slip_circle(ax, circle):
    """The limit-equilibrium slip circle (docs/method.md, "Limit equilibrium") where it cut the
    ground at the start, dashed, black over white so it shows on any colour map."""
    xc, yc, r, x_from, x_to = circle[:5]
    x = np.linspace(x_from, x_to, 361)
    y = yc - np.sqrt(np.maximum(r * r - (x - xc) ** 2, 0.0))
    ax.plot(x, y, color="white", linewidth=2.4, zorder=4, solid_capstyle="round")
    ax.plot(x, y, color="black", linewidth=1.2, linestyle=(0, (5, 3)), zorder=5)


def layout(style, xlim, ylim):
    """(figure width, height) and the plot's (left, bottom, width, height) in inches: the
    plot has the domain's aspect ratio, so the picture has no empty band."""
    dx, dy = xlim[1] - xlim[0], ylim[1] - ylim[0]
    aspect = dy / dx if dx > 0 and dy > 0 else 1.0
    m = dict(MARGIN)
    if style.arrows or style.crosses:
        m["top"] += 0.2  # a third title line names the overlays
    w = style.width - m["left"] - m["right"]
    h = w * aspect
    if h > style.max_height - m["bottom"] - m["top"]:
        h = style.max_height - m["bottom"] - m["top"]
        w = h / aspect
    h = max(h, MIN_PLOT_HEIGHT)  # the axis limits widen to keep the aspect (datalim)
    w = max(w, MIN_PLOT_WIDTH)
    return (m["left"] + w + m["right"], m["bottom"] + h + m["top"]), (m["left"], m["bottom"], w, h)


def draw_frame(frame, style, xlim, ylim, vrange=None):
    """The figure of one frame and a dict describing where things are in the picture."""
    resolve_field(frame, style)
    (fw, fh), (left, bottom, w, h) = layout(style, xlim, ylim)
    fig = plt.figure(figsize=(fw, fh), dpi=style.dpi, facecolor=BACKGROUND)
    ax = fig.add_axes([left / fw, bottom / fh, w / fw, h / fh], facecolor=BACKGROUND)
    cax = None
    info = {"cmap": None, "vmin": None, "vmax": None}
    if style.pattern:
        faces, bodies, palette = pattern_colours(frame, style)
        names = style.body_names or {}
        ax.legend(handles=[Patch(color=palette(b % 10), label=names.get(b, f"body {b}"))
                           for b in bodies], loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small")
        what = f"deformation ({style.pattern} in the reference configuration)"
    else:
        values, label = select(frame, style.field)
        vmin, vmax = vrange or style.vrange or finite_range([values])
        norm = mcolors.Normalize(vmin=vmin, vmax=vmax)
        cmap = plt.get_cmap(style.cmap).with_extremes(bad=BAD_COLOUR)
        finite = np.isfinite(values)
        faces = cmap(norm(np.where(finite, values, np.nan)))
        # The colour bar: as tall as the plot, beside it.
        cax = fig.add_axes([(left + w + BAR_GAP) / fw, bottom / fh, BAR_WIDTH / fw, h / fh])
        bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), cax=cax, label=label)
        bar.formatter.set_useOffset(False)  # the values themselves, never "1e-14 + 0.0424"
        if not finite.all():  # grey voxels: say what they are, under the colour bar
            fig.legend(handles=[Patch(facecolor=BAD_COLOUR, edgecolor="none", label="no value\n(NaN or inf)")],
                       loc="upper left", bbox_to_anchor=((left + w + 0.05) / fw, (bottom - 0.08) / fh),
                       fontsize="x-small", frameon=False, borderaxespad=0.0, handlelength=1.2)
        info.update(cmap=style.cmap, vmin=vmin, vmax=vmax, nonfinite=int(np.count_nonzero(~finite)))
        what = label
    ax.add_collection(PolyCollection(frame.quads, facecolors=faces, edgecolors=faces,
                                     linewidths=0.3, zorder=2))
    spacing = style.sample * voxel_size(frame)
    idx = subsample(frame.centres(), spacing) if (style.arrows or style.crosses) else None
    overlays = []
    if style.crosses:
        source = draw_crosses(ax, frame, idx, spacing)
        overlays.append(f"crosses: principal {source.replace('_', ' ')} (red tension)")
    if style.arrows:
        draw_arrows(ax, frame, idx, spacing)
        overlays.append("arrows: velocity")
    if style.slip_circle:
        draw_slip_circle(ax, style.slip_circle)
        overlays.append(f"dashed: Bishop's critical slip circle at the start, F = {style.slip_circle[5]:.3f}")
    if overlays:
        what += "\n" + ", ".join(overlays)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"${frame.axes[0]}$ [m]")
    ax.set_ylabel(f"${frame.axes[1]}$ [m]")
    view = f", {frame.view_label}" if frame.view_label else ""
    ax.set_title(f"{what}\n$t$ = {frame.time:.4g} s (frame {frame.step}{view})", fontsize="medium")
    fig.canvas.draw()
    info.update(image_size=[int(round(v)) for v in fig.canvas.get_width_height()],
                axes=pixel_box(fig, ax), xlim=list(ax.get_xlim()), ylim=list(ax.get_ylim()),
                colorbar=pixel_box(fig, cax) if cax else None)
    return fig, info


def pixel_box(fig, ax):
    """[left, top, right, bottom] of an axes in image pixels (origin top-left)."""
    b = ax.get_window_extent()
    h = fig.canvas.get_width_height()[1]
    return [b.x0, h - b.y1, b.x1, h - b.y0]


def save(fig, path, info=None, info_path=None):
    """Writes the PNG via a temporary name and a rename (never a half-written picture)."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + ".tmp"
    fig.savefig(tmp, format="png", dpi=fig.dpi, facecolor=fig.get_facecolor())
    plt.close(fig)
    os.replace(tmp, path)
    if info_path:
        with open(info_path + ".tmp", "w") as f:
            json.dump(info, f, indent=1)
        os.replace(info_path + ".tmp", info_path)


def check_style(frame, style):
    """Raises PostError early for a field that the frame does not have (and picks the
    default field if none was asked for)."""
    resolve_field(frame, style)
    if not style.pattern:
        select(frame, style.field)
    if style.arrows and "velocity" not in frame.arrays:
        raise PostError("--arrows needs the velocity field")
    if style.crosses and "stress" not in frame.arrays:
        raise PostError("--crosses needs the stress field")
