"""vtkNIfTIVolumeReader's part reads (issue 38): a piece or sub-extent is read
from the file itself (seeks in a .nii, a streaming inflate of a .nii.gz that
keeps only the box), not cut from VTK's whole read. Every box must equal, bit
for bit, the same box of the whole read (vtkNIFTIImageReader's), with the
same geometry, for every datatype VTK's reader maps to a scalar volume, both
byte orders, .nii and .nii.gz, NIfTI-1 and -2, qfac -1 (slices reversed), an
sform with a reflection and no qform, a 4-D file (first time point), a
header extension (vox_offset beyond 352), scl_slope/scl_inter (left as
stored, as VTK's reader does) and a vector dim[5] (read whole, then cut).
A truncated .nii.gz fails in every piece, with an error and no voxels."""
import gzip
import os
import struct
import sys
import tempfile

import numpy as np
import nibabel as nib
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator
from vtkmodules.util.numpy_support import vtk_to_numpy

from digitalgeometry import vtkNIfTIVolumeReader

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


TMP = os.environ.get("DG_TEST_TMP") or tempfile.mkdtemp()
os.makedirs(TMP, exist_ok=True)
SHAPE = (13, 11, 9)  # x, y, z
rng = np.random.default_rng(38)


def affine(flip):
    c, s = np.cos(np.radians(25)), np.sin(np.radians(25))
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])
    R[:, 2] *= flip
    A = np.eye(4)
    A[:3, :3] = R * np.array([0.8, 1.1, 1.7])
    A[:3, 3] = (3.0, -7.0, 11.0)
    return A


def values(dtype, shape=SHAPE):
    """Random values covering each type's range (both signs, high bytes set)."""
    dt = np.dtype(dtype)
    if dt.names:  # RGB24 / RGBA32
        out = np.zeros(shape, dt)
        for name in dt.names:
            out[name] = rng.integers(0, 256, size=shape, dtype=np.uint8)
        return out
    if dt.kind == "c":
        return (rng.normal(0, 1e3, shape) + 1j * rng.normal(0, 1e-3, shape)).astype(dt)
    if dt.kind == "f":
        return (rng.normal(0, 1e4, shape) * 10.0 ** rng.integers(-20, 20, shape)).astype(dt)
    info = np.iinfo(dt)
    return rng.integers(info.min, info.max, size=shape, dtype=dt, endpoint=True)


def save(name, data, nifti2=False, endian="<", flip=1, qform=True, sform=True, extension=False,
         slope=None):
    cls = nib.Nifti2Image if nifti2 else nib.Nifti1Image
    hdr_cls = nib.Nifti2Header if nifti2 else nib.Nifti1Header
    header = hdr_cls(endianness=endian)
    img = cls(data, affine(flip), header)
    img.set_data_dtype(data.dtype)  # a given header would impose its own (float32)
    img.set_qform(affine(flip), code=1 if qform else 0)
    img.set_sform(affine(flip), code=1 if sform else 0)
    if extension:
        img.header.extensions.append(nib.nifti1.Nifti1Extension(6, b"issue 38 " * 40))
    path = os.path.join(TMP, name)
    nib.save(img, path)
    if slope is not None:
        # nibabel rewrites scaling on save; patch the stored fields instead
        # (NIfTI-1: scl_slope at 112, scl_inter at 116, float32).
        opener = gzip.open if path.endswith(".gz") else open
        with opener(path, "rb") as f:
            raw = bytearray(f.read())
        raw[112:120] = struct.pack(endian + "ff", *slope)
        with opener(path, "wb") as f:
            f.write(bytes(raw))
    return path


class Errors:
    def __init__(self, obj):
        self.errors = []
        obj.AddObserver(vtkCommand.ErrorEvent, lambda o, e: self.errors.append(e))


def read(path, request=None):
    r = vtkNIfTIVolumeReader()
    seen = Errors(r)
    seen_exec = Errors(r.GetExecutive())
    r.SetFileName(path)
    if request is None:
        r.Update()
    elif len(request) == 6:
        r.UpdateExtent(request)
    else:
        r.UpdatePiece(*request)
    return r.GetOutput(), seen.errors + seen_exec.errors


def raw(image):
    """The voxels as bytes in a (z, y, x, bytes per voxel) array: a bit-for-bit comparison."""
    e = image.GetExtent()
    s = image.GetPointData().GetScalars()
    if s is None:
        return None
    a = np.ascontiguousarray(vtk_to_numpy(s)).view(np.uint8)
    return a.reshape(e[5] - e[4] + 1, e[3] - e[2] + 1, e[1] - e[0] + 1, -1)


def geometry(image):
    d = image.GetDirectionMatrix()
    return (image.GetOrigin(), image.GetSpacing(), tuple(d.GetElement(a, b) for a in range(3) for b in range(3)))


BOXES = [(0, 12, 0, 10, 0, 3), (3, 9, 2, 8, 4, 6), (12, 12, 10, 10, 8, 8), (0, 0, 0, 0, 0, 0),
         (5, 5, 0, 10, 0, 8), (0, 12, 10, 10, 0, 8), (1, 11, 0, 10, 8, 8)]
PIECES = [(0, 2, 0), (1, 2, 1), (1, 3, 2), (3, 4, 1), (7, 8, 0), (7, 8, 2)]
EMPTY = (0, -1, 0, -1, 0, -1)


