"""One rank's part read, for test_mpi_reader_memory.py and
Benchmarks/bench_piece_readers.py: reads piece RANK of SIZE (OpenMPI's
OMPI_COMM_WORLD_RANK / _SIZE; 0 of 1 without mpirun) of a .vol or NIfTI file
with GHOSTS ghost layers and prints one line of JSON: the rank, the
extent, the read's wall time, the process's RSS before the read, its peak
during the read (VmHWM, reset just before the read through
/proc/self/clear_refs, so that the import's peak does not count) and a
checksum of the voxels (sum of value x (1 + point index mod 7)). With
REPORT, the line goes to the file REPORT.RANK.json instead: mpirun forwards
the ranks' stdout through one pipe, where two ranks' lines can meet on one.

    reader_rss.py FILE [GHOSTS [REPORT]]
"""
import json
import os
import sys
import time

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator, vtkStreamingDemandDrivenPipeline

from digitalgeometry import vtkDGtalVolReader, vtkNIfTIVolumeReader


def status(key):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0


path = sys.argv[1]
ghosts = int(sys.argv[2]) if len(sys.argv) > 2 else 1
rank = int(os.environ.get("OMPI_COMM_WORLD_RANK", "0"))
size = int(os.environ.get("OMPI_COMM_WORLD_SIZE", "1"))
reader = vtkDGtalVolReader() if path.endswith(".vol") else vtkNIfTIVolumeReader()
reader.SetFileName(path)
reader.UpdateInformation()
# The piece's box (VTK's block split, grown by the ghost layers) asked for as
# an explicit extent, as the program's pipeline asks its reader: with
# UpdatePiece(r, n, g > 0) the executive would add vtkGhostType point and cell
# arrays (2 bytes a voxel, twice a one-byte volume) that are not the
# reader's.
whole = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT())
box = [0] * 6
vtkExtentTranslator().PieceToExtentThreadSafe(rank, size, ghosts, list(whole), box,
                                              vtkExtentTranslator.BLOCK_MODE, 0)
before = status("VmRSS")
with open("/proc/self/clear_refs", "w") as f:
    f.write("5")  # VmHWM := VmRSS
t0 = time.perf_counter()
ok = reader.UpdateExtent(box)
seconds = time.perf_counter() - t0
peak = status("VmHWM")
image = reader.GetOutput()
scalars = image.GetPointData().GetScalars()
checksum = 0
if scalars is not None:
    v = vtk_to_numpy(scalars).astype(np.int64).ravel()
    checksum = int(np.dot(v, 1 + np.arange(v.size, dtype=np.int64) % 7))
report = json.dumps({"rank": rank, "size": size, "ok": bool(ok), "extent": list(image.GetExtent()),
                     "seconds": seconds, "rss_before": before, "peak": peak, "checksum": checksum})
if len(sys.argv) > 3:
    with open("%s.%d.json" % (sys.argv[3], rank), "w") as f:
        f.write(report + "\n")
else:
    print(report, flush=True)
