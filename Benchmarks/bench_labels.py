"""What --labels costs against one-label runs on the whole volume: a label
map of N x N x N voxels holding 100 small labels (boxes with a ball cut out,
so each has sharp and curved parts), written as .nii.gz; the program with
--labels all, and with --label L for one label on the whole volume (what a
run per label costs, times 100). Prints medians of `runs` runs.

    /usr/bin/python3 Benchmarks/bench_labels.py [N=256] [runs=3]
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import nibabel as nib
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from label_map import hundred_label_map  # noqa: E402

N = int(sys.argv[1]) if len(sys.argv) > 1 else 256
RUNS = int(sys.argv[2]) if len(sys.argv) > 2 else 3
PROGRAM = os.environ.get("DG_PROGRAM", os.path.join(os.path.dirname(__file__), "..", "build", "bin", "piecewise-normals"))
tmp = tempfile.mkdtemp(prefix="dg_bench_labels_")
data = hundred_label_map(N)
path = os.path.join(tmp, "map.nii.gz")
nib.save(nib.Nifti1Image(data, np.eye(4)), path)
present = sorted(set(np.unique(data).tolist()) - {0})


def timed(*args):
    out = tempfile.mkdtemp(dir=tmp)
    t0 = time.perf_counter()
    p = subprocess.run([PROGRAM, "--no-png", "--output-dir", out, path] + list(args), capture_output=True, text=True)
    dt = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(p.stderr)
    surfels = int(re.search(r"(\d+) surfels", p.stdout).group(1))
    return dt, surfels, p.stdout


all_t, one_t = [], []
for _ in range(RUNS):
    dt, surfels, out = timed("--labels", "all")
    all_t.append(dt)
    dt1, surfels1, _ = timed("--label", str(present[len(present) // 2]))
    one_t.append(dt1)
load = os.getloadavg()[0]
print("volume %d^3, %d labels present, %d surfels in all" % (N, len(present), surfels))
print("--labels all: median %.2f s (runs: %s)" % (statistics.median(all_t), ", ".join("%.2f" % t for t in all_t)))
print("--label L on the whole volume (one label, %d surfels): median %.2f s; x %d labels = %.1f s"
      % (surfels1, statistics.median(one_t), len(present), statistics.median(one_t) * len(present)))
print("load average at the end: %.1f" % load)
print(out)
