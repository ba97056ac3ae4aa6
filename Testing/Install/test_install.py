"""The installed module, as a user gets it: `cmake --install` into a
temporary prefix (each case its own), then one of

  cxx      an external CMake project (Testing/Install/consumer) finds the
           package with find_package(DigitalGeometry), builds and runs the
           pipeline on a generated ball;
  buildtree  the same project against the build tree (no install);
  python   /usr/bin/python3 imports the package with only the prefix's
           Python directory on PYTHONPATH, runs a filter, reads __version__;
  plugin   pvpython loads the installed plugin by PV_PLUGIN_PATH (autoload)
           and by the plugins XML (PV_PLUGIN_CONFIG_FILE), runs its filter;
  program  the installed piecewise-normals: --version, then its built-in shape;
  deb      cpack builds the .deb; its control data and files are checked, it is
           unpacked (dpkg-deb -x) and the program and the Python package run
           from the unpacked tree.

Usage: test_install.py CASE (environment from Testing/Install/CMakeLists.txt).
"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

E = os.environ
BUILD = E["DG_BUILD_DIR"]
SOURCE = E["DG_SOURCE_DIR"]
VERSION = E["DG_VERSION"]
LIBDIR = E["DG_LIBDIR"]
PYDEST = E.get("DG_PYTHON_DESTINATION", "")
PLUGIN_SUBDIR = E.get("DG_PLUGIN_SUBDIR", "")
CMAKE = E["DG_CMAKE"]
TMP = tempfile.mkdtemp(prefix="dg_install_", dir=E.get("DG_TEST_TMP"))
failures, checks = [], []


def check(cond, what):
    checks.append(what)
    print(("ok   " if cond else "FAIL ") + what)
    sys.stdout.flush()
    if not cond:
        failures.append(what)
    return cond


def run(cmd, env=None, cwd=None, timeout=600):
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, timeout=timeout,
                       env=None if env is None else dict(os.environ, **env))
    print("[%.1f s] %s -> %d" % (time.time() - t, " ".join(cmd[:3]), p.returncode))
    if p.returncode != 0:
        print(p.stdout[-3000:])
        print(p.stderr[-3000:])
    return p


def clean_env(**extra):
    """The environment without anything pointing at the build tree."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PV_PLUGIN_PATH", "PV_PLUGIN_CONFIG_FILE", "LD_LIBRARY_PATH")}
    env.update(extra)
    return env


def install():
    prefix = os.path.join(TMP, "prefix")
    p = run([CMAKE, "--install", BUILD, "--prefix", prefix])
    if not check(p.returncode == 0, "cmake --install into " + prefix):
        finish()
    return prefix


def case_cxx():
    prefix = install()
    cmake_dir = os.path.join(prefix, LIBDIR, "cmake", "DigitalGeometry")
    for f in ("DigitalGeometryConfig.cmake", "DigitalGeometryConfigVersion.cmake",
              "DigitalGeometry-targets.cmake", "DigitalGeometry-vtk-module-properties.cmake"):
        check(os.path.isfile(os.path.join(cmake_dir, f)), "installed " + f)
    headers = glob.glob(os.path.join(prefix, "include", "DigitalGeometry", "vtk*.h"))
    check(len(headers) >= 13 and any(h.endswith("vtkDigitalGeometryModule.h") for h in headers),
          "%d public headers, with the export header" % len(headers))
    check(not glob.glob(os.path.join(prefix, "include", "DigitalGeometry", "dg*.h")),
          "no private dg*.h header installed")
    # The package must not point back at the source or build tree, nor name
    # Eigen (a private dependency).
    text = "".join(open(f).read() for f in glob.glob(os.path.join(cmake_dir, "*.cmake")))
    # (The source tree's Filters/, not the whole source folder: a VTK
    # unpacked inside it, as build-vtk91.sh does, is named as the hint.)
    check(os.path.join(SOURCE, "Filters") not in text and BUILD not in text,
          "installed CMake files name neither the source nor the build tree")
    check("Eigen" not in text, "installed CMake files do not need Eigen")
    build_consumer(["-DCMAKE_PREFIX_PATH=" + prefix], prefix)


