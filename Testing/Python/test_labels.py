"""Label maps in one run (piecewise-normals --labels): a 3-label NIfTI map
whose labels touch each other and the background. Every label's part of the
--labels output must equal a one-label run on the whole volume (--label L):
the same surfels (voxel and direction), points, normals and feature edges,
which is also the proof that each label's box (plus the estimator's reach)
gives the whole volume's result. Then the label specs and the bad inputs."""
import os
import subprocess
import sys
import tempfile

import nibabel as nib
import numpy as np
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy

PROGRAM = os.environ["DG_PROGRAM"]
ROOT = tempfile.mkdtemp(prefix="dg_labels_", dir=os.environ.get("DG_TEST_TMP"))
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def run(*args):
    out = tempfile.mkdtemp(dir=ROOT)
    p = subprocess.run([PROGRAM, "--quiet", "--no-png", "--output-dir", out, "--prefix", "m"] + list(args),
                       capture_output=True, text=True, timeout=600)
    return p, out


def read(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


# The map: label 2 a box on the background, label 5 a ball pressed into it
# (they share faces), label 9 a small slab touching both; spacing and an
# oblique affine so that the world positions are not the indices.
n = (40, 36, 32)
k, j, i = np.meshgrid(np.arange(n[2]), np.arange(n[1]), np.arange(n[0]), indexing="ij")
data = np.zeros((n[2], n[1], n[0]), np.int16)
data[(i >= 4) & (i <= 22) & (j >= 5) & (j <= 28) & (k >= 4) & (k <= 20)] = 2
data[(i - 27.3) ** 2 + (j - 17.6) ** 2 + (k - 15.2) ** 2 <= 8.5 ** 2] = 5
data[(i >= 12) & (i <= 30) & (j >= 26) & (j <= 31) & (k >= 18) & (k <= 24)] = 9
c, s = np.cos(0.3), np.sin(0.3)
affine = np.array([[0.8 * c, -0.9 * s, 0, 10], [0.8 * s, 0.9 * c, 0, -20], [0, 0, 1.2, 30], [0, 0, 0, 1]])
img = nib.Nifti1Image(np.transpose(data, (2, 1, 0)), affine)  # nibabel's axes are i, j, k
img.set_sform(affine, code=1)
path = os.path.join(ROOT, "map.nii.gz")
nib.save(img, path)

p, out = run(path, "--labels", "all")
check(p.returncode == 0, "--labels all runs (%s)" % p.stderr.strip())
if p.returncode == 0:
    check("3 labels" in p.stdout and "label 5:" in p.stdout, "the summary names the labels: %s" % p.stdout.strip())
    allS, allF = read(os.path.join(out, "m_surface.vtp")), read(os.path.join(out, "m_features.vtp"))
    lab = vtk_to_numpy(allS.GetCellData().GetArray("Label"))
    check(sorted(set(lab.tolist())) == [2, 5, 9], "the Label cell array holds 2, 5 and 9")
    flab = vtk_to_numpy(allF.GetCellData().GetArray("Label"))
    pts = vtk_to_numpy(allS.GetPoints().GetData())
    conn = vtk_to_numpy(allS.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    for L in (2, 5, 9):
        q, out1 = run(path, "--label", str(L))
        check(q.returncode == 0, "--label %d runs" % L)
        if q.returncode != 0:
            continue
        one, oneF = read(os.path.join(out1, "m_surface.vtp")), read(os.path.join(out1, "m_features.vtp"))
        sel = np.nonzero(lab == L)[0]
        key = lambda vox, d: [tuple(v) + (int(x),) for v, x in zip(vox, d)]
        cd, ocd = allS.GetCellData(), one.GetCellData()
        mine = key(vtk_to_numpy(cd.GetArray("InsideVoxel"))[sel], vtk_to_numpy(cd.GetArray("SurfelDirection"))[sel])
        ref = key(vtk_to_numpy(ocd.GetArray("InsideVoxel")), vtk_to_numpy(ocd.GetArray("SurfelDirection")))
        check(mine == ref, "label %d: the same %d surfels, in the same order" % (L, len(ref)))
        if mine != ref:
            continue
        opts = vtk_to_numpy(one.GetPoints().GetData())
        oconn = vtk_to_numpy(one.GetPolys().GetConnectivityArray()).reshape(-1, 4)
        dp = np.abs(pts[conn[sel]] - opts[oconn]).max()
        check(dp <= 1e-9, "label %d: the same world corners (max %.1e)" % (L, dp))
        for name in ("IINormals", "ATNormals", "SharpNormals"):
            d = np.abs(vtk_to_numpy(cd.GetArray(name))[sel] - vtk_to_numpy(ocd.GetArray(name))).max()
            check(d <= 1e-9, "label %d: %s equal (max %.1e)" % (L, name, d))
        nl = int((flab == L).sum())
        # The ball (5) is whole and smooth: no feature; the boxes have edges.
        check(nl == oneF.GetNumberOfLines() and (nl > 0) == (L != 5),
              "label %d: %d feature edges, one-label run %d" % (L, nl, oneF.GetNumberOfLines()))

# --interfaces: every face between two different values (the grid's outside
# is 0) once, oriented out of the larger label, II normals of that label's
# own surface, and AT on the one non-manifold complex, whose lines where
# three labels meet must come out as features.
p, out = run(path, "--labels", "all", "--interfaces")
check(p.returncode == 0, "--labels all --interfaces runs (%s)" % p.stderr.strip())
if p.returncode == 0:
    S = read(os.path.join(out, "m_surface.vtp"))
    cd = S.GetCellData()
    ins, outs = vtk_to_numpy(cd.GetArray("LabelInside")), vtk_to_numpy(cd.GetArray("LabelOutside"))
    padded = np.pad(data, 1)
    expected = sum(int((np.diff(padded, axis=a) != 0).sum()) for a in range(3))
    check(S.GetNumberOfCells() == expected, "each interface face once: %d faces, %d expected"
          % (S.GetNumberOfCells(), expected))
    check(bool(np.all(ins > outs)) and set(ins.tolist()) <= {2, 5, 9},
          "LabelInside > LabelOutside on every face")
    pairs = {(a, b) for a, b in zip(ins.tolist(), outs.tolist())}
    check(pairs == {(2, 0), (5, 0), (9, 0), (5, 2), (9, 2), (9, 5)}, "every pair of touching labels: %s" % sorted(pairs))
    vox = vtk_to_numpy(cd.GetArray("InsideVoxel"))
    d = vtk_to_numpy(cd.GetArray("SurfelDirection"))
    keys = set(map(tuple, np.column_stack([vox, d]).tolist()))
    check(len(keys) == S.GetNumberOfCells(), "no face twice")
    # Edges and their faces; the lines where 3 or more labels meet.
    quads = vtk_to_numpy(S.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    edges = {}
    for f, q in enumerate(quads):
        for a, b in zip(q, np.roll(q, -1)):
            edges.setdefault((min(a, b), max(a, b)), []).append(f)
    triple = [e for e, fs in edges.items() if len(set(ins[fs].tolist()) | set(outs[fs].tolist())) >= 3]
    v = vtk_to_numpy(S.GetPointData().GetArray("ATFeatureIndicator"))
    featured = sum(1 for a, b in triple if v[a] < 0.5 and v[b] < 0.5)
    check(len(triple) > 50 and featured >= 0.9 * len(triple),
          "the lines where 3 labels meet are features: %d of %d edges" % (featured, len(triple)))
    # Away from those lines a face keeps the II normal of its inside label's
    # own surface: label 2's faces on the background against --labels 2.
    p2, out2 = run(path, "--labels", "2")
    if p2.returncode == 0:
        one = read(os.path.join(out2, "m_surface.vtp"))
        ocd = one.GetCellData()
        ref = {k: n for k, n in zip(map(tuple, np.column_stack([vtk_to_numpy(ocd.GetArray("InsideVoxel")),
                                                              vtk_to_numpy(ocd.GetArray("SurfelDirection"))]).tolist()),
                                    vtk_to_numpy(ocd.GetArray("IINormals")))}
        sel = np.nonzero((ins == 2) & (outs == 0))[0]
        ii = vtk_to_numpy(cd.GetArray("IINormals"))
        dmax = max(np.abs(ii[f] - ref[tuple(vox[f].tolist()) + (int(d[f]),)]).max() for f in sel)
        check(dmax == 0, "II normals of label 2's background faces equal its own run's (max %.1e)" % dmax)
p, _ = run(path, "--interfaces")
check(p.returncode == 2, "--interfaces without --labels: exit 2")

# Lists and ranges; a label that is not there; bad specs and combinations.
p, out = run(path, "--labels", "2,7-9")
if p.returncode == 0:
    lab = vtk_to_numpy(read(os.path.join(out, "m_surface.vtp")).GetCellData().GetArray("Label"))
    check(sorted(set(lab.tolist())) == [2, 9], "--labels 2,7-9 gives labels 2 and 9")
else:
    check(False, "--labels 2,7-9 runs: %s" % p.stderr)
p, _ = run(path, "--labels", "42")
check(p.returncode == 1 and "42" not in p.stdout and "2, 5, 9" in p.stderr,
      "an absent label: exit 1 and the labels there (%s)" % p.stderr.strip())
for args, what in ((["--labels", "5-2"], "a reversed range"), (["--labels", "a,b"], "not a number"),
                   (["--labels", "all", "--label", "2"], "with --label"),
                   (["--labels", "all", "--noise", "0.2"], "with --noise")):
    p, _ = run(path, *args)
    check(p.returncode == 2 and p.stderr.count("\n") == 1, "%s: exit 2, one line (%s)" % (what, p.stderr.strip()))
real = np.zeros((12, 12, 12), np.float32)
real[3:8, 3:8, 3:8] = 0.5
rpath = os.path.join(ROOT, "real.nii.gz")
nib.save(nib.Nifti1Image(real, np.eye(4)), rpath)
p, _ = run(rpath, "--labels", "all")
check(p.returncode == 1 and "not an integer" in p.stderr, "a non-integer volume: exit 1 (%s)" % p.stderr.strip())

print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
