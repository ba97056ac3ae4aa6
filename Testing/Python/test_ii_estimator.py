"""A VTK Python user's pipeline: image source -> digital surface -> II normals."""
import math
import sys

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkImagingSources import vtkImageEllipsoidSource

from digitalgeometry import vtkDigitalSurfaceFilter, vtkIINormalEstimator

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


# A ball of radius 12 voxels; spacing 0.5 so that world units differ from voxels.
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

ii = vtkIINormalEstimator()
ii.SetInputConnection(surf.GetOutputPort())
ii.SetSourceData(image)
ii.SetRadius(4)
ii.ComputeCurvaturesOn()
ii.Update()
out = ii.GetOutput()
nq = out.GetNumberOfPolys()
check(nq > 1000 and nq == surf.GetOutput().GetNumberOfPolys(), "same %d quads as the surface" % nq)
normals = out.GetCellData().GetNormals()
check(normals is not None and normals.GetName() == "IINormals", "IINormals are the active normals")
trivial = out.GetCellData().GetArray("Normals")
check(trivial is not None, "trivial normals kept as 'Normals'")

# Unit length, positive dot with the trivial normal, close to the radial direction.
centre = [20.2 * 0.5, 19.7 * 0.5, 20.1 * 0.5]
ids = out.GetPolys()
from vtkmodules.vtkCommonCore import vtkIdList
lst = vtkIdList()
worst_len, min_dot, max_angle = 0.0, 1.0, 0.0
for c in range(nq):
    n = normals.GetTuple3(c)
    worst_len = max(worst_len, abs(math.sqrt(sum(x * x for x in n)) - 1))
    t = trivial.GetTuple3(c)
    min_dot = min(min_dot, sum(a * b for a, b in zip(n, t)))
    out.GetCellPoints(c, lst)
    p = [0.0, 0.0, 0.0]
    for k in range(4):
        q = out.GetPoint(lst.GetId(k))
        for a in range(3):
            p[a] += q[a] / 4
    radial = [p[a] - centre[a] for a in range(3)]
    rl = math.sqrt(sum(x * x for x in radial))
    cosang = sum(n[a] * radial[a] for a in range(3)) / rl
    max_angle = max(max_angle, math.degrees(math.acos(max(-1.0, min(1.0, cosang)))))
check(worst_len < 1e-9, "unit normals (worst |len-1| %.1e)" % worst_len)
check(min_dot > 0, "positive dot with the trivial normal (min %.3f)" % min_dot)
check(max_angle < 15, "largest angle to the radial direction %.2f deg" % max_angle)

# Mean curvature in 1/world units: the ball has radius 12 voxels = 6 world units.
H = out.GetCellData().GetArray("IIMeanCurvature")
check(H is not None, "IIMeanCurvature present")
vals = sorted(H.GetValue(c) for c in range(nq))
median = vals[len(vals) // 2]
check(abs(median * 6 - 1) < 0.15, "median mean curvature %.4f ~ 1/6 (world)" % median)
for name in ("IIGaussianCurvature", "IIK1", "IIK2", "IIK1Direction", "IIK2Direction"):
    check(out.GetCellData().GetArray(name) is not None, name + " present")

# Radius in world units: 2 world units = 4 voxels, the same normals.
ii2 = vtkIINormalEstimator()
ii2.SetInputConnection(surf.GetOutputPort())
ii2.SetSourceData(image)
ii2.SetRadiusUnitsToWorld()
ii2.SetRadius(2.0)
ii2.Update()
n2 = ii2.GetOutput().GetCellData().GetNormals()
diff = max(abs(a - b) for c in range(0, nq, 7) for a, b in zip(n2.GetTuple3(c), normals.GetTuple3(c)))
check(diff < 1e-12, "world radius 2 == voxel radius 4 (max diff %.1e)" % diff)

# Errors are reported, not crashes: no source image, then a bad radius.
errors = []
ii3 = vtkIINormalEstimator()
ii3.SetInputConnection(surf.GetOutputPort())
ii3.AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
ii3.GetExecutive().AddObserver(vtkCommand.ErrorEvent, lambda o, e: None)
ii3.Update()
check(len(errors) >= 1 and ii3.GetOutput().GetNumberOfCells() == 0, "missing image: error, empty output")
errors.clear()
ii3.SetSourceData(image)
ii3.SetRadius(-1)
ii3.Update()
check(len(errors) >= 1 and ii3.GetOutput().GetNumberOfCells() == 0, "negative radius: error, empty output")
errors.clear()
ii3.SetRadius(3)
ii3.Update()
check(len(errors) == 0 and ii3.GetOutput().GetNumberOfCells() == nq, "recovers with a good radius")
check("Radius: 3" in str(ii3), "PrintSelf shows the radius")

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
