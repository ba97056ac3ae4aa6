#include "vtkAmbrosioTortorelliFilter.h"

#include "dgLineCells.h"
#include "dgATMetric.h"
#include "dgATOperators.h"
#include "dgATSolver.h"
#include "dgHugePages.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkSmartPointer.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkAmbrosioTortorelliFilter);

// The last solve and what it was made from: an execution whose input and
// solve parameters are the same only rebuilds the outputs from it. The input
// is identified by the arrays the solve read (the field, the polygons) and
// their MTimes, not by the vtkPolyData: ParaView hands each execution a new
// shallow copy of the upstream output (its post-filter), with a new MTime.
struct vtkAmbrosioTortorelliFilter::Internals
{
  dg::PipelineAbort Abort;
  bool Valid = false;
  vtkSmartPointer<vtkDataArray> Field;
  vtkSmartPointer<vtkCellArray> Polys;
  vtkMTimeType FieldMTime = 0, PolysMTime = 0;
  vtkIdType PolyOffset = 0, NumberOfPoints = 0;
  dg::ATParameters Params;
  int FieldScaling = 0;
  int Metric = 0;
  vtkSmartPointer<vtkDataArray> PointsData; // the world metric's points
  vtkMTimeType PointsMTime = 0;
  double Scale = 1.0;
  int Iterations = 0;
  Eigen::MatrixXd U; // unnormalised, in the field's own unit
  Eigen::VectorXd V;
  std::vector<int> EdgeVertices;

  // 2 when solved (the members above hold the result), else RequestData's
  // return value (0 on error, 1 when aborted).
  int Solve(vtkAmbrosioTortorelliFilter* self,
    vtkPolyData* input,
    vtkDataArray* field,
    vtkCellArray* polys,
    bool normalField,
    Eigen::MatrixXd& g,
    const dg::ATParameters& params,
    vtkInformationVector* outputVector);

  void Remember(vtkPolyData* input, vtkDataArray* field)
  {
    this->Field = field;
    this->FieldMTime = field->GetMTime();
    this->Polys = input->GetPolys();
    this->PolysMTime = input->GetPolys()->GetMTime();
    this->PolyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
    this->NumberOfPoints = input->GetNumberOfPoints();
    this->PointsData = input->GetPoints() ? input->GetPoints()->GetData() : nullptr;
    this->PointsMTime = this->PointsData ? this->PointsData->GetMTime() : 0;
  }

  bool SameSolve(vtkPolyData* input,
    vtkDataArray* field,
    const dg::ATParameters& p,
    int scaling,
    int metric) const
  {
    const dg::ATParameters& q = this->Params;
    vtkDataArray* points = input->GetPoints() ? input->GetPoints()->GetData() : nullptr;
    const bool samePoints = metric == vtkAmbrosioTortorelliFilter::METRIC_GRID ||
      (points == this->PointsData && points && points->GetMTime() == this->PointsMTime);
    return this->Valid && metric == this->Metric && samePoints && field == this->Field &&
           field->GetMTime() == this->FieldMTime &&
           input->GetPolys() == this->Polys && input->GetPolys()->GetMTime() == this->PolysMTime &&
           input->GetNumberOfVerts() + input->GetNumberOfLines() == this->PolyOffset &&
           input->GetNumberOfPoints() == this->NumberOfPoints && scaling == this->FieldScaling &&
           p.Alpha == q.Alpha &&
           p.Lambda == q.Lambda && p.EpsilonStart == q.EpsilonStart &&
           p.EpsilonEnd == q.EpsilonEnd && p.EpsilonRatio == q.EpsilonRatio &&
           p.MaximumIterations == q.MaximumIterations && p.Tolerance == q.Tolerance &&
           p.Solver == q.Solver && p.CGTolerance == q.CGTolerance &&
           p.CGToleranceEarlyFactor == q.CGToleranceEarlyFactor &&
           p.CGMaximumIterations == q.CGMaximumIterations;
  }
};

vtkAmbrosioTortorelliFilter::vtkAmbrosioTortorelliFilter()
  : Internal(new Internals)
{
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, vtkDataSetAttributes::NORMALS);
}

vtkAmbrosioTortorelliFilter::~vtkAmbrosioTortorelliFilter() = default;

