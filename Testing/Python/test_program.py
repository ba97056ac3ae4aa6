"""The command-line program: every reader path on files written here, bad
input (one-line error, exit status, no partial output), the noise option,
and the picture: its size and four filled panels in both layouts."""
import glob
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkIOImage import vtkMetaImageWriter, vtkPNGReader
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataReader

PROGRAM = os.environ["DG_PROGRAM"]
ROOT = tempfile.mkdtemp(prefix="dg_program_", dir=os.environ.get("DG_TEST_TMP"))
failures, checks = [], []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(*args, out=None, env=None):
    out = out or tempfile.mkdtemp(dir=ROOT)
    p = subprocess.run([PROGRAM, "--quiet", "--output-dir", out] + list(args),
                       capture_output=True, text=True, timeout=600,
                       env=None if env is None else dict(os.environ, **env))
    return p, out


# A small two-label volume: a box (label 3) and a ball (label 7).
N = 28


def value(i, j, k):
    if 4 <= i <= 12 and 5 <= j <= 20 and 6 <= k <= 21:
        return 3
    if (i - 19.3) ** 2 + (j - 14.1) ** 2 + (k - 13.7) ** 2 <= 36:
        return 7
    return 0


voxels = bytes(value(i, j, k) for k in range(N) for j in range(N) for i in range(N))


