"""World geometry of the program's DICOM, MetaImage and NRRD inputs, on
volumes written here with a known, non-trivial geometry: oblique directions
with det +1 and det -1, a non-zero origin, anisotropic spacing. DICOM series
are written with pydicom (files named in a shuffled order; slices stacked
along +normal and along -normal in instance order, i.e. index-to-world
affines with det +1 and det -1; a rescale intercept); MetaImage with a
TransformMatrix and NRRD with space directions by hand (NRRD also in RAS
space). The program's surface points must equal the analytic world positions
of the voxel corners (to 1e-6 of the spacing), span the box's corners, and
every quad must face outward in world space, in LPS (default) and RAS
(--ras); under mpirun (2 ranks, pieces read as sub-extents) the MetaImage
and NRRD results hold the same. The program's bad-input rows for these
formats live in test_program.py, the module reader's in TestBadInputMatrix.
The module's vtkOrientedImageReader (the plugin's reader) is checked directly
too: the geometry on its image, LPS and RAS, sub-extents."""
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile

import numpy as np
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPPolyDataReader
from vtkmodules.util.numpy_support import vtk_to_numpy

PROGRAM = os.environ["DG_PROGRAM"]
ROOT = tempfile.mkdtemp(prefix="dg_geometry_", dir=os.environ.get("DG_TEST_TMP"))
failures, checks = [], []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)
    return cond


# A box of voxels i 4..13, j 5..12, k 3..11 in a 20 x 18 x 16 image (off
# centre, so that a flipped axis moves it).
NX, NY, NZ = 20, 18, 16
BOX = ((4, 13), (5, 12), (3, 11))
inside = np.zeros((NZ, NY, NX), np.uint8)  # [k, j, i]
inside[BOX[2][0]:BOX[2][1] + 1, BOX[1][0]:BOX[1][1] + 1, BOX[0][0]:BOX[0][1] + 1] = 1
N_QUADS = 2 * (10 * 8 + 10 * 9 + 8 * 9)
SPACING = np.array([0.7, 0.9, 1.5])
ORIGIN = np.array([10.0, -20.0, 30.0])
FLIP_RAS = np.diag([-1.0, -1.0, 1.0])


def rotation(det):
    c, s = np.cos(np.radians(37)), np.sin(np.radians(37))
    R = np.array([[c, -s, 0], [s * 0.8, c * 0.8, 0.6], [-s * 0.6, -c * 0.6, 0.8]])
    R[:, 2] *= det
    return R


def affine(R, spacing=SPACING, origin=ORIGIN):
    A = np.eye(4)
    A[:3, :3] = R * spacing
    A[:3, 3] = origin
    return A


def run(path, *args, ranks=0):
    out = tempfile.mkdtemp(dir=ROOT)
    cmd = [PROGRAM, "--quiet", "--no-png", "--output-dir", out, "--prefix", "r"] + list(args) + [path]
    if ranks:
        cmd = [shutil.which("mpirun"), "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    surface = None
    name = os.path.join(out, "r_surface." + ("pvtp" if ranks > 1 else "vtp"))
    if p.returncode == 0 and os.path.exists(name):
        r = vtkXMLPPolyDataReader() if ranks > 1 else vtkXMLPolyDataReader()
        r.SetFileName(name)
        r.Update()
        surface = r.GetOutput()
    return p, surface


def geometry_checks(what, p, pd, A, to_world=np.eye(3), box=BOX):
    """A maps (i, j, k, 1) of the written voxels to LPS; to_world maps LPS to
    the output's coordinates."""
    if not check(p.returncode == 0 and pd is not None and pd.GetNumberOfPoints() > 0,
                 "%s: the program reads it (exit %d %s)" % (what, p.returncode, p.stderr.strip()[-300:])):
        return
    pts = vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
    lps = pts @ np.linalg.inv(to_world).T
    idx = (np.linalg.inv(A) @ np.c_[lps, np.ones(len(lps))].T).T[:, :3]
    corner = np.round(idx + 0.5) - 0.5
    world = (A @ np.c_[corner, np.ones(len(corner))].T).T[:, :3] @ to_world.T
    spacing = np.linalg.norm(A[:3, :3], axis=0).min()
    err = np.abs(world - pts).max() / spacing
    e = [b[1] - b[0] + 1 for b in box]
    quads = 2 * (e[0] * e[1] + e[1] * e[2] + e[0] * e[2])
    check(pd.GetNumberOfPolys() == quads, "%s: the box's %d quads (%d)" % (what, quads, pd.GetNumberOfPolys()))
    check(err < 1e-6, "%s: points at the analytic corner positions (max error %.2g spacing)" % (what, err))
    lo, hi = corner.min(axis=0), corner.max(axis=0)
    want_lo = [b[0] - 0.5 for b in box]
    want_hi = [b[1] + 0.5 for b in box]
    check(np.allclose(lo, want_lo) and np.allclose(hi, want_hi),
          "%s: the corners span the box's indices (%s .. %s)" % (what, lo, hi))
    conn = vtk_to_numpy(pd.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    q = pts[conn]
    n = np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 1])
    centre = (A @ np.r_[[np.mean(b) for b in box], 1.0])[:3] @ to_world.T
    share = np.mean(np.einsum("ij,ij->i", n, q.mean(axis=1) - centre) > 0)
    check(share == 1.0, "%s: every quad faces outward in world space (%.3f)" % (what, share))
    return err


