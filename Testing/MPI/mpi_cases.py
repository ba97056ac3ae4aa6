"""Volumes and comparisons shared by the MPI tests (Testing/MPI).

Volumes: small (<= 64^3) ground-truth shapes as in Testing/Cxx/dgGroundTruth
(rotated cube, cube ∩ sphere; noise k = 0.3 from the module's own
vtkDigitalNoiseFilter), a clean cube whose sharp edges cross every piece
boundary, a volume where one piece holds no inside voxel, and non-manifold
voxel blocks (sharing only an edge, only a corner) placed across the piece
boundaries. Piece boundaries come from the same split as the filters
(dg::PieceExtent: vtkExtentTranslator, block mode, by points).

Comparisons go by the contract's global ids: cell GlobalIds
((k*Ny + j)*Nx + i)*6 + d, point GlobalIds from the pointel's corner index.
"""
import math
import os

import numpy as np
from vtkmodules.util import numpy_support as ns
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator
from vtkmodules.vtkIOXML import (vtkXMLImageDataWriter, vtkXMLPPolyDataReader,
                                 vtkXMLPolyDataReader)

# ---------------------------------------------------------------- pieces


def piece_extent(whole, piece, pieces):
    """The own voxel extent of a piece (dg::PieceExtent), None when empty."""
    if pieces == 1:
        return list(whole)
    t = vtkExtentTranslator()
    t.SetSplitModeToBlock()
    out = [0, -1, 0, -1, 0, -1]
    ok = t.PieceToExtentThreadSafe(piece, pieces, 0, list(whole), out, t.GetSplitMode(), 1)
    if not ok or out[0] > out[1] or out[2] > out[3] or out[4] > out[5]:
        return None
    return out


def boundaries(whole, pieces):
    """{axis: sorted first voxel indices of the pieces that start inside the whole extent}."""
    b = {0: set(), 1: set(), 2: set()}
    for p in range(pieces):
        e = piece_extent(whole, p, pieces)
        if e is None:
            continue
        for a in range(3):
            if e[2 * a] > whole[2 * a]:
                b[a].add(e[2 * a])
    return {a: sorted(v) for a, v in b.items()}


# ---------------------------------------------------------------- shapes


def rotation(ax, ay, az):
    """R = Rz Ry Rx (degrees), as dgGroundTruth's MakeRotatedCube."""
    ax, ay, az = (math.radians(a) for a in (ax, ay, az))
    rx = np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]])
    ry = np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]])
    rz = np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]])
    return rz @ ry @ rx


def grid(dims):
    k, j, i = np.meshgrid(np.arange(dims[2]), np.arange(dims[1]), np.arange(dims[0]), indexing="ij")
    return np.stack([i, j, k], axis=-1).astype(float)  # [k, j, i, xyz]


def rotated_cube(dims, center, h, angles):
    p = grid(dims) - np.asarray(center)
    local = p @ rotation(*angles)  # R^T (p - c) for each row vector
    return np.max(np.abs(local), axis=-1) <= h


def cube_edges(center, h, angles):
    r = rotation(*angles)
    corners = {}
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                corners[(sx, sy, sz)] = r @ np.array([sx, sy, sz]) * h + np.asarray(center)
    edges = []
    for c, a in corners.items():
        for axis in range(3):
            if c[axis] < 0:
                d = list(c)
                d[axis] = 1
                edges.append((a, corners[tuple(d)]))
    return edges


def cube_sphere(dims, center, h, r):
    p = grid(dims) - np.asarray(center)
    return (np.max(np.abs(p), axis=-1) <= h) & (np.linalg.norm(p, axis=-1) <= r)


def ball(dims, center, r):
    p = grid(dims) - np.asarray(center)
    return np.linalg.norm(p, axis=-1) <= r


def builtin_shape(n):
    """The program's built-in shape (Applications/dgBuiltinShape.cxx) in n^3:
    a rotated cube with a sphere near one corner and a cylindrical hole."""
    c = 0.5 * (n - 1)
    h, rs, rc = 0.26 * n, 0.22 * n, 0.12 * n
    q = (grid((n, n, n)) - c) @ rotation(20, 30, 10)
    cube = np.max(np.abs(q), axis=-1) <= h
    sphere = np.linalg.norm(q - 0.55 * h, axis=-1) <= rs
    hole = q[..., 0] ** 2 + q[..., 1] ** 2 <= rc * rc
    return (cube | sphere) & ~hole


