#!/usr/bin/python3
"""DGtal's DigitalSurfaceRegularization fed the program's SharpNormals, beside
vtkPiecewiseSmoothMeshFilter, on bench_mesh.py's ground-truth shapes, with
bench_mesh.py's metrics: vertex distance to the true surface (mean / p99 /
within 2 voxels of a true edge, voxels), the mesh's face normals against the
true ones (area-weighted mean / p95 degrees), enclosed volume against the
truth, faces whose normal is against the field (and their share of the area)
and time (median of 3; DGtal: regularize() alone, its init() in brackets).

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Benchmarks/dgtal-regularization/compare.py --driver build-dgtal-reg/dgtal_regularization \\
        [--size 64] [--shapes cube,torus] [--noise 0,0.3] [--big path/to/volume.vol]

The surfaces come from bench_mesh.py's cache (DG_MESH_CACHE or
/tmp/dg_mesh_cache; made here the same way when missing). --big runs the
program on a volume (cached beside the driver's files, in DG_REG_WORK or
/tmp/dg_reg_work) and prints time and peak memory of both mesh stages."""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import bench_mesh as bm  # noqa: E402  (shapes, volume_of, true_volume, gradient, measure, ...)

from digitalgeometry import vtkPiecewiseSmoothMeshFilter  # noqa: E402

EXPORT = os.path.join(HERE, "export_normals.py")


def arg(name, default):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def run_dgtal(driver, surf, prefix):
    """export_normals.py then the driver: its printed figures and its mesh."""
    subprocess.run([sys.executable, EXPORT, surf, prefix], check=True)
    p = subprocess.run([driver, prefix + ".vol", prefix + ".txt", "--obj", prefix + "_dgtal.obj", "--runs", "3"],
                       capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stdout + p.stderr)
    out = {}
    for line in p.stdout.splitlines():
        k, v = line.split(None, 1)
        out[k] = v
    return out, prefix + "_dgtal.obj"


def read_obj(path, surface):
    """The driver's OBJ as polydata, in the surface's world frame (the OBJ is in voxel indices)."""
    v, f = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("v "):
                v.append(line.split()[1:4])
            elif line.startswith("f "):
                f.append(line.split()[1:5])
    fd = surface.GetFieldData()
    origin = vtk_to_numpy(fd.GetArray("ImageOrigin")) if fd.GetArray("ImageOrigin") else np.zeros(3)
    spacing = vtk_to_numpy(fd.GetArray("ImageSpacing")) if fd.GetArray("ImageSpacing") else np.ones(3)
    pts = origin + spacing * np.array(v, float)
    quads = np.array(f, np.int64) - 1
    mesh = vtkPolyData()
    p = vtkPoints()
    p.SetData(numpy_to_vtk(pts, deep=1))
    mesh.SetPoints(p)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtk(np.arange(0, 4 * len(quads) + 1, 4, dtype=np.int64), deep=1),
                  numpy_to_vtk(quads.ravel(), deep=1))
    mesh.SetPolys(cells)
    return mesh


def module_mesh(surface, runs=3):
    times = []
    for _ in range(runs):
        m = vtkPiecewiseSmoothMeshFilter()
        m.SetInputData(surface)
        m.SplitFeaturePointsOff()  # as bench_mesh.py: one vertex per pointel, like DGtal
        t0 = time.time()
        m.Update()
        times.append(time.time() - t0)
    return m.GetOutput(), float(np.median(times))


def flipped(mesh, field):
    """Faces whose own (Newell) normal is against the field, and their share
    of the area: bench_mesh.py's count, computed here so that a change of
    what bench_mesh.measure returns does not change it."""
    pts = vtk_to_numpy(mesh.GetPoints().GetData()).astype(float)
    a, b, c, d = (pts[vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 4)[:, i]] for i in range(4))
    vec = np.cross(c - a, d - b) / 2
    area = np.linalg.norm(vec, axis=1)
    bad = (vec * field).sum(1) < 0
    return int(bad.sum()), 100 * area[bad].sum() / area.sum()


def row(label, mesh, field, f, centre, sharp, vol, t):
    res = bm.measure(mesh, f, centre, sharp)
    res = res[0] if isinstance(res, tuple) else res
    print("%-27s | %.3f / %.3f / %s | %.2f / %.2f | %+.2f | %d (%.2f %% of area) | %s" % (
        label, res["mean"], res["p99"], "%.3f" % res["edge"] if "edge" in res else "-",
        res["ang"], res.get("angp95", float("nan")), 100 * (res["volume"] / vol - 1), *flipped(mesh, field), t))


