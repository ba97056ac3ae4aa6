#!/usr/bin/python3
"""The paper's Fig. 5 as one picture: the normal fields of II (r = 4), VCM
(R = 10, r = 4) and RHT (r = 6, 648 trials), and of AT (alpha 0.05,
lambda 0.01, epsilon 2 -> 0.25) on each, at noise levels k = 0.1 ... 0.5.

Usage (from the repository root, with build/bin/piecewise-normals built):

    xvfb-run -a /usr/bin/python3 Benchmarks/render_fig5.py \\
        [INPUT] [--size 128] [--noise 0.1,0.2,0.3,0.4,0.5] [--seed 1] \\
        [--columns ii,vcm,rht,at-ii,at-vcm,at-rht] [--panel 260] \\
        [--view X,Y,Z] [--up X,Y,Z] [--out PATH] [--keep DIR]

INPUT is any volume piecewise-normals reads; without it, the program's
built-in shape (rotated cube + sphere - cylinder) at --size^3. The paper's
figure is fandisk 128^3:

    xvfb-run -a /usr/bin/python3 Benchmarks/render_fig5.py \\
        ../shared/data/volgallery/fandisk-128.vol --out out/fig5/fig5_fandisk-128.png

The volgallery volumes are CC BY-NC-ND: the fandisk picture goes to an
uncommitted folder (out/, which .gitignore leaves out); docs/fig5_builtin128.png
is the same figure on the project's own shape (the default output path).

For each k it runs build/bin/piecewise-normals three times on INPUT with
--noise k --seed S --plain --min-component 0 (the paper's set-up: the
noisy volume as it is, no island removal; AT's own output, no
sharp-features stage) --alpha 0.05 --lambda 0.01 and --estimator ii
(--radius 4), vcm (--vcm-radii 10 4) or rht (--rht-radius 6 --rht-trials
648): each run gives the estimator's normals (IINormals, VCMNormals,
RHTNormals) and AT's on them (ATNormals). The same seed gives the same
noisy volume in the three runs. Normals are drawn as the program's picture
draws them (Applications/dgRender.cxx): one colour per quad,
RGB = (n + 1) / 2, unlit, in the program's three-quarter view (azimuth 35,
elevation 25) with a parallel projection; every panel has the same camera,
framed on the k = first level surface's bounding box.

Needs VTK's Python module (/usr/bin/python3 with python3-paraview or
python3-vtk9), numpy, and an X display for off-screen rendering
(xvfb-run -a).
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import vtk
from vtk.util import numpy_support

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_features import read_vtp, run  # noqa: E402 (same folder)

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# column key -> (estimator run, array, title)
COLUMNS = {
    "ii": ("ii", "IINormals", "II, r = 4"),
    "vcm": ("vcm", "VCMNormals", "VCM, R = 10, r = 4"),
    "rht": ("rht", "RHTNormals", "RHT, r = 6, 648 trials"),
    "at-ii": ("ii", "ATNormals", "AT(II r = 4)"),
    "at-vcm": ("vcm", "ATNormals", "AT(VCM)"),
    "at-rht": ("rht", "ATNormals", "AT(RHT)"),
}
ESTIMATOR_OPTIONS = {
    "ii": ["--estimator", "ii", "--radius", "4"],
    "vcm": ["--estimator", "vcm", "--vcm-radii", "10", "4"],
    "rht": ["--estimator", "rht", "--rht-radius", "6", "--rht-trials", "648"],
}


def normal_colours(surface, name):
    """A copy of the surface's quads with one colour per quad, RGB = (n + 1) / 2."""
    a = surface.GetCellData().GetArray(name)
    if a is None:
        sys.exit(f"the surface has no cell array {name}")
    n = numpy_support.vtk_to_numpy(a).astype(np.float64)
    n = np.where(np.isfinite(n), np.clip(n, -1, 1), 0.0)
    rgb = np.rint(127.5 * (n + 1.0)).astype(np.uint8)
    colours = numpy_support.numpy_to_vtk(rgb, deep=1, array_type=vtk.VTK_UNSIGNED_CHAR)
    colours.SetName("NormalColours")
    data = vtk.vtkPolyData()
    data.SetPoints(surface.GetPoints())
    data.SetPolys(surface.GetPolys())
    data.GetCellData().SetScalars(colours)
    return data


