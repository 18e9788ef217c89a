"""skred's results from Python: the particle frames, series.csv, summary.json and a sweep's
sweep.csv of a run folder as NumPy arrays and dicts (pandas-friendly); also the pictures,
animations and HTML report of `skred render` / `skred report` (matplotlib).

    import skred_post as sp
    frame = sp.load_frame("out/slope")              # the last frame; sp.load_frame(d, 0): the first
    frame.time, frame.arrays["stress"][:, 1]          # [s], sigma_yy of every point [Pa]
    series = sp.read_series("out/slope")             # {column: array}: pandas.DataFrame(series)
    summary = sp.read_summary("out/slope")           # summary.json as a dict
    keys, table = sp.read_sweep("out/sweep")         # sweep.csv: the swept keys, {column: array}

Values are in the SI units the run wrote (Pa, m, s, J/m in 2D). Reading frames needs VTK
(python3-vtk9, or ParaView's python3-paraview); the rest needs NumPy only. Documented in
docs/post-processing.md, "Python access"."""
from .data import Frame, PostError, frames_index, load_frame, read_frame, read_series, read_summary
from .sweep import read_sweep

__version__ = "0.1.0"
__all__ = ["Frame", "PostError", "frames_index", "list_frames", "load_frame", "read_frame",
           "read_series", "read_summary", "read_sweep"]


def list_frames(outdir):
    """[(step, time [s], path)] of every particle frame of a run, in order."""
    return frames_index(outdir)
