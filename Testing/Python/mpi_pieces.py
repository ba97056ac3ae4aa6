"""Distributed filters under `mpirun -np N pvbatch --symmetric`: each rank
updates piece `rank` of N of reader -> islands -> surface -> II -> AT (plain
VTK classes through the Python wrapping, no plugin) and rank 0 compares the
union of the pieces with a one-process run of the same pipeline, by global
ids: the same surfels, bitwise the same II, VCM and RHT normals, AT normals within 0.01
degree and v within 1e-5 (at SolverTolerance 1e-8, the same on both sides),
the same feature edges; the N-rank result is bitwise reproducible; a rank
that fails makes every rank stop (no hang).

The volume: a thresholded analytic field (curved and creased parts), noisy
(k = 0.3, then islands < 8 voxels removed), plus voxel pairs that touch only
along an edge or at a corner placed on the first piece boundary, and a
corner region left empty, and with 3 or more pieces the last piece empty.
"""
import os

import numpy as np
from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator
from vtkmodules.vtkCommonCore import vtkIntArray
from vtkmodules.vtkImagingCore import vtkImageThreshold, vtkRTAnalyticSource
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLImageDataWriter
from vtkmodules.vtkParallelCore import vtkCommunicator, vtkMultiProcessController
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import digitalgeometry as dg

ctrl = vtkMultiProcessController.GetGlobalController()
rank, N = ctrl.GetLocalProcessId(), ctrl.GetNumberOfProcesses()
tmp = os.environ.get("DG_TEST_TMP", "/tmp")
path = os.path.join(tmp, "pieces_%d.vti" % N)
failures = []


def all_true(flag):
    """True on every rank when flag is true on every rank (collective)."""
    a, b = vtkIntArray(), vtkIntArray()
    a.InsertNextValue(1 if flag else 0)
    ctrl.AllReduce(a, b, vtkCommunicator.MIN_OP)
    return b.GetValue(0) == 1


def check(ok, what):
    if rank == 0:
        print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


WHOLE = (0, 39, -3, 30, 0, 35)
if rank == 0:
    src = vtkRTAnalyticSource()
    src.SetWholeExtent(*WHOLE)
    th = vtkImageThreshold()
    th.SetInputConnection(src.GetOutputPort())
    th.ThresholdByUpper(150)
    th.SetInValue(1)
    th.SetOutValue(0)
    th.SetOutputScalarTypeToUnsignedChar()
    noise = dg.vtkDigitalNoiseFilter()
    noise.SetInputConnection(th.GetOutputPort())
    noise.SetNoiseLevel(0.3)
    noise.SetSeed(3)
    noise.Update()
    img = noise.GetOutput()
    dims = img.GetDimensions()
    a = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(dims[2], dims[1], dims[0]).copy()
    # The first split plane of 2 pieces (block mode, by points, as the filters).
    t = vtkExtentTranslator()
    e = [0] * 6
    t.PieceToExtentThreadSafe(0, 2, 0, list(WHOLE), e, 3, 1)
    x = e[1] - WHOLE[0]  # last x index of piece 0 (split along x, the longest axis)
    # A rotated cube across the plane: sharp edges cut by the boundary.
    zz, yy, xx = np.mgrid[0:dims[2], 0:dims[1], 0:dims[0]].astype(float)
    c = np.array([x + 0.5, 8.0, 12.0])
    ca, sa, cb, sb = np.cos(0.5), np.sin(0.5), np.cos(0.3), np.sin(0.3)
    rot = np.array([[ca, -sa, 0], [sa, ca, 0], [0, 0, 1]]) @ np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    q = np.stack([xx - c[0], yy - c[1], zz - c[2]], axis=-1) @ rot
    a[np.abs(q).max(axis=-1) <= 6.5] = 1
    a[26:, 25:, :] = 0                     # an empty corner (z >= 26, y >= 25) ...
    a[28, 27, x] = a[29, 28, x + 1] = 1    # ... holding voxel pairs on the plane: one edge-touching pair,
    a[31, 27, x + 1] = a[32, 28, x] = 1    # the other diagonal,
    a[28, 31, x] = a[29, 32, x + 1] = 1    # a corner-touching pair (differs in x, y and z)
    a[30, 32, x + 1] = 1
    if N >= 3:
        # The last piece holds no inside voxel: an empty piece.
        t.PieceToExtentThreadSafe(N - 1, N, 0, list(WHOLE), e, 3, 1)
        a[e[4] - WHOLE[4]:e[5] - WHOLE[4] + 1, e[2] - WHOLE[2]:e[3] - WHOLE[2] + 1,
          e[0] - WHOLE[0]:e[1] - WHOLE[0] + 1] = 0
    img.GetPointData().SetScalars(numpy_to_vtk(a.ravel(), deep=1))
    w = vtkXMLImageDataWriter()
    w.SetInputData(img)
    w.SetFileName(path)
    w.Write()
