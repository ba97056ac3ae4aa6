"""One MPI comparison: test_mpi_compare.py TOOL CASE N, with TOOL program
(build/bin/piecewise-normals under mpirun) or pvbatch (the plugin's filters
under mpirun ... pvbatch --symmetric, Testing/MPI/pv_pipeline.py).

The case's volume (mpi_cases.py) is written here; the one-process run and
the N-rank run are compared by global ids at SolverTolerance 1e-8 (surfels
by count and ids, II normals identical, AT normals within 0.01 degree, v
within 1e-5, the same feature edges), then again at the default 1e-5
(reported; asserted only to 0.05 degree and 1e-3); the .pvtp reads as one
surface without duplicated cells; a second N-rank run is bitwise equal to
the first. N = 1 (program): mpirun -np 1 writes the same files, byte for
byte, as the program run without mpirun."""
import os
import re
import subprocess
import sys
import tempfile
import time

import mpi_cases as mc

TOOL, CASE, N = sys.argv[1], sys.argv[2], int(sys.argv[3])
MPIRUN = [os.environ["DG_MPIRUN"], "--allow-run-as-root", "--oversubscribe"]
ROOT = tempfile.mkdtemp(prefix="dg_mpi_%s_%s_np%d_" % (TOOL, CASE, N), dir=os.environ.get("DG_TEST_TMP"))
check = mc.Checks()
TIGHT, DEFAULT = "1e-8", "1e-5"


def run(cmd, timeout=300):
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    dt = time.monotonic() - t0
    if p.returncode != 0:
        print("command failed (%d): %s\n--- stdout\n%s\n--- stderr\n%s" % (
            p.returncode, " ".join(cmd), p.stdout[-3000:], p.stderr[-3000:]))
    return p, dt


STDOUT = {}


def program(ranks, tolerance, tag, plain=True, extra=(), volume=None):
    """Runs the program on `ranks` processes (0 = without mpirun); returns (folder, surface, features)."""
    out = os.path.join(ROOT, tag)
    # The built-in case runs the program's own shape (no INPUT).
    source = ["--size", str(mc.BUILTIN_SIZE)] if CASE == "builtin" and not volume else [volume or VOLUME]
    cmd = [os.environ["DG_PROGRAM"], "--quiet", "--no-png"] + (["--plain"] if plain else []) + [
           "--solver-tolerance", tolerance, "--output-dir", out, "--prefix", "r"] + source + list(extra)
    if ranks:
        cmd = MPIRUN + ["-np", str(ranks)] + cmd
    p, dt = run(cmd)
    ext = "pvtp" if ranks > 1 else "vtp"
    print("info %s: %.1f s; %s" % (tag, dt, (p.stdout.strip().splitlines() or ["no output"])[0]))
    STDOUT[tag] = p.stdout
    if not check(p.returncode == 0, "%s: the program exits 0" % tag):
        sys.exit(finish())
    return out, os.path.join(out, "r_surface." + ext), os.path.join(out, "r_features." + ext)


def pvbatch(ranks, tolerance, tag):
    out = os.path.join(ROOT, tag)
    os.makedirs(out)
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "pv_pipeline.py")
    cmd = MPIRUN + ["-np", str(ranks), os.environ["DG_PVBATCH"], "--symmetric", script,
                    os.environ["DG_PLUGIN_FILE"], VOLUME, os.path.join(out, "r"), tolerance]
    p, dt = run(cmd)
    print("info %s: %.1f s" % (tag, dt))
    if not check(p.returncode == 0, "%s: pvbatch exits 0" % tag):
        sys.exit(finish())
    return out, os.path.join(out, "r_surface.pvtp"), os.path.join(out, "r_features.pvtp")


def finish():
    return check.finish(ROOT)


VOLUME = os.path.join(ROOT, CASE + ".vti")
print("case %s: %s" % (CASE, mc.make_case(CASE, VOLUME)))

