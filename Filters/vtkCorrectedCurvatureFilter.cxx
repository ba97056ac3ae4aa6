#include "vtkCorrectedCurvatureFilter.h"

#include "dgCorrectedCurvature.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMultiProcessController.h>
#include <vtkObjectFactory.h>
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
  if (vtkMultiProcessController* c = dg::PieceController(outputVector->GetInformationObject(0)))
  {
    if (c->GetLocalProcessId() == 0)
    {
      vtkErrorMacro("The corrected-curvature stage runs in one process only (its balls would "
                    "need the neighbouring pieces' faces); run it on the gathered surface.");
    }
    return 0;
  }
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
  if (!(this->Radius > 0) || !std::isfinite(this->Radius))
  {
    vtkErrorMacro("Invalid parameters: Radius must be a positive number (it is " << this->Radius
                                                                                << ").");
    return 0;
  }
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nFaces = polys ? polys->GetNumberOfCells() : 0;
  if (nFaces == 0)
  {
    vtkErrorMacro("The input has no polygons: the corrected-curvature filter works on a surface.");
    return 0;
  }

  // ParaView sends an empty name until it knows the input's arrays: that
  // means the default (the active normals, FeatureRegion).
  int association = -1;
  vtkDataArray* normals = this->GetInputArrayToProcess(0, input, association);
  if (!normals)
  {
    normals = input->GetCellData()->GetNormals();
    association = vtkDataObject::FIELD_ASSOCIATION_CELLS;
  }
  if (!normals)
  {
    vtkErrorMacro("No cell normal field: the input has no active cell normals (run "
                  "vtkSharpFeaturesFilter or another normal estimator first, or choose the "
                  "array with SetInputArrayToProcess).");
    return 0;
  }
  const char* normalsName = normals->GetName() ? normals->GetName() : "(unnamed)";
  if (association != vtkDataObject::FIELD_ASSOCIATION_CELLS || normals->GetNumberOfComponents() != 3)
  {
    vtkErrorMacro("The normal field '" << normalsName
                                       << "' must be cell data with 3 components.");
    return 0;
  }
  vtkDataArray* regions = nullptr;
  if (this->PerSide)
  {
    int regionAssociation = -1;
    regions = this->GetInputArrayToProcess(1, input, regionAssociation);
    if (!regions)
      regions = input->GetCellData()->GetArray("FeatureRegion");
    else if (regionAssociation != vtkDataObject::FIELD_ASSOCIATION_CELLS ||
      regions->GetNumberOfComponents() != 1)
    {
      vtkErrorMacro("The region array '" << (regions->GetName() ? regions->GetName() : "")
                                         << "' must be cell data with one component.");
      return 0;
    }
  }

  const vtkIdType nCells = input->GetNumberOfCells();
  const vtkIdType nPoints = input->GetNumberOfPoints();
  const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
  std::vector<double> u(3 * nFaces), xyz(3 * nPoints);
  std::vector<int> region;
  {
    const auto nt = vtk::DataArrayTupleRange<3>(normals);
    for (vtkIdType f = 0; f < nFaces; ++f)
      for (int c = 0; c < 3; ++c)
        u[3 * f + c] = static_cast<double>(nt[polyOffset + f][c]);
    for (vtkIdType p = 0; p < nPoints; ++p)
      input->GetPoint(p, &xyz[3 * p]);
    if (regions)
    {
      region.resize(nFaces);
      for (vtkIdType f = 0; f < nFaces; ++f)
        region[f] = static_cast<int>(regions->GetComponent(polyOffset + f, 0));
    }
  }
  for (vtkIdType f = 0; f < nFaces; ++f)
  {
    const double n = std::sqrt(u[3 * f] * u[3 * f] + u[3 * f + 1] * u[3 * f + 1] + u[3 * f + 2] * u[3 * f + 2]);
    if (!(std::abs(n - 1) < 1e-3))
    {
      vtkErrorMacro("The normal field '" << normalsName << "' is not made of unit vectors (face "
                                         << f << " has length " << n << ").");
      return 0;
    }
  }

  // Radius in world units: voxels are the smallest image spacing the
  // surface came from, or its mean edge length.
  std::vector<std::int64_t> offsets(nFaces + 1), connectivity(polys->GetNumberOfConnectivityIds());
  {
    const auto off = vtk::DataArrayValueRange<1>(polys->GetOffsetsArray());
    const auto conn = vtk::DataArrayValueRange<1>(polys->GetConnectivityArray());
    std::copy(off.begin(), off.end(), offsets.begin());
    std::copy(conn.begin(), conn.end(), connectivity.begin());
  }
  double voxel = 0;
  // vtkDigitalSurfaceFilter's "ImageSpacing": 3 values, one component.
  vtkDataArray* spacing = input->GetFieldData()->GetArray("ImageSpacing");
  if (spacing && spacing->GetNumberOfComponents() == 1 && spacing->GetNumberOfTuples() == 3)
  {
    voxel = std::min({ std::abs(spacing->GetComponent(0, 0)), std::abs(spacing->GetComponent(1, 0)),
      std::abs(spacing->GetComponent(2, 0)) });
    if (!(voxel > 0) || !std::isfinite(voxel))
      voxel = 0;
  }
  if (voxel == 0)
  {
    double sum = 0;
    for (vtkIdType f = 0; f < nFaces; ++f)
    {
      const std::int64_t m = offsets[f + 1] - offsets[f];
      for (std::int64_t i = 0; i < m; ++i)
      {
        const double* a = &xyz[3 * connectivity[offsets[f] + i]];
        const double* b = &xyz[3 * connectivity[offsets[f] + (i + 1) % m]];
        sum += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
          (a[2] - b[2]) * (a[2] - b[2]));
      }
    }
    voxel = connectivity.empty() ? 1.0 : sum / static_cast<double>(connectivity.size());
  }
  const double radius = this->RadiusUnits == VOXELS ? this->Radius * voxel : this->Radius;
  const double diagonal = input->GetLength();
  if (radius > diagonal)
  {
    vtkErrorMacro("Invalid parameters: the ball radius (" << radius
                                                          << " world units) is larger than the "
                                                             "surface (bounding box diagonal "
                                                          << diagonal << ").");
    return 0;
  }
  this->UpdateProgress(0.05);

  dg::CurvatureParameters par;
  par.Radius = radius;
  dg::CurvatureResult res;
  std::string error;
  if (!dg::ComputeCorrectedCurvatures(nPoints, xyz.data(), offsets, connectivity, u.data(),
        region.empty() ? nullptr : region.data(), par, res, &error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  if (this->GetAbortExecute())
  {
    return internal.Abort.Abort(outputVector);
  }
  this->UpdateProgress(0.9);
  this->UsedRadius = radius;
  this->Area = res.Area;
  this->Volume = res.Volume;
  this->IntegralMeanCurvature = res.TotalMean;
  this->IntegralGaussianCurvature = res.TotalGaussian;
  this->CreaseIntegralMeanCurvature = res.CreaseTotalMean;
  this->EulerCharacteristic = res.EulerCharacteristic;
  this->NumberOfCreaseEdges = static_cast<vtkIdType>(res.CreaseAngle.size());

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
    { "CorrectedK2Direction", 3, &res.D2 } };
  for (const Out& o : outs)
  {
    vtkDoubleArray* a = CellArray(o.Name, o.Components, nCells);
    a->Fill(0.0);
    for (vtkIdType f = 0; f < nFaces; ++f)
      for (int c = 0; c < o.Components; ++c)
        a->SetTypedComponent(polyOffset + f, c, (*o.Values)[o.Components * f + c]);
    output->GetCellData()->AddArray(a);
    a->Delete();
  }
  output->GetCellData()->SetActiveScalars("CorrectedMeanCurvature");

  vtkNew<vtkFieldData> fd;
  fd->ShallowCopy(input->GetFieldData());
  AddValue(fd, "CorrectedArea", res.Area);
  AddValue(fd, "EnclosedVolume", res.Volume);
  AddValue(fd, "SpecificSurfaceArea",
    std::isfinite(res.Volume) && res.Volume != 0 ? res.Area / std::abs(res.Volume) : std::nan(""));
  AddValue(fd, "IntegralMeanCurvature", res.TotalMean);
  AddValue(fd, "IntegralGaussianCurvature", res.TotalGaussian);
  AddValue(fd, "GaussBonnetCharacteristic", res.TotalGaussian / (2 * M_PI));
  AddValue(fd, "EulerCharacteristic", static_cast<double>(res.EulerCharacteristic));
  AddValue(fd, "CreaseIntegralMeanCurvature", res.CreaseTotalMean);
  AddValue(fd, "CurvatureRadius", radius);
  output->SetFieldData(fd);

  const vtkIdType nLines = static_cast<vtkIdType>(res.CreaseAngle.size());
  vtkNew<vtkIdTypeArray> lineOffsets, lineConn;
  lineOffsets->SetNumberOfValues(nLines + 1);
  lineConn->SetNumberOfValues(2 * nLines);
  vtkNew<vtkDoubleArray> angle;
  angle->SetName("CreaseAngle");
  angle->SetNumberOfValues(nLines);
  for (vtkIdType l = 0; l < nLines; ++l)
  {
    lineOffsets->SetValue(l, 2 * l);
    lineConn->SetValue(2 * l, res.CreaseEdges[2 * l]);
    lineConn->SetValue(2 * l + 1, res.CreaseEdges[2 * l + 1]);
    angle->SetValue(l, res.CreaseAngle[l] * 180.0 / M_PI);
  }
  lineOffsets->SetValue(nLines, 2 * nLines);
  vtkNew<vtkCellArray> ca;
  ca->SetData(lineOffsets, lineConn);
  lines->SetPoints(input->GetPoints());
  lines->SetLines(ca);
  lines->GetCellData()->AddArray(angle);
  lines->GetCellData()->SetActiveScalars("CreaseAngle");
  this->UpdateProgress(1.0);
  return 1;
}

void vtkCorrectedCurvatureFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Radius: " << this->Radius << "\n";
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
