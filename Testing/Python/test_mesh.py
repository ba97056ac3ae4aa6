"""The piecewise-smooth mesh (issue 36) from Python and from the program:
vtkPiecewiseSmoothMeshFilter after the filters' own defaults chained as
the ParaView plugin chains them (a rotated cube: its creases at 90 degrees,
every vertex within its cell); the program's --mesh files (VTP, STL, PLY,
OBJ with normals, the picture); a three-label map's interfaces meshed once
(shared faces, closed label surfaces, the lines where three labels meet
kept as creases); bad input."""
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData
from vtkmodules.vtkIOGeometry import vtkOBJReader, vtkSTLReader
from vtkmodules.vtkIOPLY import vtkPLYReader
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLPolyDataReader

from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkDigitalSurfaceFilter,
                             vtkIINormalEstimator, vtkPiecewiseSmoothMeshFilter,
                             vtkSharpFeaturesFilter)

PROGRAM = os.environ["DG_PROGRAM"]
ROOT = tempfile.mkdtemp(prefix="dg_mesh_", dir=os.environ.get("DG_TEST_TMP"))
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def read(path):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def rotated_cube(n, h):
    a, b = math.radians(25), math.radians(35)
    ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
    rot = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]]) @ np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    k = np.arange(n)
    z, y, x = np.meshgrid(k, k, k, indexing="ij")
    p = np.stack([x, y, z], -1) - ((n - 1) / 2 + np.array([0.21, 0.13, 0.17]))
    return (np.abs(p @ rot).max(-1) <= h).astype(np.uint8)


def image_of(mask, spacing=(1, 1, 1)):
    img = vtkImageData()
    img.SetDimensions(mask.shape[2], mask.shape[1], mask.shape[0])
    img.SetSpacing(*spacing)
    img.GetPointData().SetScalars(numpy_to_vtk(mask.ravel(), deep=1))
    return img


# --- the filters chained with their defaults, as the plugin chains them ---
img = image_of(rotated_cube(36, 10.5), spacing=(0.5, 0.5, 0.5))
surface = vtkDigitalSurfaceFilter()
surface.SetInputData(img)
ii = vtkIINormalEstimator()
ii.SetInputConnection(surface.GetOutputPort())
ii.SetSourceData(img)
at = vtkAmbrosioTortorelliFilter()
at.SetInputConnection(ii.GetOutputPort())
sharp = vtkSharpFeaturesFilter()
sharp.SetInputConnection(at.GetOutputPort())
mesh = vtkPiecewiseSmoothMeshFilter()
mesh.SetInputConnection(sharp.GetOutputPort())
mesh.Update()
out = mesh.GetOutput()
digital = sharp.GetOutput()
check(out.GetNumberOfPolys() == digital.GetNumberOfPolys(), "one quad per surfel (%d)" % out.GetNumberOfPolys())
shift = vtk_to_numpy(out.GetPointData().GetArray("MeshDisplacement"))
# spacing 0.5: a cell is 0.49 voxel = 0.245 world units along each axis
check(np.abs(shift).max() <= 0.245 + 1e-9, "every vertex within its cell (largest move %.3f world units)"
      % np.abs(shift).max())
check(np.abs(shift).max() > 0.1, "the vertices moved")
normals = out.GetPointData().GetNormals()
check(normals is not None and normals.GetNumberOfTuples() == out.GetNumberOfPoints(), "point normals")
check(out.GetNumberOfPoints() > digital.GetNumberOfPoints(), "crease points split (%d -> %d)"
      % (digital.GetNumberOfPoints(), out.GetNumberOfPoints()))
creases = mesh.GetOutput(1)
angles = vtk_to_numpy(creases.GetCellData().GetArray("FeatureAngle"))
check(creases.GetNumberOfLines() > 50, "creases on port 1 (%d)" % creases.GetNumberOfLines())
check(abs(np.median(angles) - 90) < 8, "creases at the cube's 90 degrees (median %.1f)" % np.median(angles))
check(out.GetCellData().GetArray("SharpNormals") is not None, "cell data carried over")
mesh.OutputTrianglesOn()
mesh.Update()
check(mesh.GetOutput().GetNumberOfPolys() == 2 * digital.GetNumberOfPolys(), "triangles on request")
cells = vtk_to_numpy(mesh.GetOutput().GetPolys().GetOffsetsArray())
check(np.all(np.diff(cells) == 3), "every cell a triangle")

