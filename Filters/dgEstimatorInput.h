// What a normal estimator on (digital surface, source image) checks and asks
// for before its own work: the surface's per-surfel arrays, that the image is
// the one the surface came from, the radius in voxels, that a piece's image
// holds every surfel's reach, the piece request to the image's source, and
// the grid-to-world transform of normals. Written for vtkRHTNormalEstimator
// from vtkIINormalEstimator's checks (same rules, same messages).
#ifndef dgEstimatorInput_h
#define dgEstimatorInput_h

#include <string>
#include <vector>

class vtkImageData;
class vtkInformation;
class vtkInformationVector;
class vtkPolyData;

namespace dg
{

struct EstimatorInput
{
  std::vector<int> Voxels;     // 3 per surfel: inside voxel (image indices)
  std::vector<int> Directions; // 0..5
  int Extent[6];               // the image given (a piece's box, or all of it)
  int Whole[6];                // the image's whole extent
  int Dims[3];                 // of Extent
  double Origin[3], Spacing[3];
  double Radius;               // in voxels
};

/// Reads the surface's "InsideVoxel", "SurfelDirection" and its field data,
/// checks that `image` (whole extent from `sourceInfo` when it has one) is
/// the image it came from, and converts `radius` to voxels (worldUnits:
/// divided by the spacing, which must be isotropic). `what` names the
/// radius in messages ("Radius"). False with a message otherwise.
bool ReadEstimatorInput(vtkPolyData* surface, vtkImageData* image, vtkInformation* sourceInfo,
  double radius, bool worldUnits, EstimatorInput& in, std::string& error);

/// False (with a message) when the image does not hold every surfel's
/// voxels grown by `reach` (clipped to the whole extent).
bool ImageHoldsReach(const EstimatorInput& in, int reach, std::string& error);

/// Voxel layers beyond a surfel that a ball of `radius` around its centre
/// reads: ceil(r) + 1 (radius in world units when worldUnits, converted with
/// the smallest spacing of sourceInfo). 1 for radii that are not usable.
int BallReach(double radius, bool worldUnits, vtkInformation* sourceInfo);

/// RequestUpdateExtent for input 1 (the image) of an estimator whose
/// surfels read `reach` layers: the whole image for one piece; for piece p
/// of N with G ghost levels its own extent grown by G + reach, and the same
/// layers told to the surface filter (IMAGE_GHOST_LEVELS).
void RequestImageReach(vtkInformationVector** inputVector, vtkInformationVector* outputVector,
  int reach);

/// M^-1 for M = direction * diag(spacing): a grid-space normal n goes to
/// world as M^-T n (row r of M^-T is column r of M^-1).
void GridToWorldNormals(vtkImageData* image, double Minv[9]);

} // namespace dg

#endif
