#include "dgEstimatorInput.h"

#include "dgPieces.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace dg
{
namespace
{
bool Close(double a, double b)
{
  return std::abs(a - b) <= 1e-9 * std::max({ 1.0, std::abs(a), std::abs(b) });
}

bool ReadArrays(vtkDataArray* voxels, vtkDataArray* directions, vtkIdType n,
  std::vector<int>& vox, std::vector<int>& dirs)
{
  if (!voxels || !directions || voxels->GetNumberOfComponents() != 3 ||
    directions->GetNumberOfComponents() != 1 || voxels->GetNumberOfTuples() != n ||
    directions->GetNumberOfTuples() != n)
  {
    return false;
  }
  vox.resize(3 * n);
  dirs.resize(n);
  auto* intVoxels = vtkIntArray::FastDownCast(voxels);
  auto* ucharDirections = vtkUnsignedCharArray::FastDownCast(directions);
  if (intVoxels && ucharDirections)
  {
    std::copy(intVoxels->GetPointer(0), intVoxels->GetPointer(0) + 3 * n, vox.data());
    std::copy(ucharDirections->GetPointer(0), ucharDirections->GetPointer(0) + n, dirs.data());
    return true;
  }
  for (vtkIdType s = 0; s < n; ++s)
  {
    for (int a = 0; a < 3; ++a)
    {
      vox[3 * s + a] = static_cast<int>(voxels->GetComponent(s, a));
    }
    dirs[s] = static_cast<int>(directions->GetComponent(s, 0));
  }
  return true;
}

std::string Ext(const int e[6])
{
  std::ostringstream os;
  os << e[0] << ".." << e[1] << ", " << e[2] << ".." << e[3] << ", " << e[4] << ".." << e[5];
  return os.str();
}
} // namespace

bool ReadEstimatorInput(vtkPolyData* surface, vtkImageData* image, vtkInformation* sourceInfo,
  double radius, bool worldUnits, EstimatorInput& in, std::string& error)
{
  vtkFieldData* fd = surface->GetFieldData();
  vtkDataArray* extArray = fd ? fd->GetArray("ImageExtent") : nullptr;
  vtkDataArray* originArray = fd ? fd->GetArray("ImageOrigin") : nullptr;
  vtkDataArray* spacingArray = fd ? fd->GetArray("ImageSpacing") : nullptr;
  const vtkIdType n = surface->GetNumberOfCells();
  if (!extArray || !originArray || !spacingArray || extArray->GetNumberOfValues() != 6 ||
    originArray->GetNumberOfValues() != 3 || spacingArray->GetNumberOfValues() != 3 ||
    !ReadArrays(surface->GetCellData()->GetArray("InsideVoxel"),
      surface->GetCellData()->GetArray("SurfelDirection"), n, in.Voxels, in.Directions))
  {
    error = "Input 0 is not a digital surface: it needs the cell arrays 'InsideVoxel' (3 "
            "components) and 'SurfelDirection' and the field data 'ImageExtent', "
            "'ImageOrigin', 'ImageSpacing' written by vtkDigitalSurfaceFilter.";
    return false;
  }
  image->GetExtent(in.Extent);
  std::copy(in.Extent, in.Extent + 6, in.Whole);
  if (sourceInfo && sourceInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    sourceInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), in.Whole);
  }
  image->GetOrigin(in.Origin);
  image->GetSpacing(in.Spacing);
  bool same = true;
  int recorded[6];
  for (int a = 0; a < 6; ++a)
  {
    recorded[a] = static_cast<int>(extArray->GetComponent(a, 0));
    same &= recorded[a] == in.Whole[a];
  }
  for (int a = 0; a < 3; ++a)
  {
    same &= Close(originArray->GetComponent(a, 0), in.Origin[a]);
    same &= Close(spacingArray->GetComponent(a, 0), in.Spacing[a]);
  }
  if (!same)
  {
    std::ostringstream os;
    os << "The source image does not match the surface: image extent " << Ext(in.Whole)
       << ", origin (" << in.Origin[0] << ", " << in.Origin[1] << ", " << in.Origin[2]
       << "), spacing (" << in.Spacing[0] << ", " << in.Spacing[1] << ", " << in.Spacing[2]
       << "); the surface was extracted from extent " << Ext(recorded) << ", origin ("
       << originArray->GetComponent(0, 0) << ", " << originArray->GetComponent(1, 0) << ", "
       << originArray->GetComponent(2, 0) << "), spacing (" << spacingArray->GetComponent(0, 0)
       << ", " << spacingArray->GetComponent(1, 0) << ", " << spacingArray->GetComponent(2, 0)
       << ").";
    error = os.str();
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    in.Dims[a] = in.Extent[2 * a + 1] - in.Extent[2 * a] + 1;
  }
  if ((in.Dims[0] <= 0 || in.Dims[1] <= 0 || in.Dims[2] <= 0) && n > 0)
  {
    error = "The source image is empty.";
    return false;
  }
  const double* sp = in.Spacing;
  const bool isotropic =
    Close(std::abs(sp[0]), std::abs(sp[1])) && Close(std::abs(sp[0]), std::abs(sp[2]));
  in.Radius = radius;
  if (worldUnits)
  {
    if (!isotropic)
    {
      std::ostringstream os;
      os << "Radius in world units needs an isotropic spacing (the image has " << sp[0] << ", "
         << sp[1] << ", " << sp[2] << "); give the radius in voxels instead.";
      error = os.str();
      return false;
    }
    in.Radius /= std::abs(sp[0]);
  }
  const int w[3] = { in.Whole[1] - in.Whole[0] + 1, in.Whole[3] - in.Whole[2] + 1,
    in.Whole[5] - in.Whole[4] + 1 };
  if (in.Radius > std::max({ w[0], w[1], w[2] }))
  {
    std::ostringstream os;
    os << "Radius " << in.Radius << " voxels is larger than the image (" << w[0] << " x " << w[1]
       << " x " << w[2] << " voxels).";
    error = os.str();
    return false;
  }
  return true;
}

