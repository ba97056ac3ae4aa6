"""vtkSharpFeaturesFilter from Python: a digitised axis-aligned box through
the digital surface, II normals and AT, then the sharp-features stage: the
box's 12 edges come out as single lines on the edges, with side normals."""
import math
import sys

from vtkmodules.vtkCommonDataModel import vtkImageData

from digitalgeometry import (vtkAmbrosioTortorelliFilter, vtkDigitalSurfaceFilter,
                             vtkIINormalEstimator, vtkSharpFeaturesFilter)

failures = []
checks = []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


# A 16 x 14 x 12 box of voxels in a 24^3 image: voxels 4..19, 5..18, 6..17.
lo, hi = (4, 5, 6), (20, 19, 18)
img = vtkImageData()
img.SetDimensions(24, 24, 24)
img.AllocateScalars(3, 1)  # VTK_UNSIGNED_CHAR
s = img.GetPointData().GetScalars()
for k in range(24):
    for j in range(24):
        for i in range(24):
            inside = lo[0] <= i < hi[0] and lo[1] <= j < hi[1] and lo[2] <= k < hi[2]
            s.SetTuple1((k * 24 + j) * 24 + i, 1 if inside else 0)

surf = vtkDigitalSurfaceFilter()
surf.SetInputData(img)
ii = vtkIINormalEstimator()
ii.SetInputConnection(surf.GetOutputPort())
ii.SetSourceData(img)
ii.SetRadius(3)
at = vtkAmbrosioTortorelliFilter()
at.SetInputConnection(ii.GetOutputPort())
sharp = vtkSharpFeaturesFilter()
sharp.SetInputConnection(at.GetOutputPort())
sharp.Update()

out = sharp.GetOutputDataObject(0)
lines = sharp.GetOutputDataObject(1)
n = out.GetCellData().GetNormals()
check(n is not None and n.GetName() == "SharpNormals", "active normals are SharpNormals")
check(out.GetCellData().GetArray("ATNormals") is not None, "AT's normals kept")
check(sharp.GetNumberOfRegions() == 6, "six regions, one per face (%d)" % sharp.GetNumberOfRegions())

# Every feature line runs along a box edge: both end points on two of the
# box's bounding planes (voxel corners at index - 0.5).
planes = [(lo[a] - 0.5, hi[a] - 0.5) for a in range(3)]


def on_edge(p):
    return sum(1 for a in range(3) if any(abs(p[a] - b) < 1e-9 for b in planes[a])) >= 2


nl = lines.GetNumberOfLines()
all_on_edges = all(on_edge(lines.GetPoint(lines.GetCell(c).GetPointId(e)))
                   for c in range(nl) for e in range(2))
edge_length = 4 * sum(hi[a] - lo[a] for a in range(3))
check(nl == edge_length and all_on_edges,
      "%d feature lines, all on the box's edges (edge length %d; AT alone: %d)"
      % (nl, edge_length, at.GetOutputDataObject(1).GetNumberOfLines()))

# The same lines as each face's flagged sides (CreaseSides, bit i: the side
# from corner i to corner i + 1), which the mesh and curvature stages read.
flags = out.GetCellData().GetArray("CreaseSides")
flagged = set()
for c in range(out.GetNumberOfCells() if flags is not None else 0):
    ids = out.GetCell(c).GetPointIds()
    m = ids.GetNumberOfIds()
    for i in range(m):
        if int(flags.GetTuple1(c)) & (1 << i):
            a, b = ids.GetId(i), ids.GetId((i + 1) % m)
            flagged.add((min(a, b), max(a, b)))
drawn = set()
for c in range(nl):
    a, b = lines.GetCell(c).GetPointId(0), lines.GetCell(c).GetPointId(1)
    drawn.add((min(a, b), max(a, b)))
check(flags is not None and flagged == drawn,
      "CreaseSides flags the feature lines' edges, no other (%d flagged, %d lines)"
      % (len(flagged), len(drawn)))

# Side normals: every face's normal is its own axis direction, up to the
# edges (AT leaves the faces along the edges with II's blended normal).
trivial = out.GetCellData().GetArray("Normals")
u = out.GetCellData().GetArray("ATNormals")


def worst_degrees(field):
    w = 0.0
    for c in range(out.GetNumberOfCells()):
        a, b = field.GetTuple3(c), trivial.GetTuple3(c)
        w = max(w, math.degrees(math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b)))))))
    return w


ws, wa = worst_degrees(n), worst_degrees(u)
check(ws < 2.0 and ws < wa / 5, "every face has its own side's normal: worst %.2f deg (AT: %.1f)" % (ws, wa))

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
sys.exit(1 if failures else 0)