errors = {}

# ---------------------------------------------------------------- DICOM
try:
    import pydicom
    from pydicom.dataset import FileDataset, FileMetaDataset
    from pydicom.uid import ExplicitVRLittleEndian, generate_uid
except ImportError:
    pydicom = None
    print("skip DICOM: python3-pydicom absent")


def ds_number(v):
    return float("%.10g" % v)


def write_dicom(folder, R, direction=1, shuffle=True, intercept=0.0, series=None, positions=None,
                drop=None, name_prefix="img"):
    """Slices of `inside` (k = instance order) at IPP = ORIGIN + R diag(s) (0, 0, k * direction);
    rows j along R[:, 1], columns i along R[:, 0]. Returns the file-index affine."""
    os.makedirs(folder, exist_ok=True)
    series = series or generate_uid()
    order = list(range(NZ))
    names = ["%s%03d.dcm" % (name_prefix, n) for n in range(NZ)]
    if shuffle:
        random.Random(3).shuffle(names)
    n = R[:, 2] * direction
    for k in order:
        if drop is not None and k in drop:
            continue
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"
        meta.MediaStorageSOPInstanceUID = generate_uid()
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        name = os.path.join(folder, names[k])
        ds = FileDataset(name, {}, file_meta=meta, preamble=b"\0" * 128)
        ds.is_little_endian = True
        ds.is_implicit_VR = False
        ds.SOPClassUID = meta.MediaStorageSOPClassUID
        ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
        ds.SeriesInstanceUID = series
        ds.StudyInstanceUID = "1.2.3.4"
        ds.Modality = "CT"
        ds.InstanceNumber = k + 1
        pos = ORIGIN + n * SPACING[2] * k if positions is None else positions[k]
        ds.ImagePositionPatient = [ds_number(x) for x in pos]
        ds.ImageOrientationPatient = [ds_number(x) for x in list(R[:, 0]) + list(R[:, 1])]
        ds.PixelSpacing = [ds_number(SPACING[1]), ds_number(SPACING[0])]  # row spacing (j), column spacing (i)
        ds.SliceThickness = ds_number(SPACING[2])
        ds.Rows, ds.Columns = NY, NX
        ds.SamplesPerPixel = 1
        ds.PhotometricInterpretation = "MONOCHROME2"
        ds.BitsAllocated = ds.BitsStored = 16
        ds.HighBit = 15
        ds.PixelRepresentation = 0
        ds.RescaleIntercept = intercept
        ds.RescaleSlope = 1
        plane = (inside[k].astype(np.uint16) * 1000 - int(intercept)).astype("<u2")
        ds.PixelData = plane.tobytes()
        ds.save_as(name, write_like_original=False)
    Rn = R.copy()
    Rn[:, 2] = n
    return affine(Rn, origin=ORIGIN)


