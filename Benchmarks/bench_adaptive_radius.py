#!/usr/bin/python3
"""The corrected curvature's ball radius per face (AdaptiveRadius) against
one ball of 6 voxels, on what issue 37 asks and on the shapes of
bench_curvature_radius.py, all through the program's defaults (II -> AT ->
sharp features; islands removed as the program does):

- noisy spheres (k = 0.3, seeds 1 and 2, radius 10, 15, 25, 50 voxels, the
  layout of TestCorrectedCurvatureFilter.NoisySpheres): median |H R - 1|;
- clean spheres (radius 10, 25, 50, TestCorrectedCurvatureFilter.Spheres):
  median H R and K R^2;
- bench_curvature_radius.py's shapes, clean and k = 0.3: relative L2 / L-oo
  error of H (per side, and with --whole as one region);
- the radius the rule chose (10th / 50th / 90th percentile, voxels).

    /usr/bin/python3 Benchmarks/bench_adaptive_radius.py [--whole] [--quick]

--quick: the spheres only. Needs the build's Python package on PYTHONPATH
and the program (DG_PROGRAM or build/bin/piecewise-normals)."""
import os
import sys
import tempfile

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkCellCenters

from digitalgeometry import vtkCorrectedCurvatureFilter

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_curvature_radius as shapes  # noqa: E402

PROGRAM = shapes.PROGRAM
TMP = tempfile.mkdtemp(prefix="dg_adaptive_")


def grid(n):
    k = np.arange(n)
    z, y, x = np.meshgrid(k, k, k, indexing="ij")
    return np.stack([x, y, z], -1).astype(float)


def surface(inside, noise, seed):
    """The program's surface (SharpNormals, FeatureRegion) of a 0/1 volume."""
    return shapes.program_surface(inside, noise, seed, TMP)[0]


def curvature(s, adaptive, whole=False):
    f = vtkCorrectedCurvatureFilter()
    f.SetInputData(s)
    f.SetAdaptiveRadius(adaptive)
    f.SetPerSide(not whole)
    f.Update()
    cd = f.GetOutput().GetCellData()
    return {k: vtk_to_numpy(cd.GetArray(a)).copy() for k, a in (
        ("H", "CorrectedMeanCurvature"), ("G", "CorrectedGaussianCurvature"), ("r", "CorrectedBallRadius"))}


def radii(o):
    return "%.1f / %.1f / %.1f" % tuple(np.percentile(o["r"], [10, 50, 90]))


def sphere(radius, margin, noise, seed):
    n = int(2 * radius + margin)
    c = np.array([n / 2 + 0.3, n / 2 + 0.1, n / 2 + 0.2])
    return surface(np.sqrt(((grid(n) - c) ** 2).sum(-1)) <= radius, noise, seed)


def main():
    whole = "--whole" in sys.argv
    print("noisy spheres (k 0.3): median |H R - 1|, one ball of 6 -> a radius per face (its radii)")
    for radius in (10, 15, 25, 50):
        for seed in (1, 2):
            s = sphere(radius, 10, 0.3, seed)
            fixed, adaptive = curvature(s, False), curvature(s, True)
            print("  R %2d seed %d: %.4f -> %.4f (%s)" % (
                radius, seed, np.median(np.abs(fixed["H"] * radius - 1)),
                np.median(np.abs(adaptive["H"] * radius - 1)), radii(adaptive)), flush=True)
    print("clean spheres: median H R, K R^2, one ball of 6 -> a radius per face (its radii)")
    for radius in (10, 25, 50):
        s = sphere(radius, 8, 0, 0)
        fixed, adaptive = curvature(s, False), curvature(s, True)
        print("  R %2d: %.4f, %.4f -> %.4f, %.4f (%s)" % (
            radius, np.median(fixed["H"] * radius), np.median(fixed["G"] * radius ** 2),
            np.median(adaptive["H"] * radius), np.median(adaptive["G"] * radius ** 2), radii(adaptive)),
            flush=True)
    if "--quick" in sys.argv:
        return
    print("bench_curvature_radius's shapes%s: relative L2 / L-oo of H, one ball of 6 -> a radius per face"
          % (", one region" if whole else ", per side"))
    worst = [0, 0]
    for name, n, f in shapes.SHAPES:
        for noise, seed in ((0, 0), (0.3, 1)):
            centre = (n - 1) / 2 + np.array([0.31, 0.17, 0.23])
            s = surface(f(grid(n) - centre) <= 0, noise, seed)
            cc = vtkCellCenters()
            cc.SetInputData(s)
            cc.Update()
            truth = shapes.mean_curvature(f, vtk_to_numpy(cc.GetOutput().GetPoints().GetData()) - centre)
            row = []
            for k, adaptive in enumerate((False, True)):
                o = curvature(s, adaptive, whole)
                e = o["H"] - truth
                l2 = np.sqrt((e ** 2).mean() / (truth ** 2).mean())
                row.append("%.3f / %.3f" % (l2, np.abs(e).max() / np.abs(truth).max()))
                if name != "goursat h 0.5":
                    worst[k] = max(worst[k], l2)
            print("  %s, k %g: %s -> %s (%s)" % (name, noise, row[0], row[1], radii(o)), flush=True)
    print("worst relative L2 (goursat h 0.5 left out, as in bench_curvature_radius): %.3f -> %.3f"
          % tuple(worst))


if __name__ == "__main__":
    main()
