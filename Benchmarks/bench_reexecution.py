"""What a ParaView user waits for when moving AT's Feature Threshold slider:
the first execution (solve) against one after a threshold change (outputs
rebuilt from the kept solve), on the real pipeline's input (a volume ->
noise -> digital surface -> II r = 3 -> AT with its defaults). Medians of
--runs runs, in seconds.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 \\
        Benchmarks/bench_reexecution.py [VOL] [--noise K] [--runs N]
"""
import argparse
import os
import platform
import statistics
import time

from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkDGtalVolReader,
                             vtkDigitalNoiseFilter, vtkDigitalSurfaceFilter,
                             vtkIINormalEstimator)

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT = os.path.join(HERE, "..", "..", "shared", "data", "volgallery", "fandisk-128.vol")
p = argparse.ArgumentParser()
p.add_argument("vol", nargs="?", default=DEFAULT)
p.add_argument("--noise", type=float, default=0.3)
p.add_argument("--runs", type=int, default=3)
a = p.parse_args()

first, again, thresholds = [], [], []
for run in range(a.runs):
    reader = vtkDGtalVolReader()
    reader.SetFileName(a.vol)
    noise = vtkDigitalNoiseFilter()
    noise.SetInputConnection(reader.GetOutputPort())
    noise.SetNoiseLevel(a.noise)
    noise.SetSeed(1)
    surface = vtkDigitalSurfaceFilter()
    surface.SetInputConnection(noise.GetOutputPort())
    ii = vtkIINormalEstimator()
    ii.SetInputConnection(surface.GetOutputPort())
    ii.SetSourceConnection(noise.GetOutputPort())
    ii.Update()
    at = vtkAmbrosioTortorelliFilter()
    at.SetInputConnection(ii.GetOutputPort())
    t = time.perf_counter()
    at.Update()
    first.append(time.perf_counter() - t)
    at.SetFeatureThreshold(0.3)
    t = time.perf_counter()
    at.Update()
    thresholds.append(time.perf_counter() - t)
    if hasattr(at, "GetNumberOfSolves"):  # older builds always solve
        assert at.GetNumberOfSolves() == 1
    at.SetAlpha(0.2)  # a solve parameter: solves again
    t = time.perf_counter()
    at.Update()
    again.append(time.perf_counter() - t)
    surfels = surface.GetOutput().GetNumberOfCells()

print("machine: %s, %d cores; input %s, noise %g, %d surfels"
      % (platform.node(), os.cpu_count(), os.path.basename(a.vol), a.noise, surfels))
print("first execution (solve):        median %.3f s  %s" % (statistics.median(first), ["%.3f" % x for x in first]))
print("Feature Threshold 0.5 -> 0.3:   median %.3f s  %s" % (statistics.median(thresholds), ["%.3f" % x for x in thresholds]))
print("Alpha 0.1 -> 0.2 (solve again): median %.3f s  %s" % (statistics.median(again), ["%.3f" % x for x in again]))
