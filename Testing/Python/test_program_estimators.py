"""The program's --estimator ii|vcm|rht: each estimator's normals come out
(named, unit, right on flat faces), AT regularises the chosen field, its
feature lines lie on the box's edges, and bad estimator options are refused."""
import os
import subprocess
import sys
import tempfile

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataReader
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

PROGRAM = os.environ["DG_PROGRAM"]
ROOT = tempfile.mkdtemp(prefix="dg_estimators_", dir=os.environ.get("DG_TEST_TMP"))
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


# A box of voxels 8..31 in a 40^3 image: flat faces with known normals,
# twelve straight edges.
N, LO, HI = 40, 8, 31
a = np.zeros((N, N, N), np.uint8)
a[LO:HI + 1, LO:HI + 1, LO:HI + 1] = 1
img = vtkImageData()
img.SetDimensions(N, N, N)
img.GetPointData().SetScalars(numpy_to_vtk(a.ravel(), deep=1))
path = os.path.join(ROOT, "box.vti")
w = vtkXMLImageDataWriter()
w.SetInputData(img)
w.SetFileName(path)
w.Write()


def run(*args):
    out = tempfile.mkdtemp(dir=ROOT)
    p = subprocess.run([PROGRAM, "--quiet", "--no-png", "--output-dir", out] + list(args),
                       capture_output=True, text=True, timeout=600)
    return p, out


def read(out, name):
    r = vtkXMLPolyDataReader()
    r.SetFileName(os.path.join(out, name))
    r.Update()
    return r.GetOutput()


def angles(n, truth):
    return np.degrees(np.arccos(np.clip(np.sum(n * truth, axis=1), -1, 1)))


for est, name in [("ii", "IINormals"), ("vcm", "VCMNormals"), ("rht", "RHTNormals")]:
    p, out = run(path, "--estimator", est, "--plain")
    ok = p.returncode == 0
    check(ok, "--estimator %s runs (%s)" % (est, p.stderr.strip()[-200:]))
    if not ok:
        continue
    s = read(out, "box_surface.vtp")
    cd = s.GetCellData()
    n_in = cd.GetArray(name)
    check(n_in is not None and cd.GetNormals() is not None and cd.GetNormals().GetName() == "ATNormals",
          "%s: %s in the output, ATNormals active" % (est, name))
    if n_in is None:
        continue
    g = vtk_to_numpy(n_in)
    u = vtk_to_numpy(cd.GetArray("ATNormals"))
    check(np.allclose(np.linalg.norm(g, axis=1), 1, atol=1e-6), "%s: unit normals" % est)
    # Face interiors: surfels whose inside voxel is >= 5 voxels from every
    # edge of its face; the truth is the trivial (axis) normal.
    vox = vtk_to_numpy(cd.GetArray("InsideVoxel"))
    d = vtk_to_numpy(cd.GetArray("SurfelDirection")).astype(int)
    axis = d // 2
    other = np.stack([vox[np.arange(len(vox)), (axis + 1) % 3], vox[np.arange(len(vox)), (axis + 2) % 3]], 1)
    inner = np.all((other >= LO + 5) & (other <= HI - 5), axis=1)
    truth = vtk_to_numpy(cd.GetArray("Normals")).astype(float)
    e_in = np.median(angles(g[inner], truth[inner]))
    e_at = np.median(angles(u[inner], truth[inner]))
    check(e_in < 1.0 and e_at < 1.0,
          "%s: median error on the face interiors %.3f deg, after AT %.3f deg (< 1)" % (est, e_in, e_at))
    # AT's lines: their points' distance to the nearest box edge (the second
    # smallest distance to the six face planes).
    f = read(out, "box_features.vtp")
    pts = vtk_to_numpy(f.GetPoints().GetData()) if f.GetNumberOfPoints() else np.zeros((0, 3))
    used = np.unique(vtk_to_numpy(f.GetLines().GetConnectivityArray())) if f.GetNumberOfLines() else []
    q = pts[used]
    planes = np.concatenate([np.abs(q - (LO - 0.5)), np.abs(q - (HI + 0.5))], axis=1)
    dist = np.sort(planes, axis=1)[:, 1] if len(q) else np.zeros(0)
    p95 = float(np.percentile(dist, 95)) if len(dist) else float("inf")
    # II and RHT keep the edges: AT's lines sit on them. VCM rounds them over
    # a band of about its offset radius R = 10 (docs/vcm.md), and AT on VCM
    # leaves its lines along that band's sides (measured: 95 % within 4 voxels).
    bound = 2.0 if est != "vcm" else 5.0
    check(f.GetNumberOfLines() > 0 and p95 <= bound,
          "%s: %d feature edges, 95%% of their points within %.1f voxels of a box edge (<= %g)"
          % (est, f.GetNumberOfLines(), p95, bound))

for args, what in [(["--estimator", "pca"], "an unknown estimator"),
                   (["--estimator", "vcm", "--vcm-radii", "3", "5"], "VCM radii with r > R"),
                   (["--estimator", "rht", "--rht-trials", "0"], "0 RHT trials"),
                   (["--estimator", "rht", "--rht-radius", "-1"], "a negative RHT radius")]:
    p, out = run(path, *args)
    check(p.returncode == 2 and p.stderr.strip() != "" and not os.listdir(out),
          "%s is refused (exit %d: %s)" % (what, p.returncode, p.stderr.strip()[:120]))

print("%d failed" % len(failures))
sys.exit(1 if failures else 0)
