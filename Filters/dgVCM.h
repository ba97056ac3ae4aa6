// Voronoi Covariance Measure of a digital surface (docs/method.md section 9).
//
// Plain C++ core of vtkVCMNormalEstimator. The point set K is the set of
// surfel centres; every lattice point x of Z^3 (voxel centres, inside or
// outside, also beyond the image) with d(x, K) <= R belongs to the Voronoi
// cell of its nearest surfel centre p(x) (ties: the smallest site index, and
// sites are numbered in grid order (k, j, i, direction), the order of the
// surfels' GlobalIds, so that the tie-break does not depend on the piece).
// Per site VCM(p) = sum over its cell of (x - p)(x - p)^T; the convolution
// with the ball of radius r sums VCM(p) over the sites p within r of a
// surfel centre.
//
// Arithmetic: everything is in doubled coordinates (X = 2 x), where surfel
// centres and lattice points are integers: squared distances, the per-site
// sums and the convolved sums are exact 64-bit integers (4 times the grid
// values), so the result does not depend on the order of the sums, the
// thread count or the piece.
//
// Nearest-site assignment: an exact separable Euclidean distance transform
// (Felzenszwalb-Huttenlocher lower envelopes of parabolas, rational
// breakpoints compared exactly, ties kept so that the smallest index wins)
// on the doubled grid, three passes: along X (per doubled line (Y, Z), the
// sites of the line, results at even X), along Y (results at even X, Y),
// along Z (results at the lattice points). Only values <= 4 R^2 are kept
// (a farther site never matters). The Z pass runs on slabs of lattice
// planes, the X and Y passes fill a ring buffer of doubled planes, each
// computed once: memory is (4 R + 2 T + 3) planes of nx * ny * 8 bytes (T = 16
// lattice planes per slab), not the whole grid.
#ifndef dgVCM_h
#define dgVCM_h

#include <cstdint>
#include <functional>
#include <vector>

namespace dg
{

/// Squared radius in doubled units, as the integer bound of |2 d|^2: a
/// squared doubled distance D2 is within the radius when D2 <= bound.
std::int64_t DoubledRadiusBound(double radius);

/// The surfels of a voxel mask (nx*ny*nz, x fastest, mask[i] != 0 inside):
/// faces between an inside voxel and an outside 6-neighbour. A face towards
/// a voxel beyond the mask on side s (0..5 = -x, +x, -y, +y, -z, +z) is a
/// surfel only when outsideBeyond[s] is true (the mask's side is the image's
/// border); otherwise the neighbour is unknown and the face is left out.
/// Sites are returned in grid order (k, j, i, direction): Voxel (3 ints per
/// site, mask indices) and Direction.
struct VCMSites
{
  int Dims[3] = { 0, 0, 0 }; // the mask's dimensions
  std::vector<std::int32_t> Voxel;
  std::vector<std::uint8_t> Direction;
  std::int64_t Size() const { return static_cast<std::int64_t>(this->Direction.size()); }
};
VCMSites ExtractSites(const std::uint8_t* mask, const int dims[3], const bool outsideBeyond[6]);

/// The doubled centre of a surfel: 2 v + e_d.
inline void DoubledCentre(const std::int32_t* voxel, int direction, std::int64_t c[3])
{
  for (int a = 0; a < 3; ++a)
  {
    c[a] = 2 * static_cast<std::int64_t>(voxel[a]);
  }
  c[direction / 2] += (direction & 1) ? 1 : -1;
}

/// Per-site measures and the convolution.
class VoronoiCovarianceMeasure
{
public:
  /// The sites (kept by pointer: `sites` must outlive this object) and the
  /// offset radius R (grid units, > 0). `progress(f)` is called from the
  /// calling thread between slabs with f in [0, 1]; returning false aborts
  /// (Compute returns false). Parallel (vtkSMPTools).
  bool Compute(const VCMSites& sites, double offsetRadius,
    const std::function<bool(double)>& progress = nullptr);

  /// VCM(p) of site p in doubled units (4 x the grid-unit matrix): xx, xy,
  /// xz, yy, yz, zz.
  const std::int64_t* SiteMeasure(std::int64_t p) const { return &this->Measures[6 * p]; }
  const std::vector<std::int64_t>& Measures6() const { return this->Measures; }

  /// Sum of VCM(p) over the sites p with |p - c| <= r, c = the doubled
  /// centre of the surfel (voxel, direction); doubled units, xx xy xz yy yz zz.
  /// Needs Compute() first.
  void Convolve(const std::int32_t voxel[3], int direction, double r, std::int64_t out[6]) const;

  /// Lattice points assigned to some site in the last Compute (the offset's size).
  std::int64_t NumberOfOffsetPoints() const { return this->OffsetPoints; }
  /// Peak bytes of the distance transform's buffers in the last Compute.
  std::size_t BufferBytes() const { return this->Bytes; }
  /// Lattice planes per slab (T); default 16. For tests and benchmarks.
  void SetSlabPlanes(int t) { this->SlabPlanes = t < 1 ? 1 : t; }

private:
  const VCMSites* Sites = nullptr;
  std::vector<std::int64_t> Measures;
  // Sites per voxel row (j, k) of the mask's bounding box of sites, for the
  // convolution: RowFirst[(k - K0) * NJ + (j - J0)], sites sorted by (i, d).
  std::vector<std::int64_t> RowFirst;
  int J0 = 0, K0 = 0, NJ = 0, NK = 0;
  std::int64_t OffsetPoints = 0;
  std::size_t Bytes = 0;
  int SlabPlanes = 16;
};

/// Reference for tests: for every lattice point within R of a site, scans
/// all sites (smallest squared distance, then smallest index).
std::vector<std::int64_t> BruteForceSiteMeasures(const VCMSites& sites, double offsetRadius);
/// Reference convolution: scans all sites.
void BruteForceConvolve(const VCMSites& sites, const std::vector<std::int64_t>& measures,
  const std::int32_t voxel[3], int direction, double r, std::int64_t out[6]);

/// What the estimator derives from a convolved measure (doubled units) and
/// the barycentre sum of the inside voxels within r (as IIMoments::Sum:
/// 2 N (b - c), doubled, relative to the surfel centre).
struct VCMEstimate
{
  double Normal[3];       // unit, eigenvector of the largest eigenvalue, outward
  double Eigenvalues[3];  // lambda0 >= lambda1 >= lambda2, grid units (voxel^2)
  double FeatureScore;    // lambda1 / (lambda0 + lambda1 + lambda2), 0 when the sum is 0
  bool TrivialFallback;   // orientation (or the whole normal) from the surfel's axis
};
void EstimateFromMeasure(const std::int64_t v[6], const std::int64_t barycentreSum[3],
  int direction, VCMEstimate& out);

} // namespace dg

#endif
