"""vtkNIfTIVolumeReader and the program on NIfTI volumes written by nibabel
with known geometry: oblique directions with det +1 and det -1 (qfac -1),
anisotropic spacing, non-zero origin. The digital surface's points must sit
at the analytic world positions of the voxel corners (LPS by default, RAS on
request), its quads face outward in world space, the sform wins over the
qform as in nibabel, a sheared sform is refused, a header without either
gives the voxel size with a warning, and sub-extents and pieces (with ghost
layers) are the boxes of the whole read with its geometry."""
import os
import subprocess
import sys
import tempfile

import numpy as np
import nibabel as nib
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonExecutionModel import vtkAlgorithm, vtkExtentTranslator
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy

from digitalgeometry import vtkDigitalSurfaceFilter, vtkNIfTIVolumeReader

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


TMP = os.environ.get("DG_TEST_TMP") or tempfile.mkdtemp()
os.makedirs(TMP, exist_ok=True)
LPS = np.diag([-1.0, -1.0, 1.0])

# A box of voxels 5..17 x 6..16 x 4..14 in a 24 x 24 x 20 image.
data = np.zeros((24, 24, 20), np.uint8)
data[5:18, 6:17, 4:15] = 1
n_box = 2 * (13 * 11 + 13 * 11 + 11 * 11)


def affine(flip, spacing=(0.7, 0.9, 1.5), offset=(10.0, -20.0, 30.0)):
    c, s = np.cos(np.radians(37)), np.sin(np.radians(37))
    R = np.array([[c, -s, 0], [s * 0.8, c * 0.8, 0.6], [-s * 0.6, -c * 0.6, 0.8]])
    R[:, 2] *= flip
    A = np.eye(4)
    A[:3, :3] = R * np.array(spacing)
    A[:3, 3] = offset
    return A


def write(name, qform, sform, qcode=1, scode=1):
    img = nib.Nifti1Image(data, sform if sform is not None else qform)
    img.set_qform(qform, code=qcode)
    img.set_sform(sform if sform is not None else qform, code=scode)
    path = os.path.join(TMP, name)
    nib.save(img, path)
    return path


def stored(path, which):
    """The transform as the file stores it (float32 fields), in float64."""
    img = nib.load(path)
    return img.get_sform() if which == "sform" else img.get_qform()


class Errors:
    def __init__(self):
        self.errors, self.warnings = [], []

    def watch(self, obj):
        obj.AddObserver(vtkCommand.ErrorEvent, lambda o, e: self.errors.append(e))
        obj.AddObserver(vtkCommand.WarningEvent, lambda o, e: self.warnings.append(e))


def surface(path, ras=False):
    r = vtkNIfTIVolumeReader()
    seen = Errors()
    seen.watch(r)
    r.SetFileName(path)
    if ras:
        r.SetCoordinateSystemToRAS() if hasattr(r, "SetCoordinateSystemToRAS") else r.SetCoordinateSystem(1)
    s = vtkDigitalSurfaceFilter()
    s.SetInputConnection(r.GetOutputPort())
    s.Update()
    return r, s.GetOutput(), seen


def corner_error(pd, A, to_world):
    """Largest distance (in units of the smallest spacing) between a surface
    point and the nearest analytic voxel corner position, and whether every
    point maps back to a half-integer index."""
    pts = vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
    ras = pts @ to_world.T  # back to RAS (to_world is its own inverse)
    idx = (np.linalg.inv(A) @ np.c_[ras, np.ones(len(ras))].T).T[:, :3]
    corner = np.round(idx + 0.5) - 0.5
    world = (A @ np.c_[corner, np.ones(len(corner))].T).T[:, :3] @ to_world.T
    spacing = np.linalg.norm(A[:3, :3], axis=0).min()
    return np.abs(world - pts).max() / spacing, corner


def outward(pd):
    """Share of quads whose normal (right-hand rule) points away from the
    box's centroid, in world coordinates."""
    pts = vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
    conn = vtk_to_numpy(pd.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    q = pts[conn]
    n = np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 1])
    centre = pts.mean(axis=0)
    return np.mean(np.einsum("ij,ij->i", n, q.mean(axis=1) - centre) > 0)


