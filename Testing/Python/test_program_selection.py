"""The program's voxel selection on inputs the default (value != 0) does not
fit: a float or signed volume with no --range, --label or --labels is
refused (exit 1, one line naming --range and --label, nothing written);
with an explicit selection it runs. An empty selection names what was asked
(the label, the range). And --version, __version__, CITATION.cff and
CHANGELOG.md give the version of project(VERSION)."""
import os
import re
import shutil
import subprocess
import sys
import tempfile

from vtkmodules.vtkCommonCore import vtkFloatArray, vtkShortArray, vtkUnsignedCharArray
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

PROGRAM = os.environ["DG_PROGRAM"]
ROOT = tempfile.mkdtemp(prefix="dg_selection_", dir=os.environ.get("DG_TEST_TMP"))
SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
failures, checks = [], []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(*args, ranks=0):
    out = tempfile.mkdtemp(dir=ROOT)
    cmd = [PROGRAM, "--quiet", "--no-png", "--output-dir", out] + list(args)
    if ranks:
        cmd = [shutil.which("mpirun"), "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300,
                       env=dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1"))
    return p, out


def lines(text):
    return [line for line in text.strip().splitlines() if line.strip()]


# A 20^3 volume: a box (value 3 / 0.8 / -700..) in a background of 0 / -1000.
N = 20


def inside(i, j, k):
    return 5 <= i <= 13 and 4 <= j <= 15 and 6 <= k <= 12


def write_vti(name, array, inside_value, outside_value):
    image = vtkImageData()
    image.SetDimensions(N, N, N)
    array.SetName("values")
    array.SetNumberOfValues(N ** 3)
    for k in range(N):
        for j in range(N):
            for i in range(N):
                array.SetValue((k * N + j) * N + i, inside_value if inside(i, j, k) else outside_value)
    image.GetPointData().SetScalars(array)
    path = os.path.join(ROOT, name)
    w = vtkXMLImageDataWriter()
    w.SetDataModeToBinary()
    w.SetInputData(image)
    w.SetFileName(path)
    w.Write()
    return path


box_surfels = 2 * (9 * 12 + 9 * 7 + 12 * 7)
floats = write_vti("field.vti", vtkFloatArray(), 0.8, 0.0)
shorts = write_vti("ct.vti", vtkShortArray(), 300, -1000)
uchars = write_vti("mask.vti", vtkUnsignedCharArray(), 3, 0)


def surfels(out, stem):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    r = vtkXMLPolyDataReader()
    r.SetFileName(os.path.join(out, stem + "_surface.vtp"))
    r.Update()
    return r.GetOutput().GetNumberOfPolys()


# Refused without a selection: one line naming the options, exit 1, no files.
cases = [("float", floats), ("signed", shorts)]
if shutil.which("mpirun"):
    cases.append(("float under mpirun -np 2", floats))
for what, path in cases:
    mpi = "mpirun" in what
    p, out = run(path, ranks=2 if mpi else 0)
    # Under mpirun rank 0 also says that the sharp stage is not distributed,
    # and mpirun adds its own lines: the refusal is then one of the lines.
    err = [line for line in lines(p.stderr) if "--range" in line] if mpi else lines(p.stderr)
    check(p.returncode == 1 and len(err) == 1 and "--range" in err[0] and "--label" in err[0]
          and os.path.basename(path) in err[0] and not os.listdir(out),
          "%s volume without a selection: exit %d, stderr %r, files %s"
          % (what, p.returncode, p.stderr.strip()[-300:], os.listdir(out)))

# Explicit selections run.
for what, path, args in (("float with --range 0.5 1", floats, ["--range", "0.5", "1"]),
                         ("signed with --range -500 3000", shorts, ["--range", "-500", "3000"]),
                         ("signed with --label 300", shorts, ["--label", "300"]),
                         ("unsigned with the default", uchars, [])):
    p, out = run(path, *args)
    stem = os.path.splitext(os.path.basename(path))[0]
    n = surfels(out, stem) if p.returncode == 0 else -1
    check(p.returncode == 0 and n == box_surfels,
          "%s: exit %d, %d surfels (the box has %d) %s" % (what, p.returncode, n, box_surfels, p.stderr.strip()[-200:]))

# An empty selection says what was asked.
p, out = run(uchars, "--label", "7")
err = lines(p.stderr)
check(p.returncode == 1 and len(err) == 1 and re.search(r"\blabel 7\b", err[0]) and "mode" not in err[0]
      and "0 to 3" in err[0] and not os.listdir(out),
      "--label 7 on a volume of 0 and 3: exit %d, %r" % (p.returncode, p.stderr.strip()))
p, out = run(floats, "--range", "2", "5")
err = lines(p.stderr)
check(p.returncode == 1 and len(err) == 1 and "[2, 5]" in err[0],
      "--range 2 5 on values 0 to 0.8: exit %d, %r" % (p.returncode, p.stderr.strip()))

# --version: the number of project(VERSION) in CMakeLists.txt, and VTK's.
m = re.search(r"project\(DigitalGeometry VERSION (\d+\.\d+\.\d+)", open(os.path.join(SOURCE, "CMakeLists.txt")).read())
p = subprocess.run([PROGRAM, "--version"], capture_output=True, text=True, timeout=60)
check(m is not None and p.returncode == 0 and p.stdout.strip().startswith("piecewise-normals %s (VTK " % m.group(1)),
      "--version: %r (CMake: %s)" % (p.stdout.strip(), m.group(1) if m else None))
import digitalgeometry  # noqa: E402
check(m is not None and digitalgeometry.__version__ == m.group(1),
      "digitalgeometry.__version__ %s" % digitalgeometry.__version__)
# The files that must repeat the number say the same.
cff = re.search(r"^version: *\"?([0-9.]+)", open(os.path.join(SOURCE, "CITATION.cff")).read(), re.M)
check(m is not None and cff is not None and cff.group(1) == m.group(1),
      "CITATION.cff's version %s" % (cff.group(1) if cff else None))
check(m is not None and ("## [%s]" % m.group(1)) in open(os.path.join(SOURCE, "CHANGELOG.md")).read(),
      "CHANGELOG.md has a section for %s" % (m.group(1) if m else None))

print("%d passed, %d failed" % (len(checks) - len(failures), len(failures)))
if not failures:
    shutil.rmtree(ROOT, ignore_errors=True)
sys.exit(1 if failures else 0)
