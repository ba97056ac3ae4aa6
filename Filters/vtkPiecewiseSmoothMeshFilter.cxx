#include "vtkPiecewiseSmoothMeshFilter.h"

#include "dgPiecewiseSmoothMesh.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"

#include <vtkCellArray.h>
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
#include <cmath>
#include <map>
#include <string>
#include <tuple>
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
// label pair on label-map interfaces. Compact ids in order of first use.
std::vector<int> MeshRegions(vtkPolyData* input, vtkDataArray* regions,
  const std::vector<vtkIdType>& faceCell)
{
  vtkDataArray* inside = input->GetCellData()->GetArray("LabelInside");
  vtkDataArray* outside = input->GetCellData()->GetArray("LabelOutside");
  const vtkIdType nCells = input->GetNumberOfCells();
  if (!inside || !outside || inside->GetNumberOfTuples() != nCells ||
    outside->GetNumberOfTuples() != nCells)
    inside = outside = nullptr;
  if (!regions && !inside)
    return {};
  std::vector<int> region(faceCell.size());
  std::map<std::tuple<double, double, double>, int> ids;
  for (std::size_t f = 0; f < faceCell.size(); ++f)
  {
    const vtkIdType c = faceCell[f];
    const auto key = std::make_tuple(regions ? regions->GetComponent(c, 0) : 0.0,
      inside ? inside->GetComponent(c, 0) : 0.0, outside ? outside->GetComponent(c, 0) : 0.0);
    region[f] = ids.emplace(key, static_cast<int>(ids.size())).first->second;
  }
  return region;
}
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
  if (controller)
  {
    if (rank == 0)
      vtkErrorMacro("The piecewise-smooth mesh runs in one process: its input, the sharp "
                    "features stage's output, exists in one process only.");
    return 0;
  }
  dg::MeshParameters par;
  par.DataWeight = this->DataWeight;
  par.CreaseWeight = this->CreaseWeight;
  par.Iterations = this->NumberOfIterations;
  std::string problem = par.Check();
  if (!problem.empty())
  {
    vtkErrorMacro("Invalid parameters: " << problem);
    return 0;
  }

  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nFaces = polys ? polys->GetNumberOfCells() : 0;
  const vtkIdType nPoints = input->GetNumberOfPoints();
  const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
  if (nFaces == 0)
  {
    vtkErrorMacro("The input has no polygons: the piecewise-smooth mesh works on a surface.");
    return 0;
  }
  // ParaView sends an empty name until it knows the input's arrays: that
  // means the defaults.
  int association = -1;
  vtkDataArray* normals = this->GetInputArrayToProcess(0, input, association);
  if (!normals)
  {
    normals = input->GetCellData()->GetArray("SharpNormals");
    association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
  }
  if (!normals)
  {
    vtkErrorMacro("No cell normal field: the input has no 'SharpNormals' (run "
                  "vtkSharpFeaturesFilter first, or choose the array with "
                  "SetInputArrayToProcess).");
    return 0;
  }
  if (association != vtkDataObject::FIELD_ASSOCIATION_CELLS || normals->GetNumberOfComponents() != 3)
  {
    vtkErrorMacro("The normal field '" << (normals->GetName() ? normals->GetName() : "")
                                       << "' must be cell data with 3 components.");
    return 0;
  }
  vtkDataArray* regions = this->GetInputArrayToProcess(1, input, association);
  if (!regions)
    regions = input->GetCellData()->GetArray("FeatureRegion");
  else if (association != vtkDataObject::FIELD_ASSOCIATION_CELLS ||
    regions->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro("The region array '" << (regions->GetName() ? regions->GetName() : "")
                                       << "' must be cell data with one component.");
    return 0;
  }

  // Plain arrays: points, polygons, the input cell of each face.
  std::vector<double> world(3 * nPoints);
  for (vtkIdType p = 0; p < nPoints; ++p)
    input->GetPoint(p, &world[3 * p]);
  std::vector<std::int64_t> offsets(1, 0), conn;
  std::vector<vtkIdType> faceCell;
  offsets.reserve(nFaces + 1);
  conn.reserve(4 * nFaces);
  faceCell.reserve(nFaces);
  {
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    auto it = vtk::TakeSmartPointer(polys->NewIterator());
    vtkIdType f = 0;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++f)
    {
      it->GetCurrentCell(npts, ids);
      conn.insert(conn.end(), ids, ids + npts);
      offsets.push_back(static_cast<std::int64_t>(conn.size()));
      faceCell.push_back(polyOffset + f);
    }
  }
  dg::SurfaceFrame frame;
  if (!dg::FindSurfaceFrame(nPoints, world.data(), offsets, conn, frame, problem))
  {
    vtkErrorMacro("The input is not a digital surface: " << problem << ".");
    return 0;
  }
  std::vector<double> grid(3 * nPoints), gridNormals(3 * nFaces);
  for (vtkIdType p = 0; p < nPoints; ++p)
    frame.ToGrid(&world[3 * p], &grid[3 * p]);
  {
    const auto nt = vtk::DataArrayTupleRange<3>(normals);
    for (vtkIdType f = 0; f < nFaces; ++f)
    {
      const double n[3] = { static_cast<double>(nt[faceCell[f]][0]),
        static_cast<double>(nt[faceCell[f]][1]), static_cast<double>(nt[faceCell[f]][2]) };
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(std::abs(len - 1) < 1e-3))
      {
        vtkErrorMacro("The normal field '" << (normals->GetName() ? normals->GetName() : "")
                                           << "' is not made of unit vectors (face " << f
                                           << " has length " << len << ").");
        return 0;
      }
      frame.NormalToGrid(n, &gridNormals[3 * f]);
    }
  }
  const std::vector<int> region = MeshRegions(input, regions, faceCell);
  this->UpdateProgress(0.05);

  dg::MeshInput in;
  in.NumberOfPoints = nPoints;
  in.Points = grid.data();
  in.Offsets = &offsets;
  in.Connectivity = &conn;
  in.FaceNormals = gridNormals.data();
  in.FaceRegion = region.empty() ? nullptr : region.data();
  dg::MeshResult res;
  const bool ok = dg::RegularizeMesh(in, par, res, problem,
    [this](double done)
    {
      this->UpdateProgress(0.05 + 0.85 * done);
      return !this->GetAbortExecute();
    });
  if (this->GetAbortExecute())
    return internal.Abort.Abort(outputVector);
  if (!ok)
  {
    vtkErrorMacro("The piecewise-smooth mesh failed: " << problem);
    return 0;
  }
  const dg::MeshStatistics& stats = res.Statistics;
  if (!stats.Converged)
    vtkWarningMacro("The mesh's last solve did not converge to its tolerance: every vertex is "
                    "still within its cell.");
  this->NumberOfBoundCoordinates = stats.BoundCoordinates;
  this->Converged = stats.Converged;
  for (double d : res.Displacement)
    this->MaximumDisplacement = std::max(this->MaximumDisplacement, std::abs(d));

  // The moved points, world coordinates.
  std::vector<double> moved(3 * nPoints);
  vtkSMPTools::For(0, nPoints,
    [&](vtkIdType p0, vtkIdType p1)
    {
      for (vtkIdType p = p0; p < p1; ++p)
      {
        double g[3];
        for (int c = 0; c < 3; ++c)
          g[c] = grid[3 * p + c] + res.Displacement[3 * p + c];
        frame.ToWorld(g, &moved[3 * p]);
      }
    });
  std::vector<double> faceNormalsWorld(3 * nFaces);
  {
    const auto nt = vtk::DataArrayTupleRange<3>(normals);
    for (vtkIdType f = 0; f < nFaces; ++f)
      for (int c = 0; c < 3; ++c)
        faceNormalsWorld[3 * f + c] = static_cast<double>(nt[faceCell[f]][c]);
  }

  // Port 1: the creases on the moved points (before any split), with the
  // angle between the normals across each.
  {
    const vtkIdType nLines = static_cast<vtkIdType>(res.Creases.size() / 4);
    std::vector<vtkIdType> used(nPoints, -1);
    std::vector<vtkIdType> linePoint; // input point of each line point
    vtkNew<vtkIdTypeArray> lineOffsets, lineConn;
    lineOffsets->SetNumberOfValues(nLines + 1);
    lineConn->SetNumberOfValues(2 * nLines);
    vtkNew<vtkDoubleArray> angle;
    angle->SetName("FeatureAngle");
    angle->SetNumberOfValues(nLines);
    for (vtkIdType l = 0; l < nLines; ++l)
    {
      for (int k = 0; k < 2; ++k)
      {
        const std::int64_t p = res.Creases[4 * l + k];
        if (used[p] < 0)
        {
          used[p] = static_cast<vtkIdType>(linePoint.size());
          linePoint.push_back(p);
        }
        lineConn->SetValue(2 * l + k, used[p]);
      }
      lineOffsets->SetValue(l, 2 * l);
      const double* a = &faceNormalsWorld[3 * res.Creases[4 * l + 2]];
      const double* b = &faceNormalsWorld[3 * res.Creases[4 * l + 3]];
      const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      angle->SetValue(l, std::acos(std::max(-1.0, std::min(1.0, dot))) * 180.0 / M_PI);
    }
    lineOffsets->SetValue(nLines, 2 * nLines);
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetNumberOfPoints(static_cast<vtkIdType>(linePoint.size()));
    for (std::size_t i = 0; i < linePoint.size(); ++i)
      pts->SetPoint(static_cast<vtkIdType>(i), &moved[3 * linePoint[i]]);
    vtkNew<vtkCellArray> ca;
    ca->SetData(lineOffsets, lineConn);
    lines->SetPoints(pts);
    lines->SetLines(ca);
    vtkPointData* pd = lines->GetPointData();
    pd->CopyAllocate(input->GetPointData(), static_cast<vtkIdType>(linePoint.size()));
    for (std::size_t i = 0; i < linePoint.size(); ++i)
      pd->CopyData(input->GetPointData(), linePoint[i], static_cast<vtkIdType>(i));
    lines->GetCellData()->AddArray(angle);
    lines->GetCellData()->SetActiveScalars("FeatureAngle");
  }
  this->NumberOfCreaseEdges = static_cast<vtkIdType>(res.Creases.size() / 4);

  // Port 0: the crease points split per side, then the faces.
  std::vector<std::int64_t> outConn = conn, copyOf;
  if (this->SplitFeaturePoints)
    dg::SplitPointsAtCreases(nPoints, offsets, outConn, region.empty() ? nullptr : region.data(), copyOf);
  else
  {
    copyOf.resize(nPoints);
    for (vtkIdType p = 0; p < nPoints; ++p)
      copyOf[p] = p;
  }
  const vtkIdType nOut = static_cast<vtkIdType>(copyOf.size());
  vtkNew<vtkDoubleArray> outPointArray;
  outPointArray->SetNumberOfComponents(3);
  outPointArray->SetNumberOfTuples(nOut);
  double* outPoints = outPointArray->GetPointer(0);
  vtkSMPTools::For(0, nOut,
    [&](vtkIdType p0, vtkIdType p1)
    {
      for (vtkIdType p = p0; p < p1; ++p)
        std::copy_n(&moved[3 * copyOf[p]], 3, outPoints + 3 * p);
    });
  vtkNew<vtkPoints> pts;
  pts->SetData(outPointArray);
  // Point normals: the area-weighted mean of the field over each point's
  // faces (those of its region, when split).
  std::vector<double> pointNormals(3 * nOut, 0.0);
  for (vtkIdType f = 0; f < nFaces; ++f)
  {
    const std::int64_t m = offsets[f + 1] - offsets[f];
    // The polygon's vector area (Newell) gives its area.
    double area[3] = { 0, 0, 0 };
    for (std::int64_t i = 0; i < m; ++i)
    {
      const double* a = outPoints + 3 * outConn[offsets[f] + i];
      const double* b = outPoints + 3 * outConn[offsets[f] + (i + 1) % m];
      area[0] += (a[1] - b[1]) * (a[2] + b[2]);
      area[1] += (a[2] - b[2]) * (a[0] + b[0]);
      area[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    const double w = 0.5 * std::sqrt(area[0] * area[0] + area[1] * area[1] + area[2] * area[2]);
    for (std::int64_t i = 0; i < m; ++i)
      for (int c = 0; c < 3; ++c)
        pointNormals[3 * outConn[offsets[f] + i] + c] += w * faceNormalsWorld[3 * f + c];
  }
  // Float normals: the PLY writer takes no others.
  vtkNew<vtkFloatArray> pointNormalArray;
  vtkNew<vtkDoubleArray> shiftArray;
  pointNormalArray->SetName("Normals");
  pointNormalArray->SetNumberOfComponents(3);
  pointNormalArray->SetNumberOfTuples(nOut);
  shiftArray->SetName("MeshDisplacement");
  shiftArray->SetNumberOfComponents(3);
  shiftArray->SetNumberOfTuples(nOut);
  vtkSMPTools::For(0, nOut,
    [&](vtkIdType p0, vtkIdType p1)
    {
      for (vtkIdType p = p0; p < p1; ++p)
      {
        const double* n = &pointNormals[3 * p];
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        const std::int64_t q = copyOf[p];
        for (int c = 0; c < 3; ++c)
        {
          pointNormalArray->SetTypedComponent(p, c, static_cast<float>(len > 0 ? n[c] / len : 0.0));
          shiftArray->SetTypedComponent(p, c, moved[3 * q + c] - world[3 * q + c]);
        }
      }
    });

  // Cells: quads (the input's polygons), or two triangles per quad; the
  // input cell of each output cell carries its data over.
  vtkNew<vtkIdTypeArray> cellOffsets, cellConn;
  vtkNew<vtkIdList> cellSource;
  if (this->OutputTriangles)
  {
    const std::vector<unsigned char> diagonal =
      dg::QuadDiagonals(outPoints, offsets, outConn, faceNormalsWorld.data());
    vtkIdType nTriangles = 0;
    for (vtkIdType f = 0; f < nFaces; ++f)
      nTriangles += std::max<vtkIdType>(0, offsets[f + 1] - offsets[f] - 2);
    cellOffsets->SetNumberOfValues(nTriangles + 1);
    cellConn->SetNumberOfValues(3 * nTriangles);
    cellSource->SetNumberOfIds(nTriangles);
    vtkIdType t = 0;
    for (vtkIdType f = 0; f < nFaces; ++f)
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
        cellSource->SetId(t, faceCell[f]);
      }
    }
    cellOffsets->SetValue(nTriangles, 3 * nTriangles);
  }
  else
  {
    cellOffsets->SetNumberOfValues(nFaces + 1);
    cellConn->SetNumberOfValues(static_cast<vtkIdType>(outConn.size()));
    cellSource->SetNumberOfIds(nFaces);
    std::copy(offsets.begin(), offsets.end(), cellOffsets->GetPointer(0));
    std::copy(outConn.begin(), outConn.end(), cellConn->GetPointer(0));
    for (vtkIdType f = 0; f < nFaces; ++f)
      cellSource->SetId(f, faceCell[f]);
  }
  vtkNew<vtkCellArray> cells;
  cells->SetData(cellOffsets, cellConn);
  output->SetPoints(pts);
  output->SetPolys(cells);
  output->GetCellData()->CopyAllocate(input->GetCellData(), cellSource->GetNumberOfIds());
  output->GetCellData()->CopyData(input->GetCellData(), cellSource, Iota(cellSource->GetNumberOfIds()));
  vtkNew<vtkIdList> pointSource;
  pointSource->SetNumberOfIds(nOut);
  for (vtkIdType p = 0; p < nOut; ++p)
    pointSource->SetId(p, copyOf[p]);
  vtkPointData* outPD = output->GetPointData();
  outPD->CopyAllocate(input->GetPointData(), nOut);
  outPD->CopyNormalsOff();
  outPD->CopyData(input->GetPointData(), pointSource, Iota(nOut));
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
  os << indent << "OutputTriangles: " << (this->OutputTriangles ? "On" : "Off") << "\n";
  os << indent << "SplitFeaturePoints: " << (this->SplitFeaturePoints ? "On" : "Off") << "\n";
  os << indent << "NumberOfCreaseEdges: " << this->NumberOfCreaseEdges << "\n";
  os << indent << "NumberOfBoundCoordinates: " << this->NumberOfBoundCoordinates << "\n";
  os << indent << "MaximumDisplacement: " << this->MaximumDisplacement << "\n";
  os << indent << "Converged: " << (this->Converged ? "yes" : "no") << "\n";
}
