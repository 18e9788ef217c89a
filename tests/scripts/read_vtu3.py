"""read_vtu3.py FILE
Reads a 3D particle .vtu (hexahedral voxels) with VTK's own XML reader and prints, one fact a
line: cells N / points N / cell C TYPE NPOINTS VOLUME (VTK's vtkCellSizeFilter volume) /
corner C K x y z / array NAME NCOMP / value NAME CELL COMP VALUE. Floats with repr().
Exits with status 1 (printing "error ...") if VTK reports an error or warning."""
import sys

from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

problems = []
reader = vtkXMLUnstructuredGridReader()
reader.AddObserver("ErrorEvent", lambda o, e: problems.append(e))
reader.AddObserver("WarningEvent", lambda o, e: problems.append(e))
reader.SetFileName(sys.argv[1])
reader.Update()
if problems or reader.GetErrorCode() != 0:
    print(f"error VTK reported {problems}")
    sys.exit(1)
grid = reader.GetOutput()
sizes = vtkCellSizeFilter()
sizes.SetInputData(grid)
sizes.ComputeVolumeOn()
sizes.Update()
volume = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Volume"))
print(f"cells {grid.GetNumberOfCells()}")
print(f"points {grid.GetNumberOfPoints()}")
for c in range(grid.GetNumberOfCells()):
    cell = grid.GetCell(c)
    print(f"cell {c} {grid.GetCellType(c)} {cell.GetNumberOfPoints()} {float(volume[c])!r}")
    for k in range(cell.GetNumberOfPoints()):
        x, y, z = grid.GetPoint(cell.GetPointId(k))
        print(f"corner {c} {k} {x!r} {y!r} {z!r}")
data = grid.GetCellData()
for a in range(data.GetNumberOfArrays()):
    arr = data.GetArray(a)
    print(f"array {arr.GetName()} {arr.GetNumberOfComponents()}")
    for c in range(grid.GetNumberOfCells()):
        for k in range(arr.GetNumberOfComponents()):
            print(f"value {arr.GetName()} {c} {k} {arr.GetComponent(c, k)!r}")