def to_image(inside, dims):
    image = vtkImageData()
    image.SetDimensions(*dims)
    a = ns.numpy_to_vtk(np.ascontiguousarray(inside.astype(np.uint8).ravel()), deep=1,
                        array_type=vtkUnsignedCharArray().GetDataType())
    a.SetName("Inside")
    image.GetPointData().SetScalars(a)
    return image


def add_noise(image, k, seed):
    from digitalgeometry import vtkDigitalNoiseFilter
    f = vtkDigitalNoiseFilter()
    f.SetInputData(image)
    f.SetNoiseLevel(k)
    f.SetSeed(seed)
    f.Update()
    out = vtkImageData()
    out.DeepCopy(f.GetOutput())
    return out


def write_vti(image, path):
    w = vtkXMLImageDataWriter()
    w.SetInputData(image)
    w.SetFileName(path)
    w.SetDataModeToBinary()
    if not w.Write():
        raise RuntimeError("cannot write " + path)
    return path


CASES = ["rotated-cube-noisy", "cube-sphere-noisy", "edges-across", "empty-piece", "non-manifold"]


BUILTIN_SIZE = 48


def make_case(name, path, pieces=(2, 3)):
    """Writes the case's volume to path (.vti); returns a one-line description."""
    if name == "rotated-cube-noisy":
        dims = (48, 48, 48)
        inside = rotated_cube(dims, (23.6, 24.3, 23.8), 13.0, (20, 30, 10))
        image = add_noise(to_image(inside, dims), 0.3, 1)
        write_vti(image, path)
        return "rotated cube h = 13 in 48^3, noise k = 0.3 (seed 1)"
    if name == "cube-sphere-noisy":
        dims = (48, 48, 48)
        inside = cube_sphere(dims, (23.7, 24.2, 23.9), 14.0, 18.5)
        image = add_noise(to_image(inside, dims), 0.3, 2)
        write_vti(image, path)
        return "cube h = 14 ∩ sphere r = 18.5 in 48^3, noise k = 0.3 (seed 2)"
    if name == "builtin":
        # The program runs its own built-in shape (no INPUT, --size 48);
        # pvbatch reads this copy of it.
        dims = (BUILTIN_SIZE,) * 3
        write_vti(to_image(builtin_shape(BUILTIN_SIZE), dims), path)
        return "the program's built-in shape at %d^3 (cube + sphere - cylinder)" % BUILTIN_SIZE
    if name == "edges-across":
        dims = (44, 44, 44)
        center, h, angles = (21.7, 22.2, 21.4), 14.0, (35, 25, 15)
        whole = [0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1]
        # Every piece boundary plane is crossed by a true sharp edge.
        for n in pieces:
            for axis, planes in boundaries(whole, n).items():
                for b in planes:
                    x = b - 0.5
                    crossing = [e for e in cube_edges(center, h, angles)
                                if (e[0][axis] - x) * (e[1][axis] - x) < 0]
                    assert crossing, "no sharp edge crosses the plane %s = %g (%d pieces)" % (
                        "xyz"[axis], x, n)
        write_vti(to_image(rotated_cube(dims, center, h, angles), dims), path)
        return "clean rotated cube h = 14 in 44^3, sharp edges across every piece boundary"
    if name == "empty-piece":
        dims = (24, 24, 48)
        inside = ball(dims, (11.6, 12.2, 10.3), 7.5)
        whole = [0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1]
        flat = inside.transpose(2, 1, 0)  # [i, j, k]
        for n in pieces:
            empty = 0
            for p in range(n):
                e = piece_extent(whole, p, n)
                if e is None or not flat[e[0]:e[1] + 1, e[2]:e[3] + 1, e[4]:e[5] + 1].any():
                    empty += 1
            assert empty >= 1, "no empty piece with %d pieces" % n
        write_vti(to_image(inside, dims), path)
        return "ball r = 7.5 in the low third of 24x24x48: the upper piece(s) hold no inside voxel"
    if name == "non-manifold":
        dims = (32, 32, 32)
        whole = [0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1]
        inside = np.zeros((dims[2], dims[1], dims[0]), dtype=bool)  # [k, j, i]

        def box(axis, b, o, lo_a, p, q):
            """voxel ranges [lo, hi) of a 3^3 block: lo_a along axis, p and q along the others."""
            r = [None, None, None]
            r[axis] = (lo_a, lo_a + 3)
            r[o[0]] = (p, p + 3)
            r[o[1]] = (q, q + 3)
            return r

        def free(r):
            # the block and a one-voxel margin hold nothing yet
            sl = tuple(slice(max(0, r[a][0] - 1), r[a][1] + 1) for a in (2, 1, 0))
            return all(0 <= r[a][0] and r[a][1] <= dims[a] for a in range(3)) and not inside[sl].any()

        def put(r):
            inside[r[2][0]:r[2][1], r[1][0]:r[1][1], r[0][0]:r[0][1]] = True

        # 3^3 blocks (27 voxels: the island filter keeps them) meeting along
        # an edge only or at a corner only, the contact right on a piece
        # boundary b (b - 1 is the last voxel of the lower piece).
        def owner(n, r):
            # the piece of n that owns every voxel of block r (None if shared)
            for piece in range(n):
                e = piece_extent(whole, piece, n)
                if e and all(e[2 * a] <= r[a][0] and r[a][1] - 1 <= e[2 * a + 1] for a in range(3)):
                    return piece
            return None

        planes = []
        for n in pieces:
            for axis, bs in boundaries(whole, n).items():
                planes.extend((n, axis, b) for b in bs)
        placed = 0
        for n, axis, b in planes:
            o = [a for a in range(3) if a != axis]
            for kind in ("edge", "corner"):
                done = False
                for p in range(1, dims[o[0]] - 7):
                    for q in range(1, dims[o[1]] - 7):
                        a = box(axis, b, o, b - 3, p, q)
                        c = box(axis, b, o, b, p + 3, q + (3 if kind == "corner" else 0))
                        # the pair's own contact is allowed: test the two apart
                        if free(a) and free(c) and None != owner(n, a) != owner(n, c) is not None:
                            put(a)
                            put(c)
                            done = True
                            break
                    if done:
                        break
                assert done, "no room for the %s pair at %s = %d" % (kind, "xyz"[axis], b)
                placed += 1
        assert placed >= 2
        write_vti(to_image(inside, dims), path)
        return "3^3 voxel blocks touching along an edge only or at a corner only, across %d piece boundaries (2 and 3 pieces)" % len(planes)
    raise ValueError("unknown case " + name)


