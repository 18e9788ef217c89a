"""Rendering every frame and assembling an animated GIF with Pillow (python3-pil, which
python3-matplotlib already depends on)."""
import os

from PIL import Image

from .data import PostError, frames_index, read_frame
from .render import bounds, check_style, data_range, draw_frame, merge_ranges, save, select, widened


def render_all(outdir, style, gif_path, fps=8, log=print, view=None, info_path=None):
    """Renders frame_NNNNNN.png for every frame into GIF_STEM_frames/ with one set of axis
    limits and one colour range for all (the range of the data of every frame, widened only
    if it is flat), then writes the GIF. With info_path, writes where the axes and colour bar
    lie (as render --info) for the first frame. Returns the PNG paths."""
    index = frames_index(outdir)
    if not index:
        raise PostError(f"{outdir}/particles.pvd lists no frames")
    # First pass: one set of axis limits and one colour range for the whole animation
    # (frames are read twice rather than all held in memory).
    boxes, ranges = [], []
    for i, t, p in index:
        f = read_frame(p, t, i, view)
        if i == 0:
            check_style(f, style)
        boxes.append(bounds([f], margin=0.0))
        if not style.pattern and not style.vrange:
            ranges.append(data_range([select(f, style.field)[0]]))  # widened after merging
    xlim, ylim = merge_boxes(boxes)
    vrange = style.vrange or (widened(merge_ranges(ranges)) if ranges else None)
    folder = os.path.splitext(gif_path)[0] + "_frames"
    pngs = []
    for i, t, p in index:
        fig, info = draw_frame(read_frame(p, t, i, view), style, xlim, ylim, vrange)
        path = os.path.join(folder, f"frame_{i:06}.png")
        save(fig, path, info, info_path if i == 0 else None)
        pngs.append(path)
    write_gif(pngs, gif_path, fps)
    log(f"wrote {len(pngs)} frames to {folder}/ and the animation {gif_path}")
    return pngs


def write_gif(pngs, gif_path, fps):
    images = [Image.open(p).convert("RGB").convert("P", palette=Image.Palette.ADAPTIVE, colors=256)
              for p in pngs]
    tmp = gif_path + ".tmp"
    images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                   duration=max(1, round(1000 / fps)), loop=0)
    os.replace(tmp, gif_path)


def merge_boxes(boxes, margin=0.05):
    x0 = min(b[0][0] for b in boxes)
    x1 = max(b[0][1] for b in boxes)
    y0 = min(b[1][0] for b in boxes)
    y1 = max(b[1][1] for b in boxes)
    pad = margin * max(x1 - x0, y1 - y0, 1e-12)
    return (x0 - pad, x1 + pad), (y0 - pad, y1 + pad)
