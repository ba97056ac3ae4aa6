#!/usr/bin/python3
"""Time and memory of the piecewise-smooth mesh stage on a real volume
(default: octa-flower 512^3 from ../shared), against VTK's usual mesh of the
same voxels (discrete flying edges + windowed sinc, 3D Slicer's settings).

    /usr/bin/python3 Benchmarks/bench_mesh_speed.py [VOLUME.vol] [--runs 3]

The program's defaults make the surface once (cached next to the output);
each measurement then runs in a process of its own: wall time of the stage
alone, and the process's peak resident memory before and after it. Prints
every run and the medians. Needs the build's Python package on PYTHONPATH
and the program (DG_PROGRAM or build/bin/piecewise-normals)."""
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.environ.get("DG_PROGRAM", os.path.join(ROOT, "build", "bin", "piecewise-normals"))

CHILD = r'''
import resource, sys, time
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
what, path = sys.argv[1], sys.argv[2]
if what == "stage":
    from digitalgeometry import vtkPiecewiseSmoothMeshFilter
    r = vtkXMLPolyDataReader(); r.SetFileName(path); r.Update()
    data = r.GetOutput()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    f = vtkPiecewiseSmoothMeshFilter(); f.SetInputData(data)
    t = time.perf_counter(); f.Update(); dt = time.perf_counter() - t
    print(dt, before / 1024, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, data.GetNumberOfCells())
else:
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy, numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkFiltersCore import vtkWindowedSincPolyDataFilter
    from vtkmodules.vtkFiltersGeneral import vtkDiscreteFlyingEdges3D
    from digitalgeometry import vtkDGtalVolReader
    r = vtkDGtalVolReader(); r.SetFileName(path); r.Update()
    vol = r.GetOutput()
    mask = vtkImageData(); mask.SetDimensions(vol.GetDimensions())
    mask.GetPointData().SetScalars(numpy_to_vtk((vtk_to_numpy(vol.GetPointData().GetScalars()) != 0).astype(np.uint8), deep=1))
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t = time.perf_counter()
    fe = vtkDiscreteFlyingEdges3D(); fe.SetInputData(mask); fe.SetValue(0, 1)
    ws = vtkWindowedSincPolyDataFilter(); ws.SetInputConnection(fe.GetOutputPort())
    ws.SetNumberOfIterations(20); ws.SetPassBand(0.1); ws.NonManifoldSmoothingOn(); ws.NormalizeCoordinatesOn()
    ws.Update(); dt = time.perf_counter() - t
    print(dt, before / 1024, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, ws.GetOutput().GetNumberOfCells())
'''


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    volume = args[0] if args else os.path.join(ROOT, "..", "shared", "data", "volgallery", "octa-flower17k-512.vol")
    runs = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 3
    out = os.path.join(tempfile.gettempdir(), "dg_mesh_speed")
    os.makedirs(out, exist_ok=True)
    name = os.path.splitext(os.path.basename(volume))[0]
    surface = os.path.join(out, name + "_surface.vtp")
    if not os.path.exists(surface):
        p = subprocess.run([PROGRAM, volume, "--no-png", "--quiet", "--output-dir", out], capture_output=True, text=True)
        if p.returncode:
            sys.exit(p.stderr)
    print("%s: %d runs each, one process per run" % (name, runs))
    for what, path in (("stage", surface), ("vtk", volume)):
        times, peaks = [], []
        for _ in range(runs):
            p = subprocess.run([sys.executable, "-c", CHILD, what, path], capture_output=True, text=True)
            if p.returncode:
                sys.exit(p.stderr)
            dt, before, after, cells = p.stdout.split()
            times.append(float(dt))
            peaks.append(float(after) - float(before))
            print("  %-5s %.3f s, peak memory +%.0f MiB (%.0f -> %.0f), %s cells out" % (
                what, float(dt), float(after) - float(before), float(before), float(after), cells))
        print("%-5s median %.3f s, peak +%.0f MiB" % (what, statistics.median(times), statistics.median(peaks)))


if __name__ == "__main__":
    main()