# ---------------------------------------------------------------- results


def read_polydata(path):
    r = vtkXMLPPolyDataReader() if path.endswith(".pvtp") else vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0 or r.GetOutput() is None:
        raise RuntimeError("cannot read " + path)
    return r.GetOutput()


def array(data, name):
    a = data.GetArray(name)
    return None if a is None else ns.vtk_to_numpy(a)


class Result:
    """A run's surface and feature lines, indexed by global ids."""

    def __init__(self, surface, features, reference=False):
        """surface, features: file names (.vtp or .pvtp) or vtkPolyData.
        reference: a one-process run, which writes no GlobalIds (the filter
        adds them to one piece only on request): the contract's ids are
        computed from its InsideVoxel, SurfelDirection and point positions."""
        self.surface = read_polydata(surface) if isinstance(surface, str) else surface
        self.features = read_polydata(features) if isinstance(features, str) else features
        s = self.surface
        self.cell_ids = array(s.GetCellData(), "GlobalIds")
        self.point_ids = array(s.GetPointData(), "GlobalIds")
        self.derived = False
        if reference and self.cell_ids is None and s.GetNumberOfCells() and \
                s.GetCellData().GetArray("InsideVoxel") is not None:
            whole = [int(x) for x in ns.vtk_to_numpy(s.GetFieldData().GetArray("ImageExtent"))]
            self.cell_ids, self.point_ids = contract_ids(s, whole)
            self.derived = True
        self.ii = array(s.GetCellData(), "IINormals")
        self.at = array(s.GetCellData(), "ATNormals")
        self.v = array(s.GetPointData(), "ATFeatureIndicator")
        self.ghosts = array(s.GetCellData(), "vtkGhostType")
        self.curvature = {n: array(s.GetCellData(), n) for n in (
            "CorrectedMeanCurvature", "CorrectedGaussianCurvature", "CorrectedK1", "CorrectedK2")}
        fd = s.GetFieldData()
        self.totals = {n: (fd.GetArray(n).GetValue(0) if fd.GetArray(n) else None) for n in (
            "CorrectedArea", "IntegralMeanCurvature", "GaussBonnetCharacteristic", "EulerCharacteristic")}

    def drop_ghosts(self, check, label):
        """A ghost level asked for downstream (ParaView's parallel writer
        asks for one) writes the ring of ghost cells around each piece,
        marked in vtkGhostType: each must repeat a cell some piece owns, with
        its owner's values; then they are left out of the comparison."""
        if self.ghosts is None or not np.any(self.ghosts & 1) or self.cell_ids is None:
            return
        ghost = (self.ghosts & 1) != 0
        owner = {int(g): i for i, g in enumerate(self.cell_ids) if not ghost[i]}
        known = [owner.get(int(g)) for g in self.cell_ids[ghost]]
        match = all(k is not None for k in known)
        for values in [self.ii, self.at] + list(self.curvature.values()):
            if match and values is not None:
                match = np.array_equal(values[ghost], values[known])
        check(match, "%s: the %d ghost cells written repeat owned cells with their owners' values"
              % (label, int(ghost.sum())))
        keep = ~ghost
        self.cell_ids = self.cell_ids[keep]
        self.ii = None if self.ii is None else self.ii[keep]
        self.at = None if self.at is None else self.at[keep]
        self.curvature = {n: (None if c is None else c[keep]) for n, c in self.curvature.items()}
        self.ghosts = None

    def edges(self):
        """Feature edges as sorted pairs of global point ids (a list, with repeats)."""
        f = self.features
        fid = array(f.GetPointData(), "GlobalIds")
        if fid is None:
            # by position: corners sit on exact grid positions in both files
            pts = ns.vtk_to_numpy(self.surface.GetPoints().GetData()) if self.surface.GetNumberOfPoints() else np.zeros((0, 3))
            where = {tuple(p): int(g) for p, g in zip(pts, self.point_ids)}
            fp = ns.vtk_to_numpy(f.GetPoints().GetData()) if f.GetNumberOfPoints() else np.zeros((0, 3))
            fid = np.array([where.get(tuple(p), -1) for p in fp], dtype=np.int64)
        out = []
        lines = f.GetLines()
        conn = ns.vtk_to_numpy(lines.GetConnectivityArray()) if lines.GetNumberOfCells() else np.zeros(0, int)
        offs = ns.vtk_to_numpy(lines.GetOffsetsArray()) if lines.GetNumberOfCells() else np.zeros(1, int)
        for c in range(len(offs) - 1):
            ids = conn[offs[c]:offs[c + 1]]
            for a, b in zip(ids[:-1], ids[1:]):
                ga, gb = int(fid[a]), int(fid[b])
                out.append((min(ga, gb), max(ga, gb)))
        return out