def build_consumer(args, where):
    """Testing/Install/consumer configured with args, built and run: its
    package and its library must come from `where`."""
    build = os.path.join(TMP, "consumer-build")
    p = run([CMAKE, "-S", os.path.join(SOURCE, "Testing", "Install", "consumer"), "-B", build,
             "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"] + args, env=clean_env())
    check(p.returncode == 0, "consumer configures with find_package(DigitalGeometry)")
    m = re.search(r"consumer: DigitalGeometry (\S+) from (\S+?),", p.stdout)
    check(m is not None and m.group(1) == VERSION and m.group(2).startswith(where),
          "found version %s in %s" % (m.group(1) if m else None, m.group(2) if m else None))
    if p.returncode != 0:
        finish()
    p = run([CMAKE, "--build", build], env=clean_env())
    if not check(p.returncode == 0, "consumer builds"):
        finish()
    exe = os.path.join(build, "consumer")
    p = run([exe], env=clean_env(VTK_SMP_BACKEND_IN_USE="STDThread"))
    print(p.stdout)
    check(p.returncode == 0 and "FAIL" not in p.stdout and p.stdout.count("ok") >= 4,
          "consumer's pipeline checks pass")
    ldd = run(["ldd", exe]).stdout
    lib = [line for line in ldd.splitlines() if "libvtkDigitalGeometry" in line]
    check(len(lib) == 1 and where in lib[0], "consumer runs the library in %s: %s"
          % (where, lib[0].strip() if lib else "none"))


def case_buildtree():
    """The same consumer against the build tree, without installing."""
    build_consumer(["-DDigitalGeometry_DIR=" + os.path.join(BUILD, LIBDIR, "cmake", "DigitalGeometry")],
                   BUILD + os.sep)


def case_python():
    prefix = install()
    site = os.path.join(prefix, PYDEST)
    check(os.path.isfile(os.path.join(site, "digitalgeometry", "__init__.py")), "__init__.py installed")
    script = (
        "import digitalgeometry, sys\n"
        "from digitalgeometry import vtkDigitalSurfaceFilter\n"
        "from vtkmodules.vtkImagingCore import vtkRTAnalyticSource\n"
        "src = vtkRTAnalyticSource()\n"
        "src.SetWholeExtent(0, 15, 0, 15, 0, 15)\n"
        "f = vtkDigitalSurfaceFilter()\n"
        "f.SetInputConnection(src.GetOutputPort())\n"
        "f.SetSelectionModeToRange()\n"
        "f.SetLowerThreshold(200.0)\n"
        "f.Update()\n"
        "print('FILE', digitalgeometry.__file__)\n"
        "print('VERSION', digitalgeometry.__version__)\n"
        "print('QUADS', f.GetOutput().GetNumberOfPolys())\n")
    p = run(["/usr/bin/python3", "-c", script], env=clean_env(PYTHONPATH=site), cwd=TMP)
    check(p.returncode == 0, "from digitalgeometry import vtkDigitalSurfaceFilter with PYTHONPATH=" + site)
    out = dict(line.split(" ", 1) for line in p.stdout.splitlines() if " " in line)
    check(out.get("FILE", "").startswith(site), "imported from the prefix: " + out.get("FILE", ""))
    check(out.get("VERSION") == VERSION, "__version__ %s" % out.get("VERSION"))
    check(int(out.get("QUADS", "0")) > 100, "a surface of %s quads" % out.get("QUADS"))


def case_plugin():
    prefix = install()
    pvpython = E["DG_PVPYTHON"]
    plugin_dir = os.path.join(prefix, LIBDIR, PLUGIN_SUBDIR, "DigitalGeometryPlugin")
    xml = os.path.join(prefix, LIBDIR, PLUGIN_SUBDIR, "DigitalGeometry.plugins.xml")
    check(os.path.isfile(os.path.join(plugin_dir, "DigitalGeometryPlugin.so")), "plugin installed")
    check(os.path.isfile(xml) and 'name="DigitalGeometryPlugin" auto_load="1"' in open(xml).read(),
          "plugins XML installed, auto_load=1")
    script = (
        "from paraview.simple import *\n"
        "src = Wavelet(WholeExtent=[0, 15, 0, 15, 0, 15])\n"
        "s = DigitalSurface(Input=src)\n"
        "s.SelectionMode = 'Range'\n"
        "s.LowerThreshold = 200.0\n"
        "s.UpdatePipeline()\n"
        "print('QUADS', s.GetDataInformation().GetNumberOfCells())\n")
    for how, env in (("PV_PLUGIN_PATH", {"PV_PLUGIN_PATH": plugin_dir}),
                     ("PV_PLUGIN_CONFIG_FILE", {"PV_PLUGIN_CONFIG_FILE": xml})):
        p = run([pvpython, "-c", script], env=clean_env(**env), cwd=TMP)
        m = re.search(r"QUADS (\d+)", p.stdout)
        check(p.returncode == 0 and m is not None and int(m.group(1)) > 100,
              "pvpython autoloads the installed plugin with %s (%s quads)" % (how, m.group(1) if m else None))


