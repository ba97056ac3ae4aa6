#include "dgSurfaceEstimator.h"

#include "dgPieces.h"
#include "dgVoxelSelection.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellData.h>
#include <vtkAlgorithm.h>
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

// The surface's per-surfel arrays as plain int buffers (the surface filter
// writes vtkIntArray / vtkUnsignedCharArray; a file reader may give others).
bool ReadSurfels(vtkDataArray* voxels, vtkDataArray* directions, vtkIdType n,
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
  // Other array types (e.g. read from a file): serial, as the generic
  // accessors of some arrays are not thread-safe.
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

const char* const NoSourceImageMessage =
  "No source image: give the vtkImageData the surface was extracted from with "
  "SetSourceConnection or SetSourceData (input port 1).";

int FillEstimatorInputPort(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int FinishPiece(vtkInformationVector* outputVector, int status)
{
  if (!AllPiecesOk(outputVector->GetInformationObject(0), status != 0))
  {
    vtkPolyData::GetData(outputVector)->Initialize();
    return 0;
  }
  return status;
}

bool SelectInside(vtkDataArray* scalars, const VoxelSelection& select, const int dims[3],
  std::vector<std::uint8_t>& mask, std::string& error)
{
  mask.assign(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2], 0);
  std::int64_t insideCount = 0;
  if (!SelectVoxels(scalars, dims, select, mask.data(), dims[0], 0, insideCount, error))
  {
    error = "Cannot select voxels in the source image: " + error + ".";
    return false;
  }
  return true;
}

int BallReach(double radius, bool worldUnits, vtkInformation* sourceInfo)
{
  if (worldUnits && sourceInfo && sourceInfo->Has(vtkDataObject::SPACING()))
  {
    const double* sp = sourceInfo->Get(vtkDataObject::SPACING());
    const double h = std::min({ std::abs(sp[0]), std::abs(sp[1]), std::abs(sp[2]) });
    radius = h > 0 ? radius / h : radius;
  }
  // A ball centred on a surfel (half a voxel off the inside voxel's centre)
  // reads voxels up to ceil(r) + 1 away; here bad radii only must not
  // overflow.
  if (!(radius > 0) || !std::isfinite(radius) || radius > 1e6)
  {
    return 1;
  }
  return static_cast<int>(std::ceil(radius)) + 1;
}

void RequestEstimatorExtents(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, int reach)
{
  vtkInformation* sourceInfo = inputVector[1]->GetInformationObject(0);
  if (!sourceInfo || !sourceInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    return;
  }
  int whole[6];
  sourceInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
  if (pieces <= 1)
  {
    // One piece: the estimate reaches anywhere in the image, ask for all of
    // it (as vtkProbeFilter does for its source). Without this, an extent
    // requested for an earlier source would crop a new one.
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), whole, 6);
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    return;
  }
  // A piece: its own voxels grown by the ghost levels (the surfels it gets)
  // and by the estimate's reach. The surface filter is told the same reach
  // (IMAGE_GHOST_LEVELS), so that both ask the image's source for one extent.
  const int piece = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
  const int ghosts =
    std::max(0, outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS()));
  const int layers = ghosts + reach;
  vtkInformation* surfaceInfo = inputVector[0]->GetInformationObject(0);
  if (surfaceInfo)
  {
    surfaceInfo->Set(vtkDigitalSurfaceFilter::IMAGE_GHOST_LEVELS(), layers);
  }
  int own[6], need[6];
  PieceExtent(whole, piece, pieces, own);
  GrowExtent(own, layers, whole, need);
  if (ExtentEmpty(need))
  {
    const int none[6] = { 0, -1, 0, -1, 0, -1 };
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), none, 6);
  }
  else
  {
    sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), need, 6);
  }
  // The extent says it all: piece keys left from the superclass would have
  // the executive cut the source's extent again.
  sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  sourceInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
}

