#!/usr/bin/python3
"""Pictures for docs/mesh.md: a volume's digital surface, VTK's usual mesh
of it (3D Slicer's: discrete flying edges, windowed sinc with 20
iterations and pass band 0.1) and this module's piecewise-smooth mesh
(the program's defaults, then vtkPiecewiseSmoothMeshFilter), all flat
shaded in the same view, the mesh's creases in red.

    xvfb-run -a /usr/bin/python3 Benchmarks/render_mesh.py NAME OUT.png [--noise K] [--zoom Z]

NAME: cube, torus, fillet (64^3 ground-truth shapes of bench_mesh.py) or a
volume file the program reads (e.g. ../shared/data/volgallery/octa-flower17k-512.vol).
Needs the build's Python package on PYTHONPATH and the program (DG_PROGRAM
or build/bin/piecewise-normals)."""
import os
import subprocess
import sys
import tempfile

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLImageDataWriter
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkTextActor, vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingFreeType  # noqa: F401

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_mesh  # noqa: E402

from digitalgeometry import vtkPiecewiseSmoothMeshFilter  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.environ.get("DG_PROGRAM", os.path.join(ROOT, "build", "bin", "piecewise-normals"))


def read(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def main():
    name, out = sys.argv[1], sys.argv[2]
    noise = float(sys.argv[sys.argv.index("--noise") + 1]) if "--noise" in sys.argv else 0.0
    zoom = float(sys.argv[sys.argv.index("--zoom") + 1]) if "--zoom" in sys.argv else 1.0
    tmp = tempfile.mkdtemp(prefix="dg_render_mesh_")
    shapes = bench_mesh.shapes(64)
    if name in shapes:
        f, _ = shapes[name]
        inside = bench_mesh.volume_of(f, 64, 31.5 + np.array([0.31, 0.17, 0.23]))
        if noise:
            inside = bench_mesh.noisy_volume(inside, noise, 1)
        path = os.path.join(tmp, name + ".vti")
        img = vtkImageData()
        img.SetDimensions(64, 64, 64)
        img.GetPointData().SetScalars(numpy_to_vtk(inside.ravel(), deep=1))
        w = vtkXMLImageDataWriter()
        w.SetInputData(img)
        w.SetFileName(path)
        w.Write()
        noise_args = []  # the noise is in the volume already
    else:
        path = name
        noise_args = ["--noise", str(noise), "--seed", "1"] if noise else []
    p = subprocess.run([PROGRAM, path, "--no-png", "--quiet", "--output-dir", tmp, "--prefix", "s",
                        "--mesh"] + noise_args, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr)
    digital = read(os.path.join(tmp, "s_surface.vtp"))
    mesh = read(os.path.join(tmp, "s_mesh.vtp"))
    creases = read(os.path.join(tmp, "s_mesh_creases.vtp"))
    # VTK's mesh of the same voxels (the program's, after noise and islands:
    # its surface's inside voxels rebuilt from the surfels is not needed, the
    # volume is at hand for the ground-truth shapes; for files, VTK reads the
    # program's input through the same reader the program uses).
    if name in shapes:
        vtk_mesh = bench_mesh.vtk_pipeline(inside)
    elif name.endswith(".vol") and not noise:
        from digitalgeometry import vtkDGtalVolReader
        r = vtkDGtalVolReader()
        r.SetFileName(name)
        r.Update()
        vol = r.GetOutput()
        dims = vol.GetDimensions()
        mask = (vtk_to_numpy(vol.GetPointData().GetScalars()) != 0).astype(np.uint8)
        vtk_mesh = bench_mesh.vtk_pipeline(mask.reshape(dims[2], dims[1], dims[0]), dims)
        # into the reader's frame (origin and spacing)
        from vtkmodules.vtkFiltersGeneral import vtkTransformPolyDataFilter
        from vtkmodules.vtkCommonTransforms import vtkTransform
        t = vtkTransform()
        t.Translate(vol.GetOrigin())
        t.Scale(vol.GetSpacing())
        tf = vtkTransformPolyDataFilter()
        tf.SetTransform(t)
        tf.SetInputData(vtk_mesh)
        tf.Update()
        vtk_mesh = tf.GetOutput()
    else:
        vtk_mesh = None
    panels = [("digital surface", digital, None), ("VTK (flying edges + windowed sinc)", vtk_mesh, None),
              ("piecewise-smooth mesh", mesh, creases)]
    panels = [q for q in panels if q[1] is not None]
    size = 600
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(size * len(panels), size)
    cam = None
    for i, (title, pd, lines) in enumerate(panels):
        ren = vtkRenderer()
        ren.SetViewport(i / len(panels), 0, (i + 1) / len(panels), 1)
        ren.SetBackground(1, 1, 1)
        win.AddRenderer(ren)
        shown = type(pd)()
        shown.CopyStructure(pd)
        m = vtkPolyDataMapper()
        m.SetInputData(shown)
        a = vtkActor()
        a.SetMapper(m)
        a.GetProperty().SetInterpolationToFlat()
        a.GetProperty().SetColor(0.85, 0.85, 0.82)
        a.GetProperty().SetAmbient(0.25)
        a.GetProperty().SetDiffuse(0.8)
        ren.AddActor(a)
        if lines is not None and lines.GetNumberOfLines():
            lm = vtkPolyDataMapper()
            lm.SetInputData(lines)
            lm.ScalarVisibilityOff()
            la = vtkActor()
            la.SetMapper(lm)
            la.GetProperty().SetColor(0.9, 0.1, 0.1)
            la.GetProperty().SetLineWidth(2)
            la.GetProperty().SetRenderLinesAsTubes(True)
            ren.AddActor(la)
        t = vtkTextActor()
        t.SetInput(title)
        t.GetTextProperty().SetFontSize(22)
        t.GetTextProperty().SetColor(0.1, 0.1, 0.1)
        t.SetPosition(10, size - 34)
        ren.AddActor2D(t)
        if cam is None:
            ren.ResetCamera()
            cam = ren.GetActiveCamera()
            cam.Azimuth(35)
            cam.Elevation(25)
            cam.Zoom(1.1 * zoom)
            ren.ResetCameraClippingRange()
        else:
            ren.SetActiveCamera(cam)
    win.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.ReadFrontBufferOff()
    grab.Update()
    w = vtkPNGWriter()
    w.SetFileName(out)
    w.SetInputConnection(grab.GetOutputPort())
    w.Write()
    print("wrote", out)


if __name__ == "__main__":
    main()