for flip in (1, -1):
    A = affine(flip)
    path = write("oblique%+d.nii.gz" % flip, A, A)
    A = stored(path, "sform")
    for ras in (False, True):
        r, pd, seen = surface(path, ras)
        to_world = np.eye(3) if ras else LPS
        err, corner = corner_error(pd, A, to_world)
        what = "det %+d, %s" % (flip, "RAS" if ras else "LPS")
        check(not seen.errors and pd.GetNumberOfPolys() == n_box,
              "%s: the box's %d quads (%d)" % (what, n_box, pd.GetNumberOfPolys()))
        check(err < 1e-6, "%s: points at the analytic corner positions (max error %.2g spacing)" % (what, err))
        lo, hi = corner.min(axis=0), corner.max(axis=0)
        check(np.allclose(lo, [4.5, 5.5, 3.5]) and np.allclose(hi, [17.5, 16.5, 14.5]),
              "%s: the corners span the box's index range (%s .. %s)" % (what, lo, hi))
        share = outward(pd)
        check(share == 1.0, "%s: every quad faces outward in world space (%.3f)" % (what, share))
        check(r.GetGeometrySource() == 2, "%s: the sform was used" % what)

# sform against qform: the sform wins when its code is > 0, else the qform.
A, B = affine(1), affine(1, offset=(-5.0, 7.0, 2.0))
both = write("both.nii.gz", A, B)
r, pd, seen = surface(both)
err_b, _ = corner_error(pd, stored(both, "sform"), LPS)
check(r.GetGeometrySource() == 2 and err_b < 1e-6, "sform code 1 wins over the qform (error %.2g)" % err_b)
qonly = write("qonly.nii.gz", A, B, qcode=1, scode=0)
r, pd, seen = surface(qonly)
err_a, _ = corner_error(pd, stored(qonly, "qform"), LPS)
check(r.GetGeometrySource() == 1 and err_a < 1e-6, "sform code 0: the qform is used (error %.2g)" % err_a)

# A sheared sform is refused with a clear error and an empty output.
S = affine(1)
S[:3, 1] += 0.3 * S[:3, 0]
sheared = write("sheared.nii.gz", affine(1), S)
r, pd, seen = surface(sheared)
check(seen.errors and pd.GetNumberOfPolys() == 0, "sheared sform: error, empty output")
check(r.GetErrorCode() is not None, "sheared sform: reported")

# No qform, no sform: voxel size only, with a warning.
bare = write("bare.nii.gz", affine(1), affine(1), qcode=0, scode=0)
r, pd, seen = surface(bare)
check(r.GetGeometrySource() == 0 and seen.warnings and pd.GetNumberOfPolys() == n_box,
      "no qform or sform: a warning, the box in index space scaled by pixdim")

# Sub-extents and pieces: every box is the same box of the whole read, with
# the whole read's origin, spacing and direction (int16 labels, qfac -1 so
# that the slices are reversed on reading).
rng = np.random.default_rng(7)
labels = rng.integers(-3, 9, size=(21, 17, 13)).astype(np.int16)
lab_path = os.path.join(TMP, "labels.nii.gz")
img = nib.Nifti1Image(labels, affine(-1))
img.set_qform(affine(-1), code=1)
img.set_sform(affine(-1), code=0)
nib.save(img, lab_path)


def read(request=None):
    r = vtkNIfTIVolumeReader()
    seen = Errors()
    seen.watch(r)
    r.SetFileName(lab_path)
    if request is None:
        r.Update()
    elif len(request) == 6:
        r.UpdateExtent(request)
    else:
        r.UpdatePiece(*request)
    return r, seen


def voxels(image):
    e = image.GetExtent()
    shape = (e[5] - e[4] + 1, e[3] - e[2] + 1, e[1] - e[0] + 1)
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(shape)


def geometry(image):
    d = image.GetDirectionMatrix()
    return (image.GetOrigin(), image.GetSpacing(), tuple(d.GetElement(a, b) for a in range(3) for b in range(3)))


whole_r, seen = read()
whole = voxels(whole_r.GetOutput())
we = whole_r.GetOutput().GetExtent()
check(not seen.errors and we == (0, 20, 0, 16, 0, 12), "labels: whole read, extent %s" % (we,))
check(whole_r.GetOutputInformation(0).Get(vtkAlgorithm.CAN_PRODUCE_SUB_EXTENT()) == 1,
      "the reader says it produces sub-extents")
boxes = [(3, 15, 2, 9, 4, 7), (0, 20, 0, 16, 0, 3), (0, 5, 10, 16, 6, 12), (15, 20, 0, 16, 0, 12),
         (7, 7, 0, 16, 0, 12), (0, 20, 16, 16, 0, 12), (2, 18, 3, 13, 12, 12), (20, 20, 16, 16, 12, 12),
         (0, 0, 0, 0, 0, 0)]
