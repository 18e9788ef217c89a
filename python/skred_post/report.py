"""The HTML report: one self-contained page (pictures embedded as base64 PNG, inline CSS, no
outside resource) with the scenario, the summary numbers, the time series, and the first,
middle and last frames."""
import base64
import html
import io
import os

from .data import PostError, View, frames_index, read_frame, read_summary, slip_circle_of
from .render import Style, bounds, check_style, draw_frame, finite_range, select
from .scenario_info import body_names, read_scenario
from .series import plot_series

CSS = """
body { font-family: sans-serif; margin: 2em auto; max-width: 1200px; color: #222; }
h1 { font-size: 1.6em; } h2 { font-size: 1.2em; margin-top: 1.6em; }
table { border-collapse: collapse; } td, th { padding: 2px 10px; border-bottom: 1px solid #ddd;
text-align: left; } pre { background: #f6f6f6; padding: 1em; overflow-x: auto; }
figure { display: inline-block; margin: 0.5em; vertical-align: top; }
figure img { width: 560px; max-width: 100%; }
figcaption { font-size: 0.85em; text-align: center; }
table.stages td { text-align: right; } .unit { color: #666; font-weight: normal; }
"""

# Counts the pictures that decoded, so a headless browser (and a reader) can see they load.
CHECK_SCRIPT = """
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0;
  for (var i = 0; i < imgs.length; ++i) if (imgs[i].complete && imgs[i].naturalWidth > 0) ++ok;
  document.body.setAttribute('data-images-loaded', ok + '/' + imgs.length);
  document.getElementById('image-status').textContent = ok + ' of ' + imgs.length + ' pictures shown';
});
"""


