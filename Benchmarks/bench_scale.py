#!/usr/bin/python3
"""The whole program with its defaults at scale, on 1 and 2 ranks (issue 38's
scale benchmark, docs/distributed.md): wall time per stage, per-rank peak
memory and what the sharp stage's gather moves.

    /usr/bin/python3 Benchmarks/bench_scale.py [--runs 3] [--ranks 1,2]
        [--upsample 1,2] [--program PATH] [VOLUME]

VOLUME: a .vol (default ../shared/data/volgallery/octa-flower17k-512.vol).
--upsample F also runs F x the volume along each axis (each voxel an F^3
block; F = 2 turns octa-flower 512^3 into 1024^3), written as a Version 3
.vol in a temporary folder outside the repository and removed afterwards.
One rank runs the program as is (VTK's threads on every core); R > 1 ranks
run it under mpirun with one thread each (VTK_SMP_MAX_THREADS=1), so both
use the machine's cores. Prints every run, then the medians, with the
machine and its load.
"""
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT = os.path.join(ROOT, "..", "shared", "data", "volgallery", "octa-flower17k-512.vol")
STAGES = ["read", "islands", "digital surface", "II normals", "Ambrosio-Tortorelli",
          "sharp features", "write", "total"]


def upsample(path, factor, out):
    """Writes `path` (a .vol) upsampled by `factor` along each axis to `out`."""
    import numpy as np
    sys.path.insert(0, os.path.join(ROOT, "build", "lib", "python3", "dist-packages"))
    from digitalgeometry import vtkDGtalVolReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    r = vtkDGtalVolReader()
    r.SetFileName(path)
    r.Update()
    nx, ny, nz = r.GetOutput().GetDimensions()
    a = vtk_to_numpy(r.GetOutput().GetPointData().GetScalars()).reshape(nz, ny, nx)
    a = a.repeat(factor, axis=0).repeat(factor, axis=1).repeat(factor, axis=2)
    with open(out, "wb") as f:
        f.write(("X: %d\nY: %d\nZ: %d\nVoxel-Size: 1\nVersion: 3\n.\n"
                 % (factor * nx, factor * ny, factor * nz)).encode())
        c = zlib.compressobj(6)
        flat = a.reshape(-1)
        for i in range(0, flat.size, 1 << 26):
            f.write(c.compress(flat[i:i + (1 << 26)].tobytes()))
        f.write(c.flush())


def parse(text):
    out = {}
    line = next((l for l in text.splitlines() if l.strip().startswith("time")), "")
    for name in STAGES:
        m = re.search(re.escape(name) + r" ([0-9.]+) s", line)
        if m:
            out[name] = float(m.group(1))
    m = re.search(r"peak memory (\d+) MiB(?: per rank at most \(rank 0 (\d+) MiB, all ranks (\d+) MiB\))?", line)
    if m:
        out["peak max"] = float(m.group(1))
        out["peak rank 0"] = float(m.group(2) or m.group(1))
        out["peak all"] = float(m.group(3) or m.group(1))
    m = re.search(r"rank 0 sent and received ([0-9.]+) MiB in (\d+) calls \(all ranks: ([0-9.]+) MiB, (\d+) calls\)",
                  text)
    if m:
        out["gather MiB rank 0"], out["gather calls rank 0"] = float(m.group(1)), float(m.group(2))
        out["gather MiB all"], out["gather calls all"] = float(m.group(3)), float(m.group(4))
    m = re.search(r": (\d+) surfels, (\d+) feature edges", text)
    if m:
        out["surfels"], out["edges"] = float(m.group(1)), float(m.group(2))
    return out


def main(argv):
    runs, ranks, factors = 3, [1, 2], [1]
    program = os.path.join(ROOT, "build", "bin", "piecewise-normals")
    volume = DEFAULT
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--runs":
            runs = int(argv[i + 1]); i += 2
        elif a == "--ranks":
            ranks = [int(x) for x in argv[i + 1].split(",")]; i += 2
        elif a == "--upsample":
            factors = [int(x) for x in argv[i + 1].split(",")]; i += 2
        elif a == "--program":
            program = argv[i + 1]; i += 2
        else:
            volume = a; i += 1
    tmp = tempfile.mkdtemp(prefix="dg_bench_scale_")
    try:
        print("machine: %s, %d cores, %s; load average %s" % (
            platform.node(), os.cpu_count(), platform.processor() or platform.machine(),
            " ".join("%.2f" % x for x in os.getloadavg())))
        for factor in factors:
            path = volume
            if factor > 1:
                path = os.path.join(tmp, "x%d.vol" % factor)
                t0 = time.monotonic()
                upsample(volume, factor, path)
                print("upsampled %s by %d: %s (%.1f s)" % (os.path.basename(volume), factor, path,
                                                          time.monotonic() - t0))
            for r in ranks:
                cmd = [program, "--no-png", "--quiet", "--output-dir", os.path.join(tmp, "out"), path]
                env = dict(os.environ)
                if r > 1:
                    cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(r)] + cmd
                    env["VTK_SMP_MAX_THREADS"] = "1"
                results = []
                for k in range(runs):
                    t0 = time.monotonic()
                    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
                    wall = time.monotonic() - t0
                    if p.returncode != 0:
                        print(p.stdout[-2000:], p.stderr[-2000:])
                        return 1
                    res = parse(p.stdout)
                    res["process wall"] = wall
                    results.append(res)
                    print("x%d, %d rank(s), run %d: %s" % (factor, r, k + 1, ", ".join(
                        "%s %g" % (n, v) for n, v in res.items())))
                    sys.stdout.flush()
                keys = [n for n in results[0] if all(n in x for x in results)]
                print("x%d, %d rank(s), median of %d: %s" % (factor, r, runs, ", ".join(
                    "%s %g" % (n, statistics.median(x[n] for x in results)) for n in keys)))
        print("load average after: %s" % " ".join("%.2f" % x for x in os.getloadavg()))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
