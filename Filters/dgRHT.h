// Randomized Hough Transform normals (MATH.md section 10; Boulch and Marlet,
// SGP 2012).
//
// Plain C++ core of vtkRHTNormalEstimator. For a surfel with centre c, the
// candidate points are the surfel centres within radius r of c, computed
// from the inside voxels of a box (not from a surface's cells), so that a
// piece of a distributed run sees exactly the neighbours a one-process run
// sees. The candidates are listed in grid order (voxel z, y, x, then
// direction): the list, and therefore the sequence of random triplets drawn
// from it, is a function of the surfel and its neighbourhood only.
//
// All positions are exact integers in doubled grid coordinates u = 2 (p - c)
// (surfel centres are half-integers along one axis), so a triplet's cross
// product is an exact integer vector: a triplet is degenerate exactly when
// it is collinear (any other triangle of surfel centres has an area of at
// least 1/8 voxel^2, above MATH.md's 0.01 threshold).
//
// Randomness: one splitmix64 stream per surfel, seeded from (Seed, the
// surfel's inside voxel in image indices, its direction): the result does
// not depend on threads, surfel order or pieces.
#ifndef dgRHT_h
#define dgRHT_h

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace dg
{

/// The surfels of a box of voxels, in grid order, indexed by x-row.
/// Voxels beyond the box are outside.
class SurfelRows
{
public:
  /// mask[(k * ny + j) * rowStride + rowOffset + i] != 0 marks voxel (i, j, k)
  /// inside (the convention of RowRuns). Parallel (vtkSMPTools), two passes;
  /// the result does not depend on the thread count.
  void Build(const std::uint8_t* mask, const int dims[3], std::int64_t rowStride, int rowOffset);
  int Dims[3] = { 0, 0, 0 };
  std::vector<std::int64_t> RowFirst; // ny*nz + 1: first surfel of each row (j, k)
  std::vector<std::int32_t> X;        // inside voxel's x of each surfel
  std::vector<std::uint8_t> Dir;      // direction 0..5 (-x, +x, -y, +y, -z, +z)
  std::int64_t NumberOfSurfels() const { return static_cast<std::int64_t>(this->X.size()); }
  std::size_t MemoryBytes() const;

  /// The centres of the surfels within radius of the centre of surfel
  /// (i, j, k, d) (grid indices of the box, d its direction), itself
  /// included, as doubled offsets u = 2 (c_t - c) (3 ints per point), in grid
  /// order. |u|^2 <= 4 r^2 decides, exactly.
  void Neighbours(int i, int j, int k, int d, double radius, std::vector<std::int32_t>& out) const;
};

/// Brute force: every surfel of the mask's box, tested one by one. For tests.
void BruteForceNeighbours(const std::uint8_t* mask, const int dims[3], double radius, int i, int j,
  int k, int d, std::vector<std::int32_t>& out);

/// A hemisphere accumulator (z >= 0): `resolution` latitude bands of equal
/// angle from the pole, band b cut into max(1, round(pi k sin(theta_b)))
/// bins of equal longitude (theta_b the band's middle colatitude), about
/// 2 k^2 bins of nearly equal area.
class HoughAccumulator
{
public:
  void Build(int resolution);
  int NumberOfBins() const { return this->Bins; }
  int Resolution() const { return this->K; }
  /// The bin of a unit vector with z >= 0.
  int Bin(double x, double y, double z) const;

private:
  int K = 0, Bins = 0;
  std::vector<double> BandTop;  // K + 1 values: cos of each band's upper colatitude edge
  std::vector<int> BandFirst;   // first bin of each band
  std::vector<int> BandBins;    // bins in each band
  std::vector<int> Guess;       // band guess per z cell
};

struct RHTParameters
{
  double Radius = 6.0;
  int Trials = 648;
  int Accumulators = 5;
  std::uint64_t Seed = 0;
};

/// Scratch memory of one thread.
struct RHTWorkspace
{
  std::vector<std::int32_t> Points;
  std::vector<double> Normals;      // 3 per valid trial
  std::vector<std::int16_t> Votes;  // per valid trial: bin + 1, negative when folded
  std::vector<std::int32_t> Counts; // per bin
};

struct RHTEstimate
{
  double Normal[3];
  bool Fallback;   // fewer than 3 points or no valid trial: the reference direction
  int Points;      // candidate points
  int Trials;      // valid (non-degenerate) trials
};

/// The seed of the surfel (i, j, k, d) (image indices: the same in every
/// piece).
std::uint64_t SurfelSeed(std::uint64_t seed, std::int64_t i, std::int64_t j, std::int64_t k, int d);

/// The RHT normal from the candidate points (doubled offsets, 3 ints each),
/// oriented into the hemisphere of `reference` (unit, MATH.md section 6's
/// outward direction). With fewer than three points or no valid triplet
/// the estimate is the reference itself (Fallback).
void EstimateRHT(const std::int32_t* points, int numberOfPoints, const double reference[3],
  const RHTParameters& parameters, std::uint64_t surfelSeed, const HoughAccumulator& accumulator,
  RHTWorkspace& work, RHTEstimate& out);

constexpr double RHTPi = 3.14159265358979323846;

// atan2 to about 1e-5 rad (a minimax polynomial on [0, 1] and the octant
// symmetries): it only places bin boundaries, and it is the same function on
// every thread.
inline double RHTFastAtan2(double y, double x)
{
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (mx == 0)
  {
    return 0.0;
  }
  const double a = mn / mx, s = a * a;
  double r = ((-0.0464964749 * s + 0.15931422) * s - 0.327622764) * s * a + a;
  if (ay > ax)
  {
    r = 0.5 * RHTPi - r;
  }
  if (x < 0)
  {
    r = RHTPi - r;
  }
  return y < 0 ? -r : r;
}


inline int HoughAccumulator::Bin(double x, double y, double z) const
{
  const int K = this->K;
  const int cells = static_cast<int>(this->Guess.size());
  int q = static_cast<int>(z * cells);
  q = std::min(cells - 1, std::max(0, q));
  int b = this->Guess[q];
  // Band b holds BandTop[b + 1] < z <= BandTop[b] (the last band down to 0).
  while (b > 0 && z > this->BandTop[b])
  {
    --b;
  }
  while (b + 1 < K && z <= this->BandTop[b + 1])
  {
    ++b;
  }
  const int n = this->BandBins[b];
  if (n == 1)
  {
    return this->BandFirst[b];
  }
  const double t = (RHTFastAtan2(y, x) + RHTPi) * (n / (2 * RHTPi));
  const int c = std::min(n - 1, std::max(0, static_cast<int>(t)));
  return this->BandFirst[b] + c;
}


} // namespace dg

#endif
