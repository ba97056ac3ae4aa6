#!/usr/bin/python3
"""Which ball radius for the corrected curvature (issue 37): the program's
defaults (II -> AT -> sharp features) on shapes whose mean curvature is
known and varies (or not) over the surface, clean and at the paper's noise
k = 0.3 (islands removed as the program does), and the corrected mean
curvature of its SharpNormals for several ball radii (voxels). Prints, per
shape and radius, the relative L2 error RMS(H - H_true) / RMS(H_true) and
the relative L-oo error max |H - H_true| / max |H_true|, H_true at each face
centre's projection onto the implicit surface.

    /usr/bin/python3 Benchmarks/bench_curvature_radius.py [--balls 2,3,4,5,6,7,8] [--whole]

--whole: one region (PerSide off), to tell the ball's error from what the
sharp stage's lines on smooth shapes take away.

Needs the build's Python package on PYTHONPATH and the program (DG_PROGRAM
or build/bin/piecewise-normals)."""
import os
import subprocess
import sys
import tempfile

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkFiltersCore import vtkCellCenters
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataReader

from digitalgeometry import vtkCorrectedCurvatureFilter

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.environ.get("DG_PROGRAM", os.path.join(ROOT, "build", "bin", "piecewise-normals"))


def sphere(r):
    return lambda x: np.sqrt((x ** 2).sum(-1)) - r


def torus(a, b):
    return lambda x: np.sqrt((np.hypot(x[..., 0], x[..., 1]) - a) ** 2 + x[..., 2] ** 2) - b


def ellipsoid(ax):
    ax = np.array(ax, float)
    # a distance-like scale near the surface: (|x / ax| - 1) * min(ax)
    return lambda x: (np.sqrt(((x / ax) ** 2).sum(-1)) - 1) * ax.min()


def goursat(h):
    # DGtal's polynomial in world units, sampled in voxels of side h
    return lambda x: 0.03 * ((x * h) ** 4).sum(-1) - 2 * ((x * h) ** 2).sum(-1) - 8


def mean_curvature(f, c):
    """Projects the points onto f = 0 and returns H = div(grad f / |grad f|) / 2
    there, by central differences."""
    e = 1e-3
    eye = np.eye(3) * e

    def grad(x):
        return np.stack([(f(x + eye[a]) - f(x - eye[a])) / (2 * e) for a in range(3)], -1)

    x = c.copy()
    for _ in range(30):
        g = grad(x)
        x = x - (f(x) / (g * g).sum(-1))[:, None] * g
    div = sum((lambda gp, gm: (gp / np.linalg.norm(gp, axis=1)[:, None]
                               - gm / np.linalg.norm(gm, axis=1)[:, None])[:, a] / (2 * e))(
        grad(x + eye[a]), grad(x - eye[a])) for a in range(3))
    return div / 2


SHAPES = [
    ("sphere R 10", 30, sphere(10)),
    ("sphere R 25", 60, sphere(25)),
    ("torus 24, 10", 80, torus(24, 10)),
    ("ellipsoid 38, 24, 14", 88, ellipsoid((38, 24, 14))),
    ("goursat h 0.5", 41, goursat(0.5)),
    ("goursat h 0.25", 81, goursat(0.25)),
]


def program_surface(inside, noise, seed, tmp):
    """The program's default output surface (SharpNormals, FeatureRegion) of
    a cubic 0/1 volume, at noise k with that seed (k = 0: none), and the
    program's summary."""
    n = inside.shape[0]
    img = vtkImageData()
    img.SetDimensions(n, n, n)
    img.GetPointData().SetScalars(numpy_to_vtk(inside.ravel().astype(np.uint8), deep=1))
    vti = os.path.join(tmp, "shape.vti")
    w = vtkXMLImageDataWriter()
    w.SetInputData(img)
    w.SetFileName(vti)
    w.Write()
    cmd = [PROGRAM, vti, "--no-png", "--quiet", "--output-dir", tmp]
    if noise:
        cmd += ["--noise", str(noise), "--seed", str(seed)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr)
    r = vtkXMLPolyDataReader()
    r.SetFileName(os.path.join(tmp, "shape_surface.vtp"))
    r.Update()
    return r.GetOutput(), p.stdout


def main():
    balls = [2, 3, 4, 5, 6, 7, 8]
    if "--balls" in sys.argv:
        balls = [float(v) for v in sys.argv[sys.argv.index("--balls") + 1].split(",")]
    tmp = tempfile.mkdtemp(prefix="dg_radius_")
    print("relative L2 / relative L-oo error of H per ball radius (voxels)")
    print("shape, noise | " + " | ".join("ball %g" % b for b in balls))
    for name, n, f in SHAPES:
        for noise, seed in ((0, 0), (0.3, 1)):
            centre = (n - 1) / 2 + np.array([0.31, 0.17, 0.23])
            k = np.arange(n)
            z, y, x = np.meshgrid(k, k, k, indexing="ij")
            inside = (f(np.stack([x, y, z], -1) - centre) <= 0).astype(np.uint8)
            surface, summary = program_surface(inside, noise, seed, tmp)
            cc = vtkCellCenters()
            cc.SetInputData(surface)
            cc.Update()
            c = vtk_to_numpy(cc.GetOutput().GetPoints().GetData()).astype(float) - centre
            truth = mean_curvature(f, c)
            row = []
            for b in balls:
                cf = vtkCorrectedCurvatureFilter()
                cf.SetInputData(surface)
                cf.SetRadius(b)
                # One ball for every face: the radius per face (the filter's
                # default) is bench_adaptive_radius.py's subject.
                cf.SetAdaptiveRadius(False)
                cf.SetPerSide("--whole" not in sys.argv)
                cf.Update()
                H = vtk_to_numpy(cf.GetOutput().GetCellData().GetArray("CorrectedMeanCurvature"))
                e = H - truth
                row.append("%.3f / %.3f" % (np.sqrt((e ** 2).mean() / (truth ** 2).mean()),
                                           np.abs(e).max() / np.abs(truth).max()))
            lines = summary.split(" feature edges")[0].rsplit(" ", 1)[-1]
            print("%s, k %g (%s lines) | %s" % (name, noise, lines, " | ".join(row)), flush=True)


if __name__ == "__main__":
    main()