if TOOL == "program" and N == 1:
    # mpirun -np 1 is the one-process program: same files, byte for byte.
    plain, _, _ = program(0, DEFAULT, "plain")
    under, _, _ = program(1, DEFAULT, "mpirun-np1")
    a, b = mc.files_of(plain), mc.files_of(under)
    check(sorted(a) == sorted(b) == ["r_features.vtp", "r_surface.vtp"],
          "mpirun -np 1 writes the same files (%s)" % ", ".join(sorted(b)))
    check(a == b, "mpirun -np 1: files bitwise equal to the run without mpirun")
    sys.exit(finish())

runner = program if TOOL == "program" else pvbatch
one = 0 if TOOL == "program" else 1
ref_dir, ref_s, ref_f = runner(one, TIGHT, "one-tight")
run_dir, run_s, run_f = runner(N, TIGHT, "np%d-tight" % N)
ref, res = mc.Result(ref_s, ref_f, reference=True), mc.Result(run_s, run_f)
if ref.derived:
    print("info the one-process run writes no GlobalIds: the contract's, from InsideVoxel, "
          "SurfelDirection and the point positions, stand in")
check(res.surface.GetNumberOfCells() > 0, "the .pvtp reads as one surface in vtkXMLPPolyDataReader (%d cells, %d points)"
      % (res.surface.GetNumberOfCells(), res.surface.GetNumberOfPoints()))
if res.cell_ids is not None and res.surface.GetNumberOfCells():
    whole = [int(x) for x in mc.ns.vtk_to_numpy(res.surface.GetFieldData().GetArray("ImageExtent"))]
    cells, points = mc.contract_ids(res.surface, whole)
    check(mc.np.array_equal(cells, res.cell_ids) and mc.np.array_equal(points, res.point_ids),
          "%d-rank GlobalIds follow the contract (cells ((k*Ny + j)*Nx + i)*6 + d, points "
          "(ck*(Ny+1) + cj)*(Nx+1) + ci)" % N)
    check(res.surface.GetCellData().GetGlobalIds() is not None and res.surface.GetPointData().GetGlobalIds() is not None,
          "%d-rank GlobalIds are the attributes' global ids" % N)
mc.compare(ref, res, check, "np%d vs 1, SolverTolerance 1e-8" % N, 0.01, 1e-5)
if TOOL == "program":
    # The default output (the sharp-features stage, gathered on rank 0).
    # With the curvature, the mesh and the gathered PLY: the stages after it.
    # Their input, the SharpNormals, differs from one process's by AT's
    # solve (about 1e-5 degree at 1e-8): the limits follow it (the stages'
    # own distribution is compared exactly by the pvbatch pipeline).
    stages = ["--curvature", "--mesh", "--mesh-tolerance", "1e-10", "--ply"]
    sref_dir, sref_s, sref_f = program(0, TIGHT, "one-sharp", plain=False, extra=stages)
    srun_dir, srun_s, srun_f = program(N, TIGHT, "np%d-sharp" % N, plain=False, extra=stages)
    mc.compare_sharp(sref_s, sref_f, srun_s, srun_f, check, "np%d vs 1, default output" % N, 0.01)
    mc.compare_creases(sref_s, os.path.join(sref_dir, "r_creases.vtp"), srun_s,
                       os.path.join(srun_dir, "r_creases.pvtp"), check, "np%d vs 1, --curvature" % N, 1e-3, require=False)
    mc.compare_mesh(os.path.join(sref_dir, "r_mesh.vtp"), os.path.join(sref_dir, "r_mesh_creases.vtp"),
                    os.path.join(srun_dir, "r_mesh.pvtp"), os.path.join(srun_dir, "r_mesh_creases.pvtp"),
                    check, "np%d vs 1, --mesh" % N, 1e-4, require=False)
    # --second-pass: AT again on the gathered stage's side normals, which it
    # reads on its ghost ring too (the ring AT's pieces keep when asked).
    pref_dir, pref_s, pref_f = program(0, TIGHT, "one-second", plain=False, extra=["--second-pass"])
    prun_dir, prun_s, prun_f = program(N, TIGHT, "np%d-second" % N, plain=False, extra=["--second-pass"])
    mc.compare_sharp(pref_s, pref_f, prun_s, prun_f, check, "np%d vs 1, --second-pass" % N, 0.01)
    from vtkmodules.vtkIOPLY import vtkPLYReader
    plys = []
    for d in (sref_dir, srun_dir):
        r = vtkPLYReader()
        r.SetFileName(os.path.join(d, "r_surface.ply"))
        r.Update()
        plys.append(r.GetOutput().GetNumberOfCells())
    check(plys[0] == plys[1] > 0, "np%d vs 1: --ply writes every surfel (%d, %d)" % (N, plys[0], plys[1]))

    def counts(text):
        first = (text.strip().splitlines() or [""])[0]
        return first.split(": ", 1)[-1].split(" (")[0]
    check(counts(STDOUT["one-sharp"]) == counts(STDOUT["np%d-sharp" % N]) != "",
          "np%d vs 1: the same summary counts (%s | %s)" % (N, counts(STDOUT["one-sharp"]),
                                                           counts(STDOUT["np%d-sharp" % N])))
    # The summary reports what the gathered sharp stage moved (docs/distributed.md).
    moved = re.search(r"rank 0 sent and received ([0-9.]+) MiB in (\d+) calls", STDOUT["np%d-sharp" % N])
    check(moved is not None and float(moved.group(1)) >= 0 and int(moved.group(2)) >= 4 * (N - 1),
          "np%d: the summary reports the sharp stage's exchange (%s)" % (N, moved.group(0) if moved else "missing"))
    check("sent and received" not in STDOUT["one-sharp"], "one process: no exchange reported")
    if CASE == "builtin":
        # The copy pvbatch reads is the program's own shape, voxel for voxel
        # (the same surfels from the .vti as from the built-in source).
        copy_dir, copy_s, _ = program(0, DEFAULT, "one-vti", plain=True, volume=VOLUME)
        built_dir, built_s, _ = program(0, DEFAULT, "one-builtin", plain=True)
        n_copy, n_built = (mc.read_polydata(f).GetNumberOfCells() for f in (copy_s, built_s))
        check(n_copy == n_built > 0, "the built-in case's .vti gives the built-in shape's surfels (%d, %d)"
              % (n_copy, n_built))