def vol_bytes(version):
    header = "".join("%s: %s\n" % kv for kv in [
        ("Center-X", N // 2), ("Center-Y", N // 2), ("Center-Z", N // 2),
        ("X", N), ("Y", N), ("Z", N), ("Voxel-Size", 1), ("Alpha-Color", 0),
        ("Voxel-Endian", 0), ("Int-Endian", "0123"), ("Version", version)]) + ".\n"
    data = voxels if version == 2 else zlib.compress(voxels)
    return header.encode() + data


def write(name, data):
    path = os.path.join(ROOT, name)
    with open(path, "wb") as f:
        f.write(data)
    return path


image = vtkImageData()
image.SetDimensions(N, N, N)
arr = vtkUnsignedCharArray()
arr.SetName("labels")
arr.SetNumberOfValues(len(voxels))
for n, b in enumerate(voxels):
    arr.SetValue(n, b)
image.GetPointData().SetScalars(arr)

inputs = {
    "v2.vol": write("v2.vol", vol_bytes(2)),
    "v3.vol": write("v3.vol", vol_bytes(3)),
}
w = vtkXMLImageDataWriter()
w.SetInputData(image)
inputs["vti"] = os.path.join(ROOT, "labels.vti")
w.SetFileName(inputs["vti"])
w.Write()
m = vtkMetaImageWriter()
m.SetInputData(image)
inputs["mha"] = os.path.join(ROOT, "labels.mha")
m.SetFileName(inputs["mha"])
m.SetCompression(False)
m.Write()
m2 = vtkMetaImageWriter()
m2.SetInputData(image)
inputs["mhd"] = os.path.join(ROOT, "labels.mhd")
m2.SetFileName(inputs["mhd"])
m2.SetRAWFileName(os.path.join(ROOT, "labels.raw"))
m2.SetCompression(False)
m2.Write()
nrrd_header = ("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\n"
               "spacings: 1 1 1\nencoding: raw\n" % (N, N, N))
inputs["nrrd"] = write("labels.nrrd", (nrrd_header + "\n").encode() + voxels)
write("labels_detached.raw", voxels)
inputs["nhdr"] = write("labels.nhdr", (nrrd_header + "data file: labels_detached.raw\n\n").encode())


def write_dicom_series(folder, series=None, z=None, tilt=0.0, drop=(), prefix="slice"):
    """One CT-like slice per z (uint16, label 3 -> 1000), explicit VR little
    endian. z: slice positions (default 0, 1, ...); tilt: x shift per mm of
    z (gantry tilt); drop: tags to leave out."""
    import pydicom
    from pydicom.dataset import FileDataset, FileMetaDataset
    from pydicom.uid import ExplicitVRLittleEndian, generate_uid
    os.makedirs(folder, exist_ok=True)
    series = series or generate_uid()
    z = z or [float(k) for k in range(N)]
    for k in range(N):
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = "1.2.840.10008.5.1.4.1.1.2"
        meta.MediaStorageSOPInstanceUID = generate_uid()
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        name = os.path.join(folder, "%s%03d.dcm" % (prefix, k))
        ds = FileDataset(name, {}, file_meta=meta, preamble=b"\0" * 128)
        ds.is_little_endian = True
        ds.is_implicit_VR = False
        ds.SOPClassUID = meta.MediaStorageSOPClassUID
        ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
        ds.SeriesInstanceUID = series
        ds.Modality = "CT"
        ds.InstanceNumber = k + 1
        ds.ImagePositionPatient = [tilt * z[k], 0.0, z[k]]
        ds.ImageOrientationPatient = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        ds.PixelSpacing = [1.0, 1.0]
        ds.SliceThickness = 1.0
        ds.Rows = N
        ds.Columns = N
        ds.SamplesPerPixel = 1
        ds.PhotometricInterpretation = "MONOCHROME2"
        ds.BitsAllocated = 16
        ds.BitsStored = 16
        ds.HighBit = 15
        ds.PixelRepresentation = 0
        ds.RescaleIntercept = 0
        ds.RescaleSlope = 1
        plane = bytearray()
        for j in range(N):
            for i in range(N):
                plane += struct.pack("<H", 1000 if value(i, j, k) == 3 else 0)
        ds.PixelData = bytes(plane)
        for tag in drop:
            delattr(ds, tag)
        ds.save_as(name, write_like_original=False)


def surfels(out, prefix):
    r = vtkXMLPolyDataReader()
    r.SetFileName(os.path.join(out, prefix + "_surface.vtp"))
    r.Update()
    return r.GetOutput().GetNumberOfPolys()


try:
    write_dicom_series(os.path.join(ROOT, "dicom"))
    inputs["dicom"] = os.path.join(ROOT, "dicom")
except ImportError:
    print("skip DICOM: python3-pydicom absent")

counts = {}
for kind, path in inputs.items():
    label = ["--range", "500", "2000"] if kind == "dicom" else ["--label", "3"]
    p, out = run(path, "--no-png", *label)
    stem = os.path.splitext(os.path.basename(path))[0]
    ok = p.returncode == 0 and os.path.exists(os.path.join(out, stem + "_features.vtp"))
    check(ok, "reads %s (exit %d) %s" % (kind, p.returncode, p.stderr.strip()[:200]))
    if ok:
        counts[kind] = surfels(out, stem)
# The box of label 3 is 9 x 16 x 16 voxels: 2 (144 + 144 + 256) surfels.
expected = 2 * (9 * 16 + 9 * 16 + 16 * 16)
check(len(counts) == len(inputs) and all(c == expected for c in counts.values()),
      "every reader gives the box's %d surfels: %s" % (expected, counts))

# Real data when ../shared is present.
real = os.path.join(os.environ.get("DG_SHARED_DATA_DIR", ""), "fandisk-64.vol")
if os.path.exists(real):
    p, out = run(real, "--no-png")
    check(p.returncode == 0 and surfels(out, "fandisk-64") > 1000, "reads fandisk-64.vol")
else:
    print("skip real .vol file: ../shared absent")

# Bad input: one line on stderr, non-zero exit, nothing left in the output folder.
trunc = vol_bytes(3)
bad_cases = [
    ("missing file", [os.path.join(ROOT, "nope.vol")], 1),
    ("unknown extension", [write("x.xyz", b"hello")], 1),
    ("truncated .vol", [write("trunc.vol", trunc[: len(trunc) // 2])], 1),
    ("corrupt .vol header", [write("corrupt.vol", b"X: 2\nY: two\nZ: 2\nVersion: 2\n.\n" + bytes(8))], 1),
    ("truncated .nrrd", [write("trunc.nrrd", (nrrd_header + "\n").encode() + voxels[:100])], 1),
    ("no inside voxel", [write("empty.vol", vol_bytes(2)[: -len(voxels)] + bytes(len(voxels)))], 1),
    ("label that does not occur", [inputs["v2.vol"], "--label", "99"], 1),
    ("negative alpha", ["--alpha", "-1"], 2),
    ("zero lambda", ["--lambda", "0"], 2),
    ("eps end above start", ["--eps-start", "0.5", "--eps-end", "1"], 2),
    ("ratio 1", ["--eps-ratio", "1"], 2),
    ("zero iterations", ["--iterations", "0"], 2),
    ("negative radius", ["--radius", "-2"], 2),
    ("noise above 1", ["--noise", "1.5"], 2),
    ("not a number", ["--alpha", "abc"], 2),
    ("unknown option", ["--frobnicate"], 2),
    ("unknown solver", ["--solver", "gauss"], 2),
    ("unknown AT metric", ["--at-metric", "euclid"], 2),
    ("early-level tolerance factor below 1", ["--solver-tolerance-early", "0.5"], 2),
    ("sheared MetaImage", [write("sheared.mha", ("ObjectType = Image\nNDims = 3\nDimSize = %d %d %d\n"
        "ElementSpacing = 1 1 1\nOffset = 0 0 0\nTransformMatrix = 1 0 0 0.3 1 0 0 0 1\n"
        "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n" % (N, N, N)).encode() + voxels)], 1),
    ("sheared NRRD", [write("sheared.nrrd", ("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\n"
        "space: left-posterior-superior\nspace directions: (0,1,0) (1,0.5,0) (0,0,1)\nencoding: raw\n\n"
        % (N, N, N)).encode() + voxels)], 1),
    ("NRRD direction of length 0", [write("flat.nrrd", ("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\n"
        "space: left-posterior-superior\nspace directions: (1,0,0) (0,0,0) (0,0,1)\nencoding: raw\n\n"
        % (N, N, N)).encode() + voxels)], 1),
    ("NRRD in a non-patient space", [write("scanner.nrrd", ("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\n"
        "space: scanner-xyz\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nencoding: raw\n\n"
        % (N, N, N)).encode() + voxels)], 1),
    ("not a NIfTI file", [write("not-really.nii", b"not a nifti file at all")], 1),
    ("unknown compression", ["--compression", "bzip"], 2),
    ("negative component size", ["--min-component", "-1"], 2),
    ("fractional component size", ["--min-component", "2.5"], 2),
]
if "dicom" in inputs:
    from pydicom.uid import generate_uid
    two, uid = os.path.join(ROOT, "dicom-two"), generate_uid()
    write_dicom_series(two, prefix="a")
    write_dicom_series(two, series=uid, prefix="b")
    gaps = [float(k) for k in range(N // 2)] + [k + 1.0 for k in range(N // 2, N)]
    for d in ("dicom-gap", "dicom-tilt", "dicom-no-iop", "dicom-no-ipp", "dicom-none"):
        os.makedirs(os.path.join(ROOT, d), exist_ok=True)
    write_dicom_series(os.path.join(ROOT, "dicom-gap"), z=gaps)
    write_dicom_series(os.path.join(ROOT, "dicom-tilt"), tilt=0.2)
    write_dicom_series(os.path.join(ROOT, "dicom-no-iop"), drop=("ImageOrientationPatient",))
    write_dicom_series(os.path.join(ROOT, "dicom-no-ipp"), drop=("ImagePositionPatient",))
    write(os.path.join("dicom-none", "notes.txt"), b"no DICOM here")
    rng = ["--range", "500", "2000"]
    bad_cases += [
        ("DICOM: non-uniform slice spacing", [os.path.join(ROOT, "dicom-gap")] + rng, 1),
        ("DICOM: gantry tilt (slices sheared)", [os.path.join(ROOT, "dicom-tilt")] + rng, 1),
        ("DICOM: several series, no --dicom-series", [two] + rng, 1),
        ("DICOM: --dicom-series names no series there", [two, "--dicom-series", "1.2.3"] + rng, 1),
        ("DICOM: no ImageOrientationPatient", [os.path.join(ROOT, "dicom-no-iop")] + rng, 1),
        ("DICOM: no ImagePositionPatient", [os.path.join(ROOT, "dicom-no-ipp")] + rng, 1),
        ("DICOM: directory without DICOM files", [os.path.join(ROOT, "dicom-none")] + rng, 1),
    ]
    p, _ = run(two, "--no-png", "--dicom-series", uid, *rng)
    check(p.returncode == 0, "DICOM: --dicom-series chooses one of two series (exit %d %s)"
          % (p.returncode, p.stderr.strip()[-200:]))
    p, _ = run(os.path.join(ROOT, "dicom-gap"), *rng)
    check("dicom-gap" in p.stderr and "non-uniform slice spacing (1, 2 mm" in p.stderr,
          "DICOM: the spacing error names the directory and the spacings: %r" % p.stderr.strip()[-240:])

# The default output (sharp features) against the paper's (--plain), on a
# small built-in shape: one line per edge, side normals active, and islands
# reported.
def read_vtp(out, name):
    r = vtkXMLPolyDataReader()
    r.SetFileName(os.path.join(out, name))
    r.Update()
    return r.GetOutput()


p, out = run("--size", "48", "--no-png")
default_surface, default_lines = read_vtp(out, "builtin_surface.vtp"), read_vtp(out, "builtin_features.vtp")
p2, out2 = run("--size", "48", "--no-png", "--plain", "--compression", "zlib")
plain_surface, plain_lines = read_vtp(out2, "builtin_surface.vtp"), read_vtp(out2, "builtin_features.vtp")
active = default_surface.GetCellData().GetNormals()
check(p.returncode == 0 and active is not None and active.GetName() == "SharpNormals"
      and default_surface.GetCellData().GetArray("FeatureRegion") is not None
      and default_lines.GetCellData().GetArray("FeatureAngle") is not None,
      "default output: SharpNormals active, FeatureRegion, FeatureAngle")
check("inside components" in p.stdout and "one line per edge" in p.stdout,
      "the summary reports the islands and the sharp stage")
plain_active = plain_surface.GetCellData().GetNormals()
check(p2.returncode == 0 and plain_active is not None and plain_active.GetName() == "ATNormals"
      and plain_surface.GetCellData().GetArray("SharpNormals") is None,
      "--plain: the paper's output (ATNormals active, no SharpNormals), written with zlib")
check(0 < default_lines.GetNumberOfLines() < plain_lines.GetNumberOfLines() / 2,
      "one line per edge: %d feature lines against AT's %d"
      % (default_lines.GetNumberOfLines(), plain_lines.GetNumberOfLines()))

# The program runs itself again with glibc's huge-page malloc (an exec at
# start-up, dgProgramSupport.h): that must change nothing in the results,
# and DG_HUGEPAGES=0 must be honoured (the summary says which).
def cell_arrays_equal(a, b):
    ca, cb = a.GetCellData(), b.GetCellData()
    if ca.GetNumberOfArrays() != cb.GetNumberOfArrays() or a.GetNumberOfCells() != b.GetNumberOfCells():
        return False
    for i in range(ca.GetNumberOfArrays()):
        x, y = ca.GetArray(i), cb.GetArray(ca.GetArray(i).GetName())
        if y is None or x.GetNumberOfValues() != y.GetNumberOfValues():
            return False
        if any(x.GetValue(k) != y.GetValue(k) for k in range(x.GetNumberOfValues())):
            return False
    return True


p3, out3 = run("--size", "48", "--no-png", env={"DG_HUGEPAGES": "0", "GLIBC_TUNABLES": ""})
p4, out4 = run("--size", "48", "--no-png", env={"GLIBC_TUNABLES": ""})
check(p3.returncode == 0 and p4.returncode == 0
      and cell_arrays_equal(default_surface, read_vtp(out3, "builtin_surface.vtp"))
      and cell_arrays_equal(default_surface, read_vtp(out4, "builtin_surface.vtp")),
      "huge-page malloc on (default) and off (DG_HUGEPAGES=0): the same output, bit for bit")
check("huge-page malloc" in p4.stdout and "huge-page malloc" not in p3.stdout,
      "the summary says when the huge-page malloc is on: %r" % p4.stdout[-200:])

# No display for the picture: VTK's X window would abort the process; the
# program asks first and fails with one line, before any work (nothing is
# left in the output folder). --no-png needs no display.
for display, what in (("", "DISPLAY not set"), (":-1", "a display that cannot be opened")):
    p, out = run("--size", "32", env={"DISPLAY": display})
    lines = [l for l in p.stderr.strip().splitlines() if l.strip()]
    check(p.returncode == 1 and len(lines) == 1 and "--no-png" in lines[0] and "display" in lines[0]
          and not os.listdir(out),
          "picture without a display (%s): exit %d, %r, files left %s"
          % (what, p.returncode, lines[-1] if lines else "", os.listdir(out)))
p, out = run("--size", "32", "--no-png", env={"DISPLAY": ""})
check(p.returncode == 0 and sorted(os.listdir(out)) == ["builtin_features.vtp", "builtin_surface.vtp"],
      "--no-png runs without a display: %s" % sorted(os.listdir(out)))

for what, args, status in bad_cases:
    p, out = run(*args)
    lines = [l for l in p.stderr.strip().splitlines() if l.strip()]
    left = os.listdir(out)
    check(p.returncode == status and len(lines) >= 1 and lines[-1].startswith("piecewise-normals:")
          and not left,
          "%s: exit %d (want %d), message %r, files left %s" %
          (what, p.returncode, status, lines[-1] if lines else "", left))

# Output folder: created when missing; a clear one-line error, before any
# work, when it cannot be; a file that cannot be written leaves nothing.
nested = os.path.join(ROOT, "new", "nested")
p, _ = run(inputs["v2.vol"], "--no-png", "--prefix", "d", out=nested)
check(p.returncode == 0 and sorted(os.listdir(nested)) == ["d_features.vtp", "d_surface.vtp"],
      "missing output folder is created: exit %d, %s" % (p.returncode, os.listdir(nested)
                                                        if os.path.isdir(nested) else "no folder"))
blocker = write("a_file", b"x")
p, _ = run(inputs["v2.vol"], out=blocker)
lines = [l for l in p.stderr.strip().splitlines() if l.strip()]
check(p.returncode == 1 and len(lines) == 1 and "output directory" in lines[0],
      "output folder that is a file: exit %d, stderr %r" % (p.returncode, lines))
p, out = run(inputs["v2.vol"], "--ply", "--prefix", os.path.join("no_such_dir", "x"))
lines = [l for l in p.stderr.strip().splitlines() if l.strip()]
check(p.returncode == 1 and len(lines) == 1 and "cannot write" in lines[0]
      and not os.listdir(out),
      "file that cannot be opened: exit %d, stderr %r, files left %s" %
      (p.returncode, lines, os.listdir(out)))

# Noise: repeatable with a seed, different with another.
a, out_a = run(inputs["v2.vol"], "--noise", "0.3", "--seed", "4", "--no-png", "--prefix", "n")
b, out_b = run(inputs["v2.vol"], "--noise", "0.3", "--seed", "4", "--no-png", "--prefix", "n")
c, out_c = run(inputs["v2.vol"], "--noise", "0.3", "--seed", "5", "--no-png", "--prefix", "n")
if a.returncode == 0 and b.returncode == 0 and c.returncode == 0:
    with open(os.path.join(out_a, "n_surface.vtp"), "rb") as fa, open(os.path.join(out_b, "n_surface.vtp"), "rb") as fb:
        check(fa.read() == fb.read(), "same seed, same output file")
    with open(os.path.join(out_a, "n_surface.vtp"), "rb") as fa, open(os.path.join(out_c, "n_surface.vtp"), "rb") as fc:
        check(fa.read() != fc.read(), "another seed, another output file")
else:
    check(False, "noise runs: %s %s %s" % (a.stderr, b.stderr, c.stderr))

# The exact solver gives the same features as the default iterative one.
def feature_lines(out, prefix):
    r = vtkXMLPolyDataReader()
    r.SetFileName(os.path.join(out, prefix + "_features.vtp"))
    r.Update()
    return r.GetOutput().GetNumberOfLines()


d, out_d = run(inputs["v2.vol"], "--noise", "0.2", "--no-png", "--prefix", "s")
e, out_e = run(inputs["v2.vol"], "--noise", "0.2", "--no-png", "--prefix", "s", "--solver", "ldlt")
if d.returncode == 0 and e.returncode == 0:
    nd, ne = feature_lines(out_d, "s"), feature_lines(out_e, "s")
    check(nd > 0 and nd == ne, "--solver ldlt gives the default's %d feature edges (%d)" % (nd, ne))
else:
    check(False, "solver runs: %s %s" % (d.stderr, e.stderr))

# The world metric runs and finds the features (its accuracy: TestATMetric).
w, out_w = run(inputs["v2.vol"], "--noise", "0.2", "--no-png", "--prefix", "s", "--at-metric", "world")
if w.returncode == 0:
    nw = feature_lines(out_w, "s")
    check(nw > 0, "--at-metric world gives feature edges (%d)" % nw)
else:
    check(False, "--at-metric world run: %s" % w.stderr)

# The picture: the built-in shape in both layouts (2 x 2 at W x H, 1 x 4 at
# W x W/4). Each of the four panels holds the object (not background, not the
# titles' dark text) on a reasonable share of its pixels and spans most of its
# width or height; panels 2 and 3 show the normals as colours, 1 and 4 grey;
# the red feature pixels are in panel 4.
def read_png(path):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    r = vtkPNGReader()
    r.SetFileName(path)
    r.Update()
    img = r.GetOutput()
    w, h, _ = img.GetDimensions()
    a = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)[::-1, :, :3]
    return np.asarray(a, dtype=int)  # row 0 at the top


def panel_stats(a, index, columns, rows):
    h, w, _ = a.shape
    pw, ph = w // columns, h // rows
    x0, y0 = (index % columns) * pw, (index // columns) * ph
    p = a[y0 + 2:y0 + ph - 2, x0 + 2:x0 + pw - 2]  # without the dividing lines
    mx, mn = p.max(axis=2), p.min(axis=2)
    obj = (mn <= 245) & (mx >= 60)
    ys, xs = obj.nonzero()
    span = max((xs.max() - xs.min() + 1) / pw, (ys.max() - ys.min() + 1) / ph) if len(xs) else 0
    red = (p[:, :, 0] > 150) & (p[:, :, 1] < 80) & (p[:, :, 2] < 80)
    return obj.mean(), span, ((mx - mn > 40) & ~red).mean(), int(red.sum())


for layout, args, size, grid in [
        ("2 x 2", ["--width", "480", "--height", "360"], (480, 360), (2, 2)),
        ("1 x 4", ["--width", "800", "--height", "900", "--panels"], (800, 200), (4, 1))]:
    p, out = run("--size", "48", *args)
    png = os.path.join(out, "builtin.png")
    ok = p.returncode == 0 and os.path.exists(png)
    check(ok, "%s picture of the built-in shape: %s" % (layout, p.stderr.strip()[-300:]))
    if not ok:
        continue
    a = read_png(png)
    check((a.shape[1], a.shape[0]) == size, "%s picture is %dx%d (want %dx%d)"
          % (layout, a.shape[1], a.shape[0], size[0], size[1]))
    stats = [panel_stats(a, i, *grid) for i in range(4)]
    for i, (share, span, colourful, red) in enumerate(stats):
        check(share > 0.15 and span > 0.8, "%s panel %d: object on %.0f%% of it, spans %.0f%%"
              % (layout, i + 1, 100 * share, 100 * span))
    check(stats[0][2] < 0.01 and stats[3][2] < 0.08 and stats[1][2] > 0.15 and stats[2][2] > 0.15,
          "%s: normal colours in panels 2, 3 only (shares of colourful, not red pixels %s)"
          % (layout, ["%.2f" % s[2] for s in stats]))
    check(stats[3][3] > 50 and stats[0][3] == 0,
          "%s: %d red feature pixels in panel 4, %d in panel 1" % (layout, stats[3][3], stats[0][3]))
    if layout == "2 x 2":
        check("surfels" in p.stdout and "feature edges" in p.stdout and "peak memory" in p.stdout
              and "render" in p.stdout, "summary printed: %r" % p.stdout[:300])

shutil.rmtree(ROOT, ignore_errors=True)
print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
