"""Checks that the Debian packages the post-processing needs are importable."""
import importlib
import sys

# module -> Debian package that provides it for /usr/bin/python3
NEEDED = {
    "numpy": "python3-numpy",
    "matplotlib": "python3-matplotlib",
    "PIL": "python3-pil",
    "vtkmodules": "python3-vtk9",
}


def missing_modules():
    missing = []
    for module, package in NEEDED.items():
        try:
            importlib.import_module(module)
        except ImportError as exc:
            missing.append((module, package, str(exc)))
    return missing


def require_modules():
    """Exits with status 6 and a message naming the Debian packages if any module is missing."""
    missing = missing_modules()
    if not missing:
        return
    packages = " ".join(sorted({p for _, p, _ in missing}))
    lines = [f"skred: post-processing needs Python modules that {sys.executable} cannot import:"]
    lines += [f"  {m} ({p}): {e}" for m, p, e in missing]
    lines.append(f"install them with: apt-get install {packages}   (or: bash scripts/install-deps.sh)")
    print("\n".join(lines), file=sys.stderr)
    sys.exit(6)  # skred exit code: missing Python modules (src/app/exit_codes.hpp)
