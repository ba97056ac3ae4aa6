#include "vtkSharpFeaturesFilter.h"

#include "dgLineCells.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"
#include "dgSharpFeatures.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkMultiProcessController.h>
#include <vtkDoubleArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <cmath>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSharpFeaturesFilter);

struct vtkSharpFeaturesFilter::Internals
{
  dg::PipelineAbort Abort;
};

vtkSharpFeaturesFilter::vtkSharpFeaturesFilter()
  : Internal(new Internals)
{
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "ATNormals");
  this->SetInputArrayToProcess(
    1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, "ATFeatureIndicator");
}

vtkSharpFeaturesFilter::~vtkSharpFeaturesFilter() = default;

vtkMTimeType vtkSharpFeaturesFilter::GetMTime()
{
  return this->Internal->Abort.MTime(this->Superclass::GetMTime());
}

int vtkSharpFeaturesFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}


int vtkSharpFeaturesFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiProcessController* controller = dg::PieceController(outputVector->GetInformationObject(0));
  Internals& internal = *this->Internal;
  const auto abortGuard = internal.Abort.Begin(this, outputVector);
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  vtkPolyData* lines = vtkPolyData::GetData(outputVector, 1);
  this->NumberOfBandFaces = this->NumberOfUnassignedFaces = 0;
  this->NumberOfRegions = 0;
  this->ExchangedBytes = 0;
  this->ExchangedMessages = 0;
  this->NumberOfPlanarRegions = 0;
  this->NumberOfQuadricRegions = 0;
  this->NumberOfQuadricMerges = 0;
  if (!input || !output || !lines)
  {
    vtkErrorMacro("Missing input or output.");
    return 0;
  }
  if (dg::PipelineAbort::InputAborted(inputVector, 1))
  {
    return internal.Abort.Abort(outputVector);
  }
  if (controller)
    return this->RequestDataPieces(controller, input, output, lines);
  const int done = this->Execute(input, output, lines);
  return done < 0 ? internal.Abort.Abort(outputVector) : done;
}

