#!/usr/bin/python3
"""Feature lines on the README's built-in shape against its analytic edges.

Usage (from the repository root, with the build tree in build/):

    /usr/bin/python3 Benchmarks/bench_builtin_features.py [--noise 0,0.3,0.5] [--seeds 1,2,3,4]

The built-in shape (Applications/dgBuiltinShape.cxx, 96^3) is a rotated
cube united with a sphere near one corner, minus a cylindrical hole through
the cube: besides the cube's convex edges it has concave circles (where the
sphere leaves the cube's faces) and the hole's rims, which the ground-truth
shapes of the tests do not have. For each noise level and seed the program
(build/bin/piecewise-normals --no-png, its defaults) writes its surface with
AT's arrays; the sharp-features filter then runs on that surface with each
setting compared (QuadricSides off and on, QuadricMergeFactor 0 and 3), and the lines are scored like
Testing/Cxx/dgFeatureMetrics.h scores them: precision = share of the
feature edges whose midpoint lies within 1.5 voxels of a true edge, recall =
share of the true edges (sampled every 0.15 voxel on the surface) with a
feature midpoint within 1.5 voxels. The true edges are where two of the
shape's pieces (6 cube faces, sphere, cylinder wall) meet, sampled on each
piece where it bounds the solid.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(ROOT, "build", "lib", "python3", "dist-packages"))

import digitalgeometry as dg  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkIdList, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStaticPointLocator  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader  # noqa: E402

N = 96  # the program's built-in size; the shape's constants are dgBuiltinShape.cxx's
C = 0.5 * (N - 1)
H, RS, RC = 0.26 * N, 0.22 * N, 0.12 * N


def rotation():
    ax, ay, az = (math.radians(a) for a in (20, 30, 10))
    cx, sx, cy, sy, cz, sz = (math.cos(ax), math.sin(ax), math.cos(ay), math.sin(ay),
                              math.cos(az), math.sin(az))
    return np.array([[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
                     [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
                     [-sy, cy * sx, cy * cx]])


def true_edges(step=0.15):
    """Samples of the true sharp edges, in index coordinates."""
    sc = np.full(3, 0.55 * H)
    cube = lambda q: np.all(np.abs(q) < H, axis=1)
    sphere = lambda q: np.sum((q - sc) ** 2, axis=1) < RS * RS
    hole = lambda q: q[:, 0] ** 2 + q[:, 1] ** 2 < RC * RC
    pts, lab = [], []
    g = np.arange(-H, H + 1e-9, step)
    u, v = (a.ravel() for a in np.meshgrid(g, g))
    for a in range(3):
        o = [b for b in range(3) if b != a]
        for s in (-1, 1):
            q = np.zeros((u.size, 3))
            q[:, a], q[:, o[0]], q[:, o[1]] = s * H, u, v
            keep = ~sphere(q) & ~hole(q)
            pts.append(q[keep])
            lab.append(np.full(keep.sum(), 2 * a + (s > 0)))
    for t in np.arange(0, math.pi, step / RS):
        ph = np.arange(0, 2 * math.pi, step / (RS * max(math.sin(t), 1e-3)))
        q = sc + RS * np.stack([math.sin(t) * np.cos(ph), math.sin(t) * np.sin(ph),
                                math.cos(t) * np.ones_like(ph)], 1)
        keep = ~cube(q) & ~hole(q)
        pts.append(q[keep])
        lab.append(np.full(keep.sum(), 6))
    ph, z = (a.ravel() for a in np.meshgrid(np.arange(0, 2 * math.pi, step / RC),
                                             np.arange(-3 * H, 3 * H, step)))
    q = np.stack([RC * np.cos(ph), RC * np.sin(ph), z], 1)
    keep = cube(q) | sphere(q)
    pts.append(q[keep])
    lab.append(np.full(keep.sum(), 7))
    x = np.concatenate(pts) @ rotation().T + C
    lab = np.concatenate(lab)
    # An edge sample has a sample of another piece within 0.35 voxel.
    loc = locator(x)
    ids = vtkIdList()
    edge = np.zeros(len(x), bool)
    for i in range(len(x)):
        loc.FindPointsWithinRadius(0.35, x[i], ids)
        edge[i] = any(lab[ids.GetId(k)] != lab[i] for k in range(ids.GetNumberOfIds()))
    return x[edge]


def locator(x):
    pd = vtkPolyData()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(np.ascontiguousarray(x, dtype=np.float64), deep=True))
    pd.SetPoints(p)
    loc = vtkStaticPointLocator()
    loc.SetDataSet(pd)
    loc.BuildLocator()
    loc._keep = pd  # the locator does not hold its data set
    return loc


def nearest(loc, ref, queries):
    out = np.empty(len(queries))
    for i, q in enumerate(queries):
        out[i] = np.linalg.norm(ref[loc.FindClosestPoint(q)] - q)
    return out


def score(edges, edge_loc, lines):
    p = vtk_to_numpy(lines.GetPoints().GetData())
    c = vtk_to_numpy(lines.GetLines().GetConnectivityArray()).reshape(-1, 2)
    m = 0.5 * (p[c[:, 0]] + p[c[:, 1]])
    if len(m) == 0:
        return 0.0, 0.0, 0
    precision = float(np.mean(nearest(edge_loc, edges, m) <= 1.5))
    recall = float(np.mean(nearest(locator(m), m, edges) <= 1.5))
    return precision, recall, len(m)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--noise", default="0,0.3,0.5")
    ap.add_argument("--seeds", default="1,2,3,4")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    edges = true_edges()
    edge_loc = locator(edges)
    print(f"built-in shape {N}^3: {len(edges)} true-edge samples; P / R per setting")
    env = dict(os.environ, VTK_SMP_BACKEND_IN_USE=os.environ.get("VTK_SMP_BACKEND_IN_USE", "STDThread"))
    settings = (("QuadricSides off", 0, 0.0), ("QuadricSides on", 1, 0.0),
                ("QuadricSides, QuadricMergeFactor 3", 1, 3.0))
    sums = {name: [0.0, 0.0, 0] for name, _, _ in settings}
    with tempfile.TemporaryDirectory() as tmp:
        for k in (float(s) for s in a.noise.split(",")):
            for seed in ([1] if k == 0 else [int(s) for s in a.seeds.split(",")]):
                out = os.path.join(tmp, f"k{k}s{seed}")
                cmd = [os.path.join(a.build, "bin", "piecewise-normals"), "--no-png", "--output-dir", out]
                if k > 0:
                    cmd += ["--noise", str(k), "--seed", str(seed)]
                r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
                if r.returncode != 0:
                    sys.exit(f"failed: {' '.join(cmd)}\n{r.stdout}")
                reader = vtkXMLPolyDataReader()
                reader.SetFileName(os.path.join(out, "builtin_surface.vtp"))
                reader.Update()
                row = []
                for name, q, qm in settings:
                    f = dg.vtkSharpFeaturesFilter()
                    f.SetInputData(reader.GetOutput())
                    f.SetQuadricSides(q)
                    f.SetQuadricMergeFactor(qm)
                    f.Update()
                    p, rc, n = score(edges, edge_loc, f.GetOutput(1))
                    row.append(f"{name}: P {p:.3f} R {rc:.3f} ({n} edges)")
                    s = sums[name]
                    s[0] += p
                    s[1] += rc
                    s[2] += 1
                print(f"k {k:.1f} seed {seed}  " + " | ".join(row), flush=True)
    print("mean  " + " | ".join(f"{name}: P {s[0] / s[2]:.3f} R {s[1] / s[2]:.3f}" for name, s in sums.items()))


if __name__ == "__main__":
    main()