class Checks:
    def __init__(self):
        self.failures, self.count = [], 0

    def finish(self, root):
        """Prints the tally; removes the test's folder when all passed (kept
        for a look otherwise); returns the exit status."""
        import shutil
        print("%d checks, %d failed" % (self.count, len(self.failures)))
        for f in self.failures:
            print("FAILED: " + f)
        if not self.failures:
            shutil.rmtree(root, ignore_errors=True)
        return 1 if self.failures else 0

    def __call__(self, cond, what):
        self.count += 1
        print(("ok   " if cond else "FAIL ") + what, flush=True)
        if not cond:
            self.failures.append(what)
        return cond


def compare(ref, res, check, label, angle_limit, v_limit, assert_edges=True):
    """Compares res with ref (Result) by global ids; prints the figures."""
    if not check(res.cell_ids is not None and ref.cell_ids is not None,
                 "%s: cell GlobalIds present (reference %s, run %s)"
                 % (label, ref.cell_ids is not None, res.cell_ids is not None)):
        return
    res.drop_ghosts(check, label)
    uniq = np.unique(res.cell_ids)
    check(len(uniq) == len(res.cell_ids), "%s: cell GlobalIds unique (%d cells, %d duplicated)"
          % (label, len(res.cell_ids), len(res.cell_ids) - len(uniq)))
    same = np.array_equal(np.sort(ref.cell_ids), np.sort(res.cell_ids))
    only_ref = np.setdiff1d(ref.cell_ids, res.cell_ids)
    only_res = np.setdiff1d(res.cell_ids, ref.cell_ids)
    check(same, "%s: same surfels as one process (%d; %d missing, %d extra)"
          % (label, len(ref.cell_ids), len(only_ref), len(only_res)))
    common, ir, it = np.intersect1d(ref.cell_ids, res.cell_ids, return_indices=True)
    if ref.ii is not None and res.ii is not None and len(common):
        d = np.max(np.abs(ref.ii[ir] - res.ii[it]))
        check(d == 0.0, "%s: II normals identical (max component difference %.3g)" % (label, d))
    else:
        check(False, "%s: IINormals present" % label)
    if ref.at is not None and res.at is not None and len(common):
        cos = np.clip(np.sum(ref.at[ir] * res.at[it], axis=1)
                      / (np.linalg.norm(ref.at[ir], axis=1) * np.linalg.norm(res.at[it], axis=1)), -1, 1)
        ang = np.degrees(np.arccos(cos))
        # arccos loses precision near 1: the chord gives small angles
        chord = np.linalg.norm(ref.at[ir] / np.linalg.norm(ref.at[ir], axis=1)[:, None]
                               - res.at[it] / np.linalg.norm(res.at[it], axis=1)[:, None], axis=1)
        ang = np.where(ang < 1.0, np.degrees(2 * np.arcsin(np.clip(chord / 2, 0, 1))), ang)
        check(ang.max() <= angle_limit, "%s: AT normals max angle %.3g deg (limit %g; mean %.3g)"
              % (label, ang.max(), angle_limit, ang.mean()))
    else:
        check(False, "%s: ATNormals present" % label)
    if ref.point_ids is not None and res.point_ids is not None and ref.v is not None and res.v is not None:
        refv = dict(zip(ref.point_ids.tolist(), ref.v.tolist()))
        missing = [g for g in res.point_ids.tolist() if g not in refv]
        diffs = np.array([abs(v - refv[g]) for g, v in zip(res.point_ids.tolist(), res.v.tolist()) if g in refv])
        dv = diffs.max() if len(diffs) else 0.0
        check(not missing and dv <= v_limit, "%s: v max difference %.3g over %d point copies (limit %g; %d unknown points)"
              % (label, dv, len(res.v), v_limit, len(missing)))
        # the copies of a border point in several pieces agree
        copies = {}
        for g, v in zip(res.point_ids.tolist(), res.v.tolist()):
            copies.setdefault(g, set()).add(v)
        split = sum(1 for s in copies.values() if len(s) > 1)
        check(split == 0, "%s: border points' copies carry the same v (%d points differ)" % (label, split))
    else:
        check(False, "%s: point GlobalIds and ATFeatureIndicator present" % label)
    if ref.curvature["CorrectedMeanCurvature"] is not None and len(common):
        # The pvbatch pipeline's curvature reads the II normals, identical
        # in every run: the pieces' balls must see the faces one process sees.
        worst = max(np.max(np.abs(ref.curvature[n][ir] - res.curvature[n][it])) if res.curvature[n] is not None
                    else np.inf for n in ref.curvature)
        check(worst <= 1e-9, "%s: corrected curvatures equal one process's (max difference %.3g)" % (label, worst))
        same = all(res.totals[n] is not None and abs(res.totals[n] - ref.totals[n]) <= 1e-9 * max(1.0, abs(ref.totals[n]))
                   for n in ref.totals)
        check(same, "%s: whole-surface figures equal one process's (%s against %s)" % (label, res.totals, ref.totals))
    re_, te = ref.edges(), res.edges()
    dup = len(te) - len(set(te))
    rs, ts = set(re_), set(te)
    diff = "%d edges, %d only in one process, %d only here, %d listed twice" % (
        len(rs), len(rs - ts), len(ts - rs), dup)
    if assert_edges:
        check(rs == ts and dup == 0, "%s: same feature edges (%s)" % (label, diff))
    else:
        print("info %s: feature edges: %s" % (label, diff))
    if rs != ts and ref.v is not None:
        refv = dict(zip(ref.point_ids.tolist(), ref.v.tolist()))
        near = [max(refv.get(a, -1), refv.get(b, -1)) for a, b in list((rs - ts) | (ts - rs))[:5]]
        print("info %s: v at the ends of some differing edges (threshold 0.5): %s"
              % (label, ", ".join("%.6f" % x for x in near)))