# --- the corrected curvature on the mesh's positions (split points off:
# one point per vertex) ---
from digitalgeometry import vtkCorrectedCurvatureFilter  # noqa: E402
mesh.OutputTrianglesOff()
mesh.SplitFeaturePointsOff()
curv = vtkCorrectedCurvatureFilter()
curv.SetInputConnection(mesh.GetOutputPort())
curv.Update()
fd = curv.GetOutput().GetFieldData()
area = fd.GetArray("CorrectedArea").GetValue(0)
# the mesh's own area (its triangles) against the corrected measure on it
from vtkmodules.vtkFiltersCore import vtkMassProperties, vtkTriangleFilter  # noqa: E402
tri = vtkTriangleFilter()
tri.SetInputConnection(mesh.GetOutputPort())
mp = vtkMassProperties()
mp.SetInputConnection(tri.GetOutputPort())
mp.Update()
check(abs(area / mp.GetSurfaceArea() - 1) < 0.01,
      "curvature of the mesh: corrected area %.1f, the mesh's own %.1f" % (area, mp.GetSurfaceArea()))
chi = fd.GetArray("GaussBonnetCharacteristic").GetValue(0)
check(abs(chi - 2) < 1e-6, "curvature of the mesh: Gauss-Bonnet 2 (%.6f)" % chi)
mesh.SplitFeaturePointsOn()

# --- bad input: a polygon that is no voxel face; a NaN normal ---
errors = []


def on_error(obj, event):
    errors.append(event)


bad = vtkPolyData()
bad.DeepCopy(digital)
pts = vtk_to_numpy(bad.GetPoints().GetData()).copy()
pts[3] += 0.17
bad.GetPoints().SetData(numpy_to_vtk(pts, deep=1))
m2 = vtkPiecewiseSmoothMeshFilter()
m2.AddObserver(vtkCommand.ErrorEvent, on_error)
m2.GetExecutive().AddObserver(vtkCommand.ErrorEvent, on_error)
m2.SetInputData(bad)
m2.Update()
check(len(errors) >= 1 and m2.GetOutput().GetNumberOfCells() == 0, "a surface of other polygons: error, empty output")

# --- the program: --mesh and the mesh files ---
def run(*args):
    out = tempfile.mkdtemp(dir=ROOT)
    p = subprocess.run([PROGRAM, "--quiet", "--output-dir", out, "--prefix", "m"] + list(args),
                       capture_output=True, text=True, timeout=600)
    return p, out


p, d = run("--size", "40", "--mesh", "--mesh-format", "stl,ply,obj")
check(p.returncode == 0, "--mesh --mesh-format stl,ply,obj runs (%s)" % p.stderr.strip()[-300:])
if p.returncode == 0:
    for f in ("m_mesh.vtp", "m_mesh_creases.vtp", "m_mesh.stl", "m_mesh.ply", "m_mesh.obj", "m_mesh.png"):
        check(os.path.isfile(os.path.join(d, f)), "wrote " + f)
    vtp = read(os.path.join(d, "m_mesh.vtp"))
    surf = read(os.path.join(d, "m_surface.vtp"))
    check(vtp.GetNumberOfPolys() == 2 * surf.GetNumberOfPolys(), "STL implies triangles (in the .vtp too)")
    stl = vtkSTLReader()
    stl.SetFileName(os.path.join(d, "m_mesh.stl"))
    stl.Update()
    check(stl.GetOutput().GetNumberOfPolys() == vtp.GetNumberOfPolys(), "STL: every triangle")
    ply = vtkPLYReader()
    ply.SetFileName(os.path.join(d, "m_mesh.ply"))
    ply.Update()
    check(ply.GetOutput().GetNumberOfPolys() == vtp.GetNumberOfPolys()
          and ply.GetOutput().GetPointData().GetNormals() is not None, "PLY: triangles and point normals")
    obj = vtkOBJReader()
    obj.SetFileName(os.path.join(d, "m_mesh.obj"))
    obj.Update()
    check(obj.GetOutput().GetNumberOfPolys() == vtp.GetNumberOfPolys()
          and obj.GetOutput().GetPointData().GetNormals() is not None, "OBJ: triangles and point normals")
    check("mesh:" in p.stdout and "crease edges" in p.stdout, "the summary has the mesh's line")

p, d = run("--size", "32", "--no-png", "--ply", "--obj")
check(p.returncode == 0 and os.path.isfile(os.path.join(d, "m_surface.ply"))
      and os.path.isfile(os.path.join(d, "m_surface.obj")), "--ply and --obj write their files")
p, _ = run("--mesh-format", "vrml")
check(p.returncode == 2 and "--mesh-format" in p.stderr, "--mesh-format vrml: exit 2 with the option's name")

