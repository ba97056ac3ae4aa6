"""vtkAmbrosioTortorelliFilter from Python: a digitised box through the
digital surface filter (trivial normals) into AT; both output ports."""
import sys

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkImagingSources import vtkImageEllipsoidSource  # noqa: F401

from digitalgeometry import vtkAmbrosioTortorelliFilter, vtkDigitalSurfaceFilter

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


# A 10 x 8 x 6 box of voxels in a 16^3 image.
img = vtkImageData()
img.SetDimensions(16, 16, 16)
img.AllocateScalars(3, 1)  # VTK_UNSIGNED_CHAR
s = img.GetPointData().GetScalars()
for k in range(16):
    for j in range(16):
        for i in range(16):
            inside = 3 <= i < 13 and 4 <= j < 12 and 5 <= k < 11
            s.SetTuple1((k * 16 + j) * 16 + i, 1 if inside else 0)

surf = vtkDigitalSurfaceFilter()
surf.SetInputData(img)

at = vtkAmbrosioTortorelliFilter()
at.SetInputConnection(surf.GetOutputPort())
check(abs(at.GetAlpha() - 0.1) < 1e-12 and abs(at.GetLambda() - 0.01) < 1e-12,
      "paper defaults alpha 0.1, lambda 0.01")
progress = []
at.AddObserver(vtkCommand.ProgressEvent, lambda o, e: progress.append(o.GetProgress()))
at.Update()

out = at.GetOutputDataObject(0)
feat = at.GetOutputDataObject(1)
nq = out.GetNumberOfPolys()
check(nq == 2 * (10 * 8 + 10 * 6 + 8 * 6), "port 0 keeps the %d quads" % nq)
normals = out.GetCellData().GetNormals()
check(normals is not None and normals.GetName() == "ATNormals", "active normals are ATNormals")
check(out.GetCellData().GetArray("Normals") is not None, "input normals kept")
n0 = normals.GetTuple3(0)
check(abs(sum(x * x for x in n0) - 1) < 1e-9, "unit regularised normals")
v = out.GetPointData().GetArray("ATFeatureIndicator")
check(v is not None and v.GetNumberOfTuples() == out.GetNumberOfPoints(), "v per point")
nl = feat.GetNumberOfLines()
check(nl > 0, "port 1 has %d feature lines" % nl)
check(feat.GetPoints() is not None and feat.GetNumberOfPoints() == out.GetNumberOfPoints(),
      "feature lines share the surface points")
fv = feat.GetCellData().GetArray("ATFeatureIndicator")
check(fv is not None and fv.GetNumberOfTuples() == nl and fv.GetRange()[1] < 0.5,
      "v per feature line below the threshold")
# The box's 12 edges: every feature line lies on the box's boundary edges
# (corner coordinates 2.5/12.5, 3.5/11.5, 4.5/10.5), two coordinates at a box
# corner value.
bounds = [(2.5, 12.5), (3.5, 11.5), (4.5, 10.5)]
on_edges = 0
for c in range(nl):
    ids = feat.GetCell(c).GetPointIds()
    p = [feat.GetPoint(ids.GetId(a)) for a in range(2)]
    mid = [(p[0][a] + p[1][a]) / 2 for a in range(3)]
    at_bound = sum(1 for a in range(3) if min(abs(mid[a] - b) for b in bounds[a]) < 1.01)
    on_edges += at_bound >= 2
check(on_edges >= 0.9 * nl, "%d of %d feature lines near the box edges" % (on_edges, nl))
check(len(progress) > 0 and progress[-1] == 1.0, "progress reported (%d events)" % len(progress))
check(at.GetNumberOfIterations() >= 4, "%d iterations" % at.GetNumberOfIterations())

# A bad parameter: an error and empty outputs.
errors = []
at.AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
at.SetEpsilonRatio(1.0)
at.Update()
check(len(errors) >= 1 and at.GetOutputDataObject(0).GetNumberOfCells() == 0
      and at.GetOutputDataObject(1).GetNumberOfCells() == 0,
      "EpsilonRatio 1 gives an error and empty outputs")

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