def png_data_uri(fig):
    import matplotlib.pyplot as plt
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=fig.dpi, facecolor=fig.get_facecolor())
    plt.close(fig)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def figure_html(uri, caption):
    return (f'<figure><img src="{uri}" alt="{html.escape(caption)}">'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>")


# summary.json: (key, label, unit) of the run's numbers, in the order shown.
RUN_ROWS = [("status", "status", ""), ("message", "message", ""), ("steps", "steps", ""),
            ("simulated_time", "simulated time", "s"), ("end_time", "end time", "s"),
            ("time_step", "time step", "s"), ("particles", "material points", ""),
            ("cells", "grid cells", ""), ("interpolation", "interpolation", ""),
            ("scheme", "stress update", ""), ("threads", "threads", ""),
            ("limit_equilibrium", "Bishop's factor of safety F (at the start)", ""),
            ("wall_seconds", "wall time", "s"),
            ("particle_updates_per_second", "particle-updates per second", "1/s"),
            ("version", "skred version", ""), ("git_commit", "git commit", "")]

# Stage measures (summary.json "stages", docs/scenario.md): (key, label, unit in 2D, in 3D).
STAGE_ROWS = [("start_time", "start time", "s", "s"), ("end_time", "end time", "s", "s"),
              ("steps", "steps", "", ""), ("ended_by", "ended by", "", ""),
              ("runout", "runout", "m", "m"), ("runout_x_min", "runout towards −x", "m", "m"),
              ("runout_x_max", "runout towards +x", "m", "m"),
              ("runout_z_min", "runout towards −z", "m", "m"),
              ("runout_z_max", "runout towards +z", "m", "m"),
              ("max_displacement", "largest displacement", "m", "m"),
              ("height_start", "height at the start", "m", "m"),
              ("height_end", "height at the end", "m", "m"),
              ("peak_mean_speed", "peak mean speed", "m/s", "m/s"),
              ("peak_time", "time of the peak", "s", "s"),
              ("final_mean_speed", "final mean speed", "m/s", "m/s"),
              ("stop_time", "stop time (stage time)", "s", "s"),
              ("gravity_work", "gravity work", "J/m", "J"),
              ("kinetic_energy_change", "kinetic energy change", "J/m", "J"),
              ("strain_energy", "stored elastic energy change", "J/m", "J"),
              ("plastic_dissipation", "plastic dissipation", "J/m", "J"),
              ("plastic_volume", "plastified volume", "m³/m", "m³"),
              ("plastic_points", "plastified points", "", "")]


def is_empty(v):
    return v is None or v == "" or v == [] or v == {}


def format_value(v):
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return f"{v:.4g}" if abs(v) < 1e6 or v == 0 else f"{v:.3e}"
    return str(v)


def unit_html(unit):
    return f" <span class='unit'>[{html.escape(unit)}]</span>" if unit else ""


def summary_table(summary):
    """The run's numbers with units, empty fields left out."""
    if not summary:
        return "<p>summary.json not found.</p>"
    rows = "".join(f"<tr><th>{html.escape(label)}{unit_html(unit)}</th>"
                   f"<td>{html.escape(format_value(summary[key]))}</td></tr>"
                   for key, label, unit in RUN_ROWS if not is_empty(summary.get(key)))
    return f"<table>{rows}</table>"


def stages_table(summary):
    """The slide measures of every stage: one column per stage, one row per measure with its
    unit; a measure no stage has (e.g. the runout along z of a 2D run) is left out; a stage
    that did not stop shows "still moving" for its stop time."""
    stages = (summary or {}).get("stages") or []
    if not stages:
        return "<p>No stage measures in summary.json.</p>"
    three_d = (summary or {}).get("dimension") == 3
    head = "".join(f"<th>{html.escape(str(s.get('name') or f'stage {i}'))}</th>" for i, s in enumerate(stages))
    rows = []
    for key, label, unit2, unit3 in STAGE_ROWS:
        if all(key not in s for s in stages):
            continue
        cells = []
        for s in stages:
            v = s.get(key)
            cells.append("still moving" if key == "stop_time" and v is None else
                         "–" if is_empty(v) else format_value(v))
        unit = unit3 if three_d else unit2
        rows.append(f"<tr><th>{html.escape(label)}{unit_html(unit)}</th>"
                    + "".join(f"<td>{html.escape(c)}</td>" for c in cells) + "</tr>")
    return f"<table class='stages'><tr><th>measure</th>{head}</tr>{''.join(rows)}</table>"


def frame_pictures(outdir, field, names):
    """(uri, caption) of the first, middle and last frame coloured by `field`, and of the last
    frame with the checkerboard of the reference configuration, with the plastic shear strain and
    Bishop's critical circle (a run that has one), and with the smoothed mean stress and
    principal-stress crosses."""
    index = frames_index(outdir)
    if not index:
        return []
    chosen = sorted({0, len(index) // 2, len(index) - 1})
    frames = [read_frame(p, t, i, View()) for i, t, p in (index[k] for k in chosen)]
    style = Style(field=field, body_names=names, width=7.0, max_height=6.0)
    check_style(frames[-1], style)
    xlim, ylim = bounds(frames)
    vrange = finite_range([select(f, style.field)[0] for f in frames])
    out = []
    for f in frames:
        fig, _ = draw_frame(f, style, xlim, ylim, vrange)
        out.append((png_data_uri(fig), f"{style.field}, frame {f.step}, t = {f.time:.4g} s"))
    style.pattern = "checkerboard"
    fig, _ = draw_frame(frames[-1], style, xlim, ylim)
    out.append((png_data_uri(fig), f"deformation (checkerboard), t = {frames[-1].time:.4g} s"))
    try:  # Bishop's critical circle over the mechanism (docs/method.md, "Limit equilibrium")
        circle = slip_circle_of(outdir)
    except PostError:
        circle = None
    if circle is not None:
        shear = "plastic_shear_strain" if "plastic_shear_strain" in frames[-1].arrays else style.field
        s = Style(field=shear, body_names=names, width=7.0, max_height=6.0, slip_circle=circle)
        fig, _ = draw_frame(frames[-1], s, xlim, ylim)
        out.append((png_data_uri(fig), f"{shear} with Bishop's critical circle at the start (F = {circle[-1]:.3f}), "
                                       f"t = {frames[-1].time:.4g} s"))
    if "smoothed_p" in frames[-1].arrays:  # grid-smoothed stresses (Post §7.1-7.2)
        stress = Style(field="smoothed_p", crosses=True, body_names=names, width=7.0, max_height=6.0)
        fig, _ = draw_frame(frames[-1], stress, xlim, ylim)
        out.append((png_data_uri(fig), f"smoothed p with principal-stress crosses, t = {frames[-1].time:.4g} s"))
    return out


def build_report(outdir, field=None):
    text, scenario = read_scenario(outdir)
    names = body_names(scenario)
    title = (scenario or {}).get("title") or os.path.basename(os.path.abspath(outdir))
    summary = read_summary(outdir)
    parts = [f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
             f"<title>skred report: {html.escape(title)}</title><style>{CSS}</style>",
             f"<script>{CHECK_SCRIPT}</script></head><body>",
             f"<h1>{html.escape(title)}</h1>",
             f"<p>Results in <code>{html.escape(os.path.abspath(outdir))}</code>. "
             f"<span id='image-status'></span></p>",
             "<h2>Run</h2>", summary_table(summary),
             "<h2>Stage measures</h2>", stages_table(summary),
             "<h2>Time series</h2>",
             figure_html(png_data_uri(plot_series(outdir)), "series.csv").replace(
                 "<img ", "<img style='width:760px' "),
             "<h2>Frames</h2>"]
    parts += [figure_html(uri, cap) for uri, cap in frame_pictures(outdir, field, names)]
    parts.append("<h2>Scenario</h2>")
    parts.append(f"<pre>{html.escape(text)}</pre>" if text is not None
                 else "<p>scenario.toml not found in the output folder.</p>")
    parts.append("<p style='font-size:0.8em'>Made by <code>skred report</code> with matplotlib; "
                 "fields are described in docs/post-processing.md.</p></body></html>\n")
    return "\n".join(parts)


def write_report(outdir, path, field=None):
    page = build_report(outdir, field)
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(page)
    os.replace(tmp, path)
    return path
