"""What the filters' EachLabel mode costs against a Label-mode run per label
on the whole volume: bench_labels.py's map (N^3 voxels, 100 small labels:
boxes with a ball cut out), in memory; vtkDigitalSurfaceFilter +
vtkIINormalEstimator (r = 3) in EachLabel mode, and the same two filters in
Label mode on the whole volume for `sample` labels (times the number of
labels: what one run per label costs). Medians of `runs` runs.

    /usr/bin/python3 Benchmarks/bench_label_filters.py [N=256] [runs=3] [sample=10]

Needs the build tree's package on PYTHONPATH (build/lib/python3/dist-packages).
"""
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from label_map import hundred_label_map  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.util.numpy_support import numpy_to_vtk

from digitalgeometry import vtkDigitalSurfaceFilter, vtkIINormalEstimator

N = int(sys.argv[1]) if len(sys.argv) > 1 else 256
RUNS = int(sys.argv[2]) if len(sys.argv) > 2 else 3
SAMPLE = int(sys.argv[3]) if len(sys.argv) > 3 else 10
data = hundred_label_map(N)
present = sorted(set(np.unique(data).tolist()) - {0})
image = vtkImageData()
image.SetDimensions(N, N, N)
arr = numpy_to_vtk(data.ravel(), deep=1)
arr.SetName("labels")
image.GetPointData().SetScalars(arr)


def pipeline(mode, label=None):
    surf = vtkDigitalSurfaceFilter()
    surf.SetInputData(image)
    surf.SetSelectionMode(mode)
    ii = vtkIINormalEstimator()
    ii.SetInputConnection(surf.GetOutputPort())
    ii.SetSourceData(image)
    ii.SetRadius(3)
    ii.SetSelectionMode(mode)
    if label is not None:
        surf.SetLabel(label)
        ii.SetLabel(label)
    t0 = time.perf_counter()
    surf.Update()
    t1 = time.perf_counter()
    ii.Update()
    t2 = time.perf_counter()
    return t1 - t0, t2 - t1, ii.GetOutput().GetNumberOfCells()


each, one = [], []
for _ in range(RUNS):
    each.append(pipeline(vtkDigitalSurfaceFilter.EACH_LABEL))
    step = max(1, len(present) // SAMPLE)
    times = [pipeline(vtkDigitalSurfaceFilter.LABEL, L) for L in present[::step][:SAMPLE]]
    one.append((statistics.mean(t[0] for t in times), statistics.mean(t[1] for t in times)))
med = lambda xs: statistics.median(xs)
print("volume %d^3, %d labels, %d surfels in all; load average %.1f" % (N, len(present), each[0][2], os.getloadavg()[0]))
print("EachLabel: surface %.2f s + II %.2f s = %.2f s (medians; runs: %s)" % (
    med([e[0] for e in each]), med([e[1] for e in each]), med([e[0] + e[1] for e in each]),
    ", ".join("%.2f" % (e[0] + e[1]) for e in each)))
s1, i1 = med([o[0] for o in one]), med([o[1] for o in one])
print("Label mode on the whole volume, per label (mean of %d labels): surface %.3f s + II %.3f s = %.3f s;"
      " x %d labels = %.1f s" % (SAMPLE, s1, i1, s1 + i1, len(present), (s1 + i1) * len(present)))
