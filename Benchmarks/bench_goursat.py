#!/usr/bin/python3
"""Corrected mean curvature on DGtal's "goursat" polynomial surface at
DGtal's grid steps, against the true curvature, as DGtal's
curvature-comparator example measures it (issue 37): the shape
0.03 (x^4 + y^4 + z^4) - 2 (x^2 + y^2 + z^2) - 8 <= 0 digitised in
[-10, 10]^3 with voxel centres at h (i, j, k); the program with its
defaults and --curvature on it (world units: spacing h); the true H at each
face centre's projection onto the surface; errors max |H - H_true| (L-oo)
and sqrt(mean (H - H_true)^2) (L2, DGtal's getScalarsNormL2), for the
program's own CorrectedMeanCurvature (its defaults: a radius per face) and
for one ball of a few radii (voxels; the filter again on the program's
surface with AdaptiveRadius off).

    /usr/bin/python3 Benchmarks/bench_goursat.py [--h 0.5,0.25,0.125] [--balls 3,5,7]
        [-- extra program options, e.g. --radius 8]

Needs the build's Python package on PYTHONPATH (build/lib/python3/dist-packages)
and the program (build/bin/piecewise-normals, or DG_PROGRAM)."""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkFiltersCore import vtkCellCenters
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataReader

from digitalgeometry import vtkCorrectedCurvatureFilter

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.environ.get("DG_PROGRAM", os.path.join(ROOT, "build", "bin", "piecewise-normals"))


def P(x):
    return 0.03 * (x ** 4).sum(-1) - 2 * (x ** 2).sum(-1) - 8


def grad(x):
    return 0.12 * x ** 3 - 4 * x


def true_mean_curvature(c):
    """H = div(n) / 2 with n = grad P / |grad P| (outward: P grows
    outward), at the projection of each point onto P = 0."""
    x = c.copy()
    for _ in range(20):
        g = grad(x)
        x = x - (P(x) / (g * g).sum(-1))[:, None] * g
    g = grad(x)
    hess = 0.36 * x ** 2 - 4  # diagonal Hessian
    g2 = (g * g).sum(-1)
    num = g2 * hess.sum(-1) - (g * g * hess).sum(-1)
    return num / (2 * g2 ** 1.5), np.abs(P(x)).max()


def read_with_truth(path):
    """The program's surface (.vtp) and the true H at its face centres."""
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    surface = r.GetOutput()
    cc = vtkCellCenters()
    cc.SetInputData(surface)
    cc.Update()
    centres = vtk_to_numpy(cc.GetOutput().GetPoints().GetData()).astype(float)
    truth, residual = true_mean_curvature(centres)
    return surface, truth, residual


def main():
    hs, balls = [0.5, 0.25, 0.125], [3, 5, 7]
    args = sys.argv[1:]
    extra = []
    if "--" in args:
        extra = args[args.index("--") + 1:]
        args = args[:args.index("--")]
    if "--h" in args:
        hs = [float(v) for v in args[args.index("--h") + 1].split(",")]
    if "--balls" in args:
        balls = [float(v) for v in args[args.index("--balls") + 1].split(",")]
    tmp = tempfile.mkdtemp(prefix="dg_goursat_")
    print("h, surfels, program time, then per ball (voxels): H L-oo, H L2")
    for h in hs:
        n = int(round(20 / h)) + 1
        k = np.arange(n) * h - 10
        z, y, x = np.meshgrid(k, k, k, indexing="ij")
        inside = (P(np.stack([x, y, z], -1)) <= 0).astype(np.uint8)
        img = vtkImageData()
        img.SetDimensions(n, n, n)
        img.SetOrigin(-10, -10, -10)
        img.SetSpacing(h, h, h)
        img.GetPointData().SetScalars(numpy_to_vtk(inside.ravel(), deep=1))
        vti = os.path.join(tmp, "goursat.vti")
        w = vtkXMLImageDataWriter()
        w.SetInputData(img)
        w.SetFileName(vti)
        w.Write()
        t0 = time.monotonic()
        p = subprocess.run([PROGRAM, vti, "--curvature", "--no-png", "--quiet", "--output-dir", tmp,
                            "--min-component", "0"] + extra, capture_output=True, text=True)
        dt = time.monotonic() - t0
        if p.returncode != 0:
            sys.exit(p.stderr)
        surface, truth, residual = read_with_truth(os.path.join(tmp, "goursat_surface.vtp"))
        row = ["%.3f" % h, "%d" % surface.GetNumberOfCells(), "%.1f s" % dt]
        ii = surface.GetCellData().GetArray("IIMeanCurvature")  # with -- --curvatures
        if ii is not None:
            e = np.abs(vtk_to_numpy(ii) - truth)
            row.append("II: %.4f %.4f" % (e.max(), np.sqrt((e ** 2).mean())))
        own = surface.GetCellData().GetArray("CorrectedMeanCurvature")
        e = np.abs(vtk_to_numpy(own) - truth)
        row.append("program: %.4f %.4f" % (e.max(), np.sqrt((e ** 2).mean())))
        for b in balls:
            f = vtkCorrectedCurvatureFilter()
            f.SetInputData(surface)
            f.SetInputArrayToProcess(0, 0, 0, 1, "SharpNormals")
            f.SetRadius(b)
            f.SetAdaptiveRadius(False)
            f.Update()
            H = vtk_to_numpy(f.GetOutput().GetCellData().GetArray("CorrectedMeanCurvature"))
            e = np.abs(H - truth)
            row.append("ball %g: %.4f %.4f" % (b, e.max(), np.sqrt((e ** 2).mean())))
        print(" | ".join(row), "(projection residual %.1e)" % residual, flush=True)


if __name__ == "__main__":
    main()
