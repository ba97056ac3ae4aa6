// The paper's noise model (docs/method.md section 7): each voxel p is flipped
// (inside <-> outside) with probability k^(1 + dt(p)), dt(p) being the
// Euclidean distance from p to the boundary voxels of the original shape.
// Plain C++; the random draws come from a counter-based hash of (seed, voxel
// index), so the result depends on the seed only, never on the thread count.
#ifndef dgNoise_h
#define dgNoise_h

#include <climits>
#include <cstdint>
#include <functional>
#include <vector>

namespace dg
{

/// Exact squared Euclidean distance (in voxels) from every voxel to the
/// nearest voxel where seeds[v] != 0 (Meijster's separable algorithm); voxels
/// far from any seed get a large value. x fastest.
void SquaredDistanceTransform(
  const std::vector<std::uint8_t>& seeds, const int dims[3], std::vector<std::int64_t>& d2);

/// Boundary voxels: those with a 6-neighbour of the other state (both layers,
/// inside and outside, so that a flip is as likely in both directions).
/// Voxels beyond the grid count as outside, except beyond the faces set in
/// openFaces (bit 2a: the low face of axis a, bit 2a + 1: the high one),
/// where the volume goes on: there the last layer's neighbours are unknown,
/// so its voxels are left out (0).
void BoundaryVoxels(const std::vector<std::uint8_t>& inside, const int dims[3],
  std::vector<std::uint8_t>& boundary, unsigned openFaces = 0);
void BoundaryVoxels(const std::uint8_t* inside, const int dims[3],
  std::vector<std::uint8_t>& boundary, unsigned openFaces = 0);

/// Applies the noise in place to a 0/1 volume. k in [0, 1]; k = 0 leaves the
/// volume unchanged. Returns the number of flipped voxels, or -1 when
/// progress (optional: called with the done fraction after the boundary and
/// after the distance transform, before any voxel changes) returned false;
/// the volume is then unchanged.
std::int64_t ApplyNoise(std::vector<std::uint8_t>& inside, const int dims[3], double k,
  std::uint64_t seed, const std::function<bool(double)>& progress = std::function<bool(double)>());

/// The noise of a box needs the shape's boundary around it, but only so far:
/// a voxel at distance d flips with probability k^(1 + d). With the box read
/// R voxels wider on each side, every voxel whose distance to the whole
/// volume's boundary is below R gets exactly its whole-volume decision; one
/// at distance >= R flips with probability <= k^(1 + R) whatever it is, so
/// at most wholeVoxels * k^(1 + R) voxels are expected to differ anywhere.
/// Returns the smallest R >= 1 that brings this below `bound`, at most
/// `cap` (the largest axis of the whole extent: then the box is the whole
/// volume, and exact); 0 for k = 0 (no noise: nothing beyond the box
/// matters); `cap` for k >= 1, bound <= 0 or NaN.
int NoiseReach(double k, double wholeVoxels, double bound, int cap);

/// A box of a larger volume, as VTK extents (inclusive, in the whole
/// volume's index space).
struct NoiseBox
{
  int Whole[6]; // the whole volume: global voxel indices for the draws; outside beyond it
  int Box[6];   // the voxels held (the input array), inside Whole
  int Out[6];   // the voxels decided (the result array), inside Box
  /// Flips are counted in Out and this (everything by default): a piece's
  /// own voxels, so that the counts of pieces whose Out overlap add up.
  int Counted[6] = { INT_MIN, INT_MAX, INT_MIN, INT_MAX, INT_MIN, INT_MAX };
};

struct NoiseCounts
{
  std::int64_t Flipped = 0; // voxels of Out and Counted flipped
  /// Voxels of Out whose decision could differ from the whole volume's: their
  /// distance within the box exceeds their distance to the box's open faces
  /// (where boundary voxels may lie unseen), and a boundary voxel there
  /// would make them flip (their draw is below k^(1 + that distance)).
  std::int64_t Uncertain = 0;
};

/// The noise of the voxels of b.Out, given the 0/1 volume over b.Box
/// (`inside`, x fastest) and nothing beyond it: the boundary and its
/// distance transform over the box, the draws from each voxel's index in
/// b.Whole, so that over b.Whole itself this is ApplyNoise, bit for bit.
/// `result` receives b.Out's voxels (x fastest); it may be `inside` itself
/// when Out is Box. Returns false (result untouched) when progress, called
/// as in ApplyNoise, returned false.
bool ApplyNoise(const std::uint8_t* inside, const NoiseBox& b, double k, std::uint64_t seed,
  std::uint8_t* result, NoiseCounts& counts,
  const std::function<bool(double)>& progress = std::function<bool(double)>());

/// Uniform number in [0, 1) from (seed, index): SplitMix64 finaliser.
double HashUniform(std::uint64_t seed, std::uint64_t index);

} // namespace dg

#endif
