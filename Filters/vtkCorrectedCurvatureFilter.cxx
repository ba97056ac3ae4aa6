#include "vtkCorrectedCurvatureFilter.h"

#include "dgCellArrays.h"
#include "dgLineCells.h"
#include "dgCorrectedCurvature.h"
#include "dgCurvatureHalo.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"

#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkCorrectedCurvatureFilter);

struct vtkCorrectedCurvatureFilter::Internals
{
  dg::PipelineAbort Abort;
};

vtkCorrectedCurvatureFilter::vtkCorrectedCurvatureFilter()
  : Internal(new Internals)
{
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, vtkDataSetAttributes::NORMALS);
  this->SetInputArrayToProcess(
    1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "FeatureRegion");
  this->SetInputArrayToProcess(
    2, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "CreaseSides");
}

vtkCorrectedCurvatureFilter::~vtkCorrectedCurvatureFilter() = default;

vtkMTimeType vtkCorrectedCurvatureFilter::GetMTime()
{
  return this->Internal->Abort.MTime(this->Superclass::GetMTime());
}

int vtkCorrectedCurvatureFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

namespace
{
void AddValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfValues(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

vtkDoubleArray* CellArray(const char* name, int components, vtkIdType n)
{
  vtkDoubleArray* a = vtkDoubleArray::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(n);
  return a;
}
} // namespace


int vtkCorrectedCurvatureFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiProcessController* controller = dg::PieceController(outputVector->GetInformationObject(0));
  const int rank = controller ? controller->GetLocalProcessId() : 0;
  Internals& internal = *this->Internal;
  const auto abortGuard = internal.Abort.Begin(this, outputVector);
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* lines = vtkPolyData::GetData(outputVector, 1);
  this->Area = this->Volume = this->IntegralMeanCurvature = this->IntegralGaussianCurvature = 0;
  this->CreaseIntegralMeanCurvature = this->UsedRadius = 0;
  this->EulerCharacteristic = this->NumberOfCreaseEdges = 0;
  if (!input || !output || !lines)
  {
    vtkErrorMacro("Missing input or output.");
    return 0;
  }
  if (dg::PipelineAbort::InputAborted(inputVector, 1))
  {
    return internal.Abort.Abort(outputVector);
  }
  // Ghost cells of the input (a downstream request for ghost levels reaches
  // the producers upstream) get no curvature here: the piece works on, and
  // outputs, its own cells; its halo brings the neighbours' faces.
  const vtkSmartPointer<vtkPolyData> ownInput = dg::WithoutGhostCells(input);
  if (ownInput)
    input = ownInput;
  // Parameters are the same on every process: each refuses them alone.
  if (!(this->Radius > 0) || !std::isfinite(this->Radius))
  {
    if (rank == 0)
      vtkErrorMacro("Invalid parameters: Radius must be a positive number (it is " << this->Radius
                                                                                  << ").");
    return 0;
  }
  // Local checks; under pieces every process learns whether all passed, and
  // the one that found a problem says it.
  std::string problem;
  auto agree = [&](bool ok) { return dg::AllPiecesOk(outputVector->GetInformationObject(0), ok); };
  auto refuse = [&]() {
    if (!problem.empty())
      vtkErrorMacro(<< (controller ? "Piece " + std::to_string(rank) + ": " : std::string()) << problem);
    return 0;
  };
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nFaces = polys ? polys->GetNumberOfCells() : 0;
  const vtkIdType nCells = input->GetNumberOfCells();
  const vtkIdType nPoints = input->GetNumberOfPoints();
  const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
  if (nFaces == 0 && !controller)
    problem = "The input has no polygons: the corrected-curvature filter works on a surface.";

  // ParaView sends an empty name until it knows the input's arrays: that
  // means the default (the active normals, FeatureRegion).
  vtkDataArray* normals = nullptr;
  vtkDataArray* regions = nullptr;
  vtkDataArray* sides = nullptr;
  if (problem.empty() && nFaces > 0)
  {
    int association = -1;
    normals = this->GetInputArrayToProcess(0, input, association);
    if (!normals)
    {
      normals = input->GetCellData()->GetNormals();
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
    }
    if (!normals)
      problem = "No cell normal field: the input has no active cell normals (run "
                "vtkSharpFeaturesFilter or another normal estimator first, or choose the "
                "array with SetInputArrayToProcess).";
    else if (association != vtkDataObject::FIELD_ASSOCIATION_CELLS ||
      normals->GetNumberOfComponents() != 3)
      problem = std::string("The normal field '") + (normals->GetName() ? normals->GetName() : "") +
        "' must be cell data with 3 components.";
  }
  if (problem.empty() && nFaces > 0 && this->PerSide)
  {
    int association = -1;
    vtkDataArray* chosen = this->GetInputArrayToProcess(1, input, association);
    regions = dg::OneComponentCellArray(chosen, association, input, "FeatureRegion", "region", problem);
    if (regions)
    {
      chosen = this->GetInputArrayToProcess(2, input, association);
      sides = dg::OneComponentCellArray(chosen, association, input, "CreaseSides", "crease sides", problem);
    }
  }
  vtkDataArray* cellIds = controller ? dg::GlobalIdArray(input->GetCellData(), nCells) : nullptr;
  vtkDataArray* pointIds = controller ? dg::GlobalIdArray(input->GetPointData(), nPoints) : nullptr;
  if (problem.empty() && controller && nFaces > 0 && (!cellIds || !pointIds))
    problem = "A distributed run needs cell and point global ids (the 'GlobalIds' arrays of "
              "vtkDigitalSurfaceFilter) to match faces and points across pieces.";

