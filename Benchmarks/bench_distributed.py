"""Distributed pipeline benchmark: run under
    mpirun --allow-run-as-root --oversubscribe -np N pvbatch --symmetric \
        Benchmarks/bench_distributed.py VOLUME.vol [RADIUS] [REPEATS]
(N = 1 works too). Each rank updates piece `rank` of N of
vtkDGtalVolReader -> vtkDigitalSurfaceFilter -> vtkIINormalEstimator ->
vtkAmbrosioTortorelliFilter (the filters' defaults: the paper's parameters),
stage by stage with a barrier between stages, REPEATS times from scratch.
Rank 0 prints per-stage wall times (medians), and every rank its surfels,
peak RSS, CG iterations and halo values; bytes exchanged per CG iteration
follow from the halo (8 bytes per value, 3 columns for the u-system).
"""
import resource
import statistics
import sys
import time

from vtkmodules.vtkParallelCore import vtkMultiProcessController

import digitalgeometry as dg

ctrl = vtkMultiProcessController.GetGlobalController()
rank, N = ctrl.GetLocalProcessId(), ctrl.GetNumberOfProcesses()
path = sys.argv[1]
radius = float(sys.argv[2]) if len(sys.argv) > 2 else 3.0
repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 3

times = {"read+surface": [], "II": [], "AT": []}
for _ in range(repeats):
    r = dg.vtkDGtalVolReader()
    r.SetFileName(path)
    s = dg.vtkDigitalSurfaceFilter()
    s.SetInputConnection(r.GetOutputPort())
    ii = dg.vtkIINormalEstimator()
    ii.SetInputConnection(s.GetOutputPort())
    ii.SetSourceConnection(r.GetOutputPort())
    ii.SetRadius(radius)
    at = dg.vtkAmbrosioTortorelliFilter()
    at.SetInputConnection(ii.GetOutputPort())
    # The surface with the ghost ring AT will ask for, so that the stages
    # are timed apart (AT's own update then reuses it).
    ctrl.Barrier()
    t0 = time.perf_counter()
    s.UpdatePiece(rank, N, 1 if N > 1 else 0)
    ctrl.Barrier()
    t1 = time.perf_counter()
    ii.UpdatePiece(rank, N, 1 if N > 1 else 0)
    ctrl.Barrier()
    t2 = time.perf_counter()
    at.UpdatePiece(rank, N, 0)
    ctrl.Barrier()
    t3 = time.perf_counter()
    times["read+surface"].append(t1 - t0)
    times["II"].append(t2 - t1)
    times["AT"].append(t3 - t2)
rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
u_bytes = at.GetHaloFaceValues() * 3 * 8
v_bytes = at.GetHaloVertexValues() * 8
for q in range(N):
    if q == rank:
        print("rank %d/%d: %d surfels out (%d with ghosts), peak RSS %.0f MiB, %d CG iterations, "
              "halo %d face + %d vertex values = %.1f KiB per u-iteration, %.1f KiB per v-iteration"
              % (rank, N, at.GetOutput().GetNumberOfCells(), ii.GetOutput().GetNumberOfCells(), rss,
                 at.GetNumberOfCGIterations(), at.GetHaloFaceValues(), at.GetHaloVertexValues(),
                 u_bytes / 1024.0, v_bytes / 1024.0), flush=True)
    ctrl.Barrier()
if rank == 0:
    print("%s, r = %g, %d rank(s), medians of %d: " % (path.split("/")[-1], radius, N, repeats) +
          ", ".join("%s %.2f s" % (k, statistics.median(v)) for k, v in times.items()) +
          ", total %.2f s" % sum(statistics.median(v) for v in times.values()), flush=True)
