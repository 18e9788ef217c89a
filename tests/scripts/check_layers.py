"""Fails (exit 1, naming file, line and include) when a file under src/ includes a header of
a folder at or above its own layer that it may not use. The order is the one CMakeLists.txt
links the folder libraries in; a folder may include itself and any folder below it."""
import pathlib
import re
import sys

ORDER = ["core", "parallel", "shape", "material", "transfer", "solver", "implicit", "scenario", "post", "io", "run", "app"]
RANK = {name: i for i, name in enumerate(ORDER)}

src = pathlib.Path(sys.argv[1])
bad = []
seen = 0
for path in sorted(src.rglob("*")):
    if path.suffix not in (".hpp", ".cpp"):
        continue
    layer = path.relative_to(src).parts[0]
    if layer not in RANK:
        bad.append(f"{path}: folder '{layer}' is not in the layer order")
        continue
    for n, line in enumerate(path.read_text().splitlines(), 1):
        m = re.match(r'\s*#include "([a-z_]+)/', line)
        if not m:
            continue
        seen += 1
        target = m.group(1)
        if target not in RANK:
            bad.append(f"{path}:{n}: includes unknown folder '{target}'")
        elif RANK[target] > RANK[layer]:
            bad.append(f"{path}:{n}: {layer} includes {target}, a layer above it: {line.strip()}")
if seen < 50:
    bad.append(f"only {seen} project includes found under {src}: wrong folder?")
for b in bad:
    print(b)
print(f"{seen} includes checked, {len(bad)} upward")
sys.exit(1 if bad else 0)
