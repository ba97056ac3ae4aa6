"""The README's pvbatch example, as it stands there (the Python block after
the <!-- pvbatch-example --> marker), on 2 ranks and on 1: it runs, the
.pvtp reads as one surface without duplicated cells, and it matches the
1-rank run by global ids (default solver tolerance: AT normals within 0.05
degree, v within 1e-3)."""
import os
import subprocess
import sys
import tempfile

import mpi_cases as mc

readme = open(sys.argv[1]).read()
marker = readme.index("<!-- pvbatch-example -->")
block = readme[marker:].split("```python\n", 1)[1].split("```", 1)[0]
ROOT = tempfile.mkdtemp(prefix="dg_mpi_readme_", dir=os.environ.get("DG_TEST_TMP"))
script = os.path.join(ROOT, "distributed.py")
with open(script, "w") as f:
    f.write(block)
check = mc.Checks()
volume = os.path.join(ROOT, "v.vti")
mc.make_case("edges-across", volume)
results = {}
for n in (1, 2):
    out = os.path.join(ROOT, "np%d" % n)
    os.makedirs(out)
    p = subprocess.run([os.environ["DG_MPIRUN"], "--allow-run-as-root", "--oversubscribe", "-np", str(n),
                        os.environ["DG_PVBATCH"], "--symmetric", script, os.environ["DG_PLUGIN_FILE"], volume,
                        os.path.join(out, "v")], capture_output=True, text=True, timeout=170)
    if not check(p.returncode == 0, "README example on %d rank(s) exits 0" % n):
        print(p.stderr[-3000:])
        break
    results[n] = mc.Result(os.path.join(out, "v_surface.pvtp"), os.path.join(out, "v_features.pvtp"),
                           reference=(n == 1))
if len(results) == 2:
    r = results[2]
    check(r.surface.GetNumberOfCells() > 1000, "2-rank .pvtp: one surface of %d cells" % r.surface.GetNumberOfCells())
    mc.compare(results[1], r, check, "README example, 2 ranks vs 1", 0.05, 1e-3, assert_edges=False)
sys.exit(check.finish(ROOT))
