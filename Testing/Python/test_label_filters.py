"""Label maps through the filters (issue 18): vtkDigitalSurfaceFilter and
vtkIINormalEstimator in EachLabel mode on a 3-label map whose labels touch
each other and the background (test_labels.py's map, anisotropic spacing and
a rotated direction matrix). Each label's part of the combined output must
equal a Label-mode run of that label on the whole image: the same quads
(inside voxel, direction, world corners) in the same order, bitwise II
normals and curvatures; AT on the combined surface per label against AT on
the label alone; vtkSplitByLabelFilter's named blocks; the bad inputs."""
import math
import sys

import numpy as np
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData, vtkCompositeDataSet
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkDigitalSurfaceFilter,
                             vtkIINormalEstimator, vtkSplitByLabelFilter)

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


n = (40, 36, 32)
k, j, i = np.meshgrid(np.arange(n[2]), np.arange(n[1]), np.arange(n[0]), indexing="ij")
data = np.zeros((n[2], n[1], n[0]), np.int16)
data[(i >= 4) & (i <= 22) & (j >= 5) & (j <= 28) & (k >= 4) & (k <= 20)] = 2
data[(i - 27.3) ** 2 + (j - 17.6) ** 2 + (k - 15.2) ** 2 <= 8.5 ** 2] = 5
data[(i >= 12) & (i <= 30) & (j >= 26) & (j <= 31) & (k >= 18) & (k <= 24)] = 9
# A speck of label 9 on the image's border: a box clipped by the image.
data[0:2, 0:3, 37:40] = 9
LABELS = [2, 5, 9]

image = vtkImageData()
image.SetDimensions(*n)
image.SetOrigin(10, -20, 30)
image.SetSpacing(0.8, 0.9, 1.2)
c, s = math.cos(0.3), math.sin(0.3)
image.SetDirectionMatrix(c, -s, 0, s, c, 0, 0, 0, 1)
arr = numpy_to_vtk(data.ravel(), deep=1)
arr.SetName("labels")
image.GetPointData().SetScalars(arr)


def surface(mode, label=None, labels=None):
    f = vtkDigitalSurfaceFilter()
    f.SetInputData(image)
    f.SetSelectionMode(mode)
    if label is not None:
        f.SetLabel(label)
    if labels is not None:
        f.SetLabels(labels)
    f.Update()
    return f.GetOutput()


def ii(surf, mode, label=None):
    f = vtkIINormalEstimator()
    f.SetInputData(surf)
    f.SetSourceData(image)
    f.SetRadius(3)
    f.ComputeCurvaturesOn()
    f.SetSelectionMode(mode)
    if label is not None:
        f.SetLabel(label)
    f.Update()
    return f.GetOutput(), f.GetNumberOfTrivialFallbacks()


def cell_array(pd, name):
    return vtk_to_numpy(pd.GetCellData().GetArray(name))


