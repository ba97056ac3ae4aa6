// The paper's noise model (docs/method.md section 7): each voxel p is flipped
// (inside <-> outside) with probability k^(1 + dt(p)), dt(p) being the
// Euclidean distance from p to the boundary voxels of the original shape.
// Plain C++; the random draws come from a counter-based hash of (seed, voxel
// index), so the result depends on the seed only, never on the thread count.
#ifndef dgNoise_h
#define dgNoise_h

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
/// Voxels beyond the grid count as outside.
void BoundaryVoxels(
  const std::vector<std::uint8_t>& inside, const int dims[3], std::vector<std::uint8_t>& boundary);

/// Applies the noise in place to a 0/1 volume. k in [0, 1]; k = 0 leaves the
/// volume unchanged. Returns the number of flipped voxels, or -1 when
/// progress (optional: called with the done fraction after the boundary and
/// after the distance transform, before any voxel changes) returned false;
/// the volume is then unchanged.
std::int64_t ApplyNoise(std::vector<std::uint8_t>& inside, const int dims[3], double k,
  std::uint64_t seed, const std::function<bool(double)>& progress = std::function<bool(double)>());

/// Uniform number in [0, 1) from (seed, index): SplitMix64 finaliser.
double HashUniform(std::uint64_t seed, std::uint64_t index);

} // namespace dg

#endif
