"""The MPI comparisons themselves (no MPI needed): on a one-process program
run, (1) the GlobalIds follow the contract (computed here from InsideVoxel,
SurfelDirection and the point positions; a one-process run writes none, and
the computed ones stand in; test_mpi_compare checks the N-rank ones), (2) compare() passes on an exact
copy and (3) fails on each wrong result a distributed run could give: an
AT normal turned by 0.02 degree, v off by 2e-5, an II normal off by 1e-12,
a surfel missing, a surfel twice, a feature edge missing, a border point
whose copies disagree."""
import os
import subprocess
import sys
import tempfile

import numpy as np
from vtkmodules.util import numpy_support as ns
from vtkmodules.vtkCommonCore import vtkIdTypeArray
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkFiltersCore import vtkAppendPolyData

import mpi_cases as mc

ROOT = tempfile.mkdtemp(prefix="dg_mpi_harness_", dir=os.environ.get("DG_TEST_TMP"))
check = mc.Checks()
volume = os.path.join(ROOT, "v.vti")
mc.make_case("cube-sphere-noisy", volume)
p = subprocess.run([os.environ["DG_PROGRAM"], "--quiet", "--no-png", "--plain", "--output-dir", ROOT,
                    "--prefix", "r", volume], capture_output=True, text=True, timeout=300)
check(p.returncode == 0, "one-process run (%s)" % (p.stderr.strip() or "ok"))
surface = mc.read_polydata(os.path.join(ROOT, "r_surface.vtp"))
features = mc.read_polydata(os.path.join(ROOT, "r_features.vtp"))

whole = [int(x) for x in ns.vtk_to_numpy(surface.GetFieldData().GetArray("ImageExtent"))]
cells, points = mc.contract_ids(surface, whole)
written_c = mc.array(surface.GetCellData(), "GlobalIds")
written_p = mc.array(surface.GetPointData(), "GlobalIds")
if written_c is None or written_p is None:
    print("info the one-process run writes no GlobalIds (only on request): the contract's, computed here, stand in")
    for data, ids in ((surface.GetCellData(), cells), (surface.GetPointData(), points)):
        a = ns.numpy_to_vtk(ids, deep=1, array_type=vtkIdTypeArray().GetDataType())
        a.SetName("GlobalIds")
        data.SetGlobalIds(a)
else:
    check(np.array_equal(written_c, cells), "cell GlobalIds = ((k*Ny + j)*Nx + i)*6 + d (%d cells)" % len(cells))
    check(np.array_equal(written_p, points), "point GlobalIds = (ck*(Ny+1) + cj)*(Nx+1) + ci (%d points)" % len(points))
    check(surface.GetCellData().GetGlobalIds() is not None and surface.GetPointData().GetGlobalIds() is not None,
          "GlobalIds are the attributes' global ids")


def copy(pd):
    out = vtkPolyData()
    out.DeepCopy(pd)
    return out


def expect(label, s, f, should_pass, needle):
    """Runs compare() quietly on (s, f); checks it fails on `needle` (or passes)."""
    inner = mc.Checks()
    import contextlib
    import io
    with contextlib.redirect_stdout(io.StringIO()):
        mc.compare(mc.Result(surface, features), mc.Result(s, f), inner, label, 0.01, 1e-5)
    if should_pass:
        check(not inner.failures, "%s: compare passes (%s)" % (label, "; ".join(inner.failures) or "all ok"))
    else:
        hit = [x for x in inner.failures if needle in x]
        check(bool(hit), "%s: compare catches it (%s)" % (label, "; ".join(inner.failures) or "nothing failed"))


expect("exact copy", copy(surface), copy(features), True, "")

s = copy(surface)
at = ns.vtk_to_numpy(s.GetCellData().GetArray("ATNormals"))
n = at[5] / np.linalg.norm(at[5])
t = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
t /= np.linalg.norm(t)
a = np.radians(0.02)
at[5] = np.cos(a) * n + np.sin(a) * t
s.GetCellData().GetArray("ATNormals").Modified()
expect("AT normal turned 0.02 deg", s, copy(features), False, "AT normals max angle")

s = copy(surface)
v = ns.vtk_to_numpy(s.GetPointData().GetArray("ATFeatureIndicator"))
v[7] += 2e-5
expect("v + 2e-5 at one point", s, copy(features), False, "v max difference")

s = copy(surface)
ii = ns.vtk_to_numpy(s.GetCellData().GetArray("IINormals"))
ii[3, 0] += 1e-12
expect("II normal + 1e-12", s, copy(features), False, "II normals identical")


def cells_subset(pd, keep):
    from vtkmodules.vtkCommonCore import vtkIdList
    ids = vtkIdList()
    for c in keep:
        ids.InsertNextId(int(c))
    out = vtkPolyData()
    out.Allocate(len(keep))
    out.SetPoints(pd.GetPoints())
    out.GetPointData().ShallowCopy(pd.GetPointData())
    out.GetCellData().CopyGlobalIdsOn()  # VTK leaves global ids out by default
    out.GetCellData().CopyAllocate(pd.GetCellData(), len(keep))
    for n_, c in enumerate(keep):
        cell = pd.GetCell(int(c))
        out.InsertNextCell(cell.GetCellType(), cell.GetPointIds())
        out.GetCellData().CopyData(pd.GetCellData(), int(c), n_)
    return out


ncell = surface.GetNumberOfCells()
expect("a surfel missing", cells_subset(surface, list(range(1, ncell))), copy(features), False, "same surfels")
# a surfel twice: two pieces that both emit it
dup = vtkAppendPolyData()
dup.AddInputData(copy(surface))
dup.AddInputData(cells_subset(surface, [0]))
dup.Update()
expect("a surfel twice", dup.GetOutput(), copy(features), False, "GlobalIds unique")
expect("a feature edge missing", copy(surface), cells_subset(features, list(range(1, features.GetNumberOfCells()))),
       False, "same feature edges")
# a border point twice (two pieces), its copies with different v
two = vtkAppendPolyData()
half = ncell // 2
a_, b_ = cells_subset(surface, list(range(half))), cells_subset(surface, list(range(half, ncell)))
two.AddInputData(a_)
two.AddInputData(b_)
two.Update()
split = copy(two.GetOutput())
expect("two pieces, border points duplicated", copy(split), copy(features), True, "")
vv = ns.vtk_to_numpy(split.GetPointData().GetArray("ATFeatureIndicator"))
gid = ns.vtk_to_numpy(split.GetPointData().GetArray("GlobalIds"))
first = {}
for idx, g in enumerate(gid.tolist()):
    if g in first:
        vv[idx] += 1e-7  # within 1e-5 of the reference, but the copies differ
        break
    first[g] = idx
expect("border copies disagree", split, copy(features), False, "copies carry the same v")

sys.exit(check.finish(ROOT))
