// vtkAmbrosioTortorelliFilter on one piece of a distributed surface: the one
// global problem solved across processes (docs/distributed.md). The class
// description says what the outputs are; this file holds the distributed
// execution only, the one-process one is in vtkAmbrosioTortorelliFilter.cxx.
#include "vtkAmbrosioTortorelliFilter.h"

#include "dgLineCells.h"
#include "dgPieces.h"

#include "dgATHalo.h"
#include "dgATOperators.h"
#include "dgATMetric.h"
#include "dgATSolver.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkMultiProcessController.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace
{
std::vector<std::int64_t> ToInt64(vtkDataArray* a)
{
  std::vector<std::int64_t> out(a->GetNumberOfTuples());
  const auto r = vtk::DataArrayValueRange<1>(a);
  std::transform(r.begin(), r.end(), out.begin(), [](double v) { return static_cast<std::int64_t>(v); });
  return out;
}
} // namespace

int vtkAmbrosioTortorelliFilter::RequestDataPieces(vtkMultiProcessController* controller,
  vtkPolyData* input, vtkPolyData* output, vtkPolyData* features, const dg::ATParameters& params,
  int ghostLevels)
{
  const int rank = controller->GetLocalProcessId();
  auto allOk = [controller](bool ok) {
    int mine = ok ? 1 : 0, all = 0;
    controller->AllReduce(&mine, &all, 1, vtkCommunicator::MIN_OP);
    return all == 1;
  };
  // A piece that fails says why; the others stop with it, silently, so
  // that the run shows one message.
  auto fail = [&](const std::string& why) {
    if (!why.empty())
    {
      vtkErrorMacro("Piece " << rank << " of " << controller->GetNumberOfProcesses() << ": " << why);
    }
    return 0;
  };

  // 1. Local checks, then agreement.
  std::ostringstream problem;
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nFaces = polys ? polys->GetNumberOfCells() : 0;
  const vtkIdType nCells = input->GetNumberOfCells(), nPoints = input->GetNumberOfPoints();
  int association = -1;
  vtkDataArray* field = this->GetInputArrayToProcess(0, input, association);
  vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
  if (!field && arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME()) &&
    !*arrayInfo->Get(vtkDataObject::FIELD_NAME()))
  {
    field = input->GetCellData()->GetNormals();
    association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
  }
  vtkDataArray* cellIds = dg::GlobalIdArray(input->GetCellData(), nCells);
  vtkDataArray* pointIds = dg::GlobalIdArray(input->GetPointData(), nPoints);
  vtkDataArray* ghostArray = input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
  if (nCells != nFaces)
  {
    problem << "a distributed run takes polygons only (this piece has " << nCells - nFaces
            << " other cells). ";
  }
  if (!field || association != vtkDataObject::FIELD_ASSOCIATION_CELLS ||
    field->GetNumberOfTuples() != nCells)
  {
    problem << "no cell field to regularise (choose one with SetInputArrayToProcess; default: "
               "the active cell normals). ";
  }
  if (!cellIds || !pointIds)
  {
    problem << "a distributed run needs cell and point global ids (the 'GlobalIds' arrays of "
               "vtkDigitalSurfaceFilter) to match cells and points across pieces. ";
  }
  if (ghostArray && ghostArray->GetNumberOfTuples() != nCells)
  {
    ghostArray = nullptr;
  }
  const int nc = field ? field->GetNumberOfComponents() : 0;
  Eigen::MatrixXd g;
  bool unit = nc == 3, zeroVector = false;
  if (problem.str().empty())
  {
    g.resize(nFaces, nc);
    const auto tuples = vtk::DataArrayTupleRange(field);
    for (vtkIdType f = 0; f < nFaces; ++f)
    {
      double n2 = 0;
      for (int c = 0; c < nc; ++c)
      {
        g(f, c) = static_cast<double>(tuples[f][c]);
        n2 += g(f, c) * g(f, c);
      }
      if (!std::isfinite(n2))
      {
        problem << "the field has a NaN or infinite value (cell " << f << "). ";
        break;
      }
      zeroVector |= n2 == 0;
      unit &= std::abs(std::sqrt(n2) - 1) <= 1e-3;
    }
  }
  if (!allOk(problem.str().empty()))
  {
    return fail(problem.str());
  }
  const bool activeNormals = field == input->GetCellData()->GetNormals();
  const bool normalField = allOk(nc == 3 && (activeNormals || unit));
  if (!allOk(!(normalField && this->NormalizeVectorField && zeroVector)))
  {
    return fail(zeroVector ? "the normal field has a zero vector: turn NormalizeVectorField off to "
                             "regularise it as it is."
                           : "");
  }
  // The field's global half range scales a non-normal field (as in one process).
  double scale = 1.0;
  if (!normalField && this->FieldScaling == FIELD_SCALING_RANGE)
  {
    double half = 0;
    for (int c = 0; c < nc; ++c)
    {
      double hi = nFaces ? g.col(c).maxCoeff() : -VTK_DOUBLE_MAX;
      double lo = nFaces ? -g.col(c).minCoeff() : -VTK_DOUBLE_MAX;
      double ghi = hi, glo = lo;
      controller->AllReduce(&hi, &ghi, 1, vtkCommunicator::MAX_OP);
      controller->AllReduce(&lo, &glo, 1, vtkCommunicator::MAX_OP);
      half = std::max(half, 0.5 * (ghi + glo));
    }
    if (half > 0)
    {
      scale = half;
      g /= scale;
    }
  }
  this->UpdateProgress(0.05);

  // 2. Ownership and halo.
  std::vector<std::int64_t> offsets(nFaces + 1), connectivity(polys->GetNumberOfConnectivityIds());
  {
    const auto off = vtk::DataArrayValueRange<1>(polys->GetOffsetsArray());
    const auto conn = vtk::DataArrayValueRange<1>(polys->GetConnectivityArray());
    std::copy(off.begin(), off.end(), offsets.begin());
    std::copy(conn.begin(), conn.end(), connectivity.begin());
  }
  std::vector<char> ghost(nFaces, 0);
  if (ghostArray)
  {
    for (vtkIdType f = 0; f < nFaces; ++f)
    {
      ghost[f] = (static_cast<int>(ghostArray->GetComponent(f, 0)) &
                   (vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL)) != 0;
    }
  }
  const std::vector<std::int64_t> faceGids = ToInt64(cellIds), pointGids = ToInt64(pointIds);
  dg::ATHalo halo(controller);
  std::string error;
  if (!halo.Build(offsets, connectivity, faceGids, ghost, pointGids, error))
  {
    return fail(error);
  }

  // 3. The local complex: owned rows first, then the halo.
  std::vector<std::int64_t> pointRow(nPoints, -1);
  for (std::size_t r = 0; r < halo.VertexRows.size(); ++r)
  {
    pointRow[halo.VertexRows[r]] = static_cast<std::int64_t>(r);
  }
  std::vector<std::int64_t> localOffsets(1, 0), localConn;
  Eigen::MatrixXd localG(halo.FaceRows.size(), nc);
  for (std::size_t r = 0; r < halo.FaceRows.size(); ++r)
  {
    const std::int64_t f = halo.FaceRows[r];
    for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
    {
      localConn.push_back(pointRow[connectivity[k]]);
    }
    localOffsets.push_back(static_cast<std::int64_t>(localConn.size()));
    localG.row(r) = g.row(f);
  }
  dg::ATComplex complex;
  const bool built = complex.Build(
    static_cast<std::int64_t>(halo.VertexRows.size()), localOffsets, localConn, &error);
  if (!allOk(built))
  {
    return fail(built ? "" : "cannot build the complex: " + error + ".");
  }
  // The world metric from the local rows' own points: an owned row's
  // weights read only its faces, edges and their faces, all in the halo.
  dg::ATMetric metric;
  if (this->Metric == METRIC_WORLD)
  {
    const bool ok = dg::ComputeWorldMetric(
      input->GetPoints(), &halo.VertexRows, complex, localOffsets, localConn, metric, error);
    if (!allOk(ok))
    {
      return fail(ok ? "" : "cannot use the world metric: " + error + ".");
    }
  }
  this->UpdateProgress(0.1);

  // 4. The solve: every process runs the same schedule; progress only (an
  // abort on one process alone would leave the others waiting).
  dg::ATSolver solver(complex, params, dg::ATSolver::TakePatterns);
  solver.SetDistribution(&halo);
  if (this->Metric == METRIC_WORLD)
  {
    solver.SetMetric(&metric);
  }
  const bool done = solver.Run(std::move(localG), [this](double f) {
    this->UpdateProgress(0.1 + 0.85 * f);
    return true;
  });
  this->NumberOfIterations = solver.Statistics().Iterations;
  this->NumberOfCGIterations = solver.Statistics().CGIterations;
  this->HaloFaceValues = halo.HaloValues(0);
  this->HaloVertexValues = halo.HaloValues(1);
  if (!done)
  {
    return fail(rank == 0 ? "Ambrosio-Tortorelli failed: " + solver.Error() + "." : "");
  }
  if (!solver.Warnings().empty() && rank == 0)
  {
    vtkWarningMacro(<< solver.Statistics().FailedSolves
                    << " linear solve(s) failed; first: " << solver.Warnings().front() << ".");
  }
  const Eigen::MatrixXd& u = solver.U();
  const Eigen::VectorXd& v = solver.V();

  // 5. Port 0: the owned cells, then, when downstream asked for ghost
  // levels, the halo's ring of ghost cells (one level) with their owners'
  // u and v: a stage after this one that reads its input on the ring (AT
  // again, on the sharp stage's normals) sees there what one process gives.
  const std::int64_t outFaces =
    ghostLevels > 0 ? static_cast<std::int64_t>(halo.FaceRows.size()) : halo.OwnedFaces;
  std::vector<double> uRows(static_cast<std::size_t>(u.rows()) * nc), vRows(v.data(), v.data() + v.size());
  for (Eigen::Index r = 0; r < u.rows(); ++r)
  {
    for (int c = 0; c < nc; ++c)
    {
      uRows[r * nc + c] = u(r, c);
    }
  }
  halo.UpdateGhosts(0, uRows.data(), nc); // collective: every process gets here
  halo.UpdateGhosts(1, vRows.data(), 1);
  std::vector<vtkIdType> newPoint(nPoints, -1), oldPoint;
  vtkNew<vtkIdTypeArray> outOffsets, outConn;
  outOffsets->SetNumberOfValues(outFaces + 1);
  outOffsets->SetValue(0, 0);
  for (std::int64_t r = 0; r < outFaces; ++r)
  {
    const std::int64_t f = halo.FaceRows[r];
    for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
    {
      vtkIdType& id = newPoint[connectivity[k]];
      if (id < 0)
      {
        id = static_cast<vtkIdType>(oldPoint.size());
        oldPoint.push_back(connectivity[k]);
      }
      outConn->InsertNextValue(id);
    }
    outOffsets->SetValue(r + 1, outConn->GetNumberOfValues());
  }
  const vtkIdType nOut = static_cast<vtkIdType>(oldPoint.size());
  vtkNew<vtkPoints> points;
  points->SetDataType(input->GetPoints() ? input->GetPoints()->GetDataType() : VTK_DOUBLE);
  points->SetNumberOfPoints(nOut);
  vtkPointData* inPD = input->GetPointData();
  vtkPointData* outPD = output->GetPointData();
  outPD->CopyGlobalIdsOn(); // off by default in VTK's copies
  outPD->CopyAllocate(inPD, nOut);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    points->SetPoint(i, input->GetPoint(oldPoint[i]));
    outPD->CopyData(inPD, oldPoint[i], i);
  }
  vtkCellData* inCD = input->GetCellData();
  vtkCellData* outCD = output->GetCellData();
  outCD->CopyGlobalIdsOn();
  outCD->CopyAllocate(inCD, outFaces);
  for (std::int64_t r = 0; r < outFaces; ++r)
  {
    outCD->CopyData(inCD, halo.FaceRows[r], r);
  }
  outCD->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  if (outFaces > halo.OwnedFaces)
  {
    vtkNew<vtkUnsignedCharArray> cellGhosts;
    cellGhosts->SetName(vtkDataSetAttributes::GhostArrayName());
    cellGhosts->SetNumberOfTuples(outFaces);
    for (std::int64_t r = 0; r < outFaces; ++r)
    {
      cellGhosts->SetValue(r, r < halo.OwnedFaces ? 0 : vtkDataSetAttributes::DUPLICATECELL);
    }
    outCD->AddArray(cellGhosts);
  }
  vtkNew<vtkCellArray> outPolys;
  outPolys->SetData(outOffsets, outConn);
  output->SetPoints(points);
  output->SetPolys(outPolys);
  output->GetFieldData()->ShallowCopy(input->GetFieldData());

  const char* fieldName = field->GetName() ? field->GetName() : "(unnamed)";
  const bool normalize = normalField && this->NormalizeVectorField;
  vtkNew<vtkDoubleArray> uArray;
  uArray->SetName(normalField ? "ATNormals" : (std::string(fieldName) + "_AT").c_str());
  uArray->SetNumberOfComponents(nc);
  uArray->SetNumberOfTuples(outFaces);
  for (std::int64_t r = 0; r < outFaces; ++r)
  {
    double* o = uArray->GetPointer(r * nc);
    double n2 = 0;
    for (int c = 0; c < nc; ++c)
    {
      o[c] = uRows[r * nc + c] * scale;
      n2 += o[c] * o[c];
    }
    for (int c = 0; normalize && n2 > 0 && c < nc; ++c)
    {
      o[c] /= std::sqrt(n2);
    }
  }
  outCD->AddArray(uArray);
  if (normalField)
  {
    outCD->SetActiveNormals("ATNormals");
  }
  vtkNew<vtkDoubleArray> vArray;
  vArray->SetName("ATFeatureIndicator");
  vArray->SetNumberOfTuples(nOut);
  for (vtkIdType i = 0; i < nOut; ++i)
  {
    vArray->SetValue(i, vRows[pointRow[oldPoint[i]]]);
  }
  outPD->AddArray(vArray);

  // Port 1: each feature edge once over all pieces, from the owner of its
  // end point with the lower global id; its own points, with global ids.
  const double th = this->FeatureThreshold;
  vtkNew<vtkPoints> linePoints;
  linePoints->SetDataType(points->GetDataType());
  vtkNew<vtkIdTypeArray> lineIds;
  lineIds->SetName("GlobalIds");
  std::vector<vtkIdType> ends;
  std::vector<double> lineV;
  std::vector<vtkIdType> lineRow(halo.VertexRows.size(), -1);
  for (std::int64_t e = 0; e < complex.NumberOfEdges(); ++e)
  {
    const int a = complex.EdgeVertices[2 * e], b = complex.EdgeVertices[2 * e + 1];
    const int low = pointGids[halo.VertexRows[a]] < pointGids[halo.VertexRows[b]] ? a : b;
    if (halo.VertexOwner[low] != rank || !(v[a] < th && v[b] < th))
    {
      continue;
    }
    for (int end : { a, b })
    {
      if (lineRow[end] < 0)
      {
        lineRow[end] = linePoints->InsertNextPoint(input->GetPoint(halo.VertexRows[end]));
        lineIds->InsertNextValue(pointGids[halo.VertexRows[end]]);
      }
      ends.push_back(lineRow[end]);
    }
    lineV.push_back(std::max(v[a], v[b]));
  }
  features->SetPoints(linePoints);
  features->SetLines(dg::TwoPointLines(ends));
  features->GetCellData()->AddArray(dg::LineValues("ATFeatureIndicator", lineV));
  features->GetPointData()->SetGlobalIds(lineIds);
  this->FieldScale = scale;
  ++this->NumberOfSolves;
  this->UpdateProgress(1.0);
  return 1;
}