int vtkSharpFeaturesFilter::Execute(vtkPolyData* input, vtkPolyData* output, vtkPolyData* lines)
{
  dg::SharpFeatureParameters par;
  par.FeatureThreshold = this->FeatureThreshold;
  par.MinimumRegionSize = this->MinimumRegionSize;
  par.SearchDepth = this->SearchDepth;
  par.NormalSmoothingDepth = this->NormalSmoothingDepth;
  par.SmoothingPasses = this->SmoothingPasses;
  par.SmoothingDepth = this->SmoothingDepth;
  par.FitPlanes = this->FitPlanes;
  par.CurvedSides = this->CurvedSides;
  par.FitResidual = this->FitResidual;
  par.ReferenceWeight = this->ReferenceWeight;
  par.MinimumFeatureAngle = this->MinimumFeatureAngle;
  par.StrongFeatureAngle = this->StrongFeatureAngle;
  par.PlanarRegionAngle = this->PlanarRegionAngle;
  par.QuadricSides = this->QuadricSides;
  par.QuadricMergeFactor = this->QuadricMergeFactor;
  par.QuadricMergeDistance = this->QuadricMergeDistance;
  par.RegionEdgeAngle = this->RegionEdgeAngle;
  par.InputRadius = this->InputRadius;
  par.CornerDepth = this->CornerDepth;
  par.MinimumTurnShare = this->MinimumTurnShare;
  par.FieldWidth = this->FieldWidth;
  par.UndoInputBlur = this->UndoInputBlur;
  std::string problem;
  if (!(par.FeatureThreshold > 0 && par.FeatureThreshold < 1))
    problem += " FeatureThreshold must be in (0, 1).";
  if (par.MinimumRegionSize < 1)
    problem += " MinimumRegionSize must be >= 1.";
  if (par.SearchDepth < 0)
    problem += " SearchDepth must be >= 0.";
  if (par.NormalSmoothingDepth < 0)
    problem += " NormalSmoothingDepth must be >= 0.";
  if (par.SmoothingPasses < 0 || par.SmoothingDepth < 1)
    problem += " SmoothingPasses must be >= 0 and SmoothingDepth >= 1.";
  if (!(par.MinimumFeatureAngle >= 0 && par.MinimumFeatureAngle <= 180))
    problem += " MinimumFeatureAngle must be in [0, 180].";
  if (!(par.StrongFeatureAngle >= 0 && par.StrongFeatureAngle <= 180))
    problem += " StrongFeatureAngle must be in [0, 180].";
  if (!(par.PlanarRegionAngle >= 0 && par.PlanarRegionAngle <= 90))
    problem += " PlanarRegionAngle must be in [0, 90].";
  if (!(par.QuadricMergeFactor >= 0))
    problem += " QuadricMergeFactor must be >= 0.";
  if (!(par.QuadricMergeDistance >= 0))
    problem += " QuadricMergeDistance must be >= 0.";
  if (!(par.FitResidual >= 0))
    problem += " FitResidual must be >= 0.";
  if (!(par.ReferenceWeight > 0 && par.ReferenceWeight <= 1))
    problem += " ReferenceWeight must be in (0, 1].";
  if (!(par.RegionEdgeAngle > 0 && par.RegionEdgeAngle <= 180))
    problem += " RegionEdgeAngle must be in (0, 180].";
  if (!(par.InputRadius > 0 && par.InputRadius <= 1000))
    problem += " InputRadius must be in (0, 1000].";
  if (!(par.CornerDepth > 0))
    problem += " CornerDepth must be > 0.";
  if (!(par.MinimumTurnShare >= 0 && par.MinimumTurnShare <= 1))
    problem += " MinimumTurnShare must be in [0, 1].";
  if (!(par.FieldWidth <= 20))
    problem += " FieldWidth must be at most 20 edge lengths (negative: no field).";
  if (!problem.empty())
  {
    vtkErrorMacro("Invalid parameters:" << problem);
    return 0;
  }
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nFaces = polys ? polys->GetNumberOfCells() : 0;
  if (nFaces == 0)
  {
    vtkErrorMacro("The input has no polygons: the sharp-features filter works on a surface.");
    return 0;
  }
  // ParaView sends an empty name until it knows the input's arrays: that
  // means the default array.
  auto selectedArray = [&](int idx, const char* fallback, int wantedAssociation) -> vtkDataArray*
  {
    int association = -1;
    vtkDataArray* a = this->GetInputArrayToProcess(idx, input, association);
    vtkInformation* info = this->GetInputArrayInformation(idx);
    const char* name = info && info->Has(vtkDataObject::FIELD_NAME())
      ? info->Get(vtkDataObject::FIELD_NAME())
      : nullptr;
    if (!a && name && !*name)
    {
      a = wantedAssociation == vtkDataObject::FIELD_ASSOCIATION_CELLS
        ? input->GetCellData()->GetArray(fallback)
        : input->GetPointData()->GetArray(fallback);
      association = wantedAssociation;
    }
    const char* what = idx == 0 ? "cell normal field" : "point feature indicator";
    if (!a)
    {
      problem = std::string("No ") + what + ": the input has no array named '" +
        (name && *name ? name : fallback) +
        "' (run vtkAmbrosioTortorelliFilter first, or choose the arrays with "
        "SetInputArrayToProcess).";
      return nullptr;
    }
    if (association != wantedAssociation)
    {
      problem = std::string("The ") + what + " '" + (a->GetName() ? a->GetName() : "") +
        "' must be " + (idx == 0 ? "cell" : "point") + " data.";
      return nullptr;
    }
    const int nc = idx == 0 ? 3 : 1;
    if (a->GetNumberOfComponents() != nc)
    {
      problem = std::string("The ") + what + " '" + (a->GetName() ? a->GetName() : "") +
        "' must have " + std::to_string(nc) + " component" + (nc > 1 ? "s" : "") + ".";
      return nullptr;
    }
    return a;
  };
  vtkDataArray* normals = selectedArray(0, "ATNormals", vtkDataObject::FIELD_ASSOCIATION_CELLS);
  vtkDataArray* indicator = normals
    ? selectedArray(1, "ATFeatureIndicator", vtkDataObject::FIELD_ASSOCIATION_POINTS)
    : nullptr;
  if (!normals || !indicator)
  {
    vtkErrorMacro(<< problem);
    return 0;
  }
  const vtkIdType nCells = input->GetNumberOfCells();
  const vtkIdType nPoints = input->GetNumberOfPoints();
  const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
  std::vector<double> g(3 * nFaces), v(nPoints), xyz(3 * nPoints);
  {
    const auto nt = vtk::DataArrayTupleRange<3>(normals);
    for (vtkIdType f = 0; f < nFaces; ++f)
      for (int c = 0; c < 3; ++c)
        g[3 * f + c] = static_cast<double>(nt[polyOffset + f][c]);
    const auto vr = vtk::DataArrayValueRange<1>(indicator);
    std::copy(vr.begin(), vr.end(), v.begin());
    for (vtkIdType p = 0; p < nPoints; ++p)
      input->GetPoint(p, &xyz[3 * p]);
  }
  for (double x : g)
    if (!std::isfinite(x))
    {
      vtkErrorMacro("The normal field '" << normals->GetName() << "' has NaN or infinite values.");
      return 0;
    }
  for (double x : v)
    if (std::isnan(x))
    {
      vtkErrorMacro("The feature indicator '" << indicator->GetName() << "' has NaN values.");
      return 0;
    }
  // The input estimator's normals (AT's own input): the crease test reads
  // them beyond their blur, and where the stage finds no crease the output
  // field follows them (docs/sharp-features.md, steps 7 and 10).
  std::vector<double> inputField;
  {
    vtkDataArray* in = nullptr;
    if (!this->InputNormalsName.empty())
    {
      in = input->GetCellData()->GetArray(this->InputNormalsName.c_str());
      if (!in)
      {
        vtkErrorMacro("No input normal field: the input has no cell array named '"
          << this->InputNormalsName << "' (InputNormalsName).");
        return 0;
      }
    }
    for (const char* name : { "IINormals", "VCMNormals", "RHTNormals" })
      if (!in)
        in = input->GetCellData()->GetArray(name);
    if (in && in->GetNumberOfComponents() != 3)
    {
      vtkErrorMacro("The input normal field '" << (in->GetName() ? in->GetName() : "")
                                                << "' must have 3 components.");
      return 0;
    }
    if (in)
    {
      inputField.resize(3 * nFaces);
      const auto nt = vtk::DataArrayTupleRange<3>(in);
      for (vtkIdType f = 0; f < nFaces; ++f)
        for (int c = 0; c < 3; ++c)
        {
          inputField[3 * f + c] = static_cast<double>(nt[polyOffset + f][c]);
          if (!std::isfinite(inputField[3 * f + c]))
          {
            vtkErrorMacro("The input normal field '" << in->GetName() << "' has NaN or infinite values.");
            return 0;
          }
        }
    }
    else
    {
      vtkWarningMacro("No input normal field (IINormals, VCMNormals or RHTNormals; "
                      "InputNormalsName): the crease test reads the regularised normals and "
                      "the output field is not solved.");
    }
  }
  std::vector<std::int64_t> offsets(nFaces + 1), connectivity(polys->GetNumberOfConnectivityIds());
  {
    const auto off = vtk::DataArrayValueRange<1>(polys->GetOffsetsArray());
    const auto conn = vtk::DataArrayValueRange<1>(polys->GetConnectivityArray());
    std::copy(off.begin(), off.end(), offsets.begin());
    std::copy(conn.begin(), conn.end(), connectivity.begin());
  }
  this->UpdateProgress(0.05);

  dg::SharpFeatureResult res;
  std::string error;
  const bool ok = dg::ComputeSharpFeatures(nPoints, xyz.data(), offsets, connectivity, g.data(),
    v.data(), inputField.empty() ? nullptr : inputField.data(), par, res, &error, [this](double f) {
      this->UpdateProgress(0.05 + 0.9 * f);
      return !this->GetAbortExecute();
    });
  if (!ok)
  {
    if (error.empty())
      return -1; // aborted
    vtkErrorMacro(<< error);
    return 0;
  }
  this->NumberOfBandFaces = res.NumberOfBandFaces;
  this->NumberOfUnassignedFaces = res.NumberOfUnassignedFaces;
  this->NumberOfRegions = res.NumberOfRegions;
  this->NumberOfPlanarRegions = res.NumberOfPlanarRegions;
  this->NumberOfQuadricRegions = res.NumberOfQuadricRegions;
  this->NumberOfQuadricMerges = res.NumberOfQuadricMerges;
  this->NumberOfCreases = res.NumberOfCreases;
  this->NumberOfBends = res.NumberOfBends;
  this->NoiseShare = res.NoiseShare;
  this->UsedFieldWidth = res.FieldWidth;
  this->CreaseTestTime = res.CreaseTestSeconds;
  this->FieldTime = res.FieldSeconds;

  output->ShallowCopy(input);
  vtkNew<vtkDoubleArray> sharp;
  sharp->SetName("SharpNormals");
  sharp->SetNumberOfComponents(3);
  sharp->SetNumberOfTuples(nCells);
  vtkNew<vtkIntArray> region;
  region->SetName("FeatureRegion");
  region->SetNumberOfTuples(nCells);
  vtkNew<vtkUnsignedCharArray> sides;
  sides->SetName("CreaseSides");
  sides->SetNumberOfTuples(nCells);
  {
    const auto nt = vtk::DataArrayTupleRange<3>(normals);
    for (vtkIdType cell = 0; cell < nCells; ++cell)
    {
      const vtkIdType f = cell - polyOffset;
      const bool poly = f >= 0 && f < nFaces;
      for (int c = 0; c < 3; ++c)
        sharp->SetComponent(cell, c, poly ? res.Normals[3 * f + c] : static_cast<double>(nt[cell][c]));
      region->SetValue(cell, poly ? res.Region[f] : -1);
      sides->SetValue(cell, poly && res.CreaseSides.size() == static_cast<std::size_t>(nFaces)
          ? res.CreaseSides[f] : 0);
    }
  }
  // AddArray then SetActiveNormals keeps the input normals for comparison.
  output->GetCellData()->AddArray(sharp);
  output->GetCellData()->SetActiveNormals("SharpNormals");
  output->GetCellData()->AddArray(region);
  output->GetCellData()->AddArray(sides);

  std::vector<vtkIdType> ends;
  ends.reserve(2 * res.FeatureEdges.size());
  for (const auto& e : res.FeatureEdges)
    ends.insert(ends.end(), { static_cast<vtkIdType>(e[0]), static_cast<vtkIdType>(e[1]) });
  lines->SetPoints(input->GetPoints());
  lines->SetLines(dg::TwoPointLines(ends));
  lines->GetCellData()->AddArray(dg::LineValues("FeatureAngle", res.FeatureAngle));
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSharpFeaturesFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FeatureThreshold: " << this->FeatureThreshold << "\n";
  os << indent << "MinimumRegionSize: " << this->MinimumRegionSize << "\n";
  os << indent << "SearchDepth: " << this->SearchDepth << "\n";
  os << indent << "SmoothingPasses: " << this->SmoothingPasses << "\n";
  os << indent << "SmoothingDepth: " << this->SmoothingDepth << "\n";
  os << indent << "NormalSmoothingDepth: " << this->NormalSmoothingDepth << "\n";
  os << indent << "FitPlanes: " << (this->FitPlanes ? "On" : "Off") << "\n";
  os << indent << "CurvedSides: " << (this->CurvedSides ? "On" : "Off") << "\n";
  os << indent << "FitResidual: " << this->FitResidual << "\n";
  os << indent << "ReferenceWeight: " << this->ReferenceWeight << "\n";
  os << indent << "MinimumFeatureAngle: " << this->MinimumFeatureAngle << "\n";
  os << indent << "StrongFeatureAngle: " << this->StrongFeatureAngle << "\n";
  os << indent << "PlanarRegionAngle: " << this->PlanarRegionAngle << "\n";
  os << indent << "NumberOfPlanarRegions: " << this->NumberOfPlanarRegions << "\n";
  os << indent << "QuadricSides: " << (this->QuadricSides ? "On" : "Off") << "\n";
  os << indent << "NumberOfQuadricRegions: " << this->NumberOfQuadricRegions << "\n";
  os << indent << "QuadricMergeFactor: " << this->QuadricMergeFactor << "\n";
  os << indent << "QuadricMergeDistance: " << this->QuadricMergeDistance << "\n";
  os << indent << "NumberOfQuadricMerges: " << this->NumberOfQuadricMerges << "\n";
  os << indent << "RegionEdgeAngle: " << this->RegionEdgeAngle << "\n";
  os << indent << "InputNormalsName: " << (this->InputNormalsName.empty() ? "(automatic)" : this->InputNormalsName) << "\n";
  os << indent << "InputRadius: " << this->InputRadius << "\n";
  os << indent << "CornerDepth: " << this->CornerDepth << "\n";
  os << indent << "MinimumTurnShare: " << this->MinimumTurnShare << "\n";
  os << indent << "FieldWidth: " << this->FieldWidth << "\n";
  os << indent << "UndoInputBlur: " << (this->UndoInputBlur ? "on" : "off") << "\n";
  os << indent << "NumberOfCreases: " << this->NumberOfCreases << "\n";
  os << indent << "NumberOfBends: " << this->NumberOfBends << "\n";
  os << indent << "NoiseShare: " << this->NoiseShare << "\n";
  os << indent << "CreaseTestTime: " << this->CreaseTestTime << "\n";
  os << indent << "FieldTime: " << this->FieldTime << "\n";
  os << indent << "ExchangedBytes: " << this->ExchangedBytes << "\n";
  os << indent << "ExchangedMessages: " << this->ExchangedMessages << "\n";
  os << indent << "UsedFieldWidth: " << this->UsedFieldWidth << "\n";
  os << indent << "NumberOfBandFaces: " << this->NumberOfBandFaces << "\n";
  os << indent << "NumberOfUnassignedFaces: " << this->NumberOfUnassignedFaces << "\n";
  os << indent << "NumberOfRegions: " << this->NumberOfRegions << "\n";
}
