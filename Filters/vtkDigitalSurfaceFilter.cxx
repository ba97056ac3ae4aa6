#include "vtkDigitalSurfaceFilter.h"

#include "dgCubicalSurface.h"

#include <vtkArrayDispatch.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArrayRange.h>
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

#include <atomic>
#include <cmath>

vtkStandardNewMacro(vtkDigitalSurfaceFilter);

namespace
{

struct Selection
{
  int Mode;
  double Lower, Upper, Label;
  bool operator()(double v) const
  {
    switch (this->Mode)
    {
      case vtkDigitalSurfaceFilter::RANGE:
        return v >= this->Lower && v <= this->Upper;
      case vtkDigitalSurfaceFilter::LABEL:
        return v == this->Label;
      default:
        return v != 0.0;
    }
  }
};

// Fills the padded mask from any numeric array, one row per task.
struct MaskWorker
{
  template <typename ArrayT>
  void operator()(ArrayT* array, dg::PaddedMask& mask, int component, const Selection& select,
    std::atomic<bool>& sawNaN, std::atomic<std::int64_t>& insideCount) const
  {
    const auto values = vtk::DataArrayValueRange(array);
    const int nc = array->GetNumberOfComponents();
    const int nx = mask.Dims[0], ny = mask.Dims[1];
    const std::int64_t rows = static_cast<std::int64_t>(ny) * mask.Dims[2];
    vtkSMPTools::For(0, rows, [&](std::int64_t begin, std::int64_t end) {
      std::int64_t count = 0;
      bool nan = false;
      for (std::int64_t r = begin; r < end; ++r)
      {
        std::uint8_t* out = mask.Data.data() + r * mask.RowLength() + 1;
        const std::int64_t base = r * nx;
        for (int i = 0; i < nx; ++i)
        {
          const double v = static_cast<double>(values[(base + i) * nc + component]);
          nan |= std::isnan(v);
          const bool in = select(v);
          out[i] = in;
          count += in;
        }
      }
      insideCount += count;
      if (nan)
      {
        sawNaN = true;
      }
    });
  }
};

} // namespace

vtkDigitalSurfaceFilter::vtkDigitalSurfaceFilter()
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkDigitalSurfaceFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
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
  vtkDataArray* scalars = this->GetInputArrayToProcess(0, inputVector);
  if (!scalars)
  {
    vtkErrorMacro("Input image has no point scalars to select voxels from (set the active "
                  "scalars or call SetInputArrayToProcess).");
    return 0;
  }
  const std::int64_t nVoxels = static_cast<std::int64_t>(dims[0]) * dims[1] * dims[2];
  if (scalars->GetNumberOfTuples() != nVoxels)
  {
    vtkErrorMacro("Array '" << (scalars->GetName() ? scalars->GetName() : "(unnamed)") << "' has "
                            << scalars->GetNumberOfTuples() << " tuples, the image has " << nVoxels
                            << " points: only point data can select voxels.");
    return 0;
  }
  const int nc = scalars->GetNumberOfComponents();
  int component = this->SelectedComponent;
  if (component < 0)
  {
    if (nc != 1)
    {
      vtkErrorMacro("Array '" << (scalars->GetName() ? scalars->GetName() : "(unnamed)")
                              << "' has " << nc
                              << " components: choose one with SetSelectedComponent.");
      return 0;
    }
    component = 0;
  }
  if (component >= nc)
  {
    vtkErrorMacro("SelectedComponent " << component << " is out of range (the array has " << nc
                                       << " components).");
    return 0;
  }
  if (this->SelectionMode == RANGE && !(this->LowerThreshold <= this->UpperThreshold))
  {
    vtkErrorMacro("Empty threshold range [" << this->LowerThreshold << ", "
                                            << this->UpperThreshold << "].");
    return 0;
  }

  // 1. Selection mask.
  dg::PaddedMask mask;
  mask.Allocate(dims[0], dims[1], dims[2]);
  const Selection select{ this->SelectionMode, this->LowerThreshold, this->UpperThreshold,
    this->Label };
  std::atomic<bool> sawNaN(false);
  std::atomic<std::int64_t> insideCount(0);
  MaskWorker worker;
  if (!vtkArrayDispatch::Dispatch::Execute(
        scalars, worker, mask, component, select, sawNaN, insideCount))
  {
    worker(scalars, mask, component, select, sawNaN, insideCount);
  }
  if (sawNaN)
  {
    vtkErrorMacro("Array '" << (scalars->GetName() ? scalars->GetName() : "(unnamed)")
                            << "' holds NaN values: the selection of inside voxels is undefined.");
    return 0;
  }
  if (insideCount == 0)
  {
    vtkErrorMacro("No voxel matches the selection (mode "
      << this->SelectionMode << "): the surface is empty.");
    return 0;
  }
  mask.UpdateRowBounds();
  this->UpdateProgress(0.3);
  if (this->GetAbortExecute())
  {
    return 0;
  }

  // 2. The cubical complex.
  dg::CubicalSurface surface;
  const bool done = dg::ExtractCubicalSurface(mask, surface, [this](double f) {
    this->UpdateProgress(0.3 + 0.6 * f);
    return !this->GetAbortExecute();
  });
  if (!done)
  {
    return 0;
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
