#include "vtkDigitalSurfaceFilter.h"

#include "dgPipelineAbort.h"
#include "dgCubicalSurface.h"
#include "dgVoxelSelection.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>

vtkStandardNewMacro(vtkDigitalSurfaceFilter);

vtkDigitalSurfaceFilter::~vtkDigitalSurfaceFilter() = default;

vtkDigitalSurfaceFilter::vtkDigitalSurfaceFilter()
{
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkDigitalSurfaceFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

vtkMTimeType vtkDigitalSurfaceFilter::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkDigitalSurfaceFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro("Missing input image or output.");
    return 0;
  }
  const auto abortGuard = this->Abort->Begin(this, outputVector);
  if (dg::PipelineAbort::InputAborted(inputVector, this->GetNumberOfInputPorts()))
  {
    return this->Abort->Abort(outputVector);
  }
  int ext[6];
  input->GetExtent(ext);
  const int dims[3] = { ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1 };
  if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
  {
    vtkErrorMacro("Input image is empty (extent " << ext[0] << ".." << ext[1] << ", " << ext[2]
                                                  << ".." << ext[3] << ", " << ext[4] << ".."
                                                  << ext[5] << ").");
    return 0;
  }
  // A one-voxel-thick image would still bound a closed surface, but it is
  // almost always a 2D slice given by mistake: say so rather than guess.
  if (dims[0] == 1 || dims[1] == 1 || dims[2] == 1)
  {
    vtkErrorMacro("Input image is " << input->GetDataDimension()
                                    << "D; a digital surface needs a 3D image, at least 2 voxels along each axis (dimensions "
                                    << dims[0] << " x " << dims[1] << " x " << dims[2] << ").");
    return 0;
  }
  vtkDataArray* scalars = dg::SelectionArray(this->GetInputArrayToProcess(0, inputVector),
    this->GetInputArrayInformation(0), input);

  // 1. Selection mask.
  dg::PaddedMask mask;
  mask.Allocate(dims[0], dims[1], dims[2]);
  const dg::VoxelSelection select{ this->SelectionMode, this->LowerThreshold,
    this->UpperThreshold, this->Label, this->SelectedComponent };
  std::int64_t insideCount = 0;
  std::string error;
  if (!dg::SelectVoxels(scalars, dims, select, mask.Data.data(), mask.RowLength(), 1, insideCount, error))
  {
    vtkErrorMacro("Cannot select voxels: " << error << ".");
    return 0;
  }
  if (insideCount == 0)
  {
    vtkErrorMacro("No voxel matches the selection (mode "
      << this->SelectionMode << "): the surface is empty.");
    return 0;
  }
  if (insideCount == static_cast<std::int64_t>(dims[0]) * dims[1] * dims[2])
  {
    vtkWarningMacro("Every voxel is inside: the surface is the border of the image.");
  }
  mask.UpdateRowBounds();
  this->UpdateProgress(0.3);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }

  // 2. The cubical complex.
  dg::CubicalSurface surface;
  const bool done = dg::ExtractCubicalSurface(mask, surface, [this](double f) {
    this->UpdateProgress(0.3 + 0.6 * f);
    return !this->GetAbortExecute();
  });
  if (!done)
  {
    return this->Abort->Abort(outputVector);
  }
  mask = dg::PaddedMask(); // release the mask before the output is built

  // 3. World geometry. The index-to-physical matrix includes the image's
  // direction; a reflection flips the winding, so quads are then reversed.
  double origin[3], spacing[3];
  input->GetOrigin(origin);
  input->GetSpacing(spacing);
  double dir[9];
  {
    vtkMatrix3x3* d = input->GetDirectionMatrix();
    for (int a = 0; a < 9; ++a)
    {
      dir[a] = d->GetData()[a];
    }
  }
  const double det = vtkMatrix3x3::Determinant(dir);
  const bool reflect = det * spacing[0] * spacing[1] * spacing[2] < 0;

  const std::int64_t nPoints = surface.NumberOfPoints();
  const std::int64_t nSurfels = surface.NumberOfSurfels();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nPoints);
  auto* pts = vtkDoubleArray::SafeDownCast(points->GetData())->GetPointer(0);
  vtkSMPTools::For(0, nPoints, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t p = b; p < e; ++p)
    {
      double idx[3];
      for (int a = 0; a < 3; ++a)
      {
        idx[a] = spacing[a] * (ext[2 * a] + surface.Corners[3 * p + a] - 0.5);
      }
      for (int r = 0; r < 3; ++r)
      {
        pts[3 * p + r] = origin[r] + dir[3 * r] * idx[0] + dir[3 * r + 1] * idx[1] + dir[3 * r + 2] * idx[2];
      }
    }
  });

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(nSurfels + 1);
  connectivity->SetNumberOfValues(4 * nSurfels);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(nSurfels);
  vtkNew<vtkIntArray> voxels;
  voxels->SetName("InsideVoxel");
  voxels->SetNumberOfComponents(3);
  voxels->SetNumberOfTuples(nSurfels);
  vtkNew<vtkUnsignedCharArray> directions;
  directions->SetName("SurfelDirection");
  directions->SetNumberOfTuples(nSurfels);
  // Outward normal of each direction: sign(d) * (column d/2 of the direction
  // matrix), with the spacing's sign folded in.
  float dirNormals[6][3];
  for (int d = 0; d < 6; ++d)
  {
    const int axis = d / 2;
    const double sign = ((d & 1) ? 1.0 : -1.0) * (spacing[axis] < 0 ? -1.0 : 1.0);
    double n[3] = { sign * dir[axis], sign * dir[3 + axis], sign * dir[6 + axis] };
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 3; ++a)
    {
      dirNormals[d][a] = static_cast<float>(len > 0 ? n[a] / len : 0.0);
    }
  }
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  float* nrm = normals->GetPointer(0);
  int* vox = voxels->GetPointer(0);
  unsigned char* dirs = directions->GetPointer(0);
  vtkSMPTools::For(0, nSurfels, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t s = b; s < e; ++s)
    {
      off[s] = 4 * s;
      for (int c = 0; c < 4; ++c)
      {
        conn[4 * s + c] = surface.Quads[4 * s + (reflect ? 3 - c : c)];
      }
      const int d = surface.Directions[s];
      for (int a = 0; a < 3; ++a)
      {
        nrm[3 * s + a] = dirNormals[d][a];
        vox[3 * s + a] = surface.Voxels[3 * s + a] + ext[2 * a];
      }
      dirs[s] = static_cast<unsigned char>(d);
    }
  });
  off[nSurfels] = 4 * nSurfels;
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);

  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetCellData()->SetNormals(normals);
  output->GetCellData()->AddArray(voxels);
  output->GetCellData()->AddArray(directions);

  vtkNew<vtkIntArray> extArray;
  extArray->SetName("ImageExtent");
  extArray->SetNumberOfValues(6);
  for (int a = 0; a < 6; ++a)
  {
    extArray->SetValue(a, ext[a]);
  }
  vtkNew<vtkDoubleArray> originArray, spacingArray;
  originArray->SetName("ImageOrigin");
  spacingArray->SetName("ImageSpacing");
  originArray->SetNumberOfValues(3);
  spacingArray->SetNumberOfValues(3);
  for (int a = 0; a < 3; ++a)
  {
    originArray->SetValue(a, origin[a]);
    spacingArray->SetValue(a, spacing[a]);
  }
  output->GetFieldData()->AddArray(extArray);
  output->GetFieldData()->AddArray(originArray);
  output->GetFieldData()->AddArray(spacingArray);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkDigitalSurfaceFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* modes[] = { "NonZero", "Range", "Label" };
  os << indent << "SelectionMode: " << modes[this->SelectionMode] << "\n";
  os << indent << "LowerThreshold: " << this->LowerThreshold << "\n";
  os << indent << "UpperThreshold: " << this->UpperThreshold << "\n";
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "SelectedComponent: " << this->SelectedComponent << "\n";
}
