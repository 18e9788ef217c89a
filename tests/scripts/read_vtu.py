"""read_vtu.py FILE [CELL ...]
Reads a .vtu with VTK's own XML reader and prints what the C++ tests check, one fact a line:
  cells N / points N / pointtype TYPE / celltype C T / cellpoints C i0 i1 ... / point I x y z
  array NAME NCOMP TYPE (float64, uint8, int16, ...) / compname NAME K COMPNAME / value NAME CELL COMP VALUE
Floats are printed with repr(), the shortest text that reads back to the same double.
With CELL arguments, points and values are printed for those cells only (for large files).
Exits with status 1 (printing "error ...") if VTK reports an error or warning."""
import sys

try:
    from vtkmodules.vtkCommonCore import VTK_DOUBLE, VTK_FLOAT
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
except ImportError as exc:  # pragma: no cover
    print(f"error cannot import vtk ({exc}); install python3-vtk9")
    sys.exit(2)

problems = []


def value_type(arr):
    """The array's values by meaning, e.g. float64, uint8, int16 (the class name differs
    between VTK builds: vtkUnsignedCharArray or vtkTypeUInt8Array hold the same uint8)."""
    bits = 8 * arr.GetDataTypeSize()
    if arr.GetDataType() in (VTK_FLOAT, VTK_DOUBLE):
        return f"float{bits}"
    return f"{'int' if arr.GetDataTypeMin() < 0 else 'uint'}{bits}"


def on_problem(obj, event):
    problems.append(event)


def main(path, chosen):
    reader = vtkXMLUnstructuredGridReader()
    reader.AddObserver("ErrorEvent", on_problem)
    reader.AddObserver("WarningEvent", on_problem)
    reader.SetFileName(path)
    reader.Update()
    if problems or reader.GetErrorCode() != 0:
        print(f"error VTK reported {problems} (error code {reader.GetErrorCode()})")
        return 1
    grid = reader.GetOutput()
    print(f"cells {grid.GetNumberOfCells()}")
    print(f"points {grid.GetNumberOfPoints()}")
    if grid.GetPoints() is not None:
        print(f"pointtype {value_type(grid.GetPoints().GetData())}")
    cells = chosen if chosen else range(grid.GetNumberOfCells())
    for c in cells:
        print(f"celltype {c} {grid.GetCellType(c)}")
        ids = grid.GetCell(c).GetPointIds()
        print(f"cellpoints {c} " + " ".join(str(ids.GetId(k)) for k in range(ids.GetNumberOfIds())))
    for i in sorted({grid.GetCell(c).GetPointId(k) for c in cells
                     for k in range(grid.GetCell(c).GetNumberOfPoints())}):
        x, y, z = grid.GetPoint(i)
        print(f"point {i} {x!r} {y!r} {z!r}")
    print(f"pointarrays {grid.GetPointData().GetNumberOfArrays()}")
    data = grid.GetCellData()
    for a in range(data.GetNumberOfArrays()):
        arr = data.GetArray(a)
        name, ncomp = arr.GetName(), arr.GetNumberOfComponents()
        print(f"array {name} {ncomp} {value_type(arr)}")
        for k in range(ncomp):
            if arr.GetComponentName(k) is not None:
                print(f"compname {name} {k} {arr.GetComponentName(k)}")
        for c in cells:
            for k in range(ncomp):
                print(f"value {name} {c} {k} {arr.GetComponent(c, k)!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], [int(c) for c in sys.argv[2:]]))
