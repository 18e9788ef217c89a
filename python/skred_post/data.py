"""Reading skred's result folder: the PVD indexes, particle VTU frames (with VTK's own XML
reader, python3-vtk9 or ParaView's VTK, imported only when a frame is read), series.csv,
summary.json and a sweep's sweep.csv; and picking a scalar out of a field for a picture.
Values are in SI units as the run wrote them (Pa, m, s); the public functions are listed in
skred_post/__init__.py."""
import csv
import json
import math
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import numpy as np

from .labels import display, label, unit_of  # noqa: F401  (unit_of: for callers)
from .scenario_info import read_scenario


class PostError(Exception):
    """A problem with the user's request or the result files; printed without a traceback."""


@dataclass
class View:
    """How a 3D frame is drawn in the plane: "section", the voxels whose centres lie in the
    slab z0 - width/2 <= z < z0 + width/2 (default: the middle of the material, one voxel
    thick) cut through their centres, in x-y; or "top", every voxel's top face seen from
    above, in x-z (the higher drawn over the lower: the surface of the material)."""
    kind: str = "section"
    z: float = None
    width: float = None


@dataclass
class Frame:
    """One particle output step: the material points' deformed voxels and their cell data.

    arrays      name -> NumPy array, (n,) or (n, k), one row per point, SI units
    components  name -> component names, e.g. ["xx", "yy", "zz", "xy", "yz", "xz"]
    corners     (n, 4, 3) in 2D or (n, 8, 3) in 3D: the voxel corners [m] (VTK order)
    quads       (n, 4, 2): the voxels as drawn in the picture's plane; a 3D frame read for
                a picture holds only the points of its View (see project3d), and `axes`
                names the picture's axes."""
    path: str
    time: float
    step: int                      # index of the frame in particles.pvd
    quads: np.ndarray              # (n, 4, 2) corners of the deformed voxels [m]
    arrays: dict = field(default_factory=dict)       # name -> (n,) or (n, k) array
    components: dict = field(default_factory=dict)   # name -> list of component names
    dim: int = 2
    axes: tuple = ("x", "y")
    view_label: str = ""
    corners: np.ndarray = None     # (n, 4 or 8, 3) voxel corners as written [m]

    @property
    def size(self):
        return len(self.quads)

    def centres(self):
        """(n, 2) centres of the voxels in the picture's plane."""
        return self.quads.mean(axis=1)

    def positions(self):
        """(n, dim) centres of the voxels (the points' positions x_p) [m]."""
        if self.corners is None or len(self.corners) == 0:
            return np.zeros((0, self.dim))
        return self.corners.mean(axis=1)[:, :self.dim]

    def table(self):
        """The frame as flat columns {name: (n,) array}: x, y (z), then every field, a field
        of k components as NAME_COMPONENT (stress_xx, ...): pandas.DataFrame(frame.table())."""
        cols = dict(zip("xyz", self.positions().T))
        for name, values in self.arrays.items():
            if values.ndim == 1:
                cols[name] = values
            else:
                for k, comp in enumerate(self.components[name]):
                    cols[f"{name}_{comp}"] = values[:, k]
        return cols


def read_pvd(outdir, name="particles.pvd"):
    """[(time, absolute file path)] in the order of the index."""
    path = os.path.join(outdir, name)
    if not os.path.isfile(path):
        raise PostError(f"{path} not found: is {outdir} the output folder of `skred run`?")
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), os.path.join(outdir, d.get("file")))
            for d in root.iter("DataSet")]