ok_boxes = []
for box in boxes:
    r, seen = read(box)
    out = r.GetOutput()
    i0, i1, j0, j1, k0, k1 = box
    ok_boxes.append(not seen.errors and out.GetExtent() == box and
                    geometry(out) == geometry(whole_r.GetOutput()) and
                    np.array_equal(voxels(out), whole[k0:k1 + 1, j0:j1 + 1, i0:i1 + 1]) and
                    out.GetPointData().GetArray("vtkGhostType") is None)
check(all(ok_boxes), "%d sub-extents (border, one voxel thick, single voxel) equal the whole read's boxes, "
      "same geometry (%s)" % (len(boxes), ok_boxes))
ok_pieces, n_pieces = [], 0
for n in (2, 3, 4):
    for ghosts in (0, 1, 2):
        for p in range(n):
            expected, own = [0] * 6, [0] * 6
            vtkExtentTranslator().PieceToExtentThreadSafe(p, n, ghosts, list(we), expected, vtkExtentTranslator.BLOCK_MODE, 0)
            vtkExtentTranslator().PieceToExtentThreadSafe(p, n, 0, list(we), own, vtkExtentTranslator.BLOCK_MODE, 0)
            r, seen = read((p, n, ghosts))
            out = r.GetOutput()
            e = out.GetExtent()
            good = not seen.errors and e == tuple(expected) and geometry(out) == geometry(whole_r.GetOutput())
            good = good and np.array_equal(voxels(out), whole[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1])
            ghost = out.GetPointData().GetArray("vtkGhostType")
            if ghosts == 0:
                good = good and ghost is None
            else:
                g = vtk_to_numpy(ghost).reshape(voxels(out).shape) != 0
                k, j, i = np.meshgrid(np.arange(e[4], e[5] + 1), np.arange(e[2], e[3] + 1),
                                      np.arange(e[0], e[1] + 1), indexing="ij")
                inside = ((i >= own[0]) & (i <= own[1]) & (j >= own[2]) & (j <= own[3]) &
                          (k >= own[4]) & (k <= own[5]))
                good = good and np.array_equal(g, ~inside)
            ok_pieces.append(good)
            n_pieces += 1
check(all(ok_pieces), "%d pieces (2, 3, 4 pieces, 0-2 ghost layers): the executive's extents, the whole read's "
      "voxels, vtkGhostType on exactly the ghost layers" % n_pieces)
# One reader, several requests in turn: each re-reads its own box.
r = vtkNIfTIVolumeReader()
r.SetFileName(lab_path)
seq_ok = []
for box in boxes[:4]:
    r.UpdateExtent(box)
    i0, i1, j0, j1, k0, k1 = box
    out = r.GetOutput()
    # The executive may keep a larger earlier result that holds the box.
    e = out.GetExtent()
    holds = e[0] <= i0 and e[1] >= i1 and e[2] <= j0 and e[3] >= j1 and e[4] <= k0 and e[5] >= k1
    seq_ok.append(holds and np.array_equal(voxels(out), whole[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1]))
check(all(seq_ok), "one reader, successive sub-extents: right voxels each time (%s)" % seq_ok)

# The program on a .nii.gz: the written surface is in LPS.
program = os.environ.get("DG_PROGRAM")
if program:
    out = tempfile.mkdtemp(dir=TMP)
    p = subprocess.run([program, "--quiet", "--no-png", "--output-dir", out,
                        os.path.join(TMP, "oblique-1.nii.gz")], capture_output=True, text=True, timeout=300)
    check(p.returncode == 0, "the program reads .nii.gz (exit %d: %s)" % (p.returncode, p.stderr.strip()[-200:]))
    rd = vtkXMLPolyDataReader()
    rd.SetFileName(os.path.join(out, "oblique-1_surface.vtp"))
    rd.Update()
    ref = stored(os.path.join(TMP, "oblique-1.nii.gz"), "sform")
    err, _ = corner_error(rd.GetOutput(), ref, LPS) if rd.GetOutput().GetNumberOfPoints() else (1e9, None)
    check(err < 1e-6, "the program's surface is in LPS at the analytic positions (error %.2g)" % err)
    p = subprocess.run([program, "--quiet", "--no-png", "--output-dir", out, sheared],
                       capture_output=True, text=True, timeout=300)
    check(p.returncode == 1 and "sheared" in p.stderr, "the program refuses a sheared sform: %r" % p.stderr.strip()[-160:])

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
