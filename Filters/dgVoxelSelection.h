// Which voxels are "inside": the selection shared by the filters that read a
// segmented image (value != 0, a closed range, or one label, on one
// component of any numeric array).
#ifndef dgVoxelSelection_h
#define dgVoxelSelection_h

#include <cstdint>
#include <string>

class vtkDataArray;
class vtkDataSet;
class vtkInformation;

namespace dg
{

struct VoxelSelection
{
  enum Modes
  {
    NonZero = 0,
    Range = 1,
    Label = 2
  };
  int Mode = NonZero;
  double Lower = 1.0, Upper = 1e300, LabelValue = 1.0;
  int Component = -1; // -1: the array must have one component

  bool operator()(double v) const
  {
    switch (this->Mode)
    {
      case Range:
        return v >= this->Lower && v <= this->Upper;
      case Label:
        return v == this->LabelValue;
      default:
        return v != 0.0;
    }
  }
};

/// Evaluates the selection on every voxel of an nx*ny*nz array (x fastest)
/// and writes 0/1 to dst[r * rowStride + rowOffset + i] for row r = k*ny + j.
/// Returns false with a one-line reason for a bad array, a bad component,
/// NaN values or an empty range; insideCount receives the inside voxels.
bool SelectVoxels(vtkDataArray* scalars, const int dims[3], const VoxelSelection& selection,
  std::uint8_t* dst, std::int64_t rowStride, int rowOffset, std::int64_t& insideCount,
  std::string& error);

/// The array chosen with SetInputArrayToProcess (chosen, arrayInfo); when no
/// array name was given (ParaView sends an empty name before the
/// input's arrays are known), the active point scalars.
vtkDataArray* SelectionArray(vtkDataArray* chosen, vtkInformation* arrayInfo, vtkDataSet* input);

} // namespace dg

#endif