# --- label interfaces: meshed once, every shared face in both labels ---
n = (34, 30, 28)
k, j, i = np.meshgrid(np.arange(n[2]), np.arange(n[1]), np.arange(n[0]), indexing="ij")
labels = np.zeros((n[2], n[1], n[0]), np.uint8)
labels[(i - 12.3) ** 2 + (j - 14.6) ** 2 + (k - 13.2) ** 2 <= 9.2 ** 2] = 1
labels[((i - 12.3) ** 2 + (j - 14.6) ** 2 + (k - 13.2) ** 2 <= 9.2 ** 2) & (i + 0.4 * j > 20.1)] = 2
labels[(i >= 18) & (i <= 29) & (j >= 6) & (j <= 24) & (k >= 9) & (k <= 17)
       & ((i - 12.3) ** 2 + (j - 14.6) ** 2 + (k - 13.2) ** 2 > 9.2 ** 2)] = 3
vti = os.path.join(ROOT, "labels.vti")
w = vtkXMLImageDataWriter()
w.SetInputData(image_of(labels))
w.SetFileName(vti)
w.Write()
p, d = run(vti, "--labels", "all", "--interfaces", "--mesh", "--no-png")
check(p.returncode == 0, "--labels all --interfaces --mesh runs (%s)" % p.stderr.strip()[-300:])
if p.returncode == 0:
    surf = read(os.path.join(d, "m_surface.vtp"))
    m = read(os.path.join(d, "m_mesh.vtp"))
    cr = read(os.path.join(d, "m_mesh_creases.vtp"))
    check(m.GetNumberOfPolys() == surf.GetNumberOfPolys(), "every interface face once (%d)" % m.GetNumberOfPolys())
    inside = vtk_to_numpy(m.GetCellData().GetArray("LabelInside"))
    outside = vtk_to_numpy(m.GetCellData().GetArray("LabelOutside"))
    pts = vtk_to_numpy(m.GetPoints().GetData())
    quads = vtk_to_numpy(m.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    key = lambda x: tuple(np.round(x, 9))
    # Each label's closed surface: its faces, by position; every side used
    # an even number of times (twice, or four times where two of its voxels
    # touch along an edge).
    for lab in (1, 2, 3):
        faces = quads[(inside == lab) | (outside == lab)]
        sides = {}
        for q in faces:
            for a in range(4):
                e = tuple(sorted((key(pts[q[a]]), key(pts[q[(a + 1) % 4]]))))
                sides[e] = sides.get(e, 0) + 1
        odd = sum(1 for v in sides.values() if v % 2)
        check(len(faces) > 0 and odd == 0, "label %d: a closed surface of %d faces from the mesh" % (lab, len(faces)))
    # The lines where three labels (or two and the background) meet: the
    # edges with three or more faces in the unsplit complex.
    spts = vtk_to_numpy(surf.GetPoints().GetData())
    squads = vtk_to_numpy(surf.GetPolys().GetConnectivityArray()).reshape(-1, 4)
    count = {}
    for q in squads:
        for a in range(4):
            e = (min(q[a], q[(a + 1) % 4]), max(q[a], q[(a + 1) % 4]))
            count[e] = count.get(e, 0) + 1
    triple = [e for e, c in count.items() if c >= 3]
    crease_pts = vtk_to_numpy(cr.GetPoints().GetData())
    crease_lines = vtk_to_numpy(cr.GetLines().GetConnectivityArray()).reshape(-1, 2)
    moved_of = {}
    ids = vtk_to_numpy(m.GetPolys().GetConnectivityArray())
    sids = vtk_to_numpy(surf.GetPolys().GetConnectivityArray())
    for a, b in zip(sids, ids):
        moved_of[a] = key(pts[b])
    crease_set = set(tuple(sorted((key(crease_pts[a]), key(crease_pts[b])))) for a, b in crease_lines)
    kept = sum(1 for a, b in triple if tuple(sorted((moved_of[a], moved_of[b]))) in crease_set)
    check(len(triple) > 10 and kept == len(triple),
          "every edge where three labels meet is a crease (%d of %d)" % (kept, len(triple)))
    # Shared faces: the faces between labels 1 and 2 are one set of quads,
    # in both labels' surfaces, on the same (moved) points.
    shared = quads[((inside == 2) & (outside == 1))]
    check(len(shared) > 20, "labels 1 and 2 share %d faces, meshed once" % len(shared))

print("%d failed" % len(failures))
sys.exit(1 if failures else 0)