def compare_creases(ref_surface, ref_creases, res_surface, res_creases, check, label, angle_limit=1e-9,
                    require=True):
    """The Corrected Curvature filter's creases (pvbatch pipeline): the same
    edges by global point ids, each once, with the same angles."""
    def by_edge(surface, creases):
        r = Result(surface, creases, reference=True)
        angles = array(r.features.GetCellData(), "CreaseAngle")
        edges = r.edges()
        return edges, dict(zip(edges, [] if angles is None else angles.tolist()))
    re_, ra = by_edge(ref_surface, ref_creases)
    te, ta = by_edge(res_surface, res_creases)
    dup = len(te) - len(set(te))
    check((len(re_) > 0 or not require) and set(re_) == set(te) and dup == 0,
          "%s: the same crease edges (%d; %d only in one process, %d only here, %d listed twice)"
          % (label, len(set(re_)), len(set(re_) - set(te)), len(set(te) - set(re_)), dup))
    common = set(ra) & set(ta)
    worst = max((abs(ra[e] - ta[e]) for e in common), default=0.0)
    check(worst <= angle_limit, "%s: crease angles equal one process's (max difference %.3g degrees, limit %g)"
          % (label, worst, angle_limit))


def compare_ball_radius(ref_surface, res_surface, check, label):
    """Corrected Curvature of one region (pvbatch pipeline): every face's
    ball radius is chosen per face from what the balls around it measure,
    up to 3 Radius across the pieces' borders; each face's radius and
    curvatures equal one process's."""
    ref, res = Result(ref_surface, ref_surface, reference=True), Result(res_surface, res_surface)
    radius = {"ref": array(ref.surface.GetCellData(), "CorrectedBallRadius"),
              "res": array(res.surface.GetCellData(), "CorrectedBallRadius")}
    if radius["res"] is not None and res.ghosts is not None and np.any(res.ghosts & 1):
        radius["res"] = radius["res"][(res.ghosts & 1) == 0]
    res.drop_ghosts(check, label)
    ok = ref.cell_ids is not None and res.cell_ids is not None and radius["ref"] is not None and \
        radius["res"] is not None and np.array_equal(np.sort(ref.cell_ids), np.sort(res.cell_ids))
    check(ok, "%s: the same faces (%d) with CorrectedBallRadius" % (label, 0 if res.cell_ids is None else len(res.cell_ids)))
    if not ok or not len(ref.cell_ids):
        return
    ir, it = np.argsort(ref.cell_ids), np.argsort(res.cell_ids)
    worst = max(np.max(np.abs(ref.curvature[n][ir] - res.curvature[n][it])) if res.curvature[n] is not None
                else np.inf for n in ref.curvature)
    worst_radius = float(np.max(np.abs(radius["ref"][ir] - radius["res"][it])))
    base = ref.surface.GetFieldData().GetArray("CurvatureRadius").GetValue(0)
    chosen = radius["ref"] > 0
    moved = float(np.mean(np.abs(radius["ref"][chosen] - base) > 1e-9 * base)) if chosen.any() else 0.0
    check(moved > 0.5, "%s: %.0f %% of the faces have a radius of their own (%.3g to %.3g, Radius %g)"
          % (label, 100 * moved, radius["ref"][chosen].min() if chosen.any() else 0,
             radius["ref"].max(), base))
    check(worst <= 1e-9 and worst_radius <= 1e-9,
          "%s: radii and curvatures equal one process's (max difference %.3g, %.3g)" % (label, worst_radius, worst))


