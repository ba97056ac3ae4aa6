"""A VTK Python user's pipeline: image source -> digital surface -> VCM normals (and AT on them)."""
import math
import sys

from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkImagingSources import vtkImageEllipsoidSource

from digitalgeometry import (vtkDigitalSurfaceFilter, vtkVCMNormalEstimator,
                             vtkAmbrosioTortorelliFilter)

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

vcm = vtkVCMNormalEstimator()
check(vcm.GetOffsetRadius() == 10 and vcm.GetConvolutionRadius() == 4, "defaults R = 10, r = 4")
vcm.SetInputConnection(surf.GetOutputPort())
vcm.SetSourceData(image)
vcm.SetOffsetRadius(6)
vcm.SetConvolutionRadius(3)
vcm.ComputeFeatureScoreOn()
vcm.Update()
out = vcm.GetOutput()
nq = out.GetNumberOfPolys()
check(nq > 1000 and nq == surf.GetOutput().GetNumberOfPolys(), "same %d quads as the surface" % nq)
normals = out.GetCellData().GetNormals()
check(normals is not None and normals.GetName() == "VCMNormals", "VCMNormals are the active normals")
score = out.GetCellData().GetArray("VCMFeatureScore")
eig = out.GetCellData().GetArray("VCMEigenvalues")
check(score is not None and eig is not None and eig.GetNumberOfComponents() == 3,
      "VCMFeatureScore and VCMEigenvalues present")

# Unit, outward (radial) normals close to the radial direction; a sphere has no feature.
centre = [20.2 * 0.5, 19.7 * 0.5, 20.1 * 0.5]
from vtkmodules.vtkCommonCore import vtkIdList  # noqa: E402
lst = vtkIdList()
worst_len, max_angle, max_score = 0.0, 0.0, 0.0
for c in range(nq):
    n = normals.GetTuple3(c)
    worst_len = max(worst_len, abs(math.sqrt(sum(x * x for x in n)) - 1))
    out.GetCellPoints(c, lst)
    p = [sum(out.GetPoint(lst.GetId(k))[a] for k in range(4)) / 4 for a in range(3)]
    radial = [p[a] - centre[a] for a in range(3)]
    rl = math.sqrt(sum(x * x for x in radial))
    cosang = sum(n[a] * radial[a] for a in range(3)) / rl
    max_angle = max(max_angle, math.degrees(math.acos(max(-1.0, min(1.0, cosang)))))
    max_score = max(max_score, score.GetValue(c))
check(worst_len < 1e-9, "unit normals (worst |len-1| %.1e)" % worst_len)
check(max_angle < 10, "largest angle to the radial direction %.2f deg" % max_angle)
check(max_score < 0.1, "feature score below 0.1 on a sphere (max %.3f)" % max_score)

# Radii in world units: 3 and 1.5 world units = 6 and 3 voxels, the same normals.
vcm2 = vtkVCMNormalEstimator()
vcm2.SetInputConnection(surf.GetOutputPort())
vcm2.SetSourceData(image)
vcm2.SetRadiusUnitsToWorld()
vcm2.SetOffsetRadius(3.0)
vcm2.SetConvolutionRadius(1.5)
vcm2.Update()
n2 = vcm2.GetOutput().GetCellData().GetNormals()
diff = max(abs(a - b) for c in range(0, nq, 7) for a, b in zip(n2.GetTuple3(c), normals.GetTuple3(c)))
check(diff < 1e-12, "world radii (3, 1.5) == voxel radii (6, 3) (max diff %.1e)" % diff)

# AT on the VCM normals.
at = vtkAmbrosioTortorelliFilter()
at.SetInputConnection(vcm.GetOutputPort())
at.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_CELLS, "VCMNormals")
at.Update()
u = at.GetOutput(0).GetCellData().GetNormals()
check(u is not None and u.GetNumberOfTuples() == nq, "AT regularises VCMNormals (%s)" % (u and u.GetName()))

# Errors are reported, not crashes: no source image, R < r.
errors = []
vcm3 = vtkVCMNormalEstimator()
vcm3.SetInputConnection(surf.GetOutputPort())
vcm3.AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
vcm3.GetExecutive().AddObserver(vtkCommand.ErrorEvent, lambda o, e: None)
vcm3.Update()
check(len(errors) >= 1 and vcm3.GetOutput().GetNumberOfCells() == 0, "missing image: error, empty output")
errors.clear()
vcm3.SetSourceData(image)
vcm3.SetOffsetRadius(2)
vcm3.SetConvolutionRadius(3)
vcm3.Update()
check(len(errors) >= 1 and vcm3.GetOutput().GetNumberOfCells() == 0, "R < r: error, empty output")
errors.clear()
vcm3.SetOffsetRadius(5)
vcm3.Update()
check(len(errors) == 0 and vcm3.GetOutput().GetNumberOfCells() == nq, "recovers with good radii")
check("OffsetRadius: 5" in str(vcm3), "PrintSelf shows the offset radius")

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