def quads(pd):
    conn = vtk_to_numpy(pd.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    return vtk_to_numpy(pd.GetPoints().GetData())[conn]  # cells x 4 x 3


EACH = vtkDigitalSurfaceFilter.EACH_LABEL
check(EACH == 3 and vtkIINormalEstimator.EACH_LABEL == 3, "EACH_LABEL is 3 in both filters")

combined = surface(EACH)
label_of = cell_array(combined, "Label")
check(sorted(set(label_of.tolist())) == LABELS, "Label holds the 3 labels %s" % sorted(set(label_of.tolist())))
check(list(label_of) == sorted(label_of), "labels appended in increasing order")
fd = combined.GetFieldData()
check(list(vtk_to_numpy(fd.GetArray("ImageExtent"))) == [0, n[0] - 1, 0, n[1] - 1, 0, n[2] - 1],
      "ImageExtent is the whole image's")

single = {L: surface(vtkDigitalSurfaceFilter.LABEL, label=L) for L in LABELS}
point_base = 0
for L in LABELS:
    sel = label_of == L
    one = single[L]
    same_voxels = np.array_equal(cell_array(combined, "InsideVoxel")[sel], cell_array(one, "InsideVoxel"))
    same_dirs = np.array_equal(cell_array(combined, "SurfelDirection")[sel], cell_array(one, "SurfelDirection"))
    check(sel.sum() == one.GetNumberOfCells() and same_voxels and same_dirs,
          "label %d: %d surfels, the Label run's, same order" % (L, sel.sum()))
    check(np.array_equal(quads(combined)[sel], quads(one)),
          "label %d: the same world corners, bitwise" % L)
    conn = vtk_to_numpy(combined.GetPolys().GetConnectivityArray()).reshape(-1, 4)[sel]
    check(conn.min() == point_base and conn.max() == point_base + one.GetNumberOfPoints() - 1,
          "label %d: its own %d points, shared with no other label" % (L, one.GetNumberOfPoints()))
    point_base += one.GetNumberOfPoints()
check(combined.GetNumberOfPoints() == point_base, "no point beyond the labels' own")
# Faces between two labels are in both: more cells than the union of faces.
touching = int(((data[:, :, 1:] != data[:, :, :-1]) & (data[:, :, 1:] > 0) & (data[:, :, :-1] > 0)).sum())
check(touching > 0, "labels 2, 5 and 9 touch (%d faces along x)" % touching)

sub = surface(EACH, labels="2,7-9")
check(sorted(set(cell_array(sub, "Label").tolist())) == [2, 9], "Labels '2,7-9' gives labels 2 and 9")

# II normals per label: bitwise the Label-mode run's.
each_ii, each_fallbacks = ii(combined, EACH)
check(each_ii.GetNumberOfCells() == combined.GetNumberOfCells(), "II EachLabel keeps every cell")
fallbacks = 0
for L in LABELS:
    sel = label_of == L
    one, fb = ii(single[L], vtkIINormalEstimator.LABEL, label=L)
    fallbacks += fb
    for name in ("IINormals", "IIMeanCurvature", "IIK1", "IIK2", "IIK1Direction"):
        a, b = cell_array(each_ii, name)[sel], cell_array(one, name)
        check(a.shape == b.shape and np.array_equal(a, b), "label %d: %s bitwise the Label run's" % (L, name))
check(each_fallbacks == fallbacks, "trivial fallbacks summed over labels (%d)" % fallbacks)


# AT on the combined surface: labels are separate components, so each
# label's problem is a block of a block-diagonal system.
def at_run(pd, exact):
    f = vtkAmbrosioTortorelliFilter()
    f.SetInputData(pd)
    if exact:
        # An exact factorisation and a fixed number of alternations: the
        # only difference left is rounding.
        f.SetLinearSolver(vtkAmbrosioTortorelliFilter.SIMPLICIAL_LDLT)
        f.SetTolerance(0)
    f.Update()
    return f.GetOutput()


def at_differences(exact):
    both = at_run(each_ii, exact)
    worst_angle, worst_v, worst_n = 0.0, 0.0, 0.0
    conn_all = vtk_to_numpy(both.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    for L in LABELS:
        sel = label_of == L
        one_ii, _ = ii(single[L], vtkIINormalEstimator.LABEL, label=L)
        one = at_run(one_ii, exact)
        a, b = cell_array(both, "ATNormals")[sel], cell_array(one, "ATNormals")
        worst_n = max(worst_n, float(np.abs(a - b).max()))
        cosines = np.clip(np.sum(a * b, axis=1), -1, 1)
        worst_angle = max(worst_angle, float(np.degrees(np.arccos(cosines)).max()))
        va = vtk_to_numpy(both.GetPointData().GetArray("ATFeatureIndicator"))[conn_all[sel]]
        one_conn = vtk_to_numpy(one.GetPolys().GetConnectivityArray()).reshape(-1, 4)
        vb = vtk_to_numpy(one.GetPointData().GetArray("ATFeatureIndicator"))[one_conn]
        worst_v = max(worst_v, float(np.abs(va - vb).max()))
    return worst_angle, worst_v, worst_n


angle, dv, dn = at_differences(exact=True)
print("AT exact: largest |dn| %.3g (angle %.3g deg), largest |dv| %.3g" % (dn, angle, dv))
check(dn < 1e-12 and dv < 1e-12, "AT (LDLT, fixed steps) per label = the label alone, to rounding (1e-12)")
angle, dv, dn = at_differences(exact=False)
print("AT default: largest angle %.3g deg, largest |dv| %.3g" % (angle, dv))
# The default CG-IC stops on the relative residual of the whole
# block-diagonal system (1e-5), not of each label's block, and the
# alternation on the largest |v - v_prev| over all labels: each of the two
# runs is within dgATSolver.h's 0.0015 degrees and 4e-4 in v of the exact
# solve, so they differ by at most twice that.
check(angle < 0.003 and dv < 8e-4, "AT (default solver) per label within 0.003 deg and 8e-4 in v")

# The split filter: one named block per label, the label's cells and points.
split = vtkSplitByLabelFilter()
split.SetInputData(each_ii)
split.Update()
pdc = split.GetOutput()
check(pdc.GetNumberOfPartitionedDataSets() == 3, "split: 3 blocks")
for b, L in enumerate(LABELS):
    name = pdc.GetMetaData(b).Get(vtkCompositeDataSet.NAME()) if pdc.HasMetaData(b) else None
    part = pdc.GetPartition(b, 0)
    ok = part is not None and part.GetNumberOfCells() == single[L].GetNumberOfCells() and \
        part.GetNumberOfPoints() == single[L].GetNumberOfPoints()
    check(name == "Label %d" % L and ok, "block %d named %r, %d cells and %d points" %
          (b, name, part.GetNumberOfCells() if part else -1, part.GetNumberOfPoints() if part else -1))
    if part is not None:
        check(np.array_equal(cell_array(part, "IINormals"), cell_array(each_ii, "IINormals")[label_of == L]),
              "block %d keeps its cells' data" % b)


# Interfaces: each face between two different values (labels or background,
# the image's outside included) once, out of the larger label, on shared
# points; II in EachLabel mode gives each face its inside label's normal, the
# same as that label's own EachLabel surface.
inter = surface(vtkDigitalSurfaceFilter.INTERFACES)
padded = np.pad(data, 1)
pairs = sum(int((np.diff(padded, axis=a) != 0).sum()) for a in range(3))
ins, outs = cell_array(inter, "LabelInside"), cell_array(inter, "LabelOutside")
check(inter.GetNumberOfCells() == pairs, "Interfaces: one face per pair of different neighbours (%d, %d)"
      % (inter.GetNumberOfCells(), pairs))
check(bool(np.all(ins > outs)) and np.array_equal(ins, cell_array(inter, "Label")),
      "Interfaces: LabelInside > LabelOutside, Label = LabelInside")
ipts = vtk_to_numpy(inter.GetPoints().GetData())
check(len(np.unique(np.round(ipts, 9), axis=0)) == len(ipts), "Interfaces: every voxel corner once (shared points)")
ivox = vtk_to_numpy(inter.GetCellData().GetArray("InsideVoxel"))
idir = cell_array(inter, "SurfelDirection")
inorm = vtk_to_numpy(ii(inter, EACH)[0].GetCellData().GetArray("IINormals"))
cvox = vtk_to_numpy(combined.GetCellData().GetArray("InsideVoxel"))
cnorm = vtk_to_numpy(ii(combined, EACH)[0].GetCellData().GetArray("IINormals"))
where = {(int(L), tuple(v), int(d)): c for c, (L, v, d) in
         enumerate(zip(label_of, cvox.tolist(), cell_array(combined, "SurfelDirection")))}
match = [where.get((int(L), tuple(v), int(d))) for L, v, d in zip(ins, ivox.tolist(), idir)]
check(None not in match and np.array_equal(inorm, cnorm[match]),
      "Interfaces: each face's II normal is its inside label's, bit for bit")

# Bad inputs: one clear error and an empty output.
def errors_of(f):
    errors = []
    f.AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
    f.GetExecutive().AddObserver(vtkCommand.ErrorEvent, lambda o, e: None)
    f.Update()
    return errors


for labels, what in (("", "an empty label list"), ("42,100-200", "a list naming no present label"),
                     ("3-x", "a malformed list")):
    f = vtkDigitalSurfaceFilter()
    f.SetInputData(image)
    f.SetSelectionMode(EACH)
    f.SetLabels(labels)
    errs = errors_of(f)
    check(len(errs) >= 1 and f.GetOutput().GetNumberOfCells() == 0, "EachLabel with %s: error, empty output" % what)

plain = surface(vtkDigitalSurfaceFilter.NON_ZERO)
f = vtkIINormalEstimator()
f.SetInputData(plain)
f.SetSourceData(image)
f.SetSelectionMode(EACH)
errs = errors_of(f)
check(len(errs) >= 1 and f.GetOutput().GetNumberOfCells() == 0, "II EachLabel without a Label array: error, empty")

f = vtkSplitByLabelFilter()
f.SetInputData(plain)
errs = errors_of(f)
check(len(errs) >= 1 and f.GetOutput().GetNumberOfPartitionedDataSets() == 0, "split without Label: error, empty")

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