def compare_sharp(ref_surface, ref_features, res_surface, res_features, check, label, angle_limit):
    """The sharp-features stage (the program's default output, or the
    plugin's Sharp Features): the same surfels, SharpNormals within
    angle_limit degrees, the same feature lines by global point ids (each
    once), the same FeatureRegion partition up to relabelling."""
    ref, res = Result(ref_surface, ref_features, reference=True), Result(res_surface, res_features)
    rs, ts = array(ref.surface.GetCellData(), "SharpNormals"), array(res.surface.GetCellData(), "SharpNormals")
    rr, tr = array(ref.surface.GetCellData(), "FeatureRegion"), array(res.surface.GetCellData(), "FeatureRegion")
    ok = all(x is not None for x in (rs, ts, rr, tr, ref.cell_ids, res.cell_ids))
    ghosts = array(res.surface.GetCellData(), "vtkGhostType")
    if ok and ghosts is not None and np.any(ghosts & 1):
        # A ghost level asked for downstream (ParaView's writer asks for
        # one): the ring is marked, and each ghost carries its owner's values.
        ghost = (ghosts & 1) != 0
        owner = {int(g): i for i, g in enumerate(res.cell_ids) if not ghost[i]}
        known = [owner.get(int(g)) for g in res.cell_ids[ghost]]
        match = all(k is not None for k in known) and np.array_equal(ts[ghost], ts[known]) and \
            np.array_equal(tr[ghost], tr[known])
        check(match, "%s: the %d ghost cells carry their owners' SharpNormals and FeatureRegion"
              % (label, int(ghost.sum())))
        ts, tr, res.cell_ids = ts[~ghost], tr[~ghost], res.cell_ids[~ghost]
    same = ok and np.array_equal(np.sort(ref.cell_ids), np.sort(res.cell_ids))
    check(same, "%s: the same surfels (%d) with SharpNormals and FeatureRegion" % (label, len(res.cell_ids) if ok else 0))
    if not same:
        return
    ir, it = np.argsort(ref.cell_ids), np.argsort(res.cell_ids)
    dots = np.clip((rs[ir] * ts[it]).sum(1) / np.linalg.norm(rs[ir], axis=1) / np.linalg.norm(ts[it], axis=1), -1, 1)
    worst = float(np.degrees(np.arccos(dots)).max())
    check(worst <= angle_limit, "%s: SharpNormals within %g degree of one process's (max %.3g)" % (label, angle_limit, worst))
    a, b = rr[ir], tr[it]
    pairs = set(zip(a.tolist(), b.tolist()))
    bijective = len(pairs) == len(set(a.tolist())) == len(set(b.tolist()))
    check(bijective, "%s: the same FeatureRegion partition up to relabelling (%d regions, %d label pairs)"
          % (label, len(set(a.tolist())), len(pairs)))
    re_, te = ref.edges(), res.edges()
    dup = len(te) - len(set(te))
    # (a smooth case has none in both)
    check(set(re_) == set(te) and dup == 0,
          "%s: the same feature lines (%d; %d only in one process, %d only here, %d listed twice)"
          % (label, len(set(re_)), len(set(re_) - set(te)), len(set(te) - set(re_)), dup))


