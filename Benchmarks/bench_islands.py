"""What vtkDigitalIslandFilter removes from the paper's noisy volume and how
long it takes: on VOL (default fandisk-128) with vtkDigitalNoiseFilter at
k = --noise, seed 1, the islands removed, cavities filled and voxels changed
for each MinimumSize, with the digital surface's surfel count before and
after; then the filter's time on TIMED (default octa-flower17k-512), clean
and noisy, medians of --runs runs, in seconds (the digital surface's time
alongside for scale).

    VTK_SMP_BACKEND_IN_USE=STDThread PYTHONPATH=build/lib/python3/dist-packages \\
        /usr/bin/python3 Benchmarks/bench_islands.py [VOL] [--timed VOL] [--noise K] [--runs N]
"""
import argparse
import os
import platform
import statistics
import time

import numpy
from vtkmodules.util import numpy_support
from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkDGtalVolReader,
                             vtkDigitalIslandFilter, vtkDigitalNoiseFilter,
                             vtkDigitalSurfaceFilter, vtkIINormalEstimator)

HERE = os.path.dirname(os.path.abspath(__file__))
GALLERY = os.path.join(HERE, "..", "..", "shared", "data", "volgallery")
p = argparse.ArgumentParser()
p.add_argument("vol", nargs="?", default=os.path.join(GALLERY, "fandisk-128.vol"))
p.add_argument("--timed", default=os.path.join(GALLERY, "octa-flower17k-512.vol"))
p.add_argument("--noise", type=float, default=0.3)
p.add_argument("--sizes", default="2,4,8,16,32")
p.add_argument("--runs", type=int, default=3)
p.add_argument("--at", action="store_true",
               help="also II r = 3 -> AT (defaults) before and after MinimumSize 8: feature edges")
a = p.parse_args()


def surfels(port):
    s = vtkDigitalSurfaceFilter()
    s.SetInputConnection(port)
    s.Update()
    return s.GetOutput().GetNumberOfCells()


def turned(before, after):
    """Voxels turned outside and turned inside between two 0/1 images."""
    b = numpy_support.vtk_to_numpy(before.GetPointData().GetScalars()) != 0
    c = numpy_support.vtk_to_numpy(after.GetPointData().GetScalars()) != 0
    return int(numpy.count_nonzero(b & ~c)), int(numpy.count_nonzero(c & ~b))


reader = vtkDGtalVolReader()
reader.SetFileName(a.vol)
noise = vtkDigitalNoiseFilter()
noise.SetInputConnection(reader.GetOutputPort())
noise.SetNoiseLevel(a.noise)
noise.SetSeed(1)
noise.Update()
print("%s, noise k = %g seed 1: %d voxels flipped" % (os.path.basename(a.vol), a.noise,
                                                      noise.GetNumberOfFlippedVoxels()))
clean = surfels(reader.GetOutputPort())
noisy = surfels(noise.GetOutputPort())
print("surfels: noise-free %d, noisy %d" % (clean, noisy))
print("| MinimumSize | islands removed | cavities filled | voxels turned outside | "
      "voxels turned inside | voxels changed | surfels after | surfels removed |")
print("|---|---|---|---|---|---|---|---|")
for size in [int(s) for s in a.sizes.split(",")]:
    f = vtkDigitalIslandFilter()
    f.SetInputConnection(noise.GetOutputPort())
    f.SetMinimumSize(size)
    f.Update()
    out, inn = turned(noise.GetOutput(), f.GetOutput())
    assert out + inn == f.GetNumberOfChangedVoxels()
    after = surfels(f.GetOutputPort())
    print("| %d | %d | %d | %d | %d | %d | %d | %d (%.1f %%) |" % (
        size, f.GetNumberOfRemovedIslands(), f.GetNumberOfFilledCavities(), out, inn,
        f.GetNumberOfChangedVoxels(), after, noisy - after, 100.0 * (noisy - after) / noisy))

if a.at:
    def features(image_port):
        surface = vtkDigitalSurfaceFilter()
        surface.SetInputConnection(image_port)
        ii = vtkIINormalEstimator()
        ii.SetInputConnection(surface.GetOutputPort())
        ii.SetSourceConnection(image_port)
        ii.SetRadius(3)
        at = vtkAmbrosioTortorelliFilter()
        at.SetInputConnection(ii.GetOutputPort())
        at.Update()
        return at.GetOutput(1).GetNumberOfLines(), at.GetOutput(0).GetNumberOfCells()

    cleaner = vtkDigitalIslandFilter()
    cleaner.SetInputConnection(noise.GetOutputPort())
    for name, port in (("noise-free", reader.GetOutputPort()), ("noisy", noise.GetOutputPort()),
                       ("noisy, MinimumSize 8", cleaner.GetOutputPort())):
        lines, cells = features(port)
        print("AT feature edges, %-21s %6d (on %d surfels)" % (name + ":", lines, cells))

# Time on the large volume: the island filter alone (its input up to date).
if os.path.isfile(a.timed):
    big = vtkDGtalVolReader()
    big.SetFileName(a.timed)
    big.Update()
    dims = big.GetOutput().GetDimensions()
    big_noise = vtkDigitalNoiseFilter()
    big_noise.SetInputConnection(big.GetOutputPort())
    big_noise.SetNoiseLevel(a.noise)
    big_noise.SetSeed(1)
    big_noise.Update()
    print("\n%s (%d x %d x %d), %d runs, %s, SMP %s:" % (
        os.path.basename(a.timed), dims[0], dims[1], dims[2], a.runs, platform.processor() or "cpu",
        os.environ.get("VTK_SMP_BACKEND_IN_USE", "default")))
    for name, source in (("clean", big), ("noisy k = %g" % a.noise, big_noise)):
        for algorithm in (vtkDigitalIslandFilter, vtkDigitalSurfaceFilter):
            f = algorithm()
            f.SetInputConnection(source.GetOutputPort())
            times = []
            for run in range(a.runs):
                f.Modified()
                t = time.perf_counter()
                f.Update()
                times.append(time.perf_counter() - t)
            extra = ""
            if algorithm is vtkDigitalIslandFilter:
                extra = ", %d islands, %d cavities, %d voxels" % (
                    f.GetNumberOfRemovedIslands(), f.GetNumberOfFilledCavities(),
                    f.GetNumberOfChangedVoxels())
            print("  %-12s %-24s median %.3f s (%s)%s" % (
                name, algorithm.__name__, statistics.median(times),
                ", ".join("%.3f" % x for x in times), extra))
