#!/usr/bin/python3
"""Pictures for docs/quality.md: AT's plain output against the program's
default output (AT + sharp features), the same view, clean and noisy.

Usage (from the repository root, with the build tree in build/):

    xvfb-run -a /usr/bin/python3 Benchmarks/render_features.py \\
        [--shape cube] [--size 64] [--noise 0,0.3] [--seed 1] [--docs docs] \\
        [--view X,Y,Z] [--up X,Y,Z] [--distance D] [--pixels 520]

(docs/quality.md has the three commands that made its pictures.)

For each noise level k it writes the benchmark's own noisy volume
(build/bin/BenchQuality --save-volumes: the volume every method of the
quality benchmark sees), runs build/bin/piecewise-normals on it twice (with
--plain: the paper's output, AT's normals and AT's feature edges; without:
the program's default output, SharpNormals and one line per edge) and renders
each result: the surface lit with the estimated cell normals (no point
normals, so every surfel is shaded by its own normal: a flat face with good
normals looks uniform, the voxel staircase disappears, noise in the normals
shows as speckle) and the feature lines as red tubes. Writes
DOCS/features_SHAPE{SIZE}_k{K}_{plain,sharp}.png.

Needs VTK's Python module (/usr/bin/python3 with Debian's python3-vtk9 or
python3-paraview) and an X display for off-screen rendering (xvfb-run -a).
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

import vtk

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def run(cmd):
    env = dict(os.environ, VTK_SMP_BACKEND_IN_USE=os.environ.get("VTK_SMP_BACKEND_IN_USE", "STDThread"))
    r = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stdout}")
    return r.stdout


def read_vtp(path):
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    out = vtk.vtkPolyData()
    out.ShallowCopy(r.GetOutput())
    return out


def count_edges(lines):
    n = 0
    ids = vtk.vtkIdList()
    ca = lines.GetLines()
    ca.InitTraversal()
    while ca.GetNextCell(ids):
        n += max(0, ids.GetNumberOfIds() - 1)
    return n


def render(surface, normals, lines, camera, title, path, size, tube_radius):
    surface.GetCellData().SetActiveNormals(normals)
    surface.GetPointData().SetNormals(None)
    smap = vtk.vtkPolyDataMapper()
    smap.SetInputData(surface)
    smap.ScalarVisibilityOff()
    sact = vtk.vtkActor()
    sact.SetMapper(smap)
    p = sact.GetProperty()
    p.SetColor(0.86, 0.86, 0.84)
    p.SetAmbient(0.15)
    p.SetDiffuse(0.8)
    p.SetSpecular(0.25)
    p.SetSpecularPower(20)

    tubes = vtk.vtkTubeFilter()
    tubes.SetInputData(lines)
    tubes.SetRadius(tube_radius)
    tubes.SetNumberOfSides(6)
    tubes.CappingOn()
    lmap = vtk.vtkPolyDataMapper()
    lmap.SetInputConnection(tubes.GetOutputPort())
    lmap.ScalarVisibilityOff()
    lact = vtk.vtkActor()
    lact.SetMapper(lmap)
    lact.GetProperty().SetColor(0.85, 0.05, 0.05)
    lact.GetProperty().SetAmbient(0.3)

    text = vtk.vtkTextActor()
    text.SetInput(title)
    tp = text.GetTextProperty()
    tp.SetFontSize(max(12, size // 34))
    tp.SetColor(0, 0, 0)
    tp.SetVerticalJustificationToTop()
    text.SetPosition(8, size - 8)

    ren = vtk.vtkRenderer()
    ren.SetBackground(1, 1, 1)
    ren.AddActor(sact)
    ren.AddActor(lact)
    ren.AddActor2D(text)
    ren.SetActiveCamera(camera)
    ren.ResetCameraClippingRange()
    # A key light above left of the camera and a weak headlight: faces of
    # different orientation get different shades.
    key = vtk.vtkLight()
    key.SetLightTypeToCameraLight()
    key.SetPosition(-0.4, 0.7, 1)
    key.SetFocalPoint(0, 0, 0)
    key.SetIntensity(0.75)
    ren.AddLight(key)
    head = vtk.vtkLight()
    head.SetLightTypeToHeadlight()
    head.SetIntensity(0.45)
    ren.AddLight(head)

    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetMultiSamples(8)
    win.SetSize(size, size)
    win.AddRenderer(ren)
    win.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    w = vtk.vtkPNGWriter()
    w.SetFileName(path)
    w.SetInputConnection(grab.GetOutputPort())
    w.SetCompressionLevel(9)
    w.Write()
    win.Finalize()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--shape", default="cube", help="a BenchQuality shape (default cube: the rotated cube)")
    ap.add_argument("--size", type=int, default=64)
    ap.add_argument("--noise", default="0,0.3", help="noise levels, comma separated (default 0,0.3)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--pixels", type=int, default=520, help="picture width and height (default 520)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--docs", default=os.path.join(ROOT, "docs"))
    ap.add_argument("--view", default="0.75,0.55,0.5",
                    help="camera direction from the centre (x,y,z; default: three faces of the rotated cube)")
    ap.add_argument("--up", default="0,1,0", help="camera view-up (default 0,1,0)")
    ap.add_argument("--distance", type=float, default=0.8,
                    help="camera distance in bounding-sphere radii, at a 22 degree view angle (default 0.8)")
    args = ap.parse_args()

    bench = os.path.join(args.build, "bin", "BenchQuality")
    program = os.path.join(args.build, "bin", "piecewise-normals")
    levels = [float(k) for k in args.noise.split(",") if k]
    view = [float(x) for x in args.view.split(",")]
    with tempfile.TemporaryDirectory(prefix="render_features.") as tmp:
        # The benchmark's volumes (its own noise filter and seed, k = 0 has
        # one seed, like the benchmark's rows).
        run([bench, "--sizes", str(args.size), "--shapes", args.shape, "--noise", args.noise,
             "--seeds", str(args.seed), "--no-vtk", "--save-volumes", tmp,
             "--out", os.path.join(tmp, "bench")])
        camera = None
        for k in levels:
            kk = f"{k:g}"
            vol = os.path.join(tmp, f"{args.shape}-{args.size}-k{kk}-s{args.seed}.vti")
            if not os.path.exists(vol):
                sys.exit(f"BenchQuality did not write {vol}")
            for variant in ("plain", "sharp"):
                prefix = f"{variant}-{kk}"
                cmd = [program, "--quiet", "--no-png", "--output-dir", tmp, "--prefix", prefix, vol]
                if variant == "plain":
                    cmd.insert(1, "--plain")
                log = run(cmd)
                surface = read_vtp(os.path.join(tmp, prefix + "_surface.vtp"))
                lines = read_vtp(os.path.join(tmp, prefix + "_features.vtp"))
                if camera is None:
                    # One camera for every picture, from the first (clean)
                    # surface: the same view of the same place.
                    b = surface.GetBounds()
                    c = [(b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2]
                    # The bounding box's sphere, a little cut: the shape fills the view.
                    r = 0.5 * math.sqrt((b[1] - b[0]) ** 2 + (b[3] - b[2]) ** 2 + (b[5] - b[4]) ** 2)
                    angle = 22.0
                    dist = args.distance * r / math.sin(math.radians(angle / 2))
                    norm = math.sqrt(sum(x * x for x in view))
                    camera = vtk.vtkCamera()
                    camera.SetFocalPoint(c)
                    camera.SetPosition([c[i] + dist * view[i] / norm for i in range(3)])
                    camera.SetViewUp(*[float(x) for x in args.up.split(",")])
                    camera.SetViewAngle(angle)
                normals = "ATNormals" if variant == "plain" else "SharpNormals"
                name = "AT, plain output" if variant == "plain" else "AT + sharp features (default)"
                title = (f"{args.shape} {args.size}^3, k = {kk}: {name}\n"
                         f"{count_edges(lines)} feature edges, {surface.GetNumberOfCells()} surfels")
                out = os.path.join(args.docs, f"features_{args.shape}{args.size}_k{kk}_{variant}.png")
                render(surface, normals, lines, camera, title, out, args.pixels, 0.28 * args.size / 64)
                print(f"wrote {out} ({os.path.getsize(out) // 1024} KB): {log.splitlines()[0]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
