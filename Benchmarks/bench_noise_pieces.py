#!/usr/bin/python3
"""Memory and time of the noise on pieces (issue 38): vtkDigitalNoiseFilter
on a generated 256^3 volume (a rotated cube and a ball, written as a raw
.vol into a temporary folder), the whole volume in one process against each
rank of 2 (and of 4), at k = 0.3 and 0.5.

    /usr/bin/python3 Benchmarks/bench_noise_pieces.py [--runs 3] [--size 256] [--pieces 1 2 4]
        [--build DIR]

Each measurement is a process of its own, as one rank of mpirun would run
it (without mpirun): the rank's own voxels (dg::PieceExtent: VTK's block
split, by points) asked of the noise filter as an explicit extent, as the
island filter asks it in the program. The reader first reads the box the
noise will ask for (the piece grown by the reach), then the noise stage
runs alone: its wall time, the process's RSS before it (the interpreter,
VTK and the box read) and its peak during it (VmHWM reset just before it);
"the stage's peak" is the difference. One thread (VTK_SMP_BACKEND_IN_USE
Sequential), so that the times compare the work. The first run of every
piece is checked against the whole run, voxel for voxel. Prints every run,
then a Markdown table of the medians. Needs the build's Python package
(--build, default this tree's build/)."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def status(key):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    return 0


def child(path, k, rank, size, dump):
    """One rank: prints one line of JSON."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator, vtkStreamingDemandDrivenPipeline
    from digitalgeometry import vtkDGtalVolReader, vtkDigitalNoiseFilter
    reader = vtkDGtalVolReader()
    reader.SetFileName(path)
    reader.UpdateInformation()
    whole = list(reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT()))
    own = list(whole)
    if size > 1:
        t = vtkExtentTranslator()
        t.PieceToExtentThreadSafe(rank, size, 0, list(whole), own, vtkExtentTranslator.BLOCK_MODE, 1)
    noise = vtkDigitalNoiseFilter()
    noise.SetInputConnection(reader.GetOutputPort())
    noise.SetNoiseLevel(k)
    noise.SetSeed(1)
    dims = [whole[2 * a + 1] - whole[2 * a] + 1 for a in range(3)]
    reach = noise.ComputeReach(float(np.prod(dims)), max(dims))
    box = [max(whole[a], own[a] - reach) if a % 2 == 0 else min(whole[a], own[a] + reach) for a in range(6)]
    t0 = time.perf_counter()
    reader.UpdateExtent(box)
    read = time.perf_counter() - t0
    before = status("VmRSS")
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")  # VmHWM := VmRSS
    t0 = time.perf_counter()
    ok = noise.UpdateExtent(own)
    seconds = time.perf_counter() - t0
    peak = status("VmHWM")
    out = noise.GetOutput()
    if dump:
        np.save(dump, vtk_to_numpy(out.GetPointData().GetScalars()))
    print(json.dumps({"ok": bool(ok), "reach": reach, "own": own, "box": list(reader.GetOutput().GetExtent()),
                      "expected_box": box, "output": list(out.GetExtent()), "read": read, "seconds": seconds,
                      "rss_before": before, "peak": peak, "flipped": noise.GetNumberOfFlippedVoxels(),
                      "uncertain": noise.GetNumberOfUncertainVoxels()}), flush=True)


