#!/usr/bin/python3
"""The piecewise-smooth mesh (issue 36) on ground-truth shapes: the program's
defaults (II -> AT -> sharp features) give the surface, vtkPiecewiseSmoothMeshFilter
moves its vertices; prints, per shape and noise, the vertex distance to the
true surface (mean / p99 / within 2 voxels of a true edge, voxels), the
mesh's own face normals against the true ones (mean degrees), the enclosed
volume against the truth, faces flipped against their field, and time.

    /usr/bin/python3 Benchmarks/bench_mesh.py [--size 64] [--shapes cube,torus] [--noise 0,0.3]
        [--param DataWeight=0.01 ...] [--vtk]

--vtk adds VTK's flying edges + windowed sinc (20 iterations, pass band 0.1)
on the same volumes. Needs the build's Python package on PYTHONPATH and the
program (DG_PROGRAM or build/bin/piecewise-normals)."""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkFiltersCore import vtkMassProperties, vtkTriangleFilter, vtkWindowedSincPolyDataFilter
from vtkmodules.vtkFiltersGeneral import vtkDiscreteFlyingEdges3D
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataReader

from digitalgeometry import vtkPiecewiseSmoothMeshFilter

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.environ.get("DG_PROGRAM", os.path.join(ROOT, "build", "bin", "piecewise-normals"))


def rotation(a, b, c):
    ca, sa, cb, sb, cc, sc = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cc, -sc, 0], [sc, cc, 0], [0, 0, 1]])
    return rz @ ry @ rx


def box(half, rot, radius=0.0):
    """Signed distance of a box (rounded by `radius`) rotated by rot."""
    half = np.asarray(half, float) - radius

    def f(x):
        q = np.abs(x @ rot) - half
        return (np.linalg.norm(np.maximum(q, 0), axis=-1) + np.minimum(q.max(-1), 0)) - radius
    return f


def sphere(r):
    return lambda x: np.linalg.norm(x, axis=-1) - r


def torus(a, b):
    return lambda x: np.sqrt((np.hypot(x[..., 0], x[..., 1]) - a) ** 2 + x[..., 2] ** 2) - b


def octahedron(s, rot):
    return lambda x: (np.abs(x @ rot).sum(-1) - s) / np.sqrt(3)


def intersect(f, g):
    return lambda x: np.maximum(f(x), g(x))


R1 = rotation(0.3, 0.5, 0.7)


def shapes(n):
    s = n / 64.0
    return {
        "cube": (box([18 * s] * 3, R1), True),
        "octahedron": (octahedron(26 * s, R1), True),
        "octahedron0": (octahedron(26.88 * s, np.eye(3)), True),
        "cubesphere": (intersect(box([18 * s] * 3, R1), sphere(24 * s)), True),
        "torus": (torus(19.2 * s, 10.24 * s), False),
        "sphere": (sphere(22 * s), False),
        "fillet": (box([22 * s, 16 * s, 12 * s], R1, 6 * s), False),
    }


def volume_of(f, n, centre):
    k = np.arange(n)
    z, y, x = np.meshgrid(k, k, k, indexing="ij")
    return (f(np.stack([x, y, z], -1) - centre) <= 0).astype(np.uint8)


def true_volume(f, n, centre, sub=4):
    # the volume of {f <= 0} by supersampling each voxel sub^3 times near the surface
    k = np.arange(n)
    z, y, x = np.meshgrid(k, k, k, indexing="ij")
    p = np.stack([x, y, z], -1) - centre
    d = f(p)
    inside = (d <= -1).sum()
    near = p[np.abs(d) < 1]
    o = (np.arange(sub) + 0.5) / sub - 0.5
    oz, oy, ox = np.meshgrid(o, o, o, indexing="ij")
    off = np.stack([ox, oy, oz], -1).reshape(-1, 3)
    frac = 0.0
    for i in range(0, len(near), 20000):
        q = near[i:i + 20000, None, :] + off[None]
        frac += (f(q) <= 0).sum() / len(off)
    return inside + frac