def mesh_points(mesh):
    """A mesh's moved positions by the contract's point id of the voxel
    corner each vertex started from (its position minus MeshDisplacement;
    copies of a point share it), in voxels."""
    fd = mesh.GetFieldData()
    origin = ns.vtk_to_numpy(fd.GetArray("ImageOrigin"))
    spacing = ns.vtk_to_numpy(fd.GetArray("ImageSpacing"))
    whole = [int(x) for x in ns.vtk_to_numpy(fd.GetArray("ImageExtent"))]
    nx, ny = whole[1] - whole[0] + 1, whole[3] - whole[2] + 1
    pts = ns.vtk_to_numpy(mesh.GetPoints().GetData()).astype(float)
    corner = pts - ns.vtk_to_numpy(mesh.GetPointData().GetArray("MeshDisplacement"))
    c = np.rint((corner - origin) / spacing + 0.5).astype(np.int64) - np.array(whole[0::2])
    ids = (c[:, 2] * (ny + 1) + c[:, 1]) * (nx + 1) + c[:, 0]
    return dict(zip(ids.tolist(), ((pts - origin) / spacing).tolist()))


def compare_mesh(ref_mesh, ref_creases, res_mesh, res_creases, check, label, limit, require=True):
    """The Piecewise Smooth Mesh filter (pvbatch pipeline): every vertex at
    one process's position (within `limit` voxel), the same faces, the same
    crease edges each once."""
    rm, tm = read_polydata(ref_mesh), read_polydata(res_mesh)
    rp, tp = mesh_points(rm), mesh_points(tm)
    common = set(rp) & set(tp)
    worst = max((max(abs(a - b) for a, b in zip(rp[i], tp[i])) for i in common), default=np.inf)
    check(len(common) > 0 and set(rp) == set(tp) and rm.GetNumberOfCells() == tm.GetNumberOfCells(),
          "%s: the mesh's faces and vertices (%d faces, %d vertices; %d only in one process, %d only here)"
          % (label, tm.GetNumberOfCells(), len(tp), len(set(rp) - set(tp)), len(set(tp) - set(rp))))
    check(worst <= limit, "%s: mesh vertices at one process's positions (max difference %.3g voxel, limit %g)"
          % (label, worst, limit))

    out = []
    for mesh, path, byid in ((rm, ref_creases, rp), (tm, res_creases, tp)):
        c = read_polydata(path)
        fd = mesh.GetFieldData()
        origin = ns.vtk_to_numpy(fd.GetArray("ImageOrigin"))
        spacing = ns.vtk_to_numpy(fd.GetArray("ImageSpacing"))
        # crease points are mesh vertices: matched by position (cells of
        # different corners are disjoint, so positions are unique)
        keys = {}
        for i, p in byid.items():
            keys[tuple(np.round(p, 6))] = i
        pts = ns.vtk_to_numpy(c.GetPoints().GetData()).astype(float) if c.GetNumberOfPoints() else np.zeros((0, 3))
        pid = [keys.get(tuple(np.round((p - origin) / spacing, 6)), -1) for p in pts]
        lines = ns.vtk_to_numpy(c.GetLines().GetConnectivityArray()).reshape(-1, 2) if c.GetNumberOfLines() else np.zeros((0, 2), int)
        out.append([tuple(sorted((pid[a], pid[b]))) for a, b in lines])
    re_, te = out
    dup = len(te) - len(set(te))
    check((len(re_) > 0 or not require) and -1 not in {x for e in te for x in e} and set(re_) == set(te)
          and dup == 0,
          "%s: the same mesh creases (%d; %d only in one process, %d only here, %d listed twice)"
          % (label, len(set(re_)), len(set(re_) - set(te)), len(set(te) - set(re_)), dup))