if pydicom is not None:
    for det in (1, -1):
        # det -1 in file order: the slices go along -normal as the instance
        # number grows. DICOM's normal is row x column, so the reader's own
        # direction always has det +1; the world positions must not change.
        folder = os.path.join(ROOT, "dicom%+d" % det)
        A = write_dicom(folder, rotation(1), direction=det, intercept=-1024.0 if det == 1 else 0.0)
        rng = ["--range", "500", "2000"]
        p, pd = run(folder, *rng)
        errors["DICOM det %+d" % det] = geometry_checks("DICOM, slices along %snormal (file-index det %+d), shuffled "
                                                        "file names%s" % ("+" if det == 1 else "-", det,
                                                        ", rescale intercept -1024" if det == 1 else ""), p, pd, A)
        p, pd = run(folder, "--ras", *rng)
        geometry_checks("DICOM det %+d, --ras" % det, p, pd, A, FLIP_RAS)
    # Positions rounded as scanners write them (0.05% of the slice step off
    # the grid, under the 1% tolerance): read, origin at the first slice.
    jitter = os.path.join(ROOT, "dicom-jitter")
    R = rotation(1)
    wobble = [ORIGIN + R[:, 2] * SPACING[2] * (k + (0.0005 if k % 3 == 1 else 0.0)) for k in range(NZ)]
    A = write_dicom(jitter, R, positions=wobble)
    p, pd = run(jitter, "--range", "500", "2000")
    ok = p.returncode == 0 and pd is not None and pd.GetNumberOfPolys() == N_QUADS
    if ok:
        pts = vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
        idx = (np.linalg.inv(A) @ np.c_[pts, np.ones(len(pts))].T).T[:, :3]
        err = np.abs(idx - (np.round(idx + 0.5) - 0.5)).max()
        ok = err < 1e-3
    check(ok, "DICOM positions 0.05%% of a step off the grid: read (exit %d %s)"
          % (p.returncode, p.stderr.strip()[-200:]))
    # A single .dcm file is read (one slice: the digital surface then
    # refuses a 2-D image, after the reader).
    one = os.path.join(ROOT, "dicom+1")
    p, pd = run(os.path.join(one, sorted(os.listdir(one))[0]), "--range", "500", "2000")
    check(p.returncode == 1 and "20 x 18 x 1" in p.stderr,
          "a single .dcm file is read: 20 x 18 x 1 voxels (%s)" % p.stderr.strip()[-200:])
    # Two series in one folder: --dicom-series picks one.
    two = os.path.join(ROOT, "dicom-two")
    uid_a, uid_b = generate_uid(), generate_uid()
    A = write_dicom(two, rotation(1), series=uid_a, name_prefix="a")
    write_dicom(two, rotation(-1), series=uid_b, name_prefix="b")
    p, pd = run(two, "--range", "500", "2000", "--dicom-series", uid_a)
    errors["DICOM --dicom-series"] = geometry_checks("DICOM, two series, --dicom-series the first", p, pd, A)
    p, pd = run(two, "--range", "500", "2000")
    check(p.returncode == 1 and uid_a in p.stderr and uid_b in p.stderr and "--dicom-series" in p.stderr
          and len(p.stderr.strip().splitlines()) == 1,
          "two series without --dicom-series: one line listing both (%r)" % p.stderr.strip()[-300:])

# ------------------------------------------------------------ MetaImage


def write_mha(name, R, origin=ORIGIN, spacing=SPACING, matrix=None):
    m = R if matrix is None else matrix
    header = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
              "TransformMatrix = %s\nOffset = %s\nCenterOfRotation = 0 0 0\nAnatomicalOrientation = RAI\n"
              "ElementSpacing = %s\nDimSize = %d %d %d\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n" % (
                  " ".join("%.17g" % v for v in m.T.flatten()),  # the i-th triple: axis i's direction
                  " ".join("%.17g" % v for v in origin), " ".join("%.17g" % v for v in spacing), NX, NY, NZ))
    path = os.path.join(ROOT, name)
    with open(path, "wb") as f:
        f.write(header.encode() + (inside * 5).tobytes())
    return path


