"""read_vtr.py FILE
Reads a .vtr (RectilinearGrid) with VTK's own XML reader and prints, one fact a line:
  dims NX NY NZ / xcoord I X / ycoord J Y / zcoord K Z / array NAME NCOMP TYPE (float64, uint8, int16, ...) /
  compname NAME K COMPNAME / value NAME POINT COMP VALUE
Floats are printed with repr(). Exits with status 1 if VTK reports an error or warning."""
import sys

try:
    from vtkmodules.vtkCommonCore import VTK_DOUBLE, VTK_FLOAT
    from vtkmodules.vtkIOXML import vtkXMLRectilinearGridReader
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


def main(path):
    reader = vtkXMLRectilinearGridReader()
    reader.AddObserver("ErrorEvent", lambda o, e: problems.append(e))
    reader.AddObserver("WarningEvent", lambda o, e: problems.append(e))
    reader.SetFileName(path)
    reader.Update()
    if problems or reader.GetErrorCode() != 0:
        print(f"error VTK reported {problems} (error code {reader.GetErrorCode()})")
        return 1
    grid = reader.GetOutput()
    print("dims " + " ".join(str(d) for d in grid.GetDimensions()))
    for axis, coords in (("x", grid.GetXCoordinates()), ("y", grid.GetYCoordinates()),
                         ("z", grid.GetZCoordinates())):
        for i in range(coords.GetNumberOfTuples()):
            print(f"{axis}coord {i} {coords.GetValue(i)!r}")
    print(f"cellarrays {grid.GetCellData().GetNumberOfArrays()}")
    data = grid.GetPointData()
    for a in range(data.GetNumberOfArrays()):
        arr = data.GetArray(a)
        name, ncomp = arr.GetName(), arr.GetNumberOfComponents()
        print(f"array {name} {ncomp} {value_type(arr)}")
        for k in range(ncomp):
            if arr.GetComponentName(k) is not None:
                print(f"compname {name} {k} {arr.GetComponentName(k)}")
        for i in range(arr.GetNumberOfTuples()):
            for k in range(ncomp):
                print(f"value {name} {i} {k} {arr.GetComponent(i, k)!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