def files_of(folder):
    out = {}
    for root, _, names in os.walk(folder):
        for n in names:
            p = os.path.join(root, n)
            with open(p, "rb") as f:
                out[os.path.relpath(p, folder)] = f.read()
    return out


def contract_ids(surface, whole):
    """The contract's GlobalIds from the surface's own geometry: cells from
    InsideVoxel and SurfelDirection, points from their corner positions
    (origin and spacing from the field data)."""
    nx, ny = whole[1] - whole[0] + 1, whole[3] - whole[2] + 1
    voxel = array(surface.GetCellData(), "InsideVoxel").astype(np.int64)
    d = array(surface.GetCellData(), "SurfelDirection").astype(np.int64)
    i, j, k = (voxel[:, a] - whole[2 * a] for a in range(3))
    cells = ((k * ny + j) * nx + i) * 6 + d
    fd = surface.GetFieldData()
    origin = ns.vtk_to_numpy(fd.GetArray("ImageOrigin"))
    spacing = ns.vtk_to_numpy(fd.GetArray("ImageSpacing"))
    pts = ns.vtk_to_numpy(surface.GetPoints().GetData())
    c = np.rint((pts - origin) / spacing + 0.5).astype(np.int64) - np.array(whole[0::2])
    points = (c[:, 2] * (ny + 1) + c[:, 1]) * (nx + 1) + c[:, 0]
    return cells, points


def write_pvti(image, folder, name, z_cuts):
    """A .pvti of `image` in slabs along z (first voxel of each slab after the
    first in z_cuts; as VTK's writers do, each slab also holds the next
    one's first layer), one .vti per slab; returns (pvti path, slab paths)."""
    from vtkmodules.vtkImagingCore import vtkExtractVOI
    dims = image.GetDimensions()
    bounds = [0] + list(z_cuts) + [dims[2]]
    pieces = []
    for s in range(len(bounds) - 1):
        voi = vtkExtractVOI()
        voi.SetInputData(image)
        z1 = min(bounds[s + 1], dims[2] - 1)
        voi.SetVOI(0, dims[0] - 1, 0, dims[1] - 1, bounds[s], z1)
        voi.Update()
        path = os.path.join(folder, "%s_%d.vti" % (name, s))
        write_vti(voi.GetOutput(), path)
        pieces.append((path, bounds[s], z1))
    pvti = os.path.join(folder, name + ".pvti")
    with open(pvti, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="PImageData" version="0.1" byte_order="LittleEndian" '
                'header_type="UInt32">\n  <PImageData WholeExtent="0 %d 0 %d 0 %d" GhostLevel="0" '
                'Origin="0 0 0" Spacing="1 1 1">\n    <PPointData Scalars="Inside">\n'
                '      <PDataArray type="UInt8" Name="Inside"/>\n    </PPointData>\n'
                % (dims[0] - 1, dims[1] - 1, dims[2] - 1))
        for path, z0, z1 in pieces:
            f.write('    <Piece Extent="0 %d 0 %d %d %d" Source="%s"/>\n'
                    % (dims[0] - 1, dims[1] - 1, z0, z1, os.path.basename(path)))
        f.write("  </PImageData>\n</VTKFile>\n")
    return pvti, [p[0] for p in pieces]
