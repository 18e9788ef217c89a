"""check_report.py HTML DOM_FILE CHROMIUM_LOG
Checks a `skred report` page: self-contained (every image an inline base64 PNG, no outside
resource), each image decodes to a non-blank picture, the summary and scenario are there; and
that headless Chromium loaded it: its DOM (from --dump-dom) says every image was shown, and its
log has no console message. Exits 1 on any failure."""
import base64
import io
import re
import sys
from html.parser import HTMLParser

import numpy as np
from PIL import Image

failures = []


def expect(cond, what):
    print(("ok " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


class Collect(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.links = [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a.get("src", ""))
        for key in ("href", "src"):
            if key in a and tag != "img":
                self.links.append(a[key])


def main(html_path, dom_path, log_path):
    page = open(html_path, encoding="utf-8").read()
    c = Collect()
    c.feed(page)
    expect(len(c.images) == 6, f"{len(c.images)} images (series, 3 frames, deformation, stress)")
    for i, src in enumerate(c.images):
        expect(src.startswith("data:image/png;base64,"), f"image {i} is an inline PNG")
        raw = base64.b64decode(src.split(",", 1)[1], validate=True)
        img = Image.open(io.BytesIO(raw))
        img.load()
        arr = np.asarray(img.convert("RGB"), dtype=float)
        expect(img.width >= 300 and img.height >= 300, f"image {i} is {img.width}x{img.height}")
        expect(arr.std() > 10, f"image {i} is not blank (std {arr.std():.1f})")
    expect(not c.links, f"no outside resources ({c.links})")
    expect(not re.search(r"(src|href)\s*=\s*['\"]?(https?:|file:|//)", page), "no remote URL")
    expect("completed" in page, "summary shows the run's status")
    # The stage measures as a table with units, not a Python repr; empty fields left out.
    expect("<table class='stages'>" in page, "stage measures table")
    expect("runout <span class='unit'>[m]</span>" in page, "measures carry units")
    expect(not re.search(r"\[\{'|\{'name'|>None<|<td></td>", page), "no Python repr, no empty cell")
    expect("<th>message" not in page, "the empty message is left out")
    expect("[[body]]" in page, "scenario text is shown")
    dom = open(dom_path, encoding="utf-8", errors="replace").read()
    m = re.search(r'data-images-loaded="(\d+)/(\d+)"', dom)
    expect(m is not None, "Chromium ran the page's load handler")
    if m:
        expect(m.group(1) == m.group(2) == str(len(c.images)),
               f"Chromium shows {m.group(1)} of {m.group(2)} images")
    log = open(log_path, encoding="utf-8", errors="replace").read()
    console = [l for l in log.splitlines() if ":CONSOLE" in l]
    expect(not console, f"no console messages in Chromium ({console})")
    if failures:
        print("failed: " + "; ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
