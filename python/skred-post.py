#!/usr/bin/python3
"""Entry point of skred's post-processing (pictures, animations, the HTML report).

Run by `skred render` and `skred report`, which exec `/usr/bin/python3 -E -s` on this file;
it can also be run directly: /usr/bin/python3 python/skred-post.py render OUTDIR ...
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from skred_post.deps import require_modules  # noqa: E402  (standard library only)

require_modules()

from skred_post.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