vtkMTimeType vtkAmbrosioTortorelliFilter::GetMTime()
{
  return this->Internal->Abort.MTime(this->Superclass::GetMTime());
}

int vtkAmbrosioTortorelliFilter::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  // A piece's rows need one ring of ghost cells around its own.
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo && outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES()) &&
    outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()) > 1)
  {
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(),
      outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS()) + 1);
  }
  return 1;
}

int vtkAmbrosioTortorelliFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

namespace
{
// A normal field is the active cell normals, or unit 3-vectors everywhere.
constexpr double UnitTolerance = 1e-3;

// Boundary edges that have the same end coordinates as another boundary
// edge: polygons that touch in space but not in the connectivity.
std::int64_t CoincidentBoundaryEdges(vtkPoints* points, const dg::ATComplex& complex)
{
  using Key = std::array<double, 6>;
  std::vector<Key> keys;
  for (std::int64_t e = 0; e < complex.NumberOfEdges(); ++e)
  {
    if (complex.EdgeFacePtr[e + 1] - complex.EdgeFacePtr[e] != 1)
    {
      continue;
    }
    Key k;
    points->GetPoint(complex.EdgeVertices[2 * e], k.data());
    points->GetPoint(complex.EdgeVertices[2 * e + 1], k.data() + 3);
    if (std::lexicographical_compare(k.begin() + 3, k.end(), k.begin(), k.begin() + 3))
    {
      std::swap_ranges(k.begin(), k.begin() + 3, k.begin() + 3);
    }
    keys.push_back(k);
  }
  std::sort(keys.begin(), keys.end());
  std::int64_t count = 0;
  for (std::size_t i = 0; i < keys.size(); ++i)
  {
    const bool same =
      (i > 0 && keys[i] == keys[i - 1]) || (i + 1 < keys.size() && keys[i] == keys[i + 1]);
    count += same;
  }
  return count;
}
} // namespace