def gradient(f, x):
    e = 1e-4
    return np.stack([(f(x + e * np.eye(3)[a]) - f(x - e * np.eye(3)[a])) / (2 * e) for a in range(3)], -1)


def read(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def write_vti(inside, path):
    img = vtkImageData()
    n = inside.shape[0]
    img.SetDimensions(n, n, n)
    img.GetPointData().SetScalars(numpy_to_vtk(inside.ravel(), deep=1))
    w = vtkXMLImageDataWriter()
    w.SetInputData(img)
    w.SetFileName(path)
    w.Write()


def measure(mesh, f, centre, sharp):
    """Distances of the vertices to the true surface, and the faces' own
    normals (each polygon triangulated, area-weighted) against the true
    ones at their centres."""
    pts = vtk_to_numpy(mesh.GetPoints().GetData()).astype(float) - centre
    d = np.abs(f(pts)) / np.linalg.norm(gradient(f, pts), axis=1)
    t = vtkTriangleFilter()
    t.SetInputData(mesh)
    t.Update()
    tri = t.GetOutput()
    ids = vtk_to_numpy(tri.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    a, b, c = (pts[ids[:, i]] for i in range(3))
    vec = np.cross(b - a, c - a) / 2
    area = np.linalg.norm(vec, axis=1)
    nm = vec / np.maximum(area, 1e-300)[:, None]
    g = gradient(f, (a + b + c) / 3)
    g /= np.linalg.norm(g, axis=1)[:, None]
    ang = np.degrees(np.arccos(np.clip((nm * g).sum(1), -1, 1)))
    out = {"area": area, "mean": d.mean(), "p99": np.percentile(d, 99), "ang": (ang * area).sum() / area.sum(),
           "angp95": np.percentile(ang, 95)}
    if sharp:
        # vertices within 2 voxels of a true edge: where the gradient at the
        # closest point varies within 2 voxels (a probe at +-2 along axes)
        gg = gradient(f, pts)
        gg /= np.linalg.norm(gg, axis=1)[:, None]
        near = np.zeros(len(pts), bool)
        for ax in range(3):
            for sgn in (-2, 2):
                h = gradient(f, pts + sgn * np.eye(3)[ax])
                h /= np.linalg.norm(h, axis=1)[:, None]
                near |= (h * gg).sum(1) < np.cos(np.radians(20))
        out["edge"] = d[near].mean() if near.any() else float("nan")
    mp = vtkMassProperties()
    mp.SetInputData(tri)
    mp.Update()
    out["volume"] = mp.GetVolume()
    field = tri.GetCellData().GetArray("SharpNormals")
    if field is not None:
        fl = (nm * vtk_to_numpy(field)).sum(1) < 0
        out["flipped"] = 100 * area[fl].sum() / area.sum()
    return out


def vtk_pipeline(inside, dims=None):
    """VTK's usual surface of a segmentation, 3D Slicer's defaults:
    discrete flying edges, windowed sinc (20 iterations, pass band 0.1)."""
    n = inside.shape[0]
    img = vtkImageData()
    img.SetDimensions(*(dims if dims else (n, n, n)))
    img.GetPointData().SetScalars(numpy_to_vtk(inside.ravel(), deep=1))
    fe = vtkDiscreteFlyingEdges3D()
    fe.SetInputData(img)
    fe.SetValue(0, 1)
    ws = vtkWindowedSincPolyDataFilter()
    ws.SetInputConnection(fe.GetOutputPort())
    ws.SetNumberOfIterations(20)
    ws.SetPassBand(0.1)
    ws.NonManifoldSmoothingOn()
    ws.NormalizeCoordinatesOn()
    ws.Update()
    return ws.GetOutput()


def noisy_volume(inside, k, seed):
    """The program's noise and islands stages on a volume (the same voxels
    its --noise K --seed S run meshes)."""
    from digitalgeometry import vtkDigitalIslandFilter, vtkDigitalNoiseFilter
    n = inside.shape[0]
    img = vtkImageData()
    img.SetDimensions(n, n, n)
    img.GetPointData().SetScalars(numpy_to_vtk(inside.ravel(), deep=1))
    nf = vtkDigitalNoiseFilter()
    nf.SetInputData(img)
    nf.SetNoiseLevel(k)
    nf.SetSeed(seed)
    isl = vtkDigitalIslandFilter()
    isl.SetInputConnection(nf.GetOutputPort())
    isl.SetMinimumSize(8)
    isl.Update()
    return vtk_to_numpy(isl.GetOutput().GetPointData().GetScalars()).reshape(inside.shape).astype(np.uint8)


def main():
    n = int(sys.argv[sys.argv.index("--size") + 1]) if "--size" in sys.argv else 64
    names = sys.argv[sys.argv.index("--shapes") + 1].split(",") if "--shapes" in sys.argv else None
    noises = [float(v) for v in sys.argv[sys.argv.index("--noise") + 1].split(",")] if "--noise" in sys.argv else [0.0, 0.3]
    params = [a.split("=") for i, a in enumerate(sys.argv) if i > 0 and sys.argv[i - 1] == "--param"]
    cache = os.environ.get("DG_MESH_CACHE", os.path.join(tempfile.gettempdir(), "dg_mesh_cache"))
    os.makedirs(cache, exist_ok=True)
    print("shape n k mesh | vertex distance mean / p99 / near edges (voxels) | face normals (deg, area-weighted) | volume error % | flipped area %")
    for name, (f, sharp) in shapes(n).items():
        if names and name not in names:
            continue
        centre = (n - 1) / 2 + np.array([0.31, 0.17, 0.23])
        for noise in noises:
            tag = "%s%d_k%g" % (name, n, noise)
            surf = os.path.join(cache, tag + "_surface.vtp")
            inside = None
            if not os.path.exists(surf):
                inside = volume_of(f, n, centre)
                vti = os.path.join(cache, tag + ".vti")
                write_vti(inside, vti)
                cmd = [PROGRAM, vti, "--no-png", "--quiet", "--output-dir", cache]
                if noise:
                    cmd += ["--noise", str(noise), "--seed", "1"]
                p = subprocess.run(cmd, capture_output=True, text=True)
                if p.returncode != 0:
                    sys.exit(p.stderr)
            surface = read(surf)
            m = vtkPiecewiseSmoothMeshFilter()
            m.SetInputData(surface)
            m.SplitFeaturePointsOff()
            for k, v in params:
                getattr(m, "Set" + k)(int(v) if v.isdigit() else float(v))
            t0 = time.time()
            m.Update()
            dt = time.time() - t0
            vol = true_volume(f, n, centre)
            res = measure(m.GetOutput(), f, centre, sharp)
            base = measure(surface, f, centre, sharp)
            rows = [("digital surface", base), ("this stage", res)]
            if "--vtk" in sys.argv:
                inside = volume_of(f, n, centre)
                if noise:
                    inside = noisy_volume(inside, noise, 1)
                rows.append(("VTK (Slicer)", measure(vtk_pipeline(inside), f, centre, sharp)))
            for label, r in rows:
                print("%-10s %3d %.1f %-15s | %.3f / %.3f / %s | %.2f | %+.2f | %s" % (
                    name, n, noise, label, r["mean"], r["p99"],
                    "%.3f" % r["edge"] if "edge" in r else "-", r["ang"],
                    100 * (r["volume"] / vol - 1),
                    "%.2f" % r["flipped"] if "flipped" in r else "-"))
            print("%-10s %3d %.1f   time %.3f s, %d coordinates at the bound" % (
                name, n, noise, dt, m.GetNumberOfBoundCoordinates()))


if __name__ == "__main__":
    main()
