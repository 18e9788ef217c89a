"""The HTML report: one self-contained page (pictures embedded as base64 PNG, inline CSS, no
outside resource) with the scenario, the summary numbers, the time series, and the first,
middle and last frames."""
import base64
import html
import io
import os

from .data import frames_index, read_frame, read_summary
from .render import Style, bounds, check_style, draw_frame, finite_range, select
from .scenario_info import body_names, read_scenario
from .series import plot_series

CSS = """
body { font-family: sans-serif; margin: 2em auto; max-width: 1200px; color: #222; }
h1 { font-size: 1.6em; } h2 { font-size: 1.2em; margin-top: 1.6em; }
table { border-collapse: collapse; } td, th { padding: 2px 10px; border-bottom: 1px solid #ddd;
text-align: left; } pre { background: #f6f6f6; padding: 1em; overflow-x: auto; }
figure { display: inline-block; margin: 0.5em; } figure img { width: 380px; }
figcaption { font-size: 0.85em; text-align: center; }
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


def summary_table(summary):
    if not summary:
        return "<p>summary.json not found.</p>"
    rows = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(format_value(v))}</td></tr>"
                   for k, v in summary.items())
    return f"<table>{rows}</table>"


def format_value(v):
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def frame_pictures(outdir, field, names):
    """(uri, caption) of the first, middle and last frame coloured by `field`, and of the last
    frame with the checkerboard of the reference configuration and with the smoothed mean
    stress and principal-stress crosses."""
    index = frames_index(outdir)
    if not index:
        return []
    chosen = sorted({0, len(index) // 2, len(index) - 1})
    frames = [read_frame(p, t, i) for i, t, p in (index[k] for k in chosen)]
    style = Style(field=field, body_names=names, width=6.0, height=4.8)
    check_style(frames[0], style)
    xlim, ylim = bounds(frames)
    vrange = finite_range([select(f, field)[0] for f in frames])
    out = []
    for f in frames:
        fig, _ = draw_frame(f, style, xlim, ylim, vrange)
        out.append((png_data_uri(fig), f"{field}, frame {f.step}, t = {f.time:.4g} s"))
    style.pattern = "checkerboard"
    fig, _ = draw_frame(frames[-1], style, xlim, ylim)
    out.append((png_data_uri(fig), f"deformation (checkerboard), t = {frames[-1].time:.4g} s"))
    if "smoothed_p" in frames[-1].arrays:  # grid-smoothed stresses (Post §7.1-7.2)
        stress = Style(field="smoothed_p", crosses=True, body_names=names, width=6.0, height=4.8)
        fig, _ = draw_frame(frames[-1], stress, xlim, ylim)
        out.append((png_data_uri(fig), f"smoothed p with principal-stress crosses, t = {frames[-1].time:.4g} s"))
    return out


def build_report(outdir, field="speed"):
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
             "<h2>Summary</h2>", summary_table(summary),
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


def write_report(outdir, path, field="speed"):
    page = build_report(outdir, field)
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(page)
    os.replace(tmp, path)
    return path
