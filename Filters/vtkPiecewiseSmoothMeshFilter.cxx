#include "vtkPiecewiseSmoothMeshFilter.h"

#include "dgCellArrays.h"
#include "dgLineCells.h"
#include "dgPiecewiseSmoothMesh.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"

#include "dgATHalo.h"
#include "dgCurvatureHalo.h"

#include <vtkCellArray.h>
#include <vtkCommunicator.h>
#include <vtkCellArrayIterator.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkPiecewiseSmoothMeshFilter);

struct vtkPiecewiseSmoothMeshFilter::Internals
{
  dg::PipelineAbort Abort;
};

vtkPiecewiseSmoothMeshFilter::vtkPiecewiseSmoothMeshFilter()
  : Internal(new Internals)
{
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "SharpNormals");
  this->SetInputArrayToProcess(
    1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "FeatureRegion");
  this->SetInputArrayToProcess(
    2, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "CreaseSides");
}

vtkPiecewiseSmoothMeshFilter::~vtkPiecewiseSmoothMeshFilter() = default;

vtkMTimeType vtkPiecewiseSmoothMeshFilter::GetMTime()
{
  return this->Internal->Abort.MTime(this->Superclass::GetMTime());
}

int vtkPiecewiseSmoothMeshFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

namespace
{
// 0, 1, ..., n - 1: the destination of an id-list copy of data.
vtkSmartPointer<vtkIdList> Iota(vtkIdType n)
{
  auto ids = vtkSmartPointer<vtkIdList>::New();
  ids->SetNumberOfIds(n);
  for (vtkIdType i = 0; i < n; ++i)
    ids->SetId(i, i);
  return ids;
}

// The regions the creases separate: the feature regions, split further by
// label pair on label-map interfaces. An id from the values themselves (not
// their order), so that every piece gives a face the same one.
int RegionOf(double region, double inside, double outside)
{
  std::uint64_t h = 1469598103934665603ULL;
  for (double v : { region, inside, outside })
  {
    std::uint64_t x;
    std::memcpy(&x, &v, sizeof x);
    h = (h ^ x) * 1099511628211ULL;
    h ^= h >> 29;
  }
  return static_cast<int>(h ^ (h >> 32));
}


// The surface the solve sees: one process's whole input, or a piece's own
// faces followed by the faces around its points that other pieces own, in
// the distribution's row order.
struct LocalSurface
{
  std::vector<double> World;           // 3 per point
  std::vector<vtkIdType> InputPoint;   // input point of each point, -1 if received
  std::vector<std::int64_t> GlobalPoint;
  std::vector<std::int64_t> Offsets{ 0 }, Connectivity;
  std::vector<vtkIdType> InputCell;    // input cell of each face, -1 if received
  std::vector<double> Normals;         // 3 per face, world
  std::vector<int> Region;             // per face, or empty
  std::vector<unsigned char> Sides;    // per face (crease side bits), or empty
  std::int64_t OwnedFaces = 0;         // faces [0, OwnedFaces) are this process's output
  std::vector<int> VertexOwner;        // per point, with pieces
  std::int64_t Faces() const { return static_cast<std::int64_t>(this->Offsets.size()) - 1; }
  std::int64_t Points() const { return static_cast<std::int64_t>(this->World.size() / 3); }
};
} // namespace

int vtkPiecewiseSmoothMeshFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiProcessController* controller = dg::PieceController(outputVector->GetInformationObject(0));
  const int rank = controller ? controller->GetLocalProcessId() : 0;
  Internals& internal = *this->Internal;
  const auto abortGuard = internal.Abort.Begin(this, outputVector);
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* lines = vtkPolyData::GetData(outputVector, 1);
  this->NumberOfCreaseEdges = this->NumberOfBoundCoordinates = 0;
  this->MaximumDisplacement = 0;
  this->Converged = true;
  if (!input || !output || !lines)
  {
    vtkErrorMacro("Missing input or output.");
    return 0;
  }
  if (dg::PipelineAbort::InputAborted(inputVector, 1))
    return internal.Abort.Abort(outputVector);
  // Ghost cells of the input (a downstream request for ghost levels reaches
  // the producers upstream) are not moved here: the piece works on, and
  // outputs, its own cells; its halo brings the neighbours' vertices.
  const vtkSmartPointer<vtkPolyData> ownInput = dg::WithoutGhostCells(input);
  if (ownInput)
    input = ownInput;
  // Parameters are the same on every process: each refuses them alone.
  dg::MeshParameters par;
  par.DataWeight = this->DataWeight;
  par.CreaseWeight = this->CreaseWeight;
  par.Iterations = this->NumberOfIterations;
  par.EarlyTolerance = this->SolverTolerance;
  par.Tolerance = this->SolverTolerance / 100;
  std::string problem = par.Check();
  if (!problem.empty())
  {
    if (rank == 0)
      vtkErrorMacro("Invalid parameters: " << problem);
    return 0;
  }
  // Local checks; under pieces every process learns whether all passed, and
  // the one that found a problem says it.
  auto agree = [&](bool ok) { return dg::AllPiecesOk(outputVector->GetInformationObject(0), ok); };
  auto refuse = [&]()
  {
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
    problem = "The input has no polygons: the piecewise-smooth mesh works on a surface.";
  // ParaView sends an empty name until it knows the input's arrays: that
  // means the defaults.
  vtkDataArray* normals = nullptr;
  vtkDataArray* regions = nullptr;
  vtkDataArray* sides = nullptr;
  if (problem.empty() && nFaces > 0)
  {
    int association = -1;
    normals = this->GetInputArrayToProcess(0, input, association);
    if (!normals)
    {
      normals = input->GetCellData()->GetArray("SharpNormals");
      association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
    }
    if (!normals)
      problem = "No cell normal field: the input has no 'SharpNormals' (run vtkSharpFeaturesFilter "
                "first, or choose the array with SetInputArrayToProcess).";
    else if (association != vtkDataObject::FIELD_ASSOCIATION_CELLS ||
      normals->GetNumberOfComponents() != 3)
      problem = std::string("The normal field '") + (normals->GetName() ? normals->GetName() : "") +
        "' must be cell data with 3 components.";
    // The sharp stage's drawn edges, when the input has them, are the
    // creases: a line may end where its two regions still meet (a sharp
    // edge that fades into a fillet), which the regions cannot say.
    if (problem.empty())
    {
      vtkDataArray* chosen = this->GetInputArrayToProcess(1, input, association);
      regions = dg::OneComponentCellArray(chosen, association, input, "FeatureRegion", "region", problem);
      chosen = this->GetInputArrayToProcess(2, input, association);
      sides = dg::OneComponentCellArray(chosen, association, input, "CreaseSides", "crease sides", problem);
      if (sides)
        regions = nullptr;
    }
  }
  vtkDataArray* cellIds = controller ? dg::GlobalIdArray(input->GetCellData(), nCells) : nullptr;
  vtkDataArray* pointIds = dg::GlobalIdArray(input->GetPointData(), nPoints);
  if (problem.empty() && controller && nFaces > 0 && (!cellIds || !pointIds))
    problem = "A distributed run needs cell and point global ids (the 'GlobalIds' arrays of "
              "vtkDigitalSurfaceFilter) to match faces and points across pieces.";
  vtkDataArray* inside = input->GetCellData()->GetArray("LabelInside");
  vtkDataArray* outside = input->GetCellData()->GetArray("LabelOutside");
  if (!inside || !outside || inside->GetNumberOfTuples() != nCells ||
    outside->GetNumberOfTuples() != nCells)
    inside = outside = nullptr;
  vtkDataArray* ghostArray = input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
  if (ghostArray && ghostArray->GetNumberOfTuples() != nCells)
    ghostArray = nullptr;

  // The input's own faces (its ghost cells left out: their owners send them).
  LocalSurface own;
  if (problem.empty() && nFaces > 0)
  {
    own.World.resize(3 * nPoints);
    for (vtkIdType p = 0; p < nPoints; ++p)
      input->GetPoint(p, &own.World[3 * p]);
    own.InputPoint.resize(nPoints);
    for (vtkIdType p = 0; p < nPoints; ++p)
      own.InputPoint[p] = p;
    if (pointIds)
      for (vtkIdType p = 0; p < nPoints; ++p)
        own.GlobalPoint.push_back(static_cast<std::int64_t>(pointIds->GetComponent(p, 0)));
    const auto nt = vtk::DataArrayTupleRange<3>(normals);
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    vtkIdType f = 0;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal() && problem.empty(); it->GoToNextCell(), ++f)
    {
      const vtkIdType cell = polyOffset + f;
      if (ghostArray &&
        (static_cast<int>(ghostArray->GetComponent(cell, 0)) &
          (vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL)))
        continue;
      it->GetCurrentCell(npts, ids);
      own.Connectivity.insert(own.Connectivity.end(), ids, ids + npts);
      own.Offsets.push_back(static_cast<std::int64_t>(own.Connectivity.size()));
      own.InputCell.push_back(cell);
      double len2 = 0;
      for (int c = 0; c < 3; ++c)
      {
        const double x = static_cast<double>(nt[cell][c]);
        own.Normals.push_back(x);
        len2 += x * x;
      }
      if (!(std::abs(std::sqrt(len2) - 1) < 1e-3))
        problem = std::string("The normal field '") + (normals->GetName() ? normals->GetName() : "") +
          "' is not made of unit vectors (face " + std::to_string(f) + " has length " +
          std::to_string(std::sqrt(len2)) + ").";
      if (regions || inside)
        own.Region.push_back(RegionOf(regions ? regions->GetComponent(cell, 0) : 0.0,
          inside ? inside->GetComponent(cell, 0) : 0.0, outside ? outside->GetComponent(cell, 0) : 0.0));
      if (sides)
        own.Sides.push_back(static_cast<unsigned char>(sides->GetComponent(cell, 0)));
    }
    own.OwnedFaces = own.Faces();
  }
  if (!agree(problem.empty()))
    return refuse();
  double faces = static_cast<double>(own.Faces());
  if (controller)
    dg::SumOverPieces(controller, &faces, 1);
  if (faces == 0)
  {
    if (rank == 0)
      vtkErrorMacro("The input has no polygons: the piecewise-smooth mesh works on a surface.");
    return 0;
  }

  // With pieces: the faces of the others around this piece's points, then
  // the rows of the distributed solve (owned first).
  LocalSurface local;
  std::unique_ptr<dg::ATHalo> halo;
  if (!controller)
    local = std::move(own);
  else
  {
    // A voxel: the longest polygon side of all pieces.
    double side = 0;
    for (std::int64_t f = 0; f < own.Faces(); ++f)
    {
      const std::int64_t m = own.Offsets[f + 1] - own.Offsets[f];
      for (std::int64_t i = 0; i < m; ++i)
      {
        const double* a = &own.World[3 * own.Connectivity[own.Offsets[f] + i]];
        const double* b = &own.World[3 * own.Connectivity[own.Offsets[f] + (i + 1) % m]];
        side = std::max(side, std::sqrt((a[0] - b[0]) * (a[0] - b[0]) +
                                (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2])));
      }
    }
    double all = side;
    controller->AllReduce(&side, &all, 1, vtkCommunicator::MAX_OP);
    dg::CurvatureMesh cm;
    cm.Points = own.World;
    cm.PointIds = own.GlobalPoint;
    cm.Offsets = own.Offsets;
    cm.Connectivity = own.Connectivity;
    cm.Normals = own.Normals;
    cm.Region = own.Region;
    cm.CreaseSides = own.Sides;
    for (vtkIdType cell : own.InputCell)
      cm.FaceIds.push_back(static_cast<std::int64_t>(cellIds->GetComponent(cell, 0)));
    cm.Ghost.assign(own.Faces(), 0);
    cm.OwnFaces = own.Faces();
    cm.OwnPoints = nPoints;
    // Every face around a point of this piece has its centre within a
    // voxel's diagonal of the piece's faces.
    if (!dg::GatherCurvatureHalo(controller, 2 * all, cm, problem))
    {
      if (rank == 0)
        vtkErrorMacro(<< problem);
      return 0;
    }
    halo.reset(new dg::ATHalo(controller));
    std::vector<char> ghost(cm.Ghost.begin(), cm.Ghost.end());
    if (!halo->Build(cm.Offsets, cm.Connectivity, cm.FaceIds, ghost, cm.PointIds, problem))
      return refuse();
    std::vector<std::int64_t> row(cm.PointIds.size(), -1);
    for (std::size_t r = 0; r < halo->VertexRows.size(); ++r)
    {
      const std::int64_t q = halo->VertexRows[r];
      row[q] = static_cast<std::int64_t>(r);
      local.World.insert(local.World.end(), &cm.Points[3 * q], &cm.Points[3 * q] + 3);
      local.InputPoint.push_back(q < nPoints ? q : -1);
      local.GlobalPoint.push_back(cm.PointIds[q]);
    }
    for (std::int64_t f : halo->FaceRows)
    {
      for (std::int64_t k = cm.Offsets[f]; k < cm.Offsets[f + 1]; ++k)
        local.Connectivity.push_back(row[cm.Connectivity[k]]);
      local.Offsets.push_back(static_cast<std::int64_t>(local.Connectivity.size()));
      local.InputCell.push_back(f < cm.OwnFaces ? own.InputCell[f] : -1);
      local.Normals.insert(local.Normals.end(), &cm.Normals[3 * f], &cm.Normals[3 * f] + 3);
      if (!cm.Region.empty())
        local.Region.push_back(cm.Region[f]);
      if (!cm.CreaseSides.empty())
        local.Sides.push_back(cm.CreaseSides[f]);
    }
    local.OwnedFaces = halo->OwnedFaces;
    local.VertexOwner = halo->VertexOwner;
  }
  const std::int64_t nLocalPoints = local.Points(), nLocalFaces = local.Faces();

  dg::SurfaceFrame frame;
  if (nLocalFaces > 0 &&
    !dg::FindSurfaceFrame(nLocalPoints, local.World.data(), local.Offsets, local.Connectivity, frame,
      problem))
    problem = "The input is not a digital surface: " + problem + ".";
  if (!agree(problem.empty()))
    return refuse();
  std::vector<double> grid(3 * nLocalPoints), gridNormals(3 * nLocalFaces);
  for (std::int64_t p = 0; p < nLocalPoints; ++p)
    frame.ToGrid(&local.World[3 * p], &grid[3 * p]);
  for (std::int64_t f = 0; f < nLocalFaces; ++f)
    frame.NormalToGrid(&local.Normals[3 * f], &gridNormals[3 * f]);
  this->UpdateProgress(0.05);

  dg::MeshInput in;
  in.NumberOfPoints = nLocalPoints;
  in.Points = grid.data();
  in.Offsets = &local.Offsets;
  in.Connectivity = &local.Connectivity;
  in.FaceNormals = gridNormals.data();
  in.FaceRegion = local.Region.empty() ? nullptr : local.Region.data();
  in.FaceCreaseSides = local.Sides.empty() ? nullptr : local.Sides.data();
  in.Distribution = halo.get();
  dg::MeshResult res;
  const bool ok = dg::RegularizeMesh(in, par, res, problem,
    [this, controller](double done)
    {
      this->UpdateProgress(0.05 + 0.85 * done);
      return controller || !this->GetAbortExecute();
    });
  if (!controller && this->GetAbortExecute())
    return internal.Abort.Abort(outputVector);
  if (!agree(ok))
  {
    if (!ok && rank == 0)
      vtkErrorMacro("The piecewise-smooth mesh failed: " << problem);
    return 0;
  }
  const dg::MeshStatistics& stats = res.Statistics;
  if (!stats.Converged && rank == 0)
    vtkWarningMacro("The mesh's last solve did not converge to its tolerance: every vertex is "
                    "still within its cell.");
  this->NumberOfBoundCoordinates = stats.BoundCoordinates;
  this->Converged = stats.Converged;

  // The moved points, world coordinates.
  std::vector<double> moved(3 * nLocalPoints);
  vtkSMPTools::For(0, nLocalPoints,
    [&](std::int64_t p0, std::int64_t p1)
    {
      for (std::int64_t p = p0; p < p1; ++p)
      {
        double g[3];
        for (int c = 0; c < 3; ++c)
          g[c] = grid[3 * p + c] + res.Displacement[3 * p + c];
        frame.ToWorld(g, &moved[3 * p]);
      }
    });
  const std::int64_t ownedPoints = halo ? halo->OwnedVertices : nLocalPoints;
  double largest = 0;
  for (std::int64_t i = 0; i < 3 * ownedPoints; ++i)
    largest = std::max(largest, std::abs(res.Displacement[i]));
  this->MaximumDisplacement = largest;
  if (controller)
  {
    double all = largest;
    controller->AllReduce(&largest, &all, 1, vtkCommunicator::MAX_OP);
    this->MaximumDisplacement = all;
  }

  // Port 1: the creases on the moved points (before any split), with the
  // angle between the normals across each; with pieces each once, by the
  // owner of its end of smaller global id.
  {
    std::vector<std::int64_t> kept;
    for (std::size_t e = 0; e + 3 < res.Creases.size(); e += 4)
    {
      const std::int64_t a = res.Creases[e], b = res.Creases[e + 1];
      if (halo)
      {
        const std::int64_t first = local.GlobalPoint[a] < local.GlobalPoint[b] ? a : b;
        if (local.VertexOwner[first] != rank)
          continue;
      }
      kept.insert(kept.end(), res.Creases.begin() + e, res.Creases.begin() + e + 4);
    }
    const vtkIdType nLines = static_cast<vtkIdType>(kept.size() / 4);
    std::vector<vtkIdType> used(nLocalPoints, -1);
    std::vector<std::int64_t> linePoint;
    std::vector<vtkIdType> ends(2 * nLines);
    std::vector<double> angle(nLines);
    for (vtkIdType l = 0; l < nLines; ++l)
    {
      for (int k = 0; k < 2; ++k)
      {
        const std::int64_t p = kept[4 * l + k];
        if (used[p] < 0)
        {
          used[p] = static_cast<vtkIdType>(linePoint.size());
          linePoint.push_back(p);
        }
        ends[2 * l + k] = used[p];
      }
      const double* a = &local.Normals[3 * kept[4 * l + 2]];
      const double* b = &local.Normals[3 * kept[4 * l + 3]];
      const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      angle[l] = std::acos(std::max(-1.0, std::min(1.0, dot))) * 180.0 / M_PI;
    }
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetNumberOfPoints(static_cast<vtkIdType>(linePoint.size()));
    for (std::size_t i = 0; i < linePoint.size(); ++i)
      pts->SetPoint(static_cast<vtkIdType>(i), &moved[3 * linePoint[i]]);
    lines->SetPoints(pts);
    lines->SetLines(dg::TwoPointLines(ends));
    if (!local.GlobalPoint.empty())
    {
      vtkNew<vtkIdTypeArray> gid;
      gid->SetName("GlobalIds");
      gid->SetNumberOfValues(static_cast<vtkIdType>(linePoint.size()));
      for (std::size_t i = 0; i < linePoint.size(); ++i)
        gid->SetValue(static_cast<vtkIdType>(i), local.GlobalPoint[linePoint[i]]);
      lines->GetPointData()->SetGlobalIds(gid);
    }
    lines->GetCellData()->AddArray(dg::LineValues("FeatureAngle", angle));
    lines->GetCellData()->SetActiveScalars("FeatureAngle");
    double count = static_cast<double>(nLines);
    if (controller)
      dg::SumOverPieces(controller, &count, 1);
    this->NumberOfCreaseEdges = static_cast<vtkIdType>(count);
  }

  // Port 0: the crease points split per side (over every local face, so
  // that a piece's border points get the sides one process gives them),
  // then this process's own faces.
  std::vector<std::int64_t> splitConn = local.Connectivity, copyOf;
  if (this->SplitFeaturePoints)
    dg::SplitPointsAtCreases(nLocalPoints, local.Offsets, splitConn,
      local.Region.empty() ? nullptr : local.Region.data(),
      local.Sides.empty() ? nullptr : local.Sides.data(), copyOf);
  else
  {
    copyOf.resize(nLocalPoints);
    for (std::int64_t p = 0; p < nLocalPoints; ++p)
      copyOf[p] = p;
  }
  const std::int64_t nCopies = static_cast<std::int64_t>(copyOf.size());
  // Point normals: the area-weighted mean of the field over each copy's
  // faces (those of its side, when split).
  std::vector<double> copyNormals(3 * nCopies, 0.0);
  for (std::int64_t f = 0; f < nLocalFaces; ++f)
  {
    const std::int64_t m = local.Offsets[f + 1] - local.Offsets[f];
    // The polygon's vector area (Newell) gives its area.
    double area[3] = { 0, 0, 0 };
    for (std::int64_t i = 0; i < m; ++i)
    {
      const double* a = &moved[3 * local.Connectivity[local.Offsets[f] + i]];
      const double* b = &moved[3 * local.Connectivity[local.Offsets[f] + (i + 1) % m]];
      area[0] += (a[1] - b[1]) * (a[2] + b[2]);
      area[1] += (a[2] - b[2]) * (a[0] + b[0]);
      area[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    const double w = 0.5 * std::sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
    for (std::int64_t i = local.Offsets[f]; i < local.Offsets[f + 1]; ++i)
      for (int c = 0; c < 3; ++c)
        copyNormals[3 * splitConn[i] + c] += w * local.Normals[3 * f + c];
  }
  // The copies the own faces use (in one process: every copy, so that the
  // points keep the input's order), numbered in copy order.
  std::vector<std::int64_t> outOf(nCopies, controller ? -1 : 0), usedCopies;
  std::vector<std::int64_t> offsets(local.Offsets.begin(), local.Offsets.begin() + local.OwnedFaces + 1);
  std::vector<std::int64_t> outConn(splitConn.begin(), splitConn.begin() + offsets.back());
  for (std::int64_t c : outConn)
    outOf[c] = 0;
  for (std::int64_t c = 0; c < nCopies; ++c)
    if (outOf[c] == 0)
    {
      outOf[c] = static_cast<std::int64_t>(usedCopies.size());
      usedCopies.push_back(c);
    }
  for (std::int64_t& c : outConn)
    c = outOf[c];
  const vtkIdType nOut = static_cast<vtkIdType>(usedCopies.size());
  const vtkIdType nOutFaces = static_cast<vtkIdType>(local.OwnedFaces);
  vtkNew<vtkDoubleArray> outPointArray;
  outPointArray->SetNumberOfComponents(3);
  outPointArray->SetNumberOfTuples(nOut);
  double* outPoints = outPointArray->GetPointer(0);
  // Float normals: the PLY writer takes no others.
  vtkNew<vtkFloatArray> pointNormalArray;
  vtkNew<vtkDoubleArray> shiftArray;
  pointNormalArray->SetName("Normals");
  pointNormalArray->SetNumberOfComponents(3);
  pointNormalArray->SetNumberOfTuples(nOut);
  shiftArray->SetName("MeshDisplacement");
  shiftArray->SetNumberOfComponents(3);
  shiftArray->SetNumberOfTuples(nOut);
  vtkNew<vtkIdList> pointSource;
  pointSource->SetNumberOfIds(nOut);
  for (vtkIdType p = 0; p < nOut; ++p)
  {
    const std::int64_t c = usedCopies[p], q = copyOf[c];
    const double* n = &copyNormals[3 * c];
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k)
    {
      outPoints[3 * p + k] = moved[3 * q + k];
      pointNormalArray->SetTypedComponent(p, k, static_cast<float>(len > 0 ? n[k] / len : 0.0));
      shiftArray->SetTypedComponent(p, k, moved[3 * q + k] - local.World[3 * q + k]);
    }
    // An own face's points are the input's.
    pointSource->SetId(p, local.InputPoint[q]);
  }
  vtkNew<vtkPoints> pts;
  pts->SetData(outPointArray);
  std::vector<double> faceNormals(local.Normals.begin(), local.Normals.begin() + 3 * nOutFaces);

  // Cells: quads (the input's polygons), or two triangles per quad; the
  // input cell of each output cell carries its data over.
  vtkNew<vtkIdTypeArray> cellOffsets, cellConn;
  vtkNew<vtkIdList> cellSource;
  if (this->OutputTriangles)
  {
    const std::vector<unsigned char> diagonal =
      dg::QuadDiagonals(outPoints, offsets, outConn, faceNormals.data());
    vtkIdType nTriangles = 0;
    for (vtkIdType f = 0; f < nOutFaces; ++f)
      nTriangles += std::max<vtkIdType>(0, offsets[f + 1] - offsets[f] - 2);
    cellOffsets->SetNumberOfValues(nTriangles + 1);
    cellConn->SetNumberOfValues(3 * nTriangles);
    cellSource->SetNumberOfIds(nTriangles);
    vtkIdType t = 0;
    for (vtkIdType f = 0; f < nOutFaces; ++f)
    {
      const std::int64_t* q = &outConn[offsets[f]];
      const std::int64_t m = offsets[f + 1] - offsets[f];
      // A quad along its diagonal; other polygons as a fan.
      const int s = m == 4 ? diagonal[f] : 0;
      for (std::int64_t i = 1; i + 1 < m; ++i, ++t)
      {
        cellOffsets->SetValue(t, 3 * t);
        cellConn->SetValue(3 * t, q[s % m]);
        cellConn->SetValue(3 * t + 1, q[(s + i) % m]);
        cellConn->SetValue(3 * t + 2, q[(s + i + 1) % m]);
        cellSource->SetId(t, local.InputCell[f]);
      }
    }
    cellOffsets->SetValue(nTriangles, 3 * nTriangles);
  }
  else
  {
    cellOffsets->SetNumberOfValues(nOutFaces + 1);
    cellConn->SetNumberOfValues(static_cast<vtkIdType>(outConn.size()));
    cellSource->SetNumberOfIds(nOutFaces);
    std::copy(offsets.begin(), offsets.end(), cellOffsets->GetPointer(0));
    std::copy(outConn.begin(), outConn.end(), cellConn->GetPointer(0));
    for (vtkIdType f = 0; f < nOutFaces; ++f)
      cellSource->SetId(f, local.InputCell[f]);
  }
  vtkNew<vtkCellArray> cells;
  cells->SetData(cellOffsets, cellConn);
  output->SetPoints(pts);
  output->SetPolys(cells);
  // The input's data: passed as they are where the output's cells (points)
  // are the input's, in order; copied otherwise.
  auto identity = [](vtkIdList* ids, vtkIdType n)
  {
    if (ids->GetNumberOfIds() != n)
      return false;
    for (vtkIdType i = 0; i < n; ++i)
      if (ids->GetId(i) != i)
        return false;
    return true;
  };
  vtkCellData* outCD = output->GetCellData();
  if (identity(cellSource, nCells))
    outCD->PassData(input->GetCellData());
  else
  {
    outCD->CopyGlobalIdsOn(); // off by default in VTK's copies
    outCD->CopyAllocate(input->GetCellData(), cellSource->GetNumberOfIds());
    outCD->CopyData(input->GetCellData(), cellSource, Iota(cellSource->GetNumberOfIds()));
  }
  outCD->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  vtkPointData* outPD = output->GetPointData();
  if (identity(pointSource, nPoints))
  {
    outPD->PassData(input->GetPointData());
    outPD->SetNormals(nullptr);
  }
  else
  {
    outPD->CopyGlobalIdsOn();
    outPD->CopyAllocate(input->GetPointData(), nOut);
    outPD->CopyNormalsOff();
    outPD->CopyData(input->GetPointData(), pointSource, Iota(nOut));
  }
  outPD->AddArray(shiftArray);
  outPD->SetNormals(pointNormalArray);
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  this->UpdateProgress(1.0);
  return 1;
}

void vtkPiecewiseSmoothMeshFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "DataWeight: " << this->DataWeight << "\n";
  os << indent << "CreaseWeight: " << this->CreaseWeight << "\n";
  os << indent << "NumberOfIterations: " << this->NumberOfIterations << "\n";
  os << indent << "SolverTolerance: " << this->SolverTolerance << "\n";
  os << indent << "OutputTriangles: " << (this->OutputTriangles ? "On" : "Off") << "\n";
  os << indent << "SplitFeaturePoints: " << (this->SplitFeaturePoints ? "On" : "Off") << "\n";
  os << indent << "NumberOfCreaseEdges: " << this->NumberOfCreaseEdges << "\n";
  os << indent << "NumberOfBoundCoordinates: " << this->NumberOfBoundCoordinates << "\n";
  os << indent << "MaximumDisplacement: " << this->MaximumDisplacement << "\n";
  os << indent << "Converged: " << (this->Converged ? "yes" : "no") << "\n";
}