def case_program():
    prefix = install()
    exe = os.path.join(prefix, "bin", "piecewise-normals")
    env = clean_env(VTK_SMP_BACKEND_IN_USE="STDThread")
    p = run([exe, "--version"], env=env)
    check(p.returncode == 0 and p.stdout.startswith("piecewise-normals %s " % VERSION),
          "--version: " + p.stdout.strip())
    out = os.path.join(TMP, "out")
    p = run([exe, "--size", "32", "--no-png", "--quiet", "--output-dir", out], env=env, cwd=TMP)
    check(p.returncode == 0 and os.path.getsize(os.path.join(out, "builtin_surface.vtp")) > 1000
          and os.path.isfile(os.path.join(out, "builtin_features.vtp")),
          "installed program on its built-in shape writes its surface and features")


def case_deb():
    cpack = E["DG_CPACK"]
    out = os.path.join(TMP, "cpack")
    p = run([cpack, "-G", "DEB", "--config", os.path.join(BUILD, "CPackConfig.cmake"), "-B", out])
    debs = glob.glob(os.path.join(out, "*.deb"))
    if not check(p.returncode == 0 and len(debs) == 1, "cpack -G DEB makes one .deb"):
        finish()
    deb = debs[0]
    print("%s: %.1f MiB" % (os.path.basename(deb), os.path.getsize(deb) / 2 ** 20))
    info = run(["dpkg-deb", "-f", deb]).stdout
    fields = dict(re.findall(r"^(\S+): (.*)$", info, re.M))
    check(fields.get("Package") == "digitalgeometry" and fields.get("Version") == VERSION,
          "package digitalgeometry %s" % fields.get("Version"))
    depends = fields.get("Depends", "")
    check(re.search(r"(^|, )paraview \(>= 5\.11", depends) is not None and "python3-paraview (>= 5.11)" in depends,
          "Depends on Debian's ParaView 5.11: " + depends)
    root = os.path.join(TMP, "root")
    if not check(run(["dpkg-deb", "-x", deb, root]).returncode == 0, "dpkg-deb -x"):
        finish()
    usr = os.path.join(root, "usr")
    expect = ["bin/piecewise-normals",
              "include/DigitalGeometry/vtkDigitalSurfaceFilter.h",
              LIBDIR + "/cmake/DigitalGeometry/DigitalGeometryConfig.cmake",
              "share/doc/digitalgeometry/LICENSE",
              "share/doc/digitalgeometry/CITATION.cff"]
    if PYDEST:
        check(PYDEST == "lib/python3/dist-packages",
              "Python package in lib/python3/dist-packages (/usr/bin/python3 reads /usr/lib/python3/dist-packages)")
        expect.append(PYDEST + "/digitalgeometry/__init__.py")
    if PLUGIN_SUBDIR:
        expect += [LIBDIR + "/" + PLUGIN_SUBDIR + "/DigitalGeometryPlugin/DigitalGeometryPlugin.so",
                   LIBDIR + "/" + PLUGIN_SUBDIR + "/DigitalGeometry.plugins.xml"]
    for f in expect:
        check(os.path.isfile(os.path.join(usr, f)), "/usr/" + f)
    check(glob.glob(os.path.join(usr, LIBDIR, "libvtkDigitalGeometry.so.*")), "/usr/%s/libvtkDigitalGeometry.so.*" % LIBDIR)
    env = clean_env(LD_LIBRARY_PATH=os.path.join(usr, LIBDIR), VTK_SMP_BACKEND_IN_USE="STDThread")
    p = run([os.path.join(usr, "bin", "piecewise-normals"), "--version"], env=env)
    check(p.returncode == 0 and VERSION in p.stdout, "unpacked program runs: " + p.stdout.strip())
    res = os.path.join(TMP, "res")
    p = run([os.path.join(usr, "bin", "piecewise-normals"), "--size", "24", "--no-png", "--quiet",
             "--output-dir", res], env=env)
    check(p.returncode == 0 and os.path.isfile(os.path.join(res, "builtin_surface.vtp")),
          "unpacked program runs the pipeline on its built-in shape")
    if PYDEST:
        p = run(["/usr/bin/python3", "-c", "import digitalgeometry as d; print(d.__file__, d.__version__, d.vtkAmbrosioTortorelliFilter)"],
                env=clean_env(PYTHONPATH=os.path.join(usr, PYDEST)), cwd=TMP)
        check(p.returncode == 0 and p.stdout.startswith(os.path.join(usr, PYDEST)),
              "unpacked Python package imports: " + p.stdout.strip())


def finish():
    print("%d checks, %d failed" % (len(checks), len(failures)))
    if failures:
        print("kept for inspection: " + TMP)
        sys.exit(1)
    shutil.rmtree(TMP, ignore_errors=True)
    sys.exit(0)


if __name__ == "__main__":
    {"cxx": case_cxx, "buildtree": case_buildtree, "python": case_python, "plugin": case_plugin,
     "program": case_program, "deb": case_deb}[sys.argv[1]]()
    finish()