def write_nrrd(name, R, origin=ORIGIN, spacing=SPACING, space="left-posterior-superior", to_space=np.eye(3)):
    cols = to_space @ (R * spacing)
    o = to_space @ origin
    header = ("NRRD0004\ntype: uint8\ndimension: 3\nspace: %s\nsizes: %d %d %d\nspace directions: %s\n"
              "kinds: domain domain domain\nendian: little\nencoding: raw\nspace origin: (%s)\n\n" % (
                  space, NX, NY, NZ,
                  " ".join("(%s)" % ",".join("%.17g" % v for v in cols[:, a]) for a in range(3)),
                  ",".join("%.17g" % v for v in o)))
    path = os.path.join(ROOT, name)
    with open(path, "wb") as f:
        f.write(header.encode() + (inside * 5).tobytes())
    return path


have_mpi = shutil.which("mpirun") is not None
for det in (1, -1):
    R = rotation(det)
    A = affine(R)
    mha = write_mha("oblique%+d.mha" % det, R)
    p, pd = run(mha)
    errors["MHA det %+d" % det] = geometry_checks("MetaImage, TransformMatrix det %+d" % det, p, pd, A)
    p, pd = run(mha, "--ras")
    geometry_checks("MetaImage det %+d, --ras" % det, p, pd, A, FLIP_RAS)
    nrrd = write_nrrd("oblique%+d.nrrd" % det, R)
    p, pd = run(nrrd)
    errors["NRRD det %+d" % det] = geometry_checks("NRRD (LPS), space directions det %+d" % det, p, pd, A)
    ras = write_nrrd("oblique-ras%+d.nrrd" % det, R, space="right-anterior-superior", to_space=FLIP_RAS)
    p, pd = run(ras)
    errors["NRRD RAS det %+d" % det] = geometry_checks("NRRD in RAS space, det %+d, converted to LPS" % det,
                                                       p, pd, A)
    p, pd = run(ras, "--ras")
    geometry_checks("NRRD in RAS space, det %+d, --ras" % det, p, pd, A, FLIP_RAS)
    if have_mpi:
        for path, what in ((mha, "MetaImage"), (nrrd, "NRRD")):
            p, pd = run(path, ranks=2)
            errors["%s det %+d, 2 ranks" % (what, det)] = geometry_checks(
                "%s det %+d under mpirun -np 2 (sub-extents)" % (what, det), p, pd, A)

# A TransformMatrix with scaled columns: direction = normalised columns,
# spacing = ElementSpacing x their lengths.
R = rotation(-1)
scale = np.array([2.0, 0.5, 1.25])
mha = write_mha("scaled.mha", R, spacing=SPACING / scale, matrix=R * scale)
p, pd = run(mha)
geometry_checks("MetaImage with scaled TransformMatrix columns", p, pd, affine(R))
if not have_mpi:
    print("skip mpirun runs: mpirun not found")

# ------------------------------------------- the module's reader (ParaView's)
# vtkOrientedImageReader is what the program and the plugin use: its image
# carries the geometry (origin, spacing, direction) itself, a sub-extent keeps
# it, and its surface lies at the analytic corners.
from digitalgeometry import vtkDigitalSurfaceFilter, vtkOrientedImageReader  # noqa: E402


def reader_surface(reader):
    s = vtkDigitalSurfaceFilter()
    s.SetInputConnection(reader.GetOutputPort())
    s.Update()
    return s.GetOutput()


class Ok:
    returncode = 0
    stderr = ""