def compare(path, label):
    """Every box and piece equals the whole read's box, bit for bit; returns the whole image."""
    whole, errors = read(path)
    W = raw(whole)
    if errors or W is None:
        check(False, "%s: whole read (%s)" % (label, errors[:1]))
        return None
    we = whole.GetExtent()
    name = whole.GetPointData().GetScalars().GetName()
    kind = whole.GetPointData().GetScalars().GetDataType()
    bad = []
    requests = BOXES + PIECES
    for request in requests:
        out, errors = read(path, request)
        if len(request) == 6:
            e = request
        else:
            e = [0] * 6
            vtkExtentTranslator().PieceToExtentThreadSafe(request[0], request[1], request[2], list(we), e,
                                                          vtkExtentTranslator.BLOCK_MODE, 0)
            e = tuple(e)
        P = raw(out)
        s = out.GetPointData().GetScalars()
        good = (not errors and out.GetExtent() == e and P is not None and s.GetName() == name and
                s.GetDataType() == kind and geometry(out) == geometry(whole) and
                np.array_equal(P, W[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1]))
        if not good:
            bad.append(request)
    out, errors = read(path, EMPTY)
    empty_ok = not errors and out.GetNumberOfPoints() == 0
    check(not bad and empty_ok, "%s: %d boxes and pieces (ghost layers, edge pieces 7 of 8) equal the whole "
          "read's bit for bit, same geometry; an empty extent is empty%s" %
          (label, len(requests), "" if not bad else " (wrong: %s)" % bad))
    return whole


# Every datatype vtkNIFTIImageReader maps to a scalar type, both byte orders, both containers.
TYPES = ["u1", "i1", "i2", "u2", "i4", "u4", "i8", "u8", "f4", "f8", "c8", "c16",
         [("R", "u1"), ("G", "u1"), ("B", "u1")], [("R", "u1"), ("G", "u1"), ("B", "u1"), ("A", "u1")]]
for t in TYPES:
    data = values(t)
    tname = "rgb%d" % len(t) if isinstance(t, list) else t
    for endian in "<>":
        for ext in (".nii", ".nii.gz"):
            path = save("t-%s-%s%s" % (tname, "le" if endian == "<" else "be", ext), data, endian=endian)
            whole = compare(path, "%s %s-endian %s" % (tname, "little" if endian == "<" else "big", ext))
            if whole is not None and endian == ">" and ext == ".nii":
                # The whole read itself against nibabel's values (native order).
                ref = np.asarray(nib.load(path).dataobj.get_unscaled())
                got = raw(whole)
                native = np.ascontiguousarray(ref.astype(np.dtype(t).newbyteorder("=")) if not isinstance(t, list) else ref)
                want = native.transpose(2, 1, 0).copy().view(np.uint8).reshape(got.shape)
                check(np.array_equal(got, want), "%s: the whole read holds nibabel's values" % tname)

# Orientation and layout variants (int16, both containers).
data = values("i2")
for ext in (".nii", ".nii.gz"):
    compare(save("qfac-neg" + ext, data, flip=-1, sform=False), "qfac -1 (slices reversed) " + ext)
    compare(save("sform-det-neg" + ext, data, flip=-1, qform=False), "sform det -1, no qform " + ext)
    compare(save("nifti2" + ext, data, nifti2=True, flip=-1, sform=False), "NIfTI-2, qfac -1 " + ext)
    compare(save("nifti2-be" + ext, data, nifti2=True, endian=">"), "NIfTI-2 big-endian " + ext)
    compare(save("extension" + ext, data, extension=True), "header extension (vox_offset > 352) " + ext)
    compare(save("time" + ext, values("f4", SHAPE + (3,))), "4-D, first time point " + ext)
    compare(save("vector" + ext, values("i2", SHAPE + (1, 2))), "dim[5] = 2 vector (read whole, cut) " + ext)
    slope_path = save("slope" + ext, data, slope=(2.0, 5.0))
    whole = compare(slope_path, "scl_slope 2, scl_inter 5 " + ext)
    if whole is not None:
        stored = np.asarray(nib.load(slope_path).dataobj.get_unscaled()).transpose(2, 1, 0)
        check(np.array_equal(vtk_to_numpy(whole.GetPointData().GetScalars()).reshape(stored.shape), stored),
              "scl_slope / scl_inter: the values as stored, as VTK's reader leaves them " + ext)

# A truncated .nii.gz (the gzip stream cut at 60 %): the whole read and
# every piece fail with an error and no voxels, the first piece too, whose
# box lies in the part that inflates.
big = values("i2", (40, 30, 24))
src = save("cut.nii.gz", big)
with open(src, "rb") as f:
    blob = f.read()
cut = os.path.join(TMP, "cut-short.nii.gz")
with open(cut, "wb") as f:
    f.write(blob[:int(len(blob) * 0.6)])
fails = []
for request in (None, (0, 4, 0), (3, 4, 1), (0, 39, 0, 29, 0, 1)):
    out, errors = read(cut, request)
    fails.append(bool(errors) and (out.GetPointData().GetScalars() is None or out.GetNumberOfPoints() == 0))
check(all(fails), "truncated .nii.gz: the whole read and every piece give an error and no voxels (%s)" % fails)

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