int vtkAmbrosioTortorelliFilter::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  Internals& cache = *this->Internal;
  const auto abortGuard = cache.Abort.Begin(this, outputVector);
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* features = vtkPolyData::GetData(outputVector, 1);
  if (!input || !output || !features)
  {
    vtkErrorMacro("Missing input or output.");
    return 0;
  }
  if (dg::PipelineAbort::InputAborted(inputVector, 1))
  {
    cache.Valid = false;
    return cache.Abort.Abort(outputVector);
  }

  dg::ATParameters params;
  params.Alpha = this->Alpha;
  params.Lambda = this->Lambda;
  params.EpsilonStart = this->EpsilonStart;
  params.EpsilonEnd = this->EpsilonEnd;
  params.EpsilonRatio = this->EpsilonRatio;
  params.MaximumIterations = this->MaximumIterations;
  params.Tolerance = this->Tolerance;
  params.Solver = static_cast<dg::ATLinearSolver>(this->LinearSolver);
  params.CGTolerance = this->SolverTolerance;
  // Checked here, so that the message names this filter's property.
  const bool earlyValid =
    this->SolverToleranceEarlyFactor >= 1 && std::isfinite(this->SolverToleranceEarlyFactor);
  params.CGToleranceEarlyFactor = earlyValid ? this->SolverToleranceEarlyFactor : 1.0;
  // Normalisation is applied to the outputs, so the kept solve serves both.
  params.Normalize = false;
  std::string problem = params.Check();
  if (!earlyValid)
  {
    problem += (problem.empty() ? "" : " ") +
               std::string("SolverToleranceEarlyFactor must be finite and >= 1 (got ") +
               std::to_string(this->SolverToleranceEarlyFactor) + ").";
  }
  if (!(this->FeatureThreshold > 0 && this->FeatureThreshold < 1))
  {
    problem += (problem.empty() ? "" : " ") +
               std::string("FeatureThreshold must be in (0, 1) (got ") +
               std::to_string(this->FeatureThreshold) + ").";
  }
  if (!problem.empty())
  {
    vtkErrorMacro("Invalid parameters: " << problem);
    return 0;
  }
  if (vtkMultiProcessController* controller =
        dg::PieceController(outputVector->GetInformationObject(0)))
  {
    // One of several pieces: the distributed solve (no kept solution).
    cache.Valid = false;
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    const int ghostLevels =
      outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS())
      ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS())
      : 0;
    return this->RequestDataPieces(controller, input, output, features, params, ghostLevels);
  }

  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nFaces = polys ? polys->GetNumberOfCells() : 0;
  if (nFaces == 0)
  {
    vtkErrorMacro("The input has no polygons: the Ambrosio-Tortorelli filter works on a surface.");
    return 0;
  }
  int association = -1;
  vtkDataArray* field = this->GetInputArrayToProcess(0, input, association);
  vtkInformation* arrayInfo = this->GetInputArrayInformation(0);
  if (!field && arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME()) &&
      !*arrayInfo->Get(vtkDataObject::FIELD_NAME()))
  {
    // ParaView sends an empty name until it knows the input's arrays: that
    // means the default, the active cell normals.
    field = input->GetCellData()->GetNormals();
    association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
  }
  if (!field)
  {
    // Say what there is to choose from: the plugin's default (IINormals)
    // is missing on inputs that did not come from the II estimator.
    std::string available;
    vtkCellData* cd = input->GetCellData();
    for (int i = 0; i < cd->GetNumberOfArrays(); ++i)
    {
      if (vtkDataArray* a = cd->GetArray(i))
      {
        available += (available.empty() ? "" : ", ") + std::string(a->GetName() ? a->GetName() : "(unnamed)");
      }
    }
    const char* wanted = arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
      ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
      : nullptr;
    vtkErrorMacro("No field to regularise: the input has no cell array "
      << (wanted && *wanted ? "named '" + std::string(wanted) + "'"
                            : std::string("matching the selection (default: the active cell normals)"))
      << ". Its cell arrays: " << (available.empty() ? "none" : available)
      << ". Choose one with SetInputArrayToProcess (ParaView: Field).");
    return 0;
  }
  if (association != vtkDataObject::FIELD_ASSOCIATION_CELLS)
  {
    vtkErrorMacro("The field '" << (field->GetName() ? field->GetName() : "")
                                << "' is not cell data: u lives on the polygons.");
    return 0;
  }
  // Cell data order in vtkPolyData: verts, lines, polys, strips.
  const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
  const vtkIdType nCells = input->GetNumberOfCells();
  if (field->GetNumberOfTuples() != nCells)
  {
    vtkErrorMacro(
      "The field has " << field->GetNumberOfTuples() << " tuples for " << nCells << " cells.");
    return 0;
  }
  const int nc = field->GetNumberOfComponents();
  const char* fieldName = field->GetName() ? field->GetName() : "(unnamed)";

  Eigen::MatrixXd g(nFaces, nc);
  dg::AdviseHugePages(g.data(), static_cast<std::size_t>(g.size()) * sizeof(double)); // before first touch
  std::atomic<vtkIdType> badValue(-1), zeroVector(-1), notUnit(-1);
  {
    const auto tuples = vtk::DataArrayTupleRange(field);
    vtkSMPTools::For(0, nFaces, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType f = b; f < e; ++f)
      {
        const auto t = tuples[polyOffset + f];
        double n2 = 0;
        for (int c = 0; c < nc; ++c)
        {
          const double x = static_cast<double>(t[c]);
          g(f, c) = x;
          n2 += x * x;
          if (!std::isfinite(x))
          {
            badValue = polyOffset + f;
          }
        }
        if (n2 == 0)
        {
          zeroVector = polyOffset + f;
        }
        if (!(std::abs(std::sqrt(n2) - 1) <= UnitTolerance))
        {
          notUnit = polyOffset + f;
        }
      }
    });
  }
  if (badValue >= 0)
  {
    vtkErrorMacro("The field '" << fieldName << "' has a NaN or infinite value (e.g. cell "
                                << badValue.load() << ").");
    return 0;
  }
  const bool activeNormals = field == input->GetCellData()->GetNormals();
  const bool normalField = nc == 3 && (activeNormals || notUnit < 0);
  if (normalField && this->NormalizeVectorField && zeroVector >= 0)
  {
    vtkErrorMacro(
      "The field '"
      << fieldName << "' (the active normals) has a zero vector (e.g. cell " << zeroVector.load()
      << "): it cannot be a normal. Turn NormalizeVectorField off to regularise it as it is.");
    return 0;
  }
  this->UpdateProgress(0.02);
  if (this->GetAbortExecute())
  {
    return cache.Abort.Abort(outputVector); // the kept solve stays valid
  }

  const int scaling = normalField ? FIELD_SCALING_NONE : this->FieldScaling;
  if (!cache.SameSolve(input, field, params, scaling, this->Metric))
  {
    cache.Valid = false;
    const int status = cache.Solve(this, input, field, polys, normalField, g, params, outputVector);
    if (status != 2)
    {
      return status;
    }
    cache.Valid = true;
    cache.Remember(input, field);
    cache.Params = params;
    cache.FieldScaling = scaling;
    cache.Metric = this->Metric;
    ++this->NumberOfSolves;
  }
  this->NumberOfIterations = cache.Iterations;
  this->FieldScale = cache.Scale;
  this->UpdateProgress(0.96);

  // Port 0: the surface with u and v.
  output->ShallowCopy(input);
  const bool normalize = normalField && this->NormalizeVectorField;
  vtkNew<vtkDoubleArray> uArray;
  uArray->SetName(normalField ? "ATNormals" : (std::string(fieldName) + "_AT").c_str());
  uArray->SetNumberOfComponents(nc);
  uArray->SetNumberOfTuples(nCells);
  {
    double* out = uArray->GetPointer(0);
    const Eigen::MatrixXd& u = cache.U;
    const double scale = cache.Scale;
    const auto tuples = vtk::DataArrayTupleRange(field);
    vtkSMPTools::For(0, nCells, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType cell = b; cell < e; ++cell)
      {
        const vtkIdType f = cell - polyOffset;
        double* o = out + cell * nc;
        if (!(f >= 0 && f < nFaces))
        {
          for (int c = 0; c < nc; ++c)
          {
            o[c] = static_cast<double>(tuples[cell][c]);
          }
          continue;
        }
        double n2 = 0;
        for (int c = 0; c < nc; ++c)
        {
          o[c] = u(f, c) * scale;
          n2 += o[c] * o[c];
        }
        if (normalize && n2 > 0)
        {
          const double inv = 1.0 / std::sqrt(n2);
          for (int c = 0; c < nc; ++c)
          {
            o[c] *= inv;
          }
        }
      }
    });
  }
  // AddArray then SetActiveNormals: SetNormals would drop the input normals
  // (the previous active array), which users want to compare with.
  output->GetCellData()->AddArray(uArray);
  if (normalField)
  {
    output->GetCellData()->SetActiveNormals("ATNormals");
  }
  const Eigen::VectorXd& v = cache.V;
  vtkNew<vtkDoubleArray> vArray;
  vArray->SetName("ATFeatureIndicator");
  vArray->SetNumberOfTuples(v.size());
  std::copy(v.data(), v.data() + v.size(), vArray->GetPointer(0));
  output->GetPointData()->AddArray(vArray);

  // Port 1: feature edges, in the complex's (deterministic) edge order.
  const double th = this->FeatureThreshold;
  const std::vector<int>& edges = cache.EdgeVertices;
  std::vector<vtkIdType> selected;
  for (std::size_t e = 0; e < edges.size() / 2; ++e)
  {
    if (v[edges[2 * e]] < th && v[edges[2 * e + 1]] < th)
    {
      selected.push_back(static_cast<vtkIdType>(e));
    }
  }
  std::vector<vtkIdType> ends(2 * selected.size());
  std::vector<double> lineV(selected.size());
  for (std::size_t l = 0; l < selected.size(); ++l)
  {
    const int a = edges[2 * selected[l]], b = edges[2 * selected[l] + 1];
    ends[2 * l] = a;
    ends[2 * l + 1] = b;
    lineV[l] = std::max(v[a], v[b]);
  }
  features->SetPoints(input->GetPoints());
  features->SetLines(dg::TwoPointLines(ends));
  features->GetCellData()->AddArray(dg::LineValues("ATFeatureIndicator", lineV));
  this->UpdateProgress(1.0);
  return 1;
}