ctrl.Barrier()


def pipeline(tol):
    r = vtkXMLImageDataReader()
    r.SetFileName(path)
    isl = dg.vtkDigitalIslandFilter()
    isl.SetInputConnection(r.GetOutputPort())
    s = dg.vtkDigitalSurfaceFilter()
    s.SetInputConnection(isl.GetOutputPort())
    s.GenerateGlobalIdsOn()
    ii = dg.vtkIINormalEstimator()
    ii.SetInputConnection(s.GetOutputPort())
    ii.SetSourceConnection(isl.GetOutputPort())
    ii.SetRadius(3)
    at = dg.vtkAmbrosioTortorelliFilter()
    at.SetInputConnection(ii.GetOutputPort())
    at.SetSolverTolerance(tol)
    # The other two estimators on the same surface (compared bitwise).
    vcm = dg.vtkVCMNormalEstimator()
    vcm.SetInputConnection(s.GetOutputPort())
    vcm.SetSourceConnection(isl.GetOutputPort())
    vcm.SetOffsetRadius(6)
    vcm.SetConvolutionRadius(3)
    rht = dg.vtkRHTNormalEstimator()
    rht.SetInputConnection(s.GetOutputPort())
    rht.SetSourceConnection(isl.GetOutputPort())
    rht.SetRadius(4)
    rht.SetNumberOfTrials(100)
    return at, (r, isl, s, ii, vcm, rht)


def estimator_normals(est, name):
    o = est.GetOutput()
    return dict(cid=vtk_to_numpy(o.GetCellData().GetArray("GlobalIds")),
                n=vtk_to_numpy(o.GetCellData().GetArray(name)))


def arrays(at):
    o, f = at.GetOutput(), at.GetOutput(1)
    cd, pd = o.GetCellData(), o.GetPointData()
    res = dict(cid=vtk_to_numpy(cd.GetArray("GlobalIds")), ii=vtk_to_numpy(cd.GetArray("IINormals")),
               at=vtk_to_numpy(cd.GetArray("ATNormals")), pid=vtk_to_numpy(pd.GetArray("GlobalIds")),
               v=vtk_to_numpy(pd.GetArray("ATFeatureIndicator")))
    if f.GetNumberOfLines():
        conn = vtk_to_numpy(f.GetLines().GetConnectivityArray())
        # Distributed: the lines have their own points and ids; one
        # process: they share the surface's points.
        ids = f.GetPointData().GetArray("GlobalIds")
        ids = vtk_to_numpy(ids) if ids else res["pid"]
        res["edges"] = np.sort(ids[conn].reshape(-1, 2), axis=1)
    else:
        res["edges"] = np.zeros((0, 2), np.int64)
    res["ghosts"] = cd.GetArray("vtkGhostType") is not None
    return res


def gather(res):
    np.savez(os.path.join(tmp, "piece_%d_%d.npz" % (N, rank)), **{k: v for k, v in res.items() if k != "ghosts"})
    ctrl.Barrier()
    if rank != 0:
        return None
    parts = [np.load(os.path.join(tmp, "piece_%d_%d.npz" % (N, r))) for r in range(N)]
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0].files}


at, keep = pipeline(1e-8)
at.UpdatePiece(rank, N, 0)
mine = arrays(at)
print("rank %d: %d surfels, %d feature edges" % (rank, len(mine["cid"]), len(mine["edges"])), flush=True)
ctrl.Barrier()
dist = gather(mine)
estimates = {}
for k, name in ((4, "VCMNormals"), (5, "RHTNormals")):
    keep[k].UpdatePiece(rank, N, 0)
    estimates[name] = gather(estimator_normals(keep[k], name))
# Determinism: the same N-rank solve again, from scratch.
at.Modified()
at.UpdatePiece(rank, N, 0)
again = arrays(at)
same = bool(np.array_equal(again["at"], mine["at"]) and np.array_equal(again["v"], mine["v"]))
check(all_true(same), "two %d-rank solves are bitwise equal" % N)
check(not mine["ghosts"], "no vtkGhostType in the output")
if N >= 3:
    check(all_true(rank != N - 1 or len(mine["cid"]) == 0), "the empty last piece works (0 surfels)")