for det in (1, -1):
    R = rotation(det)
    A = affine(R)
    for path, what in ((write_mha("reader%+d.mha" % det, R), "MetaImage"),
                       (write_nrrd("reader%+d.nrrd" % det, R), "NRRD"),
                       (write_nrrd("reader-ras%+d.nrrd" % det, R, space="right-anterior-superior",
                                   to_space=FLIP_RAS), "NRRD (RAS space)")):
        for system, to_world in ((vtkOrientedImageReader.LPS, np.eye(3)), (vtkOrientedImageReader.RAS, FLIP_RAS)):
            label = "vtkOrientedImageReader, %s det %+d, %s" % (what, det, "LPS" if system == 0 else "RAS")
            r = vtkOrientedImageReader()
            r.SetFileName(path)
            r.SetCoordinateSystem(system)
            r.Update()
            im = r.GetOutput()
            D = np.array([im.GetDirectionMatrix().GetElement(a, b) for a in range(3) for b in range(3)]).reshape(3, 3)
            check(r.GetOriented() and np.allclose(D, to_world @ R, atol=1e-12)
                  and np.allclose(im.GetSpacing(), SPACING, atol=1e-12)
                  and np.allclose(im.GetOrigin(), to_world @ ORIGIN, atol=1e-9),
                  "%s: origin, spacing and direction on the image" % label)
            geometry_checks(label, Ok, reader_surface(r), A, to_world)
        # A sub-extent (a piece) keeps the geometry and the voxels.
        r = vtkOrientedImageReader()
        r.SetFileName(path)
        r.UpdateExtent((3, 15, 2, 17, 4, 12))
        sub = r.GetOutput()
        full = vtkOrientedImageReader()
        full.SetFileName(path)
        full.Update()
        v_sub = vtk_to_numpy(sub.GetPointData().GetScalars()).reshape(9, 16, 13)
        v_full = vtk_to_numpy(full.GetOutput().GetPointData().GetScalars()).reshape(NZ, NY, NX)
        check(tuple(sub.GetExtent()) == (3, 15, 2, 17, 4, 12) and np.array_equal(v_sub, v_full[4:13, 2:18, 3:16])
              and np.allclose(sub.GetOrigin(), full.GetOutput().GetOrigin())
              and np.allclose(sub.GetPoint(0), full.GetOutput().GetPoint(full.GetOutput().ComputePointId([3, 2, 4]))),
              "vtkOrientedImageReader, %s det %+d: a sub-extent has the box's voxels at their world positions" % (what, det))

# A 3-D NRRD whose first axis is shorter than 10 voxels: VTK's vtkNrrdReader
# reads it as a 2-D image of that many components; the module's reader gives
# the 3-D grid, voxel for voxel, and refuses it without space directions.
small = (np.arange(7 * 6 * 5) % 7).astype(np.uint8).reshape(7, 6, 5)  # [k, j, i], 5 x 6 x 7
R = rotation(-1)
for sub in (None, (1, 3, 0, 5, 2, 6)):
    path = os.path.join(ROOT, "thin.nrrd")
    with open(path, "wb") as f:
        f.write(("NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\nsizes: 5 6 7\n"
                 "space directions: %s\nkinds: domain domain domain\nendian: little\nencoding: raw\n"
                 "space origin: (%s)\n\n" % (
                     " ".join("(%s)" % ",".join("%.17g" % v for v in (R * SPACING)[:, a]) for a in range(3)),
                     ",".join("%.17g" % v for v in ORIGIN))).encode() + small.tobytes())
    r = vtkOrientedImageReader()
    r.SetFileName(path)
    if sub:
        r.UpdateExtent(sub)
    else:
        r.Update()
    im = r.GetOutput()
    e = sub or (0, 4, 0, 5, 0, 6)
    got = vtk_to_numpy(im.GetPointData().GetScalars()) if im.GetPointData().GetScalars() else np.zeros(0)
    want = small[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1].ravel()
    corner = np.array(im.GetPoint(0)) if im.GetNumberOfPoints() else None
    check(tuple(im.GetExtent()) == tuple(e) and im.GetPointData().GetScalars().GetNumberOfComponents() == 1
          and np.array_equal(got, want)
          and np.allclose(corner, ORIGIN + (R * SPACING) @ np.array(e[0::2], float)),
          "vtkOrientedImageReader: a NRRD 5 x 6 x 7 (first axis < 10) read as 3-D, voxel for voxel%s"
          % (", sub-extent %s" % (sub,) if sub else ""))

# An axis-aligned NRRD (spacings only) keeps VTK's reader's geometry.
axis = os.path.join(ROOT, "axis.nrrd")
with open(axis, "wb") as f:
    f.write(("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nspacings: 0.5 0.25 2\nencoding: raw\n\n"
             % (NX, NY, NZ)).encode() + (inside * 5).tobytes())
r = vtkOrientedImageReader()
r.SetFileName(axis)
r.Update()
check(not r.GetOriented() and np.allclose(r.GetOutput().GetSpacing(), (0.5, 0.25, 2))
      and r.GetOutput().GetNumberOfPoints() == NX * NY * NZ,
      "vtkOrientedImageReader: an axis-aligned NRRD keeps its spacings, no orientation")

print("max errors (in units of the smallest spacing): " +
      ", ".join("%s %.2g" % (k, v) for k, v in errors.items() if v is not None))
print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
