"""The program's --noise under mpirun (issue 38): test_mpi_noise.py N.

Each rank reads its piece of a clean volume and adds the noise on it, its
noise filter reading only the layers the noise's reach needs (the filter's
own test, TestNoisePieces, checks the box it reads). The N-rank run must be
one process's: the same surfels by global ids (so the same noisy volume
once the islands are removed), bitwise the same II normals, AT within the
tight solver tolerance, the same feature edges, and the same summary
counts, the noise's flipped voxels and the islands' counts included (each
rank counts its own voxels). k = 0.3 and 0.5.

The volume is long along z (40 x 40 x 192) so that no rank's noise box is
the whole volume: the pieces are slabs, and their boxes (own voxels, the
II and surface layers, the island filter's reach, then the noise's) stop
short of the far end; the script prints them.
"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import mpi_cases as mc

N = int(sys.argv[1])
MPIRUN = [os.environ["DG_MPIRUN"], "--allow-run-as-root", "--oversubscribe"]
ROOT = tempfile.mkdtemp(prefix="dg_mpi_noise_np%d_" % N, dir=os.environ.get("DG_TEST_TMP"))
check = mc.Checks()
DIMS = (40, 40, 192)
WHOLE = [0, DIMS[0] - 1, 0, DIMS[1] - 1, 0, DIMS[2] - 1]


def make_volume(path):
    # A rotated cube in the lower half, a ball in the upper one: boundary
    # across the slabs' cuts, and voxels far from it on both sides.
    cube = mc.rotated_cube(DIMS, (19.6, 20.3, 64.7), 13.0, (20, 30, 10))
    ball = mc.ball(DIMS, (19.8, 20.1, 130.4), 16.5)
    mc.write_vti(mc.to_image(cube | ball, DIMS), path)


def program(ranks, k, tag):
    out = os.path.join(ROOT, tag)
    cmd = [os.environ["DG_PROGRAM"], "--quiet", "--no-png", "--plain", "--solver-tolerance", "1e-8",
           "--noise", str(k), "--seed", "3", "--output-dir", out, "--prefix", "r", VOLUME]
    if ranks:
        cmd = MPIRUN + ["-np", str(ranks)] + cmd
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    print("info %s: %.1f s; %s" % (tag, time.monotonic() - t0,
                                   (p.stdout.strip().splitlines() or ["no output"])[0]))
    if not check(p.returncode == 0, "%s: the program exits 0" % tag):
        print("--- stdout\n%s\n--- stderr\n%s" % (p.stdout[-3000:], p.stderr[-3000:]))
        sys.exit(check.finish(ROOT))
    ext = "pvtp" if ranks > 1 else "vtp"
    return p.stdout, os.path.join(out, "r_surface." + ext), os.path.join(out, "r_features." + ext)


def summary(text):
    """The summary's counts: surfels and edges, the noise's line, the islands' line."""
    lines = text.strip().splitlines()
    first = lines[0].split(": ", 1)[-1].split(" (")[0] if lines else ""
    noise = [x.strip() for x in lines if x.strip().startswith("noise k =")]
    islands = [x.strip() for x in lines if x.strip().startswith("removed ")]
    return first, noise, islands


VOLUME = os.path.join(ROOT, "slabs.vti")
make_volume(VOLUME)
print("case: rotated cube and ball in 40 x 40 x 192, --noise 0.3 and 0.5 (seed 3), %d ranks" % N)
from digitalgeometry import vtkDigitalNoiseFilter  # noqa: E402

for k in (0.3, 0.5):
    f = vtkDigitalNoiseFilter()
    f.SetNoiseLevel(k)
    reach = f.ComputeReach(float(np.prod(DIMS)), max(DIMS))
    # Layers asked of the noise around a rank's own voxels: II (r = 4:
    # ceil(r) + 1) through the surface, the island filter's 2 (8 - 1), the noise's.
    layers = 5 + 14 + reach
    boxes = []
    for p in range(N):
        e = mc.piece_extent(WHOLE, p, N)
        boxes.append("z %d..%d" % (max(0, e[4] - layers), min(WHOLE[5], e[5] + layers)))
    print("info k = %g: reach %d layers; each rank's noise box (own slab + %d layers): %s of z 0..%d"
          % (k, reach, layers, ", ".join(boxes), WHOLE[5]))
    one_out, one_s, one_f = program(0, k, "one-k%g" % k)
    run_out, run_s, run_f = program(N, k, "np%d-k%g" % (N, k))
    ref, res = mc.Result(one_s, one_f, reference=True), mc.Result(run_s, run_f)
    mc.compare(ref, res, check, "k = %g, np%d vs 1" % (k, N), 0.01, 1e-5)
    a, b = summary(one_out), summary(run_out)
    check(a[0] == b[0] != "", "k = %g: the same surfels and edges in the summary (%s | %s)" % (k, a[0], b[0]))
    check(a[1] == b[1] and len(a[1]) == 1,
          "k = %g: the same flipped voxels in the summary (%s | %s)" % (k, a[1], b[1]))
    check(a[2] == b[2] and len(a[2]) == 1,
          "k = %g: the same islands' counts in the summary (%s | %s)" % (k, a[2], b[2]))
sys.exit(check.finish(ROOT))
