"""The sharp-features stage measures in edge lengths: the same voxels with
another spacing (CT and MRI volumes are in millimetres) give the same
lines and the same normals. A digitised torus (no crease) and a rotated
cube (12 creases) run through the digital surface, II, AT and the stage at
spacings 1, 0.3 and 2.7 with an offset origin. Before the crease test
counted its search in face steps, a spacing of 2.7 drew a false loop on the
torus and moved its normals by up to 57 degrees."""
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkDigitalSurfaceFilter,
                             vtkIINormalEstimator, vtkSharpFeaturesFilter)

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


n = 48
z, y, x = np.mgrid[0:n, 0:n, 0:n].astype(float)
centre = (n - 1) / 2 + np.array([0.13, 0.07, 0.11])
a, b = np.radians(20), np.radians(30)
rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
q = (np.stack([x, y, z], -1) - centre) @ (ry @ rx)
shapes = {
    "torus": (np.hypot(q[..., 0], q[..., 1]) - 13) ** 2 + q[..., 2] ** 2 <= 7 ** 2,
    "cube": (np.abs(q) <= 13).all(-1),
}


def run(inside, spacing):
    img = vtkImageData()
    img.SetDimensions(n, n, n)
    img.SetSpacing(spacing, spacing, spacing)
    img.SetOrigin(-3.0, 5.0, 1.0)
    scalars = numpy_to_vtk(inside.astype(np.uint8).ravel(), deep=1)
    scalars.SetName("label")
    img.GetPointData().SetScalars(scalars)
    surf = vtkDigitalSurfaceFilter()
    surf.SetInputData(img)
    ii = vtkIINormalEstimator()
    ii.SetInputConnection(surf.GetOutputPort())
    ii.SetSourceData(img)
    ii.SetRadius(4)
    at = vtkAmbrosioTortorelliFilter()
    at.SetInputConnection(ii.GetOutputPort())
    sharp = vtkSharpFeaturesFilter()
    sharp.SetInputConnection(at.GetOutputPort())
    sharp.Update()
    normals = vtk_to_numpy(sharp.GetOutputDataObject(0).GetCellData().GetArray("SharpNormals"))
    return sharp.GetOutputDataObject(1).GetNumberOfLines(), sharp.GetNumberOfRegions(), normals


for name, inside in shapes.items():
    lines1, regions1, normals1 = run(inside, 1.0)
    if name == "torus":
        check(lines1 == 0, "the torus has no line at spacing 1 (%d)" % lines1)
    for spacing in (0.3, 2.7):
        lines, regions, normals = run(inside, spacing)
        worst = np.degrees(np.arccos(np.clip((normals * normals1).sum(1), -1, 1))).max()
        # Rounding moves a few faces across the searches' reach: hundredths
        # of a degree on average, a fraction of a degree at most.
        check(lines == lines1 and regions == regions1 and worst < 1.0,
              "%s, spacing %g: %d lines, %d regions, normals within %.3f deg of spacing 1's "
              "(%d lines, %d regions)" % (name, spacing, lines, regions, worst, lines1, regions1))

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
