#!/usr/bin/python3
"""Writes what dgtal_regularization reads, from a surface the program wrote
(PREFIX_surface.vtp), so the DGtal driver needs no VTK:

    /usr/bin/python3 export_normals.py surface.vtp OUT [--normals SharpNormals]

OUT.txt  a header line "# surfels N offset ox oy oz", then one line per surfel
         in the .vtp's cell order: "i j k dir nx ny nz" (InsideVoxel minus
         the offset, SurfelDirection 0..5 for -x,+x,-y,+y,-z,+z, the normal).
OUT.vol  the binary volume (DGtal's Vol format, version 3: zlib), 255 inside.

The volume is rebuilt from the surface, not read from the input: the program
removes small islands and fills small cavities (--min-component) and adds its
noise (--noise) before it builds the surface, so the input file is not the
volume whose boundary the surface is. Along each x line the inside voxels run
from a -x surfel to the next +x surfel; the boundary of the rebuilt volume is
then checked to be exactly the surface's surfels. The volume keeps one empty
voxel around the surface (DGtal's boundary extraction stays inside the domain)."""
import sys
import zlib

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader


def load(path, normals):
    r = vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    cd = r.GetOutput().GetCellData()
    ijk = vtk_to_numpy(cd.GetArray("InsideVoxel")).astype(np.int64)
    d = vtk_to_numpy(cd.GetArray("SurfelDirection")).astype(np.int64)
    n = vtk_to_numpy(cd.GetArray(normals)).astype(float)
    return ijk, d, n


def rebuild_volume(ijk, d):
    """Inside voxels (array [z, y, x]) whose boundary is the surfels (ijk, d)."""
    dims = ijk.max(0) + 2  # + the empty voxel after the last inside one
    mark = np.zeros((dims[2], dims[1], dims[0] + 1), np.int8)
    lo, hi = ijk[d == 0], ijk[d == 1]
    np.add.at(mark, (lo[:, 2], lo[:, 1], lo[:, 0]), 1)       # a run starts here
    np.add.at(mark, (hi[:, 2], hi[:, 1], hi[:, 0] + 1), -1)  # and ends after this voxel
    inside = np.cumsum(mark, axis=2, dtype=np.int8)[:, :, :-1]
    if inside.min() < 0 or inside.max() > 1:
        sys.exit("export_normals: the x surfels do not pair up into runs (open surface?)")
    return inside.astype(bool)


def boundary_count(inside):
    # faces between an inside voxel and an outside one (the volume has an empty margin)
    p = np.pad(inside, 1)
    return sum(int((p != np.roll(p, 1, axis=a)).sum()) for a in range(3))


def check(inside, ijk, d):
    if boundary_count(inside) != len(d):
        sys.exit("export_normals: the rebuilt volume's boundary is not the surface")
    step = np.array([[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]])[d]
    o = ijk + step
    p = np.pad(inside, 1)  # index + 1: outside neighbours may be at -1
    if not (p[ijk[:, 2] + 1, ijk[:, 1] + 1, ijk[:, 0] + 1].all()
            and not p[o[:, 2] + 1, o[:, 1] + 1, o[:, 0] + 1].any()):
        sys.exit("export_normals: a surfel is not between its inside voxel and an outside one")


def write_vol(inside, path):
    z, y, x = inside.shape
    head = "X: %d\nY: %d\nZ: %d\nVoxel-Size: 1\nAlpha-Color: 0\nVoxel-Endian: 0\nInt-Endian: 0123\nVersion: 3\n.\n" % (x, y, z)
    with open(path, "wb") as f:
        f.write(head.encode())
        f.write(zlib.compress((inside.astype(np.uint8) * 255).tobytes(), 1))  # x fastest


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    normals = sys.argv[sys.argv.index("--normals") + 1] if "--normals" in sys.argv else "SharpNormals"
    ijk, d, n = load(sys.argv[1], normals)
    # Voxel indices from 1: voxel 0 stays empty (see the docstring)
    offset = ijk.min(0) - 1
    ijk = ijk - offset
    inside = rebuild_volume(ijk, d)
    check(inside, ijk, d)
    out = sys.argv[2]
    write_vol(inside, out + ".vol")
    with open(out + ".txt", "w") as f:
        f.write("# surfels %d offset %d %d %d\n" % (len(d), *offset))
        np.savetxt(f, np.column_stack([ijk, d, n]), fmt="%d %d %d %d %.17g %.17g %.17g")


if __name__ == "__main__":
    main()
