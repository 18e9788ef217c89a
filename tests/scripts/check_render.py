"""check_render.py MODE PNG INFO_JSON
Checks the pixels of the picture `skred render` drew of the two-particle state of
tests/test_post_render.cpp, using the axes and colour-bar boxes it reported with --info.
Voxel A: centre (0.5, 0.5), square of half-size 0.2, stress xx 2.5, body 0.
Voxel B: centre (1.5, 0.5), sheared by F = [[1, 1], [0, 1]], stress xx 10, body 1.
MODE: field   (--field stress:xx --range 0 10 [kPa]: A = viridis(0.25), B = viridis(1), colour bar)
      nan     (--field relative_yield with no strength: both grey #c8c8c8)
      checker (--checkerboard --pattern-width 1: A light body-0 blue, B dark body-1 orange)
      circle  (field, with --slip-circle from a summary.json: the dashed arc crosses voxel A)
      zero    (the first frame of --all, displacement 0 of a range 0 ... 0.4 m: both viridis(0))
      layout  (the plot box has the aspect of its axis limits, the colour bar its height, and
               the image holds little besides them)
Prints one line per check and exits 1 if any fails."""
import json
import sys

import numpy as np
from matplotlib import colormaps
from PIL import Image

WHITE = (255, 255, 255)
failures = []


def rgb(c):
    return tuple(int(round(255 * v)) for v in c[:3])


def check(what, got, want, tol=2):
    ok = all(abs(int(g) - int(w)) <= tol for g, w in zip(got, want))
    print(f"{'ok' if ok else 'FAIL'} {what}: got {tuple(int(g) for g in got)} want {want}")
    if not ok:
        failures.append(what)


def main(mode, png, info_path):
    img = np.asarray(Image.open(png).convert("RGB"))
    info = json.load(open(info_path))
    h, w = img.shape[:2]
    if [w, h] != info["image_size"]:
        failures.append(f"image is {w}x{h}, info says {info['image_size']}")
    left, top, right, bottom = info["axes"]
    (x0, x1), (y0, y1) = info["xlim"], info["ylim"]

    def at(x, y):
        px = left + (x - x0) / (x1 - x0) * (right - left)
        py = top + (y1 - y) / (y1 - y0) * (bottom - top)
        return img[int(py), int(px)]

    if mode == "layout":
        pw, ph = right - left, bottom - top
        data_aspect = (y1 - y0) / (x1 - x0)
        check("plot box aspect (x1000) = axis limits' aspect", [1000 * ph / pw], [1000 * data_aspect],
              0.02 * 1000 * data_aspect)
        bl, bt, br, bb = info["colorbar"]
        check("colour bar top and bottom = the plot's", [bt, bb], [top, bottom], 1.5)
        # Margins only: at most 1.6 inch (0.2 of the 8 inch width) above and below the plot,
        # 2.4 inch (0.3) beside it.
        check("image height beyond the plot (x100 of the width)", [100 * (h - ph) / w], [0], 20)
        check("image width beyond the plot (x100 of the width)", [100 * (w - pw) / w], [0], 30)
        return report()
    a_in = [(0.5, 0.5), (0.35, 0.62), (0.66, 0.36)]
    b_in = [(1.5, 0.5), (1.8, 0.65), (1.2, 0.35)]   # (1.8, 0.65): sheared part, outside the square
    background = [(1.0, 0.5), (1.35, 0.65),        # (1.35, 0.65): inside the square, not the voxel
                  (0.5, 0.75), (x0 + 0.01 * (x1 - x0), y0 + 0.01 * (y1 - y0))]
    if mode == "circle":  # field's colours, and the slip circle (1, 1.9), r 1.6, from x 0.2 to 1.8
        want_a = rgb(colormaps["viridis"](0.25))
        on_arc = at(0.5, 1.9 - np.sqrt(1.6 ** 2 - 0.5 ** 2))  # y = 0.38, inside voxel A
        away = max(abs(int(g) - int(w)) for g, w in zip(on_arc, want_a))
        print(f"{'ok' if away > 60 else 'FAIL'} the arc over voxel A: got {tuple(int(g) for g in on_arc)}")
        if away <= 60:
            failures.append("no slip circle over voxel A")
        check("voxel A off the arc", at(0.5, 0.62), want_a)
        check("the arc's end at x = 0.2 is not drawn beyond it", at(0.1, 0.5), WHITE, 0)
        return report()
    if mode == "field":
        viridis = colormaps["viridis"]
        want_a, want_b = rgb(viridis(0.25)), rgb(viridis(1.0))
        check("viridis(0.25) is the textbook #3b528b", want_a, (59, 82, 139), 1)
    elif mode == "nan":
        want_a = want_b = (200, 200, 200)
    elif mode == "zero":
        want_a = want_b = rgb(colormaps["viridis"](0.0))
        check("colour range (x1e6)", [1e6 * info["vmin"], 1e6 * info["vmax"]], [0, 0.4e6], 1)
    else:
        tab = colormaps["tab10"]
        want_a = rgb([0.45 * c + 0.55 for c in tab(0)[:3]])  # light shade of body 0
        want_b = rgb(tab(1))                                 # dark shade of body 1
    for p in a_in:
        check(f"voxel A at {p}", at(*p), want_a)
    for p in b_in:
        check(f"voxel B at {p}", at(*p), want_b)
    for p in background:
        check(f"background at {p}", at(*p), WHITE, 0)
    if mode in ("field", "nan", "zero"):
        bl, bt, br, bb = info["colorbar"]
        cx = int(0.5 * (bl + br))
        for frac in (0.05, 0.25, 0.5, 0.75, 0.95):
            py = int(bb - frac * (bb - bt))
            check(f"colour bar at {frac}", img[py, cx], rgb(colormaps["viridis"](frac)), 6)
        check("between plot and colour bar is background",
              img[int(0.5 * (bt + bb)), int(0.5 * (right + bl))], WHITE, 0)
    else:
        if info["colorbar"] is not None:
            failures.append("a pattern picture has no colour bar")
    return report()


def report():
    if failures:
        print("failed: " + "; ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
