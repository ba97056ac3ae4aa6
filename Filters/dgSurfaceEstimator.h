// What the estimators on a digital surface share (vtkIINormalEstimator,
// vtkVCMNormalEstimator, vtkRHTNormalEstimator): the piece request of the
// image (own extent grown by the ghost levels and the estimator's reach,
// told to the surface filter too), reading the surface's surfels, checking
// that the surface was made from the source image, radii in voxels, that a
// piece's image holds the reach, the per-surfel checks and the normals'
// grid-to-world transform.
#ifndef dgSurfaceEstimator_h
#define dgSurfaceEstimator_h

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

class vtkDataArray;
class vtkImageData;
class vtkInformation;
class vtkInformationVector;
class vtkPolyData;

namespace dg
{
struct VoxelSelection;

/// FillInputPortInformation of an estimator: port 0 the surface
/// (vtkPolyData), port 1 the image (vtkImageData, optional for the pipeline
/// so that a missing image gets the estimator's own message).
int FillEstimatorInputPort(int port, vtkInformation* info);

/// The end of an estimator's RequestData: in a distributed run every piece
/// fails when one does (dg::AllPiecesOk; the later stages' collective steps
/// would otherwise wait for it forever), with an empty output.
int FinishPiece(vtkInformationVector* outputVector, int status);

/// The message when input 1 (the image) is missing.
extern const char* const NoSourceImageMessage;

/// RequestUpdateExtent of an estimator whose input 0 is the surface and
/// input 1 the image: one piece asks for the whole image; piece p of N with
/// G ghost levels asks for the piece's own extent grown by G + reach and
/// sets vtkDigitalSurfaceFilter::IMAGE_GHOST_LEVELS() to the same layers.
void RequestEstimatorExtents(vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, int reach);

/// Voxel layers beyond a surfel's inside voxel that a ball of `radius`
/// around its centre reads: ceil(r) + 1, with the radius in world units when
/// worldUnits (converted with the smallest spacing of sourceInfo). 1 for
/// radii that are not usable (RequestData reports them).
int BallReach(double radius, bool worldUnits, vtkInformation* sourceInfo);

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

/// Radii in world units to voxels (the spacing must be isotropic): false
/// with a message otherwise ("Radius ..." for one radius, "Radii ..." for
/// more).
bool RadiiToVoxels(const SurfaceOnImage& s, double* radii, int count, std::string& error);

/// False with a message when `radius` (voxels; `name` in the message) is
/// larger than the whole image's largest side.
bool RadiusFitsImage(const SurfaceOnImage& s, const char* name, double radius, std::string& error);

/// When the image is a piece's box: true when it holds every voxel within
/// `reach` layers of the surfels' inside voxels (clipped to the whole
/// extent); otherwise false, with that box in `need`.
bool ImageHoldsReach(const SurfaceOnImage& s, int reach, int need[6]);

/// The message when it does not: "The source image holds the voxels <extent>
/// but <reads> <need><note>: connect ...".
std::string MissingReachMessage(
  const SurfaceOnImage& s, const int need[6], const std::string& reads, const std::string& note);

/// The per-surfel check: surfel s's voxel in the image box (ijk) and its
/// direction d; Bad when outside the box or d outside 0..5, NotSelected when
/// the runs do not see an inside voxel with an outside neighbour there.
enum class SurfelCheck
{
  Ok,
  Bad,
  NotSelected
};
template <class Runs>
SurfelCheck CheckSurfel(const SurfaceOnImage& s, const Runs& runs, long long surfel, int ijk[3], int& d)
{
  const int* v = s.Voxels.data() + 3 * surfel;
  d = s.Directions[surfel];
  for (int a = 0; a < 3; ++a)
  {
    ijk[a] = v[a] - s.Extent[2 * a];
  }
  if (d < 0 || d > 5 || ijk[0] < 0 || ijk[1] < 0 || ijk[2] < 0 || ijk[0] >= s.Dims[0] ||
    ijk[1] >= s.Dims[1] || ijk[2] >= s.Dims[2])
  {
    return SurfelCheck::Bad;
  }
  int o[3] = { ijk[0], ijk[1], ijk[2] };
  o[d / 2] += (d & 1) ? 1 : -1;
  if (!runs.Inside(ijk[0], ijk[1], ijk[2]) || runs.Inside(o[0], o[1], o[2]))
  {
    return SurfelCheck::NotSelected;
  }
  return SurfelCheck::Ok;
}

/// The byte mask (dims[0] * dims[1] * dims[2], x fastest) of the image's
/// inside voxels under `select`; false with "Cannot select voxels in the
/// source image: ...".
bool SelectInside(vtkDataArray* scalars, const VoxelSelection& select, const int dims[3],
  std::vector<std::uint8_t>& mask, std::string& error);

/// M^-1 for M = direction * diag(spacing): a grid-space normal n goes to
/// the world as M^-T n (then normalised; row r of M^-T is column r of M^-1).
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
  // Divided, not multiplied by 1 / len: the estimators' results to the bit.
  len = std::sqrt(len);
  for (int r = 0; r < 3; ++r)
  {
    out[r] = len > 0 ? out[r] / len : 0.0;
  }
}

/// The messages of the per-surfel checks (a surfel outside the image or
/// with a bad direction; a surfel that the estimator's selection does not
/// see as one).
std::string BadSurfelMessage(long long surfel);
std::string NotSelectedMessage(const SurfaceOnImage& s, long long surfel);

} // namespace dg

#endif