bool ReadSurfaceOnImage(vtkPolyData* surface, vtkImageData* image, vtkInformation* sourceInfo,
  SurfaceOnImage& out, std::string& error)
{
  vtkFieldData* fd = surface->GetFieldData();
  vtkDataArray* extArray = fd ? fd->GetArray("ImageExtent") : nullptr;
  vtkDataArray* originArray = fd ? fd->GetArray("ImageOrigin") : nullptr;
  vtkDataArray* spacingArray = fd ? fd->GetArray("ImageSpacing") : nullptr;
  if (!extArray || !originArray || !spacingArray || extArray->GetNumberOfValues() != 6 ||
    originArray->GetNumberOfValues() != 3 || spacingArray->GetNumberOfValues() != 3 ||
    !ReadSurfels(surface->GetCellData()->GetArray("InsideVoxel"),
      surface->GetCellData()->GetArray("SurfelDirection"), surface->GetNumberOfCells(),
      out.Voxels, out.Directions))
  {
    error = "Input 0 is not a digital surface: it needs the cell arrays 'InsideVoxel' (3 "
            "components) and 'SurfelDirection' and the field data 'ImageExtent', "
            "'ImageOrigin', 'ImageSpacing' written by vtkDigitalSurfaceFilter.";
    return false;
  }
  int* ext = out.Extent;
  int* whole = out.Whole;
  image->GetExtent(ext);
  std::copy(ext, ext + 6, whole);
  if (sourceInfo && sourceInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    sourceInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  }
  double origin[3];
  image->GetOrigin(origin);
  image->GetSpacing(out.Spacing);
  const double* spacing = out.Spacing;
  bool same = true;
  for (int a = 0; a < 6; ++a)
  {
    same &= static_cast<int>(extArray->GetComponent(a, 0)) == whole[a];
  }
  for (int a = 0; a < 3; ++a)
  {
    same &= Close(originArray->GetComponent(a, 0), origin[a]);
    same &= Close(spacingArray->GetComponent(a, 0), spacing[a]);
  }
  if (!same)
  {
    auto e = [&](int a) { return static_cast<int>(extArray->GetComponent(a, 0)); };
    std::ostringstream os;
    os << "The source image does not match the surface: image extent " << whole[0] << ".."
       << whole[1] << ", " << whole[2] << ".." << whole[3] << ", " << whole[4] << ".." << whole[5]
       << ", origin (" << origin[0] << ", " << origin[1] << ", " << origin[2] << "), spacing ("
       << spacing[0] << ", " << spacing[1] << ", " << spacing[2]
       << "); the surface was extracted from extent " << e(0) << ".." << e(1) << ", " << e(2)
       << ".." << e(3) << ", " << e(4) << ".." << e(5) << ", origin ("
       << originArray->GetComponent(0, 0) << ", " << originArray->GetComponent(1, 0) << ", "
       << originArray->GetComponent(2, 0) << "), spacing (" << spacingArray->GetComponent(0, 0)
       << ", " << spacingArray->GetComponent(1, 0) << ", " << spacingArray->GetComponent(2, 0)
       << ").";
    error = os.str();
    return false;
  }
  for (int a = 0; a < 3; ++a)
  {
    out.Dims[a] = ext[2 * a + 1] - ext[2 * a] + 1;
  }
  // An empty piece of a distributed surface gets an empty image: normal.
  if ((out.Dims[0] <= 0 || out.Dims[1] <= 0 || out.Dims[2] <= 0) && !out.Directions.empty())
  {
    error = "The source image is empty.";
    return false;
  }
  out.Isotropic = Close(std::abs(spacing[0]), std::abs(spacing[1])) &&
    Close(std::abs(spacing[0]), std::abs(spacing[2]));
  return true;
}

bool ImageHoldsReach(const SurfaceOnImage& s, int reach, int need[6])
{
  const std::size_t n = s.Directions.size();
  if (n == 0 || ExtentContains(s.Extent, s.Whole))
  {
    return true;
  }
  const std::vector<int>& vox = s.Voxels;
  int box[6] = { vox[0], vox[0], vox[1], vox[1], vox[2], vox[2] };
  for (std::size_t c = 1; c < n; ++c)
  {
    for (int a = 0; a < 3; ++a)
    {
      box[2 * a] = std::min(box[2 * a], vox[3 * c + a]);
      box[2 * a + 1] = std::max(box[2 * a + 1], vox[3 * c + a]);
    }
  }
  GrowExtent(box, reach, s.Whole, need);
  return ExtentContains(s.Extent, need);
}

bool RadiiToVoxels(const SurfaceOnImage& s, double* radii, int count, std::string& error)
{
  const double* sp = s.Spacing;
  if (!s.Isotropic)
  {
    std::ostringstream os;
    os << (count > 1 ? "Radii in world units need" : "Radius in world units needs")
       << " an isotropic spacing (the image has " << sp[0] << ", " << sp[1] << ", " << sp[2]
       << "); give the " << (count > 1 ? "radii" : "radius") << " in voxels instead.";
    error = os.str();
    return false;
  }
  for (int c = 0; c < count; ++c)
  {
    radii[c] /= std::abs(sp[0]);
  }
  return true;
}

bool RadiusFitsImage(const SurfaceOnImage& s, const char* name, double radius, std::string& error)
{
  const int* whole = s.Whole;
  const int w[3] = { whole[1] - whole[0] + 1, whole[3] - whole[2] + 1, whole[5] - whole[4] + 1 };
  if (radius > std::max({ w[0], w[1], w[2] }))
  {
    std::ostringstream os;
    os << name << " " << radius << " voxels is larger than the image (" << w[0] << " x " << w[1]
       << " x " << w[2] << " voxels).";
    error = os.str();
    return false;
  }
  return true;
}

std::string MissingReachMessage(
  const SurfaceOnImage& s, const int need[6], const std::string& reads, const std::string& note)
{
  return "The source image holds the voxels " + Ext(s.Extent) + " but " + reads + " " +
    Ext(need) + note +
    ": connect the surface filter and this filter to the same image source, the surface "
    "directly to this filter's input, or give the whole image.";
}

void NormalToWorldMatrix(vtkImageData* image, double Minv[9])
{
  double M[9], spacing[3];
  image->GetSpacing(spacing);
  const double* d = image->GetDirectionMatrix()->GetData();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
    {
      M[3 * r + c] = d[3 * r + c] * spacing[c];
    }
  vtkMatrix3x3::Invert(M, Minv);
}

std::string BadSurfelMessage(long long surfel)
{
  std::ostringstream os;
  os << "Surfel " << surfel
     << " has an inside voxel outside the image extent or a direction outside 0..5: the "
        "surface does not belong to this image.";
  return os.str();
}

std::string NotSelectedMessage(const SurfaceOnImage& s, long long surfel)
{
  std::ostringstream os;
  os << "Surfel " << surfel << " (voxel " << s.Voxels[3 * surfel] << ", "
     << s.Voxels[3 * surfel + 1] << ", " << s.Voxels[3 * surfel + 2] << ", direction "
     << s.Directions[surfel]
     << ") does not separate an inside voxel from an outside one under this filter's "
        "selection: set the same selection (SelectionMode, thresholds, Label, array) as on "
        "vtkDigitalSurfaceFilter.";
  return os.str();
}

} // namespace dg