int vtkAmbrosioTortorelliFilter::Internals::Solve(vtkAmbrosioTortorelliFilter* self,
  vtkPolyData* input,
  vtkDataArray* field,
  vtkCellArray* polys,
  bool normalField,
  Eigen::MatrixXd& g,
  const dg::ATParameters& params,
  vtkInformationVector* outputVector)
{
  const vtkIdType nFaces = polys->GetNumberOfCells();
  const char* fieldName = field->GetName() ? field->GetName() : "(unnamed)";

  // The energy is quadratic in the field's jumps but not in v's terms:
  // scale a non-normal field to the range unit normals have.
  double scale = 1.0;
  if (!normalField)
  {
    double half = 0;
    for (Eigen::Index c = 0; c < g.cols(); ++c)
    {
      half = std::max(half, 0.5 * (g.col(c).maxCoeff() - g.col(c).minCoeff()));
    }
    if (self->FieldScaling == FIELD_SCALING_RANGE && half > 0)
    {
      scale = half;
      g /= scale;
    }
    else if (self->FieldScaling == FIELD_SCALING_NONE && half > 0 && (half < 0.1 || half > 10))
    {
      vtkWarningWithObjectMacro(self,
        "The field '"
          << fieldName << "' spans " << 2 * half
          << " (largest component range): Alpha and Lambda assume jumps on the scale of unit "
             "normals (range 2), so AT will find "
          << (half > 10 ? "features on nearly every edge" : "almost no features")
          << ". Use FieldScaling RANGE, or scale Lambda by (range / 2)^2.");
    }
  }

  // Plain buffers for the core.
  std::vector<std::int64_t> offsets, connectivity;
  dg::AssignHuge(offsets, static_cast<std::size_t>(nFaces + 1), std::int64_t(0));
  dg::AssignHuge(connectivity, static_cast<std::size_t>(polys->GetNumberOfConnectivityIds()), std::int64_t(0));
  {
    const auto off = vtk::DataArrayValueRange<1>(polys->GetOffsetsArray());
    const auto conn = vtk::DataArrayValueRange<1>(polys->GetConnectivityArray());
    vtkSMPTools::For(0, nFaces + 1, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
      {
        offsets[i] = static_cast<std::int64_t>(off[i]);
      }
    });
    vtkSMPTools::For(0, static_cast<vtkIdType>(connectivity.size()), [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType i = b; i < e; ++i)
      {
        connectivity[i] = static_cast<std::int64_t>(conn[i]);
      }
    });
  }
  dg::ATComplex complex;
  std::string error;
  if (!complex.Build(input->GetNumberOfPoints(), offsets, connectivity, &error))
  {
    vtkErrorWithObjectMacro(self, "Cannot build the complex: " << error << ".");
    return 0;
  }
  dg::ATMetric metric;
  if (self->Metric == METRIC_WORLD &&
    !dg::ComputeWorldMetric(input->GetPoints(), nullptr, complex, offsets, connectivity, metric, error))
  {
    vtkErrorWithObjectMacro(self, "Cannot use the world metric: " << error << ".");
    return 0;
  }
  offsets = std::vector<std::int64_t>();
  connectivity = std::vector<std::int64_t>();
  // Two polygons of opposite winding across an edge make B compare u1 + u2
  // instead of u1 - u2: the jump term is then meaningless there. Still
  // compute (the rest of the surface is fine), but say so. A surface whose
  // polygons share no edge has no jump to find at all.
  std::int64_t inconsistent = 0, interior = 0, boundary = 0;
  for (std::int64_t e = 0; e < complex.NumberOfEdges(); ++e)
  {
    const std::int64_t b = complex.EdgeFacePtr[e], n = complex.EdgeFacePtr[e + 1] - b;
    interior += n >= 2;
    boundary += n == 1;
    if (n == 2 && complex.EdgeFaceSigns[b] == complex.EdgeFaceSigns[b + 1])
    {
      ++inconsistent;
    }
  }
  const std::int64_t coincident = CoincidentBoundaryEdges(input->GetPoints(), complex);
  if (interior == 0)
  {
    vtkWarningWithObjectMacro(self,
      "No two polygons share an edge ("
        << boundary
        << " boundary edges): the cells do not share points, so AT sees no jump and finds no "
           "feature. Merge the points first (vtkCleanPolyData), and turn splitting off where "
           "the surface came from vtkPolyDataNormals (SplittingOff).");
  }
  else if (coincident > 0)
  {
    vtkWarningWithObjectMacro(self,
      << coincident << " of the " << boundary
      << " boundary edges lie on another polygon's edge with other point ids: the polygons do "
         "not share points there (split by vtkPolyDataNormals, or never merged), so AT sees no "
         "jump across them and finds no feature there. Merge the points first "
         "(vtkCleanPolyData), and turn splitting off in vtkPolyDataNormals.");
  }
  if (inconsistent > 0)
  {
    vtkWarningWithObjectMacro(self,
      << inconsistent
      << " edges join two polygons of opposite winding: the surface is not "
         "consistently oriented and the result is unreliable near them (orient it "
         "first, e.g. vtkPolyDataNormals with ConsistencyOn).");
  }
  self->UpdateProgress(0.1);
  if (self->GetAbortExecute())
  {
    return this->Abort.Abort(outputVector);
  }

  dg::ATSolver solver(complex, params, dg::ATSolver::TakePatterns);
  if (self->Metric == METRIC_WORLD)
  {
    solver.SetMetric(&metric);
  }
  // When the field's own values are g (doubles, not scaled), the solver
  // reads the right-hand sides alpha g there instead of keeping a copy of g
  // (24 bytes per face; it checks that the values are the same).
  vtkDoubleArray* doubles = vtkDoubleArray::FastDownCast(field);
  if (scale == 1.0 && doubles)
  {
    const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
    solver.SetFieldSource(doubles->GetPointer(polyOffset * g.cols()), g.cols(), 1);
  }
  // g is not read after the solve: the solver takes it instead of a copy.
  const bool done = solver.Run(std::move(g), [self](double f) {
    self->UpdateProgress(0.1 + 0.85 * f);
    return !self->GetAbortExecute();
  });
  self->NumberOfIterations = solver.Statistics().Iterations;
  if (!done)
  {
    if (!solver.Error().empty())
    {
      vtkErrorWithObjectMacro(self, "Ambrosio-Tortorelli failed: " << solver.Error() << ".");
      return 0;
    }
    return this->Abort.Abort(outputVector);
  }
  if (!solver.Warnings().empty())
  {
    std::ostringstream s;
    s << solver.Statistics().FailedSolves
      << " linear solve(s) failed; first: " << solver.Warnings().front() << ".";
    vtkWarningWithObjectMacro(self, << s.str());
  }
  this->U = solver.U();
  this->V = solver.V();
  this->EdgeVertices = complex.EdgeVertices;
  this->Iterations = solver.Statistics().Iterations;
  self->NumberOfCGIterations = solver.Statistics().CGIterations;
  self->HaloFaceValues = self->HaloVertexValues = 0;
  this->Scale = scale;
  return 2;
}

void vtkAmbrosioTortorelliFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* solvers[] = {
    "ConjugateGradient", "SimplicialLDLT", "Cholmod", "ConjugateGradientIC"
  };
  os << indent << "Alpha: " << this->Alpha << "\n";
  os << indent << "Lambda: " << this->Lambda << "\n";
  os << indent << "EpsilonStart: " << this->EpsilonStart << "\n";
  os << indent << "EpsilonEnd: " << this->EpsilonEnd << "\n";
  os << indent << "EpsilonRatio: " << this->EpsilonRatio << "\n";
  os << indent << "MaximumIterations: " << this->MaximumIterations << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "FeatureThreshold: " << this->FeatureThreshold << "\n";
  os << indent << "NormalizeVectorField: " << (this->NormalizeVectorField ? "On" : "Off") << "\n";
  os << indent << "LinearSolver: " << solvers[this->LinearSolver] << "\n";
  os << indent << "SolverTolerance: " << this->SolverTolerance << "\n";
  os << indent << "SolverToleranceEarlyFactor: " << this->SolverToleranceEarlyFactor << "\n";
  os << indent << "Metric: " << (this->Metric == METRIC_WORLD ? "World" : "Grid") << "\n";
  os << indent << "FieldScaling: " << (this->FieldScaling == FIELD_SCALING_RANGE ? "Range" : "None")
     << "\n";
  os << indent << "FieldScale: " << this->FieldScale << "\n";
  os << indent << "NumberOfIterations: " << this->NumberOfIterations << "\n";
  os << indent << "NumberOfSolves: " << this->NumberOfSolves << "\n";
}
