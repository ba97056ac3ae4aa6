#!/usr/bin/python3
"""Time and memory of the readers' part reads (issue 38): a whole read against
one piece of 2 and one of 4, for fandisk-256.vol and octa-flower17k-512.vol
(../shared/data/volgallery) and the same volumes as .nii.gz (written by
nibabel into a temporary folder).

    /usr/bin/python3 Benchmarks/bench_piece_readers.py [--runs 3] [--ghosts 1] [--volumes A.vol B.vol]
        [--build DIR]

--build: the build tree whose Python package is measured (default: this
tree's build/; another checkout's build gives the figures before a change).

Each measurement is a process of its own (Testing/MPI/reader_rss.py, as one
rank of mpirun would run it, without mpirun): piece 0 of N as VTK's block
split makes it, grown by --ghosts layers, asked for as an explicit extent;
the read's wall time, the process's RSS before the read and its peak
during the read (VmHWM reset just before it). Prints every run, then a
Markdown table of the medians. Needs the build's Python package on
PYTHONPATH (build/lib/python3/dist-packages)."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "data", "volgallery")
CHILD = os.path.join(ROOT, "Testing", "MPI", "reader_rss.py")

parser = argparse.ArgumentParser()
parser.add_argument("--runs", type=int, default=3)
parser.add_argument("--ghosts", type=int, default=1)
parser.add_argument("--build", default=os.path.join(ROOT, "build"))
parser.add_argument("--volumes", nargs="*", default=[os.path.join(SHARED, "fandisk-256.vol"),
                                                     os.path.join(SHARED, "octa-flower17k-512.vol")])
args = parser.parse_args()

env = dict(os.environ)
package = os.path.join(os.path.abspath(args.build), "lib", "python3", "dist-packages")
env["PYTHONPATH"] = package + (":" + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
env.setdefault("VTK_SMP_BACKEND_IN_USE", "Sequential")
tmp = tempfile.mkdtemp(prefix="dg_bench_piece_readers_")


def to_nifti(vol):
    """The .vol's voxels as a .nii.gz (nibabel's default compression), in tmp."""
    code = r'''
import sys, numpy as np, nibabel as nib
from vtkmodules.util.numpy_support import vtk_to_numpy
from digitalgeometry import vtkDGtalVolReader
r = vtkDGtalVolReader(); r.SetFileName(sys.argv[1]); r.Update()
e = r.GetOutput().GetExtent()
v = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(e[5] + 1, e[3] + 1, e[1] + 1)
nib.save(nib.Nifti1Image(v.transpose(2, 1, 0), np.eye(4)), sys.argv[2])
'''
    out = os.path.join(tmp, os.path.basename(vol)[:-4] + ".nii.gz")
    subprocess.run([sys.executable, "-c", code, vol, out], check=True, env=env)
    return out


def measure(path, pieces):
    e = dict(env, OMPI_COMM_WORLD_RANK="0", OMPI_COMM_WORLD_SIZE=str(pieces))
    p = subprocess.run([sys.executable, CHILD, path, str(args.ghosts)], capture_output=True, text=True, env=e,
                       timeout=600)
    line = [l for l in p.stdout.splitlines() if l.startswith("{")]
    if p.returncode != 0 or not line:
        sys.exit("%s, piece 0 of %d failed: %s" % (path, pieces, p.stderr[-400:]))
    return json.loads(line[0])


files = []
for vol in args.volumes:
    files += [vol, to_nifti(vol)]
print("package: " + package)
with open("/proc/loadavg") as f:
    print("load average before: " + f.read().strip())
rows = []
for path in files:
    for pieces in (1, 2, 4):
        runs = []
        for _ in range(args.runs):
            r = measure(path, pieces)
            runs.append(r)
            print("%s piece 0 of %d: extent %s, %.3f s, RSS before %.1f MB, peak %.1f MB" % (
                os.path.basename(path), pieces, r["extent"], r["seconds"], r["rss_before"] / 1e6, r["peak"] / 1e6),
                flush=True)
        e = runs[0]["extent"]
        rows.append((os.path.basename(path), pieces, "%d x %d x %d" % (e[1] - e[0] + 1, e[3] - e[2] + 1, e[5] - e[4] + 1),
                     statistics.median(r["seconds"] for r in runs),
                     statistics.median((r["peak"] - r["rss_before"]) / 1e6 for r in runs),
                     statistics.median(r["peak"] / 1e6 for r in runs),
                     os.path.getsize(path)))
with open("/proc/loadavg") as f:
    print("load average after: " + f.read().strip())
print()
print("| file | request | extent | read | the read's peak | process peak |")
print("|---|---|---|---|---|---|")
for name, pieces, extent, seconds, own, peak, size in rows:
    request = "whole" if pieces == 1 else "piece 0 of %d" % pieces
    print("| %s | %s | %s | %.3f s | %.1f MB | %.1f MB |" % (name, request, extent, seconds, own, peak))