def read_frame(path, time=math.nan, step=-1, view=None):
    """The Frame in a particle VTU file. A 3D frame is cut to `view` (a View) for a picture;
    with view None it keeps every point (quads then holds the z- faces in x-y)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLPUnstructuredGridReader, vtkXMLUnstructuredGridReader
    # .pvtu: a frame of a run split among processes, one piece per process
    reader = vtkXMLPUnstructuredGridReader() if path.endswith(".pvtu") else vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        raise PostError(f"VTK cannot read {path}")
    grid = reader.GetOutput()
    n = grid.GetNumberOfCells()
    hexes = None
    if n == 0 or grid.GetPoints() is None:
        quads, corners = np.zeros((0, 4, 2)), np.zeros((0, 4, 3))
    else:
        points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)  # Float32 or Float64 corners
        cells = grid.GetCells()
        offsets = vtk_to_numpy(cells.GetOffsetsArray())
        ids = vtk_to_numpy(cells.GetConnectivityArray())
        if np.all(np.diff(offsets) == 8):
            hexes = corners = points[ids.reshape(-1, 8)]
            quads = hexes[:, :4, :2]
        elif np.all(np.diff(offsets) == 4):
            corners = points[ids.reshape(-1, 4)]
            quads = corners[:, :, :2]
        else:
            raise PostError(f"{path}: expected one quadrilateral or hexahedron (deformed voxel) per cell")
    frame = Frame(path, time, step, quads, corners=corners, dim=3 if hexes is not None else 2)
    data = grid.GetCellData()
    for a in range(data.GetNumberOfArrays()):
        arr = data.GetArray(a)
        values = vtk_to_numpy(arr).astype(float)
        frame.arrays[arr.GetName()] = values
        k = arr.GetNumberOfComponents()
        frame.components[arr.GetName()] = [arr.GetComponentName(c) or str(c) for c in range(k)]
    if hexes is not None and view is not None:
        project3d(frame, hexes, view)
    return frame


# Swapping y and z for the top view: vectors (x, z, y); Voigt (xx, zz, yy, xz, zy, xy).
SWAP_YZ = {3: [0, 2, 1], 6: [0, 2, 1, 5, 4, 3]}


def project3d(frame, hexes, view):
    """Turns a 3D frame's hexahedra (n, 8, 3; VTK order: the z- face, then the z+ face) into
    the quadrilaterals of `view` and keeps the cell data of the cells shown (Post §5)."""
    frame.dim = 3
    centres = hexes.mean(axis=1)
    if view.kind == "top":
        order = np.argsort(centres[:, 1], kind="stable")   # the highest drawn last
        top = hexes[order][:, [3, 2, 6, 7]]                # the +y face
        frame.quads = top[:, :, [0, 2]]
        frame.corners = hexes[order]
        frame.axes = ("x", "z")
        frame.view_label = "top view (seen from +y)"
        for name, values in frame.arrays.items():
            values = values[order]
            if values.ndim == 2 and values.shape[1] in SWAP_YZ and name not in ("principal_stress", "smoothed_principal_stress"):
                values = values[:, SWAP_YZ[values.shape[1]]]
                frame.components[name] = [frame.components[name][k] for k in SWAP_YZ[values.shape[1]]]
            frame.arrays[name] = values
        return
    if view.kind != "section":
        raise PostError(f"unknown view '{view.kind}'; views: section, top")
    z = centres[:, 2]
    z0 = view.z if view.z is not None else 0.5 * (float(z.min()) + float(z.max())) if len(z) else 0.0
    thickness = np.median(hexes[:, :, 2].max(axis=1) - hexes[:, :, 2].min(axis=1)) if len(z) else 1.0
    width = view.width if view.width is not None else float(thickness)
    keep = np.nonzero((z >= z0 - 0.5 * width) & (z < z0 + 0.5 * width))[0]
    if len(keep) == 0:
        raise PostError(f"no voxel centre lies in the section {z0 - 0.5 * width:.6g} <= z < "
                        f"{z0 + 0.5 * width:.6g}; the points span z = {float(z.min()):.6g} to "
                        f"{float(z.max()):.6g} (choose --section-z and --slab)")
    mid = 0.5 * (hexes[keep, :4] + hexes[keep, 4:])       # the voxel cut through its centre
    frame.quads = mid[:, :, :2]
    frame.corners = hexes[keep]
    frame.view_label = f"section z = {z0:.4g} m (slab {width:.3g} m)"
    for name in frame.arrays:
        frame.arrays[name] = frame.arrays[name][keep]


def frames_index(outdir):
    """[(step, time, path)] of every particle frame."""
    return [(i, t, p) for i, (t, p) in enumerate(read_pvd(outdir))]


def load_frame(outdir, step=-1, view=None):
    """Frame number `step` of a run (negative: from the end; default the last), read with
    VTK's XML reader. A 3D frame keeps every point unless a View is given (pictures)."""
    index = frames_index(outdir)
    if not index:
        raise PostError(f"{outdir}/particles.pvd lists no frames")
    if step < 0:
        step += len(index)
    if not 0 <= step < len(index):
        raise PostError(f"step {step} out of range: {outdir} has frames 0..{len(index) - 1}")
    i, t, p = index[step]
    frame = read_frame(p, t, i, view)
    _, scenario = read_scenario(outdir)
    if scenario and (scenario.get("grid") or {}).get("geometry") == "axisymmetric":
        frame.axes = ("r", "y")  # the r-y section: x is the radius (grid.geometry, App. A1)
    return frame


