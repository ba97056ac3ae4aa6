#include "vtkAmbrosioTortorelliFilter.h"

#include "dgATOperators.h"
#include "dgATSolver.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <atomic>
#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkAmbrosioTortorelliFilter);

vtkAmbrosioTortorelliFilter::vtkAmbrosioTortorelliFilter()
{
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, vtkDataSetAttributes::NORMALS);
}

int vtkAmbrosioTortorelliFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

int vtkAmbrosioTortorelliFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* features = vtkPolyData::GetData(outputVector, 1);
  this->NumberOfIterations = 0;
  if (!input || !output || !features)
  {
    vtkErrorMacro("Missing input or output.");
    return 0;
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
  std::string problem = params.Check();
  if (!(this->FeatureThreshold > 0 && this->FeatureThreshold < 1))
  {
    problem += (problem.empty() ? "" : " ") + std::string("FeatureThreshold must be in (0, 1) (got ") +
      std::to_string(this->FeatureThreshold) + ").";
  }
  if (!problem.empty())
  {
    vtkErrorMacro("Invalid parameters: " << problem);
    return 0;
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
    vtkErrorMacro("No field to regularise: the input has no cell array matching the selection "
                  "(default: the active cell normals). Use SetInputArrayToProcess.");
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
    vtkErrorMacro("The field has " << field->GetNumberOfTuples() << " tuples for " << nCells
                                   << " cells.");
    return 0;
  }
  const int nc = field->GetNumberOfComponents();
  const bool normalize = this->NormalizeVectorField && nc == 3;

  // Plain buffers for the core.
  std::vector<std::int64_t> offsets(nFaces + 1), connectivity(polys->GetNumberOfConnectivityIds());
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
  Eigen::MatrixXd g(nFaces, nc);
  std::atomic<vtkIdType> badValue(-1), zeroVector(-1);
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
        if (normalize && n2 == 0)
        {
          zeroVector = polyOffset + f;
        }
      }
    });
  }
  const char* fieldName = field->GetName() ? field->GetName() : "(unnamed)";
  if (badValue >= 0)
  {
    vtkErrorMacro("The field '" << fieldName << "' has a NaN or infinite value (e.g. cell "
                                << badValue.load() << ").");
    return 0;
  }
  if (zeroVector >= 0)
  {
    vtkErrorMacro("The field '"
      << fieldName << "' has a zero vector (e.g. cell " << zeroVector.load()
      << "): it cannot be a normal. Turn NormalizeVectorField off to regularise it as it is.");
    return 0;
  }
  this->UpdateProgress(0.02);

  dg::ATComplex complex;
  std::string error;
  if (!complex.Build(input->GetNumberOfPoints(), offsets, connectivity, &error))
  {
    vtkErrorMacro("Cannot build the complex: " << error << ".");
    return 0;
  }
  offsets = std::vector<std::int64_t>();
  connectivity = std::vector<std::int64_t>();
  // Two polygons of opposite winding across an edge make B compare u1 + u2
  // instead of u1 - u2: the jump term is then meaningless there. Still
  // compute (the rest of the surface is fine), but say so.
  std::int64_t inconsistent = 0;
  for (std::int64_t e = 0; e < complex.NumberOfEdges(); ++e)
  {
    const std::int64_t b = complex.EdgeFacePtr[e];
    if (complex.EdgeFacePtr[e + 1] - b == 2 &&
      complex.EdgeFaceSigns[b] == complex.EdgeFaceSigns[b + 1])
    {
      ++inconsistent;
    }
  }
  if (inconsistent > 0)
  {
    vtkWarningMacro(<< inconsistent
                    << " edges join two polygons of opposite winding: the surface is not "
                       "consistently oriented and the result is unreliable near them (orient it "
                       "first, e.g. vtkPolyDataNormals with ConsistencyOn).");
  }
  this->UpdateProgress(0.1);
  if (this->GetAbortExecute())
  {
    return 0;
  }

  params.Normalize = normalize;
  dg::ATSolver solver(complex, params);
  const bool done = solver.Run(g, [this](double f) {
    this->UpdateProgress(0.1 + 0.85 * f);
    return !this->GetAbortExecute();
  });
  this->NumberOfIterations = solver.Statistics().Iterations;
  if (!done)
  {
    if (!solver.Error().empty())
    {
      vtkErrorMacro("Ambrosio-Tortorelli failed: " << solver.Error() << ".");
    }
    return 0;
  }
  if (!solver.Warnings().empty())
  {
    std::ostringstream s;
    s << solver.Statistics().FailedSolves << " linear solve(s) failed; first: "
      << solver.Warnings().front() << ".";
    vtkWarningMacro(<< s.str());
  }

  // Port 0: the surface with u and v.
  output->ShallowCopy(input);
  vtkNew<vtkDoubleArray> uArray;
  uArray->SetName(nc == 3 ? "ATNormals" : (std::string(fieldName) + "_AT").c_str());
  uArray->SetNumberOfComponents(nc);
  uArray->SetNumberOfTuples(nCells);
  {
    double* out = uArray->GetPointer(0);
    const Eigen::MatrixXd& u = solver.U();
    const auto tuples = vtk::DataArrayTupleRange(field);
    vtkSMPTools::For(0, nCells, [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType cell = b; cell < e; ++cell)
      {
        const vtkIdType f = cell - polyOffset;
        const bool isPoly = f >= 0 && f < nFaces;
        for (int c = 0; c < nc; ++c)
        {
          out[cell * nc + c] = isPoly ? u(f, c) : static_cast<double>(tuples[cell][c]);
        }
      }
    });
  }
  // AddArray then SetActiveNormals: SetNormals would drop the input normals
  // (the previous active array), which users want to compare with.
  output->GetCellData()->AddArray(uArray);
  if (nc == 3)
  {
    output->GetCellData()->SetActiveNormals("ATNormals");
  }
  const Eigen::VectorXd& v = solver.V();
  vtkNew<vtkDoubleArray> vArray;
  vArray->SetName("ATFeatureIndicator");
  vArray->SetNumberOfTuples(v.size());
  std::copy(v.data(), v.data() + v.size(), vArray->GetPointer(0));
  output->GetPointData()->AddArray(vArray);

  // Port 1: feature edges, in the complex's (deterministic) edge order.
  const double th = this->FeatureThreshold;
  std::vector<vtkIdType> selected;
  for (std::int64_t e = 0; e < complex.NumberOfEdges(); ++e)
  {
    if (v[complex.EdgeVertices[2 * e]] < th && v[complex.EdgeVertices[2 * e + 1]] < th)
    {
      selected.push_back(static_cast<vtkIdType>(e));
    }
  }
  const vtkIdType nLines = static_cast<vtkIdType>(selected.size());
  vtkNew<vtkIdTypeArray> lineOffsets, lineConn;
  lineOffsets->SetNumberOfValues(nLines + 1);
  lineConn->SetNumberOfValues(2 * nLines);
  vtkNew<vtkDoubleArray> lineV;
  lineV->SetName("ATFeatureIndicator");
  lineV->SetNumberOfTuples(nLines);
  for (vtkIdType l = 0; l < nLines; ++l)
  {
    const int a = complex.EdgeVertices[2 * selected[l]], b = complex.EdgeVertices[2 * selected[l] + 1];
    lineOffsets->SetValue(l, 2 * l);
    lineConn->SetValue(2 * l, a);
    lineConn->SetValue(2 * l + 1, b);
    lineV->SetValue(l, std::max(v[a], v[b]));
  }
  lineOffsets->SetValue(nLines, 2 * nLines);
  vtkNew<vtkCellArray> lines;
  lines->SetData(lineOffsets, lineConn);
  features->SetPoints(input->GetPoints());
  features->SetLines(lines);
  features->GetCellData()->AddArray(lineV);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkAmbrosioTortorelliFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* solvers[] = { "ConjugateGradient", "SimplicialLDLT", "Cholmod",
    "ConjugateGradientIC" };
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
  os << indent << "NumberOfIterations: " << this->NumberOfIterations << "\n";
}
