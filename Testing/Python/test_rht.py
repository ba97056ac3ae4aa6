"""A VTK Python user's pipeline: image -> digital surface -> RHT normals -> AT."""
import math
import sys

from vtkmodules.vtkImagingSources import vtkImageEllipsoidSource
from vtkmodules.vtkCommonCore import vtkCommand

from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkDigitalSurfaceFilter,
                             vtkRHTNormalEstimator)

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


# A ball of radius 12 voxels, spacing 0.5.
src = vtkImageEllipsoidSource()
src.SetWholeExtent(0, 39, 0, 39, 0, 39)
src.SetCenter(20.2, 19.7, 20.1)
src.SetRadius(12, 12, 12)
src.SetInValue(255)
src.SetOutValue(0)
src.Update()
image = src.GetOutput()
image.SetSpacing(0.5, 0.5, 0.5)

surf = vtkDigitalSurfaceFilter()
surf.SetInputData(image)
rht = vtkRHTNormalEstimator()
rht.SetInputConnection(surf.GetOutputPort())
rht.SetSourceData(image)
check(rht.GetRadius() == 6 and rht.GetNumberOfTrials() == 648 and rht.GetNumberOfAccumulators() == 5,
      "defaults: r = 6, 648 trials, 5 accumulators")
rht.SetNumberOfTrials(200)
rht.Update()
out = rht.GetOutput()
nq = out.GetNumberOfCells()
normals = out.GetCellData().GetNormals()
check(nq > 1000 and normals is not None and normals.GetName() == "RHTNormals",
      "RHTNormals active on %d quads" % nq)

# Radial error (the ball's centre in world: 0.5 * grid centre).
vox = out.GetCellData().GetArray("InsideVoxel")
dirs = out.GetCellData().GetArray("SurfelDirection")
errors = []
for c in range(nq):
    p = [vox.GetComponent(c, a) for a in range(3)]
    d = int(dirs.GetTuple1(c))
    p[d // 2] += 0.5 if d % 2 else -0.5
    radial = [p[0] - 20.2, p[1] - 19.7, p[2] - 20.1]
    ln = math.sqrt(sum(x * x for x in radial))
    n = normals.GetTuple3(c)
    dot = sum(radial[a] * n[a] for a in range(3)) / ln
    errors.append(math.degrees(math.acos(max(-1.0, min(1.0, dot)))))
errors.sort()
check(errors[len(errors) // 2] < 3.0, "median error on the ball %.2f deg" % errors[len(errors) // 2])

# Same seed, same output; another seed, another.
rht2 = vtkRHTNormalEstimator()
rht2.SetInputConnection(surf.GetOutputPort())
rht2.SetSourceData(image)
rht2.SetNumberOfTrials(200)
rht2.Update()
a = rht2.GetOutput().GetCellData().GetArray("RHTNormals")
check(all(a.GetValue(v) == normals.GetValue(v) for v in range(a.GetNumberOfValues())),
      "same seed: bitwise the same normals")
rht2.SetSeed(3)
rht2.Update()
a = rht2.GetOutput().GetCellData().GetArray("RHTNormals")
check(any(a.GetValue(v) != normals.GetValue(v) for v in range(a.GetNumberOfValues())),
      "another seed: other normals")

at = vtkAmbrosioTortorelliFilter()
at.SetInputConnection(rht.GetOutputPort())
at.Update()
u = at.GetOutput(0).GetCellData().GetArray("ATNormals")
check(u is not None and u.GetNumberOfTuples() == nq, "AT on RHTNormals")

errors = []
bad = vtkRHTNormalEstimator()
bad.SetInputConnection(surf.GetOutputPort())
bad.AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
bad.GetExecutive().AddObserver(vtkCommand.ErrorEvent, lambda o, e: None)
bad.Update()
check(len(errors) >= 1 and bad.GetOutput().GetNumberOfCells() == 0, "missing image: error, empty output")
bad.SetSourceData(image)
for setter, value in (("SetRadius", 0), ("SetNumberOfTrials", 0), ("SetNumberOfAccumulators", 0)):
    errors.clear()
    getattr(bad, setter)(value)
    bad.Update()
    check(len(errors) >= 1 and bad.GetOutput().GetNumberOfCells() == 0, "%s(%d): error, empty output" % (setter, value))
    getattr(bad, setter)({"SetRadius": 3, "SetNumberOfTrials": 50, "SetNumberOfAccumulators": 5}[setter])
errors.clear()
bad.Update()
check(len(errors) == 0 and bad.GetOutput().GetNumberOfCells() == nq, "recovers")
check("NumberOfTrials: 50" in str(bad), "PrintSelf shows the trials")

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