def write_volume(path, n):
    """A rotated cube (half-side 0.23 n) and a ball (radius 0.2 n), overlapping, as a raw .vol."""
    c, s = np.cos(0.5), np.sin(0.5)
    j, i = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float), indexing="ij")
    head = "X: %d\nY: %d\nZ: %d\nVoxel-Size: 1\nAlpha-Color: 0\nVoxel-Endian: 0\nInt-Endian: 0123\nVersion: 2\n.\n" % (n, n, n)
    with open(path, "wb") as f:
        f.write(head.encode())
        for k in range(n):
            x, y, zc, zb = i - 0.5 * n + 0.3, j - 0.5 * n - 0.2, k - 0.4 * n + 0.1, k - 0.66 * n
            rx, ry = c * x - s * y, s * x + c * y
            cube = (np.abs(rx) < 0.23 * n) & (np.abs(c * ry - s * zc) < 0.21 * n) & (np.abs(s * ry + c * zc) < 0.22 * n)
            ball = x * x + y * y + zb * zb < (0.2 * n) ** 2
            f.write((cube | ball).astype(np.uint8).tobytes())  # x fastest


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--pieces", type=int, nargs="*", default=[1, 2, 4])
    parser.add_argument("--levels", type=float, nargs="*", default=[0.3, 0.5])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--child", nargs=5, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        path, k, rank, size, dump = args.child
        return child(path, float(k), int(rank), int(size), dump if dump != "-" else None)

    env = dict(os.environ)
    package = os.path.join(os.path.abspath(args.build), "lib", "python3", "dist-packages")
    env["PYTHONPATH"] = package + (":" + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["VTK_SMP_BACKEND_IN_USE"] = "Sequential"
    tmp = tempfile.mkdtemp(prefix="dg_bench_noise_pieces_")
    vol = os.path.join(tmp, "shapes-%d.vol" % args.size)
    write_volume(vol, args.size)
    print("package: " + package)
    print("volume: %s (%d^3, raw .vol)" % (vol, args.size))
    with open("/proc/loadavg") as f:
        print("load average before: " + f.read().strip())

    def measure(k, rank, size, dump):
        p = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", vol, str(k), str(rank), str(size),
                            dump or "-"], capture_output=True, text=True, env=env, timeout=900)
        line = [x for x in p.stdout.splitlines() if x.startswith("{")]
        if p.returncode != 0 or not line:
            sys.exit("k %g, rank %d of %d failed: %s" % (k, rank, size, p.stderr[-600:]))
        r = json.loads(line[0])
        if not r["ok"] or r["box"] != r["expected_box"]:
            sys.exit("k %g, rank %d of %d: update failed or read %s, not %s" % (k, rank, size, r["box"], r["expected_box"]))
        return r

    rows = []
    for k in args.levels:
        whole = None
        for size in args.pieces:
            flipped = 0
            for rank in range(size):
                runs = []
                for run in range(args.runs):
                    dump = os.path.join(tmp, "out.npy") if run == 0 else None
                    r = measure(k, rank, size, dump)
                    runs.append(r)
                    if dump:
                        got = np.load(dump)
                        if size == 1:
                            whole = got.reshape(args.size, args.size, args.size)
                        else:
                            e = r["own"]
                            want = whole[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1].ravel()
                            if not np.array_equal(got, want):
                                sys.exit("k %g, rank %d of %d: differs from the whole run in %d voxels"
                                         % (k, rank, size, int(np.sum(got != want))))
                        os.remove(dump)
                    print("k %g rank %d of %d: reach %d, box %s, read %.3f s, noise %.3f s, RSS before %.1f MB, "
                          "peak %.1f MB, flipped %d, uncertain %d" % (
                              k, rank, size, r["reach"], r["box"], r["read"], r["seconds"], r["rss_before"] / 1e6,
                              r["peak"] / 1e6, r["flipped"], r["uncertain"]), flush=True)
                flipped += runs[0]["flipped"]
                b = runs[0]["box"]
                rows.append((k, size, rank, runs[0]["reach"], b, statistics.median(r["seconds"] for r in runs),
                             statistics.median((r["peak"] - r["rss_before"]) / 1e6 for r in runs),
                             statistics.median(r["peak"] / 1e6 for r in runs),
                             max(r["uncertain"] for r in runs)))
            print("k %g, %d piece(s): %d voxels flipped in all" % (k, size, flipped))
    with open("/proc/loadavg") as f:
        print("load average after: " + f.read().strip())
    print()
    print("| k | run | reach | box read (z) | voxels read | noise stage | the stage's peak | process peak | uncertain |")
    print("|---|---|---|---|---|---|---|---|---|")
    n3 = float(args.size) ** 3
    for k, size, rank, reach, b, seconds, own, peak, uncertain in rows:
        run = "one process" if size == 1 else "rank %d of %d" % (rank, size)
        voxels = (b[1] - b[0] + 1) * (b[3] - b[2] + 1) * (b[5] - b[4] + 1)
        box = "%d..%d, %d..%d, %d..%d" % tuple(b)
        print("| %g | %s | %d | %s | %.2f | %.2f s | %.0f MB | %.0f MB | %d |" % (
            k, run, reach, box, voxels / n3, seconds, own, peak, uncertain))


if __name__ == "__main__":
    sys.exit(main())