if TOOL == "pvbatch":
    mc.compare_sharp(ref_s.replace("r_surface", "r_sharp"), ref_s.replace("r_surface", "r_sharplines"),
                     run_s.replace("r_surface", "r_sharp"), run_s.replace("r_surface", "r_sharplines"),
                     check, "np%d vs 1, Sharp Features" % N, 0.01)
    mc.compare_creases(ref_s, os.path.join(ref_dir, "r_creases.pvtp"), run_s,
                       os.path.join(run_dir, "r_creases.pvtp"), check, "np%d vs 1" % N)
    mc.compare_ball_radius(ref_s.replace("r_surface", "r_wholecurvature"),
                           run_s.replace("r_surface", "r_wholecurvature"), check,
                           "np%d vs 1, Corrected Curvature of one region" % N)
    mc.compare_mesh(os.path.join(ref_dir, "r_mesh.pvtp"), os.path.join(ref_dir, "r_meshcreases.pvtp"),
                    os.path.join(run_dir, "r_mesh.pvtp"), os.path.join(run_dir, "r_meshcreases.pvtp"),
                    check, "np%d vs 1" % N, 1e-6)

again_dir, _, _ = runner(N, TIGHT, "np%d-tight-again" % N)
a, b = mc.files_of(run_dir), mc.files_of(again_dir)
differ = [n for n in sorted(set(a) | set(b)) if a.get(n) != b.get(n)]
check(not differ and len(a) >= 2, "two %d-rank runs bitwise equal (%d files; differ: %s)"
      % (N, len(a), ", ".join(differ) or "none"))

_, dref_s, dref_f = runner(one, DEFAULT, "one-default")
_, drun_s, drun_f = runner(N, DEFAULT, "np%d-default" % N)
mc.compare(mc.Result(dref_s, dref_f, reference=True), mc.Result(drun_s, drun_f), check,
           "np%d vs 1, default SolverTolerance 1e-5" % N, 0.05, 1e-3, assert_edges=False)
sys.exit(finish())