bool ImageHoldsReach(const EstimatorInput& in, int reach, std::string& error)
{
  const std::size_t n = in.Directions.size();
  if (n == 0 || ExtentContains(in.Extent, in.Whole))
  {
    return true;
  }
  const std::vector<int>& v = in.Voxels;
  int box[6] = { v[0], v[0], v[1], v[1], v[2], v[2] };
  for (std::size_t c = 1; c < n; ++c)
  {
    for (int a = 0; a < 3; ++a)
    {
      box[2 * a] = std::min(box[2 * a], v[3 * c + a]);
      box[2 * a + 1] = std::max(box[2 * a + 1], v[3 * c + a]);
    }
  }
  int need[6];
  GrowExtent(box, reach, in.Whole, need);
  if (ExtentContains(in.Extent, need))
  {
    return true;
  }
  std::ostringstream os;
  os << "The source image holds the voxels " << Ext(in.Extent) << " but the balls of radius "
     << in.Radius << " around these surfels read " << Ext(need)
     << ": connect the surface filter and this filter to the same image source, the surface "
        "directly to this filter's input, or give the whole image.";
  error = os.str();
  return false;
}

int BallReach(double radius, bool worldUnits, vtkInformation* sourceInfo)
{
  if (worldUnits && sourceInfo && sourceInfo->Has(vtkDataObject::SPACING()))
  {
    const double* sp = sourceInfo->Get(vtkDataObject::SPACING());
    const double h = std::min({ std::abs(sp[0]), std::abs(sp[1]), std::abs(sp[2]) });
    radius = h > 0 ? radius / h : radius;
  }
  if (!(radius > 0) || !std::isfinite(radius) || radius > 1e6)
  {
    return 1;
  }
  return static_cast<int>(std::ceil(radius)) + 1;
}

void RequestImageReach(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int reach)
{
  vtkInformation* sourceInfo = inputVector[1]->GetInformationObject(0);
  if (!sourceInfo || !sourceInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    return;
  }
  using SDDP = vtkStreamingDemandDrivenPipeline;
  int whole[6];
  sourceInfo->Get(SDDP::WHOLE_EXTENT(), whole);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int pieces =
    outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES()) ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()) : 1;
  if (pieces <= 1)
  {
    sourceInfo->Set(SDDP::UPDATE_EXTENT(), whole, 6);
  }
  else
  {
    const int piece = outInfo->Get(SDDP::UPDATE_PIECE_NUMBER());
    const int ghosts = std::max(0, outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS()));
    const int layers = ghosts + reach;
    if (vtkInformation* surfaceInfo = inputVector[0]->GetInformationObject(0))
    {
      surfaceInfo->Set(vtkDigitalSurfaceFilter::IMAGE_GHOST_LEVELS(), layers);
    }
    int own[6], need[6];
    PieceExtent(whole, piece, pieces, own);
    GrowExtent(own, layers, whole, need);
    const int none[6] = { 0, -1, 0, -1, 0, -1 };
    sourceInfo->Set(SDDP::UPDATE_EXTENT(), ExtentEmpty(need) ? none : need, 6);
    sourceInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  // The extent says it all: piece keys would have the executive cut it again.
  sourceInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), 0);
  sourceInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), 1);
}

void GridToWorldNormals(vtkImageData* image, double Minv[9])
{
  double M[9];
  const double* d = image->GetDirectionMatrix()->GetData();
  const double* spacing = image->GetSpacing();
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      M[3 * r + c] = d[3 * r + c] * spacing[c];
    }
  }
  vtkMatrix3x3::Invert(M, Minv);
}

} // namespace dg
