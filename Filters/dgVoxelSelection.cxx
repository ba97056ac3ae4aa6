#include "dgVoxelSelection.h"

#include <vtkArrayDispatch.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkInformation.h>
#include <vtkPointData.h>
#include <vtkDataArrayRange.h>
#include <vtkSMPTools.h>

#include <atomic>
#include <cmath>
#include <sstream>

namespace dg
{
namespace
{
struct SelectWorker
{
  template <typename ArrayT>
  void operator()(ArrayT* array, const int* dims, const VoxelSelection& select, int component,
    std::uint8_t* dst, std::int64_t rowStride, int rowOffset, std::atomic<bool>& sawNaN,
    std::atomic<std::int64_t>& insideCount) const
  {
    const auto values = vtk::DataArrayValueRange(array);
    const int nc = array->GetNumberOfComponents();
    const int nx = dims[0];
    const std::int64_t rows = static_cast<std::int64_t>(dims[1]) * dims[2];
    vtkSMPTools::For(0, rows, [&](std::int64_t begin, std::int64_t end) {
      std::int64_t count = 0;
      bool nan = false;
      for (std::int64_t r = begin; r < end; ++r)
      {
        std::uint8_t* out = dst + r * rowStride + rowOffset;
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

std::string NameOf(vtkDataArray* a)
{
  return a->GetName() ? std::string("'") + a->GetName() + "'" : std::string("(unnamed)");
}
} // namespace

vtkDataArray* SelectionArray(vtkDataArray* chosen, vtkInformation* arrayInfo, vtkDataSet* input)
{
  const char* name = arrayInfo && arrayInfo->Has(vtkDataObject::FIELD_NAME())
    ? arrayInfo->Get(vtkDataObject::FIELD_NAME())
    : nullptr;
  if (!chosen && name && !*name && input)
  {
    return input->GetPointData()->GetScalars();
  }
  return chosen;
}

bool SelectVoxels(vtkDataArray* scalars, const int dims[3], const VoxelSelection& selection,
  std::uint8_t* dst, std::int64_t rowStride, int rowOffset, std::int64_t& insideCount,
  std::string& error)
{
  std::ostringstream msg;
  insideCount = 0;
  if (!scalars)
  {
    error = "the image has no point scalars to select voxels from (set the active scalars or "
            "choose an array)";
    return false;
  }
  const std::int64_t nVoxels = static_cast<std::int64_t>(dims[0]) * dims[1] * dims[2];
  if (scalars->GetNumberOfTuples() != nVoxels)
  {
    msg << "array " << NameOf(scalars) << " has " << scalars->GetNumberOfTuples()
        << " tuples, the image has " << nVoxels << " points: only point data selects voxels";
    error = msg.str();
    return false;
  }
  const int nc = scalars->GetNumberOfComponents();
  int component = selection.Component;
  if (component < 0)
  {
    if (nc != 1)
    {
      msg << "array " << NameOf(scalars) << " has " << nc
          << " components: choose one (SelectedComponent)";
      error = msg.str();
      return false;
    }
    component = 0;
  }
  if (component >= nc)
  {
    msg << "component " << component << " is out of range (array " << NameOf(scalars) << " has "
        << nc << ")";
    error = msg.str();
    return false;
  }
  if (selection.Mode == VoxelSelection::Range && !(selection.Lower <= selection.Upper))
  {
    msg << "empty threshold range [" << selection.Lower << ", " << selection.Upper << "]";
    error = msg.str();
    return false;
  }
  std::atomic<bool> sawNaN(false);
  std::atomic<std::int64_t> count(0);
  SelectWorker worker;
  if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker, dims, selection, component, dst,
        rowStride, rowOffset, sawNaN, count))
  {
    worker(scalars, dims, selection, component, dst, rowStride, rowOffset, sawNaN, count);
  }
  if (sawNaN)
  {
    error = "array " + NameOf(scalars) + " holds NaN values: the selection is undefined";
    return false;
  }
  insideCount = count;
  return true;
}

} // namespace dg
