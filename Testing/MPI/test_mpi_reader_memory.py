"""The readers read only their piece (issue 38): a 2-rank run of a .vol
(Version 3, one zlib stream) or a .nii.gz of a 256^3 one-byte volume has a
per-rank peak memory of the read below 0.75 x the one-rank run's, and each
rank's voxels are its box of the volume.

    test_mpi_reader_memory.py vol|nii.gz

The volume (a ball and a slab with a ramp, 16.8 MB) is generated here. Each
rank runs reader_rss.py: piece r of N with one ghost layer, peak RSS during
the read (VmHWM reset just before it) minus the RSS before it, i.e. what
the read itself holds at its peak; the ~60 MB of Python and VTK every rank
carries whatever it reads are left out, or no reader could reach 0.75. One
rank reads the whole volume (16.8 MB); before issue 38 each of 2 ranks
inflated the whole file too, so its read peaked at the whole volume plus
its box (x 1.5 of one rank's)."""
import json
import os
import subprocess
import sys
import tempfile
import zlib

import numpy as np

import mpi_cases as mc

KIND = sys.argv[1]
N = 256
HERE = os.path.dirname(os.path.abspath(__file__))
MPIRUN = [os.environ["DG_MPIRUN"], "--allow-run-as-root", "--oversubscribe"]
ROOT = tempfile.mkdtemp(prefix="dg_mpi_reader_memory_", dir=os.environ.get("DG_TEST_TMP"))
check = mc.Checks()

# x fastest in the files: volume[z, y, x].
z, y, x = np.ogrid[0:N, 0:N, 0:N]
volume = np.where((x - 120) ** 2 + (y - 130) ** 2 + (z - 110) ** 2 < 90 ** 2, 200, 0).astype(np.uint8)
volume[:, 40:60, :] = (x % 251).astype(np.uint8)
if KIND == "vol":
    path = os.path.join(ROOT, "v.vol")
    header = "X: %d\nY: %d\nZ: %d\nVoxel-Size: 1\nVersion: 3\n.\n" % (N, N, N)
    with open(path, "wb") as f:
        f.write(header.encode() + zlib.compress(volume.tobytes(), 6))
else:
    import nibabel as nib
    path = os.path.join(ROOT, "v.nii.gz")
    nib.save(nib.Nifti1Image(volume.transpose(2, 1, 0), np.eye(4)), path)


def weights(box):
    n = (box[1] - box[0] + 1) * (box[3] - box[2] + 1) * (box[5] - box[4] + 1)
    return 1 + np.arange(n, dtype=np.int64) % 7


def run(ranks):
    # Each rank's report in a file of its own: through mpirun's one stdout
    # pipe two ranks' lines can end up on one line.
    report = os.path.join(ROOT, "report%d" % ranks)
    p = subprocess.run(MPIRUN + ["-np", str(ranks), sys.executable, os.path.join(HERE, "reader_rss.py"), path, "1",
                                 report], capture_output=True, text=True, timeout=120)
    lines = []
    for r in range(ranks):
        if os.path.exists("%s.%d.json" % (report, r)):
            with open("%s.%d.json" % (report, r)) as f:
                lines.append(json.loads(f.read()))
    check(p.returncode == 0 and len(lines) == ranks and all(l["ok"] for l in lines),
          "%s, %d rank(s): exit %d, %d report(s)%s" % (KIND, ranks, p.returncode, len(lines),
                                                     "" if p.returncode == 0 else ": " + p.stderr[-300:]))
    return sorted(lines, key=lambda l: l["rank"])


one = run(1)
two = run(2)
if len(one) == 1 and len(two) == 2:
    for l in one + two:
        e = l["extent"]
        box = volume[e[4]:e[5] + 1, e[2]:e[3] + 1, e[0]:e[1] + 1].astype(np.int64).ravel()
        check(int(np.dot(box, weights(e))) == l["checksum"],
              "rank %d of %d: the voxels of its box %s" % (l["rank"], l["size"], e))
    base = one[0]["peak"] - one[0]["rss_before"]
    print("one rank: read %.3f s, peak %.1f MB above %.1f MB" % (one[0]["seconds"], base / 1e6, one[0]["rss_before"] / 1e6))
    for l in two:
        own = l["peak"] - l["rss_before"]
        check(own < 0.75 * base,
              "%s, rank %d of 2: the read's peak %.1f MB = %.2f x the one-rank run's %.1f MB (< 0.75); read %.3f s, "
              "process peak %.1f MB against %.1f MB" % (KIND, l["rank"], own / 1e6, own / base, base / 1e6, l["seconds"],
                                                        l["peak"] / 1e6, one[0]["peak"] / 1e6))
sys.exit(check.finish(ROOT))
