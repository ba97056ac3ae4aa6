// What the estimators on a digital surface share (vtkIINormalEstimator,
// vtkVCMNormalEstimator): the piece request of the image (own extent grown
// by the ghost levels and the estimator's reach, told to the surface filter
// too), reading the surface's surfels, checking that the surface was made
// from the source image and that a piece's image holds the reach, and the
// normals' grid-to-world matrix.
#ifndef dgSurfaceEstimator_h
#define dgSurfaceEstimator_h

#include <cmath>
#include <string>
#include <vector>

class vtkImageData;
class vtkInformation;
class vtkInformationVector;
class vtkPolyData;

namespace dg
{

/// RequestUpdateExtent of an estimator whose input 0 is the surface and
/// input 1 the image: one piece asks for the whole image; piece p of N with
/// G ghost levels asks for the piece's own extent grown by G + reach and
/// sets vtkDigitalSurfaceFilter::IMAGE_GHOST_LEVELS() to the same layers.
void RequestEstimatorExtents(vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, int reach);

/// The surface's surfels and the image's geometry, checked.
struct SurfaceOnImage
{
  std::vector<int> Voxels;     // 3 per surfel, whole-extent indices
  std::vector<int> Directions; // 0..5
  int Extent[6];               // the image's (piece's) extent
  int Whole[6];                // its whole extent
  int Dims[3];                 // of Extent
  double Spacing[3];
  bool Isotropic = false;
};

/// Reads the surfels of `surface` and checks that it was made from `image`
/// (field data ImageExtent / Origin / Spacing against the image's whole
/// extent, origin and spacing). False with a message in `error`.
bool ReadSurfaceOnImage(vtkPolyData* surface, vtkImageData* image, vtkInformation* sourceInfo,
  SurfaceOnImage& out, std::string& error);

/// When the image is a piece's box: true when it holds every voxel within
/// `reach` layers of the surfels' inside voxels (clipped to the whole
/// extent); otherwise false, with that box in `need`.
bool ImageHoldsReach(const SurfaceOnImage& s, int reach, int need[6]);

/// Rows of M^-T, M = direction * diag(spacing): a grid-space normal n goes
/// to the world as Minv^T n (then normalised).
void NormalToWorldMatrix(vtkImageData* image, double Minv[9]);
inline void NormalToWorld(const double Minv[9], const double n[3], double out[3])
{
  double len = 0;
  for (int r = 0; r < 3; ++r)
  {
    // Row r of M^-T is column r of M^-1.
    out[r] = Minv[r] * n[0] + Minv[3 + r] * n[1] + Minv[6 + r] * n[2];
    len += out[r] * out[r];
  }
  len = len > 0 ? 1.0 / std::sqrt(len) : 0.0;
  for (int r = 0; r < 3; ++r)
  {
    out[r] *= len;
  }
}

/// The messages of the per-surfel checks (a surfel outside the image or
/// with a bad direction; a surfel that the estimator's selection does not
/// see as one).
std::string BadSurfelMessage(long long surfel);
std::string NotSelectedMessage(const SurfaceOnImage& s, long long surfel);

} // namespace dg

#endif
