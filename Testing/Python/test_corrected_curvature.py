"""vtkCorrectedCurvatureFilter from Python, chained as the ParaView plugin
chains it (every filter's defaults): a digitised ball of radius 12 with a
spacing of 0.5 mm, so that the radius in voxels and the curvature in world
units are both exercised; then the program's --curvature on the same ball
as a .vti file."""
import math
import os
import subprocess
import sys

from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataReader

from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkCorrectedCurvatureFilter,
                             vtkDigitalSurfaceFilter, vtkIINormalEstimator,
                             vtkSharpFeaturesFilter)

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


n, r, h = 34, 12.0, 0.5
c = (n / 2 + 0.3, n / 2 + 0.1, n / 2 + 0.2)
img = vtkImageData()
img.SetDimensions(n, n, n)
img.SetSpacing(h, h, h)
img.AllocateScalars(3, 1)  # VTK_UNSIGNED_CHAR
s = img.GetPointData().GetScalars()
for k in range(n):
    for j in range(n):
        for i in range(n):
            inside = (i - c[0]) ** 2 + (j - c[1]) ** 2 + (k - c[2]) ** 2 <= r * r
            s.SetTuple1((k * n + j) * n + i, 1 if inside else 0)

surf = vtkDigitalSurfaceFilter()
surf.SetInputData(img)
ii = vtkIINormalEstimator()
ii.SetInputConnection(surf.GetOutputPort())
ii.SetSourceData(img)
at = vtkAmbrosioTortorelliFilter()
at.SetInputConnection(ii.GetOutputPort())
sharp = vtkSharpFeaturesFilter()
sharp.SetInputConnection(at.GetOutputPort())
curv = vtkCorrectedCurvatureFilter()
curv.SetInputConnection(sharp.GetOutputPort())
curv.Update()
out = curv.GetOutput(0)
check(curv.GetRadius() == 6 and curv.GetRadiusUnits() == curv.VOXELS and curv.GetPerSide() and
      curv.GetAdaptiveRadius(), "defaults: ball 6 voxels, a radius per face, per side")
check(abs(curv.GetUsedRadius() - 6 * h) < 1e-12, "the ball is 6 voxels of 0.5: %g" % curv.GetUsedRadius())
# A radius per face: from 2/3 to 3 times the ball of 6 voxels (world units),
# larger than 6 voxels on most of a clean ball.
radius = out.GetCellData().GetArray("CorrectedBallRadius")
radii = sorted(radius.GetValue(f) for f in range(radius.GetNumberOfTuples())) if radius else []
check(radii and 4 * h - 1e-9 <= radii[0] and radii[-1] <= 18 * h + 1e-9 and radii[len(radii) // 2] > 6 * h,
      "CorrectedBallRadius in [4, 18] voxels of 0.5, median %.2f" % (radii[len(radii) // 2] if radii else -1))
fixed = vtkCorrectedCurvatureFilter()
fixed.SetInputConnection(sharp.GetOutputPort())
fixed.AdaptiveRadiusOff()
fixed.Update()
fr = fixed.GetOutput(0).GetCellData().GetArray("CorrectedBallRadius")
check(fr is not None and all(abs(fr.GetValue(f) - 6 * h) < 1e-12 for f in range(fr.GetNumberOfTuples())),
      "AdaptiveRadius off: every ball 6 voxels")
H = out.GetCellData().GetArray("CorrectedMeanCurvature")
check(H is not None and H.GetNumberOfTuples() == out.GetNumberOfCells(), "CorrectedMeanCurvature per face")
R = r * h
values = sorted(H.GetValue(f) * R for f in range(H.GetNumberOfTuples()))
median = values[len(values) // 2]
check(abs(median - 1) < 0.02, "median H R = %.4f (world units)" % median)
for name in ("CorrectedGaussianCurvature", "CorrectedK1", "CorrectedK2"):
    check(out.GetCellData().GetArray(name) is not None, name)
for name in ("CorrectedK1Direction", "CorrectedK2Direction"):
    a = out.GetCellData().GetArray(name)
    check(a is not None and a.GetNumberOfComponents() == 3, name + " (3 components)")
fd = out.GetFieldData()
gb = fd.GetArray("GaussBonnetCharacteristic").GetValue(0)
chi = fd.GetArray("EulerCharacteristic").GetValue(0)
check(abs(gb - 2) < 0.01 and chi == 2, "Gauss-Bonnet %.4f, V - E + F %g" % (gb, chi))
area = fd.GetArray("CorrectedArea").GetValue(0)
check(abs(area / (4 * math.pi * R * R) - 1) < 0.01, "corrected area %.4f of the ball's" % (area / (4 * math.pi * R * R)))
ssa = fd.GetArray("SpecificSurfaceArea").GetValue(0)
check(abs(ssa * R / 3 - 1) < 0.01, "specific surface area %.4f of 3 / R" % (ssa * R / 3))
check(curv.GetOutput(1).GetNumberOfLines() == 0, "no crease on a ball")

# Bad input: an error and empty outputs.
bad = vtkCorrectedCurvatureFilter()
bad.SetInputConnection(sharp.GetOutputPort())
bad.SetRadius(-1)
bad.GlobalWarningDisplayOff()
bad.Update()
check(bad.GetOutput(0).GetNumberOfCells() == 0, "Radius -1: empty output")

# The program on the same volume, as a file.
tmp = os.environ.get("DG_TEST_TMP", ".")
vti = os.path.join(tmp, "ball.vti")
w = vtkXMLImageDataWriter()
w.SetInputData(img)
w.SetFileName(vti)
w.Write()
program = os.environ.get("DG_PROGRAM")
if program:
    p = subprocess.run([program, vti, "--curvature", "--quiet", "--output-dir", tmp, "--width", "600"],
                       capture_output=True, text=True)
    check(p.returncode == 0, "piecewise-normals --curvature exits 0 (%s)" % p.stderr.strip()[-200:])
    check("Euler characteristic 2.0000 by Gauss-Bonnet, 2 by V - E + F" in p.stdout,
          "summary line: " + next((l for l in p.stdout.splitlines() if l.startswith("  curvature")), ""))
    for f in ("ball_creases.vtp", "ball_curvature.png", "ball_surface.vtp"):
        check(os.path.exists(os.path.join(tmp, f)), "wrote " + f)
    rd = vtkXMLPolyDataReader()
    rd.SetFileName(os.path.join(tmp, "ball_surface.vtp"))
    rd.Update()
    check(rd.GetOutput().GetCellData().GetArray("CorrectedMeanCurvature") is not None,
          "the surface file has CorrectedMeanCurvature")
    radius = rd.GetOutput().GetCellData().GetArray("CorrectedBallRadius")
    check(radius is not None and "ball radius per face from 6 voxels, 10/50/90 %" in p.stdout,
          "the surface file has CorrectedBallRadius; the summary gives the radii")
    p = subprocess.run([program, vti, "--curvature-fixed-radius", "--quiet", "--output-dir", tmp, "--no-png"],
                       capture_output=True, text=True)
    check(p.returncode == 0 and "curvature (ball 6 voxels)" in p.stdout,
          "--curvature-fixed-radius: one ball of 6 voxels (%s)" % p.stderr.strip()[-200:])
    p = subprocess.run([program, vti, "--curvature-radius", "0", "--quiet", "--output-dir", tmp],
                       capture_output=True, text=True)
    check(p.returncode == 2 and "--curvature-radius" in p.stderr, "--curvature-radius 0 is refused")

print("%d checks, %d failures" % (len(checks), len(failures)))
sys.exit(1 if failures else 0)
