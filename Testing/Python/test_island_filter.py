"""The island filter from Python: a stock VTK image source with a speck and
a cavity added -> vtkDigitalIslandFilter -> vtkDigitalSurfaceFilter."""
import sys

from vtkmodules.vtkImagingSources import vtkImageEllipsoidSource

from digitalgeometry import vtkDigitalIslandFilter, vtkDigitalSurfaceFilter

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


src = vtkImageEllipsoidSource()
src.SetWholeExtent(0, 39, 0, 39, 0, 39)
src.SetCenter(20.2, 19.7, 20.1)
src.SetRadius(12, 9, 7)
src.SetInValue(255)
src.SetOutValue(0)
src.Update()
image = src.GetOutput()
image.SetOrigin(-3.0, 2.0, 0.5)
image.SetSpacing(0.5, 0.5, 1.0)
scalars = image.GetPointData().GetScalars()


def voxel(i, j, k):
    return (k * 40 + j) * 40 + i


clean = [scalars.GetValue(v) != 0 for v in range(scalars.GetNumberOfTuples())]
# A 3-voxel speck in a corner region and a 2-voxel cavity at the centre.
for i in (3, 4, 5):
    scalars.SetValue(voxel(i, 3, 3), 255)
for i in (20, 21):
    check(scalars.GetValue(voxel(i, 20, 20)) == 255, "voxel (%d, 20, 20) inside the ellipsoid" % i)
    scalars.SetValue(voxel(i, 20, 20), 0)
scalars.Modified()

islands = vtkDigitalIslandFilter()
islands.SetInputData(image)
check(islands.GetMinimumSize() == 8 and islands.GetRemoveIslands() and islands.GetFillCavities(),
      "defaults: MinimumSize 8, RemoveIslands and FillCavities on")
islands.Update()
out = islands.GetOutput()
inside = out.GetPointData().GetScalars()
check(inside is not None and inside.GetName() == "Inside", "output array 'Inside'")
check(out.GetOrigin() == image.GetOrigin() and out.GetSpacing() == image.GetSpacing()
      and out.GetExtent() == image.GetExtent(), "output keeps the input's geometry")
check(all((inside.GetValue(v) != 0) == clean[v] for v in range(inside.GetNumberOfTuples())),
      "speck removed and cavity filled: the clean ellipsoid again")
check(islands.GetNumberOfRemovedIslands() == 1 and islands.GetNumberOfFilledCavities() == 1
      and islands.GetNumberOfChangedVoxels() == 5,
      "1 island, 1 cavity, 5 voxels (%d, %d, %d)" % (islands.GetNumberOfRemovedIslands(),
                                                     islands.GetNumberOfFilledCavities(),
                                                     islands.GetNumberOfChangedVoxels()))
fd = out.GetFieldData()
check(fd.GetArray("RemovedIslands").GetValue(0) == 1 and fd.GetArray("FilledCavities").GetValue(0) == 1,
      "field data RemovedIslands = FilledCavities = 1")

surface = vtkDigitalSurfaceFilter()
surface.SetInputConnection(islands.GetOutputPort())
surface.Update()
raw = vtkDigitalSurfaceFilter()
raw.SetInputData(image)
raw.Update()
removed = raw.GetOutput().GetNumberOfCells() - surface.GetOutput().GetNumberOfCells()
check(removed == 14 + 10, "the speck's 14 and the cavity's 10 surfels are gone (%d)" % removed)

islands.SetMinimumSize(3)
islands.Update()
check(islands.GetNumberOfRemovedIslands() == 0 and islands.GetNumberOfFilledCavities() == 1,
      "MinimumSize 3 keeps the 3-voxel speck and fills the 2-voxel cavity")
islands.SetMinimumSize(0)
islands.GlobalWarningDisplayOff()
islands.Update()
check(islands.GetOutput().GetPointData().GetScalars() is None, "MinimumSize 0: error, empty output")

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
