"""The MPI tests' pvbatch pipeline (run as mpirun -np N pvbatch --symmetric
pv_pipeline.py PLUGIN INPUT.vti OUTPREFIX SOLVER_TOLERANCE): the plugin's
filters Digital Surface -> II Normal Estimator -> Ambrosio-Tortorelli ->
Corrected Curvature and Piecewise Smooth Mesh (of the II normals, which
every process count gives bit for bit, so that the stages' own distribution
is what is compared; per side of the faces' axis directions,
SurfelDirection, so that every edge where the staircase turns is a crease
and the creases cross the pieces' borders everywhere) on every rank's
piece, written with ParaView's parallel writer as OUTPREFIX_surface.pvtp,
OUTPREFIX_features.pvtp, OUTPREFIX_creases.pvtp, OUTPREFIX_mesh.pvtp and
OUTPREFIX_meshcreases.pvtp, Sharp Features after Ambrosio-Tortorelli
as OUTPREFIX_sharp.pvtp and OUTPREFIX_sharplines.pvtp, and Corrected
Curvature of the II normals as one region (PerSide off: each face's ball
radius chosen per face, balls up to 3 Radius across the pieces' borders) as
OUTPREFIX_wholecurvature.pvtp (pieces in folders of those names).

DG_MPI_BAD_RANK=r gives rank r a bad II radius (-1): that rank reports the
filter's error in one line and exits 1 at once, so that mpirun ends the
ranks that wait for it."""
import os
import sys

from paraview.simple import *  # noqa: F401,F403
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkParallelCore import vtkMultiProcessController
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING

plugin, volume_path, prefix, tolerance = sys.argv[1:5]
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller else 0
size = controller.GetNumberOfProcesses() if controller else 1

LoadPlugin(plugin, remote=False, ns=globals())
volume = XMLImageDataReader(FileName=[volume_path])
surface = DigitalSurface(Input=volume)
ii = IINormalEstimator(Input=surface, Source=volume, Radius=4)
if os.environ.get("DG_MPI_BAD_RANK", "") == str(rank):
    ii.Radius = -1
at = AmbrosioTortorelli(Input=ii, Alpha=0.05, Lambda=0.005, SolverTolerance=float(tolerance))
curvature = CorrectedCurvature(Input=at, Radius=5)
curvature.Normals = ["CELLS", "IINormals"]
curvature.Regions = ["CELLS", "SurfelDirection"]
# One region: no crease stops a ball, so every face's radius is chosen from
# the noise and variation measured around it (AdaptiveRadius, the default).
whole = CorrectedCurvature(Input=at, Radius=5, PerSide=0)
whole.Normals = ["CELLS", "IINormals"]
# The mesh of the II normals (every process count gives them bit for bit),
# the same regions: creases everywhere, across every piece border.
mesh = PiecewiseSmoothMesh(Input=at, SolverTolerance=float(tolerance) / 100)
mesh.Normals = ["CELLS", "IINormals"]
mesh.Regions = ["CELLS", "SurfelDirection"]


@calldata_type(VTK_STRING)  # the observer receives the message
def fail(obj, event, message=None):
    text = (message or "error").strip().splitlines()[-1]
    text = text.split("): ", 1)[-1]  # "vtkClass (0x...): message" -> "message"
    sys.stderr.write("pv_pipeline: rank %d of %d: %s: %s\n" % (rank, size, obj.GetClassName(), text))
    sys.stderr.flush()
    os._exit(1)


sharp = SharpFeatures(Input=at)
for proxy in (volume, surface, ii, at, curvature, whole, mesh, sharp):
    proxy.GetClientSideObject().AddObserver(vtkCommand.ErrorEvent, fail)

curvature.UpdatePipeline()
SaveData(prefix + "_surface.pvtp", proxy=OutputPort(curvature, 0), CompressorType="LZ4", DataMode="Binary")
SaveData(prefix + "_features.pvtp", proxy=OutputPort(at, 1), CompressorType="LZ4", DataMode="Binary")
SaveData(prefix + "_creases.pvtp", proxy=OutputPort(curvature, 1), CompressorType="LZ4", DataMode="Binary")
whole.UpdatePipeline()
SaveData(prefix + "_wholecurvature.pvtp", proxy=OutputPort(whole, 0), CompressorType="LZ4", DataMode="Binary")
sharp.UpdatePipeline()
SaveData(prefix + "_sharp.pvtp", proxy=OutputPort(sharp, 0), CompressorType="LZ4", DataMode="Binary")
SaveData(prefix + "_sharplines.pvtp", proxy=OutputPort(sharp, 1), CompressorType="LZ4", DataMode="Binary")
mesh.UpdatePipeline()
SaveData(prefix + "_mesh.pvtp", proxy=OutputPort(mesh, 0), CompressorType="LZ4", DataMode="Binary")
SaveData(prefix + "_meshcreases.pvtp", proxy=OutputPort(mesh, 1), CompressorType="LZ4", DataMode="Binary")