if rank == 0:
    one, keep1 = pipeline(1e-8)
    one.Update()
    ref = arrays(one)
    check(len(dist["cid"]) == len(set(dist["cid"])), "every surfel once over the pieces (%d)" % len(dist["cid"]))
    check(set(dist["cid"]) == set(ref["cid"]), "the same surfels as one process (%d)" % len(ref["cid"]))
    order = {c: i for i, c in enumerate(ref["cid"])}
    idx = np.array([order[c] for c in dist["cid"]])
    check(np.array_equal(dist["ii"], ref["ii"][idx]), "II normals bitwise equal")
    for k, name in ((4, "VCMNormals"), (5, "RHTNormals")):
        keep1[k].Update()
        one_e = estimator_normals(keep1[k], name)
        e = estimates[name]
        pos = {c: i for i, c in enumerate(one_e["cid"])}
        same_set = len(e["cid"]) == len(one_e["cid"]) and set(e["cid"]) == set(one_e["cid"])
        check(same_set and np.array_equal(e["n"], one_e["n"][[pos[c] for c in e["cid"]]]),
              "%s bitwise equal to one process" % name)
    cosang = np.clip(np.abs(np.sum(dist["at"] * ref["at"][idx], axis=1)), 0, 1)
    maxang = float(np.degrees(np.arccos(cosang)).max())
    check(maxang <= 0.01, "AT normals within 0.01 degree (max %.2e)" % maxang)
    vref = dict(zip(ref["pid"], ref["v"]))
    maxdv = max(abs(v - vref[p]) for p, v in zip(dist["pid"], dist["v"]))
    check(maxdv <= 1e-5, "v within 1e-5 (max %.2e)" % maxdv)
    e1 = set(map(tuple, ref["edges"]))
    eN = list(map(tuple, dist["edges"]))
    check(len(eN) == len(set(eN)), "each feature edge once over the pieces (%d)" % len(eN))
    check(set(eN) == e1, "the same feature edges (%d, symmetric difference %d)" % (len(e1), len(e1 ^ set(eN))))
ctrl.Barrier()

# The world metric (docs/at-metric.md): each rank weighs its rows from its
# own points and halo; the result must be one process's.
atw = dg.vtkAmbrosioTortorelliFilter()
atw.SetInputConnection(keep[3].GetOutputPort())
atw.SetSolverTolerance(1e-8)
atw.SetMetricToWorld()
atw.UpdatePiece(rank, N, 0)
distw = gather(arrays(atw))
if rank == 0:
    onew = dg.vtkAmbrosioTortorelliFilter()
    onew.SetInputConnection(keep1[3].GetOutputPort())
    onew.SetSolverTolerance(1e-8)
    onew.SetMetricToWorld()
    onew.Update()
    refw = arrays(onew)
    order = {c: i for i, c in enumerate(refw["cid"])}
    idx = np.array([order[c] for c in distw["cid"]])
    cosang = np.clip(np.abs(np.sum(distw["at"] * refw["at"][idx], axis=1)), 0, 1)
    maxang = float(np.degrees(np.arccos(cosang)).max())
    vref = dict(zip(refw["pid"], refw["v"]))
    maxdv = max(abs(v - vref[p]) for p, v in zip(distw["pid"], distw["v"]))
    check(maxang <= 0.01 and maxdv <= 1e-5,
          "world metric: AT normals within 0.01 degree (max %.2e), v within 1e-5 (max %.2e)" % (maxang, maxdv))
    eW = set(map(tuple, distw["edges"]))
    check(eW == set(map(tuple, refw["edges"])), "world metric: the same feature edges (%d)" % len(eW))
ctrl.Barrier()

# A rank that fails (a bad radius on the last rank only) stops every rank.
at2, keep2 = pipeline(1e-8)
keep2[3].SetRadius(-1.0 if rank == N - 1 else 3.0)
at2.UpdatePiece(rank, N, 0)
check(all_true(at2.GetOutput().GetNumberOfCells() == 0), "a failing rank leaves every rank with an empty output, no hang")

ctrl.Barrier()
passed = all_true(not failures)
if rank == 0:
    print("%d rank(s): %s" % (N, "passed" if passed else "FAILED"), flush=True)
if not passed:
    # pvbatch exits non-zero on an uncaught error (sys.exit would skip MPI's finalize).
    raise RuntimeError("%d check(s) failed" % len(failures))