  // The piece's own faces (ghost cells of the input are left out: their
  // owners send them).
  dg::CurvatureMesh mesh;
  std::vector<vtkIdType> ownCell; // input cell of each own face
  vtkDataArray* ghostArray = input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
  if (problem.empty() && nFaces > 0)
  {
    mesh.Points.resize(3 * nPoints);
    // Sized once: growing by doubling copied them and touched fresh memory
    // at each step (2.7 million corners on octa-flower 512^3).
    mesh.Offsets.reserve(nFaces + 1);
    mesh.Connectivity.reserve(polys->GetNumberOfConnectivityIds());
    mesh.Normals.reserve(3 * nFaces);
    mesh.Region.reserve(regions ? nFaces : 0);
    mesh.FaceIds.reserve(cellIds ? nFaces : 0);
    mesh.Ghost.reserve(nFaces);
    ownCell.reserve(nFaces);
    for (vtkIdType p = 0; p < nPoints; ++p)
      input->GetPoint(p, &mesh.Points[3 * p]);
    if (pointIds)
      for (vtkIdType p = 0; p < nPoints; ++p)
        mesh.PointIds.push_back(static_cast<std::int64_t>(pointIds->GetComponent(p, 0)));
    const auto nt = vtk::DataArrayTupleRange<3>(normals);
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    vtkIdType f = 0;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++f)
    {
      const vtkIdType cell = polyOffset + f;
      if (ghostArray && ghostArray->GetNumberOfTuples() == nCells &&
        (static_cast<int>(ghostArray->GetComponent(cell, 0)) & vtkDataSetAttributes::DUPLICATECELL))
        continue;
      it->GetCurrentCell(npts, ids);
      for (vtkIdType k = 0; k < npts; ++k)
        mesh.Connectivity.push_back(ids[k]);
      mesh.Offsets.push_back(static_cast<std::int64_t>(mesh.Connectivity.size()));
      double len2 = 0;
      for (int c = 0; c < 3; ++c)
      {
        const double x = static_cast<double>(nt[cell][c]);
        mesh.Normals.push_back(x);
        len2 += x * x;
      }
      if (!(std::abs(std::sqrt(len2) - 1) < 1e-3) && problem.empty())
        problem = std::string("The normal field '") + (normals->GetName() ? normals->GetName() : "") +
          "' is not made of unit vectors (face " + std::to_string(f) + " has length " +
          std::to_string(std::sqrt(len2)) + ").";
      if (regions)
        mesh.Region.push_back(static_cast<int>(regions->GetComponent(cell, 0)));
      if (sides)
        mesh.CreaseSides.push_back(static_cast<unsigned char>(sides->GetComponent(cell, 0)));
      if (cellIds)
        mesh.FaceIds.push_back(static_cast<std::int64_t>(cellIds->GetComponent(cell, 0)));
      mesh.Ghost.push_back(0);
      ownCell.push_back(cell);
    }
    mesh.OwnFaces = static_cast<std::int64_t>(ownCell.size());
    mesh.OwnPoints = nPoints;
  }
  if (!agree(problem.empty()))
    return refuse();

  // Radius in world units: voxels are the smallest image spacing the
  // surface came from (vtkDigitalSurfaceFilter's "ImageSpacing": 3 values,
  // one component), or the faces' mean edge length over all pieces.
  double edge[2] = { 0, 0 }; // sum of lengths, number of edges
  double bounds[6] = { 0, -1, 0, -1, 0, -1 };
  for (std::int64_t f = 0; f < mesh.OwnFaces; ++f)
  {
    const std::int64_t m = mesh.Offsets[f + 1] - mesh.Offsets[f];
    for (std::int64_t i = 0; i < m; ++i)
    {
      const double* a = &mesh.Points[3 * mesh.Connectivity[mesh.Offsets[f] + i]];
      const double* b = &mesh.Points[3 * mesh.Connectivity[mesh.Offsets[f] + (i + 1) % m]];
      edge[0] += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
        (a[2] - b[2]) * (a[2] - b[2]));
      edge[1] += 1;
    }
  }
  input->GetBounds(bounds);
  double extent[6]; // -min and max per axis: the whole surface's box is their maximum
  for (int a = 0; a < 3; ++a)
  {
    const bool empty = !(bounds[2 * a] <= bounds[2 * a + 1]) || mesh.OwnFaces == 0;
    extent[2 * a] = empty ? -std::numeric_limits<double>::max() : -bounds[2 * a];
    extent[2 * a + 1] = empty ? -std::numeric_limits<double>::max() : bounds[2 * a + 1];
  }
  if (controller)
  {
    dg::SumOverPieces(controller, edge, 2);
    std::vector<double> all(6 * controller->GetNumberOfProcesses());
    controller->AllGather(extent, all.data(), 6);
    for (std::size_t i = 0; i < all.size(); ++i)
      extent[i % 6] = std::max(extent[i % 6], all[i]);
  }
  const double meanEdge = edge[1] > 0 ? edge[0] / edge[1] : 1.0;
  double voxel = 0;
  vtkDataArray* spacing = input->GetFieldData()->GetArray("ImageSpacing");
  if (spacing && spacing->GetNumberOfComponents() == 1 && spacing->GetNumberOfTuples() == 3)
  {
    voxel = std::min({ std::abs(spacing->GetComponent(0, 0)), std::abs(spacing->GetComponent(1, 0)),
      std::abs(spacing->GetComponent(2, 0)) });
    if (!(voxel > 0) || !std::isfinite(voxel))
      voxel = 0;
  }
  if (voxel == 0)
    voxel = meanEdge;
  const double radius = this->RadiusUnits == VOXELS ? this->Radius * voxel : this->Radius;
  double diagonal = 0;
  for (int a = 0; a < 3; ++a)
  {
    const double w = extent[2 * a + 1] + extent[2 * a];
    diagonal += w > 0 ? w * w : 0;
  }
  diagonal = std::sqrt(diagonal);
  if (edge[1] == 0)
  {
    if (rank == 0)
      vtkErrorMacro("The input has no polygons: the corrected-curvature filter works on a surface.");
    return 0;
  }
  if (radius > diagonal)
  {
    if (rank == 0)
      vtkErrorMacro("Invalid parameters: the ball radius ("
        << radius << " world units) is larger than the surface (bounding box diagonal " << diagonal
        << ").");
    return 0;
  }
  this->UpdateProgress(0.05);

  dg::CurvatureParameters par;
  par.Radius = radius;
  par.EdgeLength = meanEdge;
  par.AdaptiveRadius = this->AdaptiveRadius;
  // Under pieces: the faces of the other pieces that this piece's balls and
  // their corner normals reach (the largest ball, its ramp, a face ring).
  if (controller &&
    !dg::GatherCurvatureHalo(controller, dg::CurvatureReach(par, meanEdge), mesh, problem))
  {
    if (rank == 0)
      vtkErrorMacro(<< problem);
    return 0;
  }
  dg::CurvatureResult res;
  const bool ok = dg::ComputeCorrectedCurvatures(static_cast<std::int64_t>(mesh.Points.size() / 3),
    mesh.Points.data(), mesh.Offsets, mesh.Connectivity, mesh.Normals.data(),
    mesh.Region.empty() ? nullptr : mesh.Region.data(), par, res, &problem, mesh.Ghost.data(),
    mesh.FaceIds.empty() ? nullptr : mesh.FaceIds.data(),
    mesh.CreaseSides.empty() ? nullptr : mesh.CreaseSides.data());
  if (!agree(ok))
    return refuse();
  if (this->GetAbortExecute())
  {
    return internal.Abort.Abort(outputVector);
  }
  this->UpdateProgress(0.9);
  // Whole-surface figures: each piece's share, added over the pieces.
  double totals[7] = { res.Area, std::isfinite(res.Volume) ? res.Volume : 0.0, res.TotalMean,
    res.TotalGaussian, res.CreaseTotalMean, res.EulerShare,
    static_cast<double>(res.BoundaryEdges) };
  if (controller)
    dg::SumOverPieces(controller, totals, 7);
  this->UsedRadius = radius;
  this->Area = totals[0];
  this->Volume = totals[6] > 0 ? std::nan("") : totals[1];
  this->IntegralMeanCurvature = totals[2];
  this->IntegralGaussianCurvature = totals[3];
  this->CreaseIntegralMeanCurvature = totals[4];
  this->EulerCharacteristic = static_cast<vtkIdType>(std::llround(totals[5]));
  this->NumberOfCreaseEdges = static_cast<vtkIdType>(res.CreaseAngle.size());

  // Port 0: the input's own faces with the arrays (the input's ghost
  // cells, if any, are kept with zeros: their owners hold the values).
  output->ShallowCopy(input);
  struct Out
  {
    const char* Name;
    int Components;
    const std::vector<double>* Values;
  };
  const Out outs[] = { { "CorrectedMeanCurvature", 1, &res.Mean },
    { "CorrectedGaussianCurvature", 1, &res.Gaussian }, { "CorrectedK1", 1, &res.K1 },
    { "CorrectedK2", 1, &res.K2 }, { "CorrectedK1Direction", 3, &res.D1 },
    { "CorrectedK2Direction", 3, &res.D2 }, { "CorrectedBallRadius", 1, &res.BallRadius } };
  for (const Out& o : outs)
  {
    vtkDoubleArray* a = CellArray(o.Name, o.Components, nCells);
    a->Fill(0.0);
    for (std::int64_t f = 0; f < mesh.OwnFaces; ++f)
      for (int c = 0; c < o.Components; ++c)
        a->SetTypedComponent(ownCell[f], c, (*o.Values)[o.Components * f + c]);
    output->GetCellData()->AddArray(a);
    a->Delete();
  }
  output->GetCellData()->SetActiveScalars("CorrectedMeanCurvature");

  vtkNew<vtkFieldData> fd;
  fd->ShallowCopy(input->GetFieldData());
  AddValue(fd, "CorrectedArea", this->Area);
  AddValue(fd, "EnclosedVolume", this->Volume);
  AddValue(fd, "SpecificSurfaceArea",
    std::isfinite(this->Volume) && this->Volume != 0 ? this->Area / std::abs(this->Volume)
                                                     : std::nan(""));
  AddValue(fd, "IntegralMeanCurvature", this->IntegralMeanCurvature);
  AddValue(fd, "IntegralGaussianCurvature", this->IntegralGaussianCurvature);
  AddValue(fd, "GaussBonnetCharacteristic", this->IntegralGaussianCurvature / (2 * M_PI));
  AddValue(fd, "EulerCharacteristic", static_cast<double>(this->EulerCharacteristic));
  AddValue(fd, "CreaseIntegralMeanCurvature", this->CreaseIntegralMeanCurvature);
  AddValue(fd, "CurvatureRadius", radius);
  output->SetFieldData(fd);

  // Port 1: the crease edges this piece reports, on the input's points
  // (a reported edge belongs to an own face, so its points are the input's).
  std::vector<vtkIdType> ends(2 * res.CreaseAngle.size());
  std::vector<double> degrees(res.CreaseAngle.size());
  for (std::size_t l = 0; l < degrees.size(); ++l)
  {
    ends[2 * l] = static_cast<vtkIdType>(res.CreaseEdges[2 * l]);
    ends[2 * l + 1] = static_cast<vtkIdType>(res.CreaseEdges[2 * l + 1]);
    degrees[l] = res.CreaseAngle[l] * 180.0 / M_PI;
  }
  lines->SetPoints(input->GetPoints());
  lines->GetPointData()->PassData(input->GetPointData());
  lines->SetLines(dg::TwoPointLines(ends));
  lines->GetCellData()->AddArray(dg::LineValues("CreaseAngle", degrees));
  lines->GetCellData()->SetActiveScalars("CreaseAngle");
  this->UpdateProgress(1.0);
  return 1;
}

void vtkCorrectedCurvatureFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "AdaptiveRadius: " << (this->AdaptiveRadius ? "On" : "Off") << "\n";
  os << indent << "RadiusUnits: " << (this->RadiusUnits == VOXELS ? "Voxels" : "World") << "\n";
  os << indent << "PerSide: " << (this->PerSide ? "On" : "Off") << "\n";
  os << indent << "UsedRadius: " << this->UsedRadius << "\n";
  os << indent << "Area: " << this->Area << "\n";
  os << indent << "Volume: " << this->Volume << "\n";
  os << indent << "IntegralMeanCurvature: " << this->IntegralMeanCurvature << "\n";
  os << indent << "IntegralGaussianCurvature: " << this->IntegralGaussianCurvature << "\n";
  os << indent << "CreaseIntegralMeanCurvature: " << this->CreaseIntegralMeanCurvature << "\n";
  os << indent << "EulerCharacteristic: " << this->EulerCharacteristic << "\n";
  os << indent << "NumberOfCreaseEdges: " << this->NumberOfCreaseEdges << "\n";
}