def three_quarter_view(view, up):
    c = vtk.vtkCamera()
    c.SetFocalPoint(0, 0, 0)
    if view is None:
        c.SetPosition(0, 0, 1)
        c.SetViewUp(0, 1, 0)
        c.Azimuth(35)
        c.Elevation(25)
    else:
        c.SetPosition(*view)
        c.SetViewUp(*up)
    c.OrthogonalizeViewUp()
    return np.array(c.GetDirectionOfProjection()), np.array(c.GetViewUp())


def frame(surface, direction, up):
    """Centre, width and height of the surface's points seen along direction."""
    pts = numpy_support.vtk_to_numpy(surface.GetPoints().GetData()).astype(np.float64)
    right = np.cross(direction, up)
    x, y = pts @ right, pts @ up
    cx, cy = 0.5 * (x.min() + x.max()), 0.5 * (y.min() + y.max())
    depth = pts @ direction
    centre = cx * right + cy * up + 0.5 * (depth.min() + depth.max()) * direction
    diag = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    return centre, x.max() - x.min(), y.max() - y.min(), diag


def text_actor(text, size, bold=False, justify="centre"):
    t = vtk.vtkTextActor()
    t.SetInput(text)
    p = t.GetTextProperty()
    p.SetFontSize(size)
    p.SetBold(bold)
    p.SetColor(0, 0, 0)
    if justify == "centre":
        p.SetJustificationToCentered()
    p.SetVerticalJustificationToCentered()
    t.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
    t.GetPositionCoordinate().SetValue(0.5, 0.5)
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input", nargs="?", help="a volume (default: the built-in shape)")
    ap.add_argument("--size", type=int, default=128, help="grid size of the built-in shape (default 128)")
    ap.add_argument("--noise", default="0.1,0.2,0.3,0.4,0.5")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--columns", default="ii,vcm,rht,at-ii,at-vcm,at-rht",
                    help="panels per row, from " + ",".join(COLUMNS))
    ap.add_argument("--panel", type=int, default=260, help="panel width and height in pixels (default 260)")
    ap.add_argument("--view", help="camera position relative to the focal point (x,y,z; default: the "
                                   "program's three-quarter view)")
    ap.add_argument("--up", default="0,1,0", help="view up with --view (default 0,1,0)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", help="PNG path (default docs/fig5_builtin{size}.png, or "
                                  "out/fig5/fig5_NAME.png for an INPUT)")
    ap.add_argument("--keep", help="keep the program's outputs in this directory (default: a temporary one)")
    args = ap.parse_args()

    program = os.path.join(args.build, "bin", "piecewise-normals")
    levels = [k for k in args.noise.split(",") if k]
    columns = [c for c in args.columns.split(",") if c]
    for c in columns:
        if c not in COLUMNS:
            sys.exit(f"unknown column {c}")
    name = (os.path.splitext(os.path.basename(args.input))[0] if args.input else f"builtin{args.size}")
    out = args.out or (os.path.join(ROOT, "out", "fig5", f"fig5_{name}.png") if args.input
                       else os.path.join(ROOT, "docs", f"fig5_builtin{args.size}.png"))
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    tmp = args.keep or tempfile.mkdtemp(prefix="render_fig5.")
    os.makedirs(tmp, exist_ok=True)

    # One program run per (noise level, estimator).
    surfaces = {}
    counts = {}
    for k in levels:
        for est in sorted({COLUMNS[c][0] for c in columns}, key=["ii", "vcm", "rht"].index):
            prefix = f"{name}-k{k}-{est}"
            path = os.path.join(tmp, prefix + "_surface.vtp")
            if not os.path.exists(path):
                cmd = [program, "--quiet", "--no-png", "--plain", "--min-component", "0",
                       "--noise", k, "--seed", str(args.seed), "--alpha", "0.05", "--lambda", "0.01",
                       "--output-dir", tmp, "--prefix", prefix] + ESTIMATOR_OPTIONS[est]
                if args.input:
                    cmd.append(args.input)
                else:
                    cmd += ["--size", str(args.size)]
                t0 = time.time()
                run(cmd)
                print(f"k = {k}, {est}: {time.time() - t0:.1f} s", flush=True)
            surfaces[(k, est)] = read_vtp(path)
            counts[k] = surfaces[(k, est)].GetNumberOfCells()

    if args.view:
        direction, up = three_quarter_view([float(x) for x in args.view.split(",")],
                                           [float(x) for x in args.up.split(",")])
    else:
        direction, up = three_quarter_view(None, None)
    # The frame of the first level's surface (the noise adds at most a few
    # voxels around it); every panel uses the same camera.
    centre, width, height, diag = frame(surfaces[(levels[0], COLUMNS[columns[0]][0])], direction, up)
    margin = 1.04
    scale = 0.5 * margin * max(height, width)  # square panels

    P = args.panel
    header = max(34, P // 7)
    left = max(110, int(P / 2.2))
    W, H = left + P * len(columns), header + P * len(levels)
    win = vtk.vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetSize(W, H)

    def viewport(x0, y0, w, h):
        # pixels from the top-left corner -> VTK's normalised viewport
        return (x0 / W, 1 - (y0 + h) / H, (x0 + w) / W, 1 - y0 / H)

    def add_text(x0, y0, w, h, text, size, bold=False):
        r = vtk.vtkRenderer()
        r.SetBackground(1, 1, 1)
        r.SetViewport(*viewport(x0, y0, w, h))
        r.AddViewProp(text_actor(text, size, bold))
        win.AddRenderer(r)

    font = max(12, P // 17)
    label = name if args.input else f"built-in, {args.size}³"
    add_text(0, 0, left, header, f"{label}, seed {args.seed}\nRGB = (n + 1) / 2", max(10, font - 4))
    for j, c in enumerate(columns):
        add_text(left + j * P, 0, P, header, COLUMNS[c][2], font, bold=True)
    for i, k in enumerate(levels):
        top = (P * 11) // 20
        add_text(0, header + i * P, left, top, f"k = {k}", font + 2, bold=True)
        add_text(0, header + i * P + top, left, P - top, f"{counts[k]:,} quads\n\n".replace(",", " "),
                 max(10, font - 3))
        for j, c in enumerate(columns):
            est, array, _ = COLUMNS[c]
            r = vtk.vtkRenderer()
            r.SetBackground(1, 1, 1)
            r.SetViewport(*viewport(left + j * P, header + i * P, P, P))
            m = vtk.vtkPolyDataMapper()
            m.SetInputData(normal_colours(surfaces[(k, est)], array))
            m.ScalarVisibilityOn()
            m.SetScalarModeToUseCellData()
            m.SetColorModeToDirectScalars()
            a = vtk.vtkActor()
            a.SetMapper(m)
            a.GetProperty().LightingOff()
            r.AddActor(a)
            cam = r.GetActiveCamera()
            cam.ParallelProjectionOn()
            cam.SetFocalPoint(*centre)
            cam.SetPosition(*(centre - direction * 2 * diag))
            cam.SetViewUp(*up)
            cam.SetParallelScale(scale)
            r.ResetCameraClippingRange()
            win.AddRenderer(r)
    # A thin grey grid between the panels.
    grid = vtk.vtkRenderer()
    grid.SetViewport(0, 0, 1, 1)
    grid.SetLayer(1)
    grid.InteractiveOff()
    pts = vtk.vtkPoints()
    lines = vtk.vtkCellArray()
    for j in range(len(columns) + 1):
        x = left + j * P
        ids = [pts.InsertNextPoint(x, 0, 0), pts.InsertNextPoint(x, H - header, 0)]
        lines.InsertNextCell(2, ids)
    for i in range(len(levels) + 1):
        y = H - header - i * P
        ids = [pts.InsertNextPoint(0, y, 0), pts.InsertNextPoint(W, y, 0)]
        lines.InsertNextCell(2, ids)
    gpd = vtk.vtkPolyData()
    gpd.SetPoints(pts)
    gpd.SetLines(lines)
    coord = vtk.vtkCoordinate()
    coord.SetCoordinateSystemToDisplay()
    gm = vtk.vtkPolyDataMapper2D()
    gm.SetInputData(gpd)
    gm.SetTransformCoordinate(coord)
    ga = vtk.vtkActor2D()
    ga.SetMapper(gm)
    ga.GetProperty().SetColor(0.7, 0.7, 0.7)
    grid.AddViewProp(ga)
    win.SetNumberOfLayers(2)
    win.AddRenderer(grid)

    win.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    w = vtk.vtkPNGWriter()
    w.SetFileName(out)
    w.SetInputConnection(grab.GetOutputPort())
    w.SetCompressionLevel(9)
    w.Write()
    win.Finalize()
    if not args.keep:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"wrote {out} ({W} x {H}, {os.path.getsize(out) // 1024} KB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
