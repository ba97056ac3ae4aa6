"""A VTK Python user's pipeline: a stock VTK image source -> our filter."""
import math
import os
import sys
import tempfile

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkImagingSources import vtkImageEllipsoidSource
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter

from digitalgeometry import vtkDigitalSurfaceFilter, vtkDGtalVolReader

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


# A box: the ellipsoid source with huge radii along y, z would fill the image;
# use a true ellipsoid and check invariants instead of a count.
src = vtkImageEllipsoidSource()
src.SetWholeExtent(0, 39, 0, 39, 0, 39)
src.SetCenter(20.2, 19.7, 20.1)
src.SetRadius(12, 9, 7)
src.SetInValue(255)
src.SetOutValue(0)

surf = vtkDigitalSurfaceFilter()
surf.SetInputConnection(src.GetOutputPort())
surf.Update()
out = surf.GetOutput()
nq = out.GetNumberOfPolys()
check(nq > 500, "ellipsoid gives %d quads" % nq)
# Closed quad surface of genus 0: every edge shared by two quads, V - E + F = 2.
edges = set()
ids = out.GetPolys()
from vtkmodules.vtkCommonCore import vtkIdList
lst = vtkIdList()
for c in range(out.GetNumberOfCells()):
    out.GetCellPoints(c, lst)
    for a in range(4):
        p, q = lst.GetId(a), lst.GetId((a + 1) % 4)
        edges.add((min(p, q), max(p, q)))
chi = out.GetNumberOfPoints() - len(edges) + nq
check(chi == 2, "Euler characteristic %d == 2" % chi)
normals = out.GetCellData().GetNormals()
check(normals is not None and normals.GetNumberOfComponents() == 3, "active cell normals")
s = [0.0, 0.0, 0.0]
for c in range(nq):
    n = normals.GetTuple3(c)
    for a in range(3):
        s[a] += n[a]
check(all(abs(x) < 1e-6 for x in s), "normals sum to zero: %s" % (s,))
check(out.GetCellData().GetArray("InsideVoxel") is not None, "InsideVoxel array")
check(out.GetFieldData().GetArray("ImageSpacing") is not None, "ImageSpacing field")

# Label mode from Python, and an error observed for an empty selection.
surf.SetSelectionModeToLabel()
surf.SetLabel(17)
errors = []
surf.AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
surf.Update()
check(len(errors) >= 1 and surf.GetOutput().GetNumberOfCells() == 0,
      "empty selection gives an error and an empty output")

# Written with the stock XML writer and read back.
tmp = os.environ.get("DG_TEST_TMP", tempfile.gettempdir())
path = os.path.join(tmp, "py_surface.vtp")
surf.SetSelectionModeToNonZero()
w = vtkXMLPolyDataWriter()
# Inline binary: appended data is misparsed by VTK 9.2's reader with Debian's
# current expat (2.5.0-1+deb12u5 defers reparsing into the raw section).
w.SetDataModeToBinary()
w.SetInputConnection(surf.GetOutputPort())
w.SetFileName(path)
check(w.Write() == 1, "written to %s" % path)
r = vtkXMLPolyDataReader()
r.SetFileName(path)
r.Update()
check(r.GetOutput().GetNumberOfPolys() == nq, "read back %d quads" % r.GetOutput().GetNumberOfPolys())

check(vtkDGtalVolReader().CanReadFile(path) == 0, "a .vtp is not a .vol")

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