def select(frame, spec):
    """Values (n,) in the unit pictures show (kPa for stresses) and a label with symbol and
    unit for a field spec NAME or NAME:COMPONENT. COMPONENT is a component name (xx, yy, s1,
    ...), an index, or `mag` (magnitude). A vector field (velocity, displacement) without a
    component means its magnitude."""
    name, _, comp = spec.partition(":")
    if name not in frame.arrays:
        raise PostError(f"field '{name}' is not in {os.path.basename(frame.path)}; fields: "
                        + ", ".join(sorted(frame.arrays)))
    scale = display(name, frame.dim)[1]
    values = frame.arrays[name] * scale
    names = frame.components[name]
    if values.ndim == 1:
        if comp:
            raise PostError(f"field '{name}' has a single component; drop ':{comp}'")
        return values, label(name, None, frame.dim)
    if comp in ("", "mag", "magnitude"):
        if comp == "" and values.shape[1] != 3:
            raise PostError(f"field '{name}' has components {', '.join(names)}: "
                            f"choose one, e.g. {name}:{names[0]}")
        return np.linalg.norm(values, axis=1), label(name, "mag", frame.dim)
    if comp in names:
        k = names.index(comp)
    elif comp.isdigit() and int(comp) < values.shape[1]:
        k = int(comp)
    else:
        raise PostError(f"field '{name}' has no component '{comp}'; components: "
                        + ", ".join(names) + ", mag")
    return values[:, k], label(name, names[k], frame.dim)


def reference_centres(frame):
    """Centre of each voxel at the stage start, x_ref = x - displacement (Post eq. 56)."""
    x = frame.centres()
    if "displacement" in frame.arrays:
        x = x - frame.arrays["displacement"][:, :2]
    return x


def voxel_size(frame):
    """Median reference edge length of the voxels, sqrt(volume / det F)."""
    if frame.size == 0:
        return 1.0
    if "volume" in frame.arrays and "det_F" in frame.arrays:
        area = frame.arrays["volume"] / frame.arrays["det_F"]  # V0: an area in 2D, a volume in 3D
        return float(np.median(area) ** (1.0 / frame.dim))
    edges = np.linalg.norm(frame.quads[:, 1] - frame.quads[:, 0], axis=1)
    return float(np.median(edges))


def numeric_column(values):
    """A CSV column as a NumPy array: int64 if every entry is an integer, else float (an
    empty entry or "nan" is NaN)."""
    try:
        return np.array([int(v) for v in values], dtype=np.int64)
    except ValueError:
        return np.array([float(v) if v else np.nan for v in values])


def read_csv_columns(path, text_columns=()):
    """(header, {column: NumPy array}) of a CSV table with a header row: the columns named in
    `text_columns` as str, the others as numeric_column makes them."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None) or []
        rows = list(reader)
    return header, {name: (np.array([r[k] for r in rows], dtype=str) if name in text_columns
                           else numeric_column([r[k] for r in rows])) for k, name in enumerate(header)}


def read_series(outdir):
    """OUTDIR/series.csv as {column: NumPy array} (step, stage, num_particles... as int64, the
    rest float), one entry per row: pandas.DataFrame(read_series(d)) takes it as it is.
    Energies and gravity work are measured from the start of each row's stage."""
    path = os.path.join(outdir, "series.csv")
    if not os.path.isfile(path):
        raise PostError(f"{path} not found")
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        rows = [r for r in reader if len(r) == len(header or [])]
    if not header or not rows:
        raise PostError(f"{path} has no rows")
    return {name: numeric_column([r[k] for r in rows]) for k, name in enumerate(header)}


def read_summary(outdir):
    """OUTDIR/summary.json as a dict (JSON null: None), or None if the run wrote none yet:
    status, steps, simulated_time, ..., and "stages", a list of dicts of slide measures."""
    path = os.path.join(outdir, "summary.json")
    if not os.path.isfile(path):
        return None
    with open(path) as f:
        return json.load(f)


def slip_circle_of(outdir):
    """(xc, yc, radius, x_from, x_to, F) of summary.json's limit-equilibrium slip circle
    (docs/method.md, "Limit equilibrium"): its centre, radius and where it cuts the ground;
    PostError if the run has none."""
    summary = read_summary(outdir) or {}
    circle, factor = summary.get("slip_circle"), summary.get("limit_equilibrium")
    if not circle or factor is None or any(v is None for v in circle):
        raise PostError(f"{outdir}/summary.json has no slip circle: limit equilibrium is computed for a "
                        "finished 2D run of a slope (one soil or layers) under gravity along -y")
    return (*circle, factor)