def shapes_table(driver, work):
    n = int(arg("--size", 64))
    names = arg("--shapes", None)
    names = names.split(",") if names else None
    noises = [float(v) for v in arg("--noise", "0,0.3").split(",")]
    cache = os.environ.get("DG_MESH_CACHE", os.path.join(tempfile.gettempdir(), "dg_mesh_cache"))
    os.makedirs(cache, exist_ok=True)
    print("shape       n  k   method   | dist mean / p99 / near edges | face normal mean / p95 deg "
          "| volume err % | flipped | s")
    for name, (f, sharp) in bm.shapes(n).items():
        if names and name not in names:
            continue
        centre = (n - 1) / 2 + np.array([0.31, 0.17, 0.23])  # bench_mesh.py's
        vol = bm.true_volume(f, n, centre)
        for noise in noises:
            tag = "%s%d_k%g" % (name, n, noise)
            surf = os.path.join(cache, tag + "_surface.vtp")
            if not os.path.exists(surf):  # as bench_mesh.py makes it
                vti = os.path.join(cache, tag + ".vti")
                bm.write_vti(bm.volume_of(f, n, centre), vti)
                cmd = [bm.PROGRAM, vti, "--no-png", "--quiet", "--output-dir", cache]
                if noise:
                    cmd += ["--noise", str(noise), "--seed", "1"]
                subprocess.run(cmd, check=True, capture_output=True)
            surface = bm.read(surf)
            field = vtk_to_numpy(surface.GetCellData().GetArray("SharpNormals"))
            mesh, t = module_mesh(surface)
            label = "%-11s %d %.1f" % (name, n, noise)
            row(label + " module", mesh, vtk_to_numpy(mesh.GetCellData().GetArray("SharpNormals")),
                f, centre, sharp, vol, "%.3f" % t)
            fig, obj = run_dgtal(driver, surf, os.path.join(work, tag))
            t = "%s (init %s)" % (fig["t_regularize"].split("median ")[1].split()[0], fig["t_init"].split()[0])
            row(label + " DGtal", read_obj(obj, surface), field, f, centre, sharp, vol, t)
            digital = bm.measure(surface, f, centre, sharp)
            digital = digital[0] if isinstance(digital, tuple) else digital
            print("%-27s | %.3f / %.3f / %s | (digital surface) | %+.2f" % (
                label + " digital", digital["mean"], digital["p99"],
                "%.3f" % digital["edge"] if "edge" in digital else "-", 100 * (digital["volume"] / vol - 1)))


MODULE_PEAK = """
import sys, time
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from digitalgeometry import vtkPiecewiseSmoothMeshFilter
def status(key):
    for line in open("/proc/self/status"):
        if line.startswith(key):
            return int(line.split()[1]) / 1024.0
r = vtkXMLPolyDataReader(); r.SetFileName(sys.argv[1]); r.Update()
times = []
rss0 = status("VmRSS")
open("/proc/self/clear_refs", "w").write("5")  # peak of the mesh stage alone, as the driver
for _ in range(3):
    m = vtkPiecewiseSmoothMeshFilter(); m.SetInputData(r.GetOutput()); m.SplitFeaturePointsOff()
    t0 = time.time(); m.Update(); times.append(time.time() - t0)
    del m
print("t_mesh %s median %.3f" % (" ".join("%.3f" % t for t in times), sorted(times)[1]))
print("rss_before %.1f MiB, peak_mesh %.1f MiB" % (rss0, status("VmHWM")))
"""


def big(driver, work, volume):
    base = os.path.splitext(os.path.basename(volume))[0]
    surf = os.path.join(work, base + "_surface.vtp")
    if not os.path.exists(surf):
        subprocess.run([bm.PROGRAM, volume, "--no-png", "--quiet", "--output-dir", work], check=True)
    surface = bm.read(surf)
    print("%s: %d surfels, %d points" % (base, surface.GetNumberOfCells(), surface.GetNumberOfPoints()))
    p = subprocess.run([sys.executable, "-c", MODULE_PEAK, surf], capture_output=True, text=True, check=True)
    print("module  " + p.stdout.strip().replace("\n", "\n        "))
    fig, _ = run_dgtal(driver, surf, os.path.join(work, base))
    print("DGtal   t_regularize %s; t_init %s; t_attach_normals %s; t_volume+surface %s;\n"
          "        rss_before_init %s, peak_init+regul %s, peak_process %s" % (
              fig["t_regularize"], fig["t_init"], fig["t_attach_normals"], fig["t_volume+surface"],
              fig["rss_before_init"], fig["peak_init+regul"], fig["peak_process"]))


def main():
    driver = os.path.abspath(arg("--driver", "build-dgtal-reg/dgtal_regularization"))
    work = os.environ.get("DG_REG_WORK", os.path.join(tempfile.gettempdir(), "dg_reg_work"))
    os.makedirs(work, exist_ok=True)
    if "--big" in sys.argv:
        big(driver, work, arg("--big", None))
    else:
        shapes_table(driver, work)


if __name__ == "__main__":
    main()
