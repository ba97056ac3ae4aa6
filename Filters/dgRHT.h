// Randomized Hough Transform normals (docs/method.md section 10; Boulch and Marlet,
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
// least 1/8 voxel^2, above docs/method.md's 0.01 threshold).
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

/// The accumulators of a run: a pool of rotations drawn from the seed alone
/// (the same for every surfel; still independent of threads and pieces),
/// and per rotation a look-up table from a cube-map cell of the unrotated
/// sphere to the bin of the cell's centre once rotated and folded onto
/// z >= 0. Each surfel turns its A accumulators by A distinct rotations of
/// the pool, picked with its own generator, so that neighbouring surfels
/// mostly use different ones. A vote is then one cell computation per
/// normal and one load per accumulator and distinct cell, in place of a
/// rotation, a fold, a band search and an atan2. The cube map covers half
/// the sphere: a direction is first flipped so that its largest component
/// (in absolute value) is positive, n and -n being one plane. Cells:
/// CellsPerSide^2 per face, 3 faces.
class HoughTables
{
public:
  static constexpr int CellsPerSide = 32;
  /// A pool of max(MinimumPool, accumulators) rotations.
  static constexpr int MinimumPool = 32;
  static constexpr int NumberOfCells() { return 3 * CellsPerSide * CellsPerSide; }
  void Build(int resolution, int accumulators, std::uint64_t seed);
  int NumberOfBins() const { return this->Accumulator.NumberOfBins(); }
  int NumberOfAccumulators() const { return this->A; }
  int PoolSize() const { return this->P; }
  const HoughAccumulator& GetAccumulator() const { return this->Accumulator; }
  /// Row-major rotation a of the pool.
  const double* Rotation(int a) const { return this->Rotations.data() + 9 * a; }
  /// Table of rotation a of the pool: per cell, 2 bin + 1 when the cell's
  /// (flipped) direction folds, 2 bin otherwise.
  const std::uint16_t* Table(int a) const
  {
    return this->Tables.data() + static_cast<std::size_t>(a) * 3 * CellsPerSide * CellsPerSide;
  }
  /// The cell of a non-zero integer vector, and its largest component in
  /// absolute value (the first of x, y, z among equals), signed: the
  /// direction is flipped when that component is negative. Integer selects
  /// in place of branches: the face and the sign of a random normal are
  /// coin tosses that a branch predictor loses.
  template <typename I>
  static int Cell(const I c[3], I& major)
  {
    constexpr int signBit = 8 * sizeof(I) - 1;
    const I ax = c[0] < 0 ? -c[0] : c[0];
    const I ay = c[1] < 0 ? -c[1] : c[1];
    const I az = c[2] < 0 ? -c[2] : c[2];
    // The face from sign bits (-1 or 0), so that no compiler turns it into
    // a branch.
    const I notX = ((ax - ay) >> signBit) | ((ax - az) >> signBit);
    const I notY = (ay - az) >> signBit;
    const int face = static_cast<int>(-notX - (notX & notY));
    // (m, u, v) = (x, y, z), (y, z, x) or (z, x, y).
    const I w[5] = { c[0], c[1], c[2], c[0], c[1] };
    const I m = w[face], u = w[face + 1], v = w[face + 2];
    major = m;
    // u / m in [-1, 1] after the flip; the flip is in the sign of m.
    const double h = 0.5 * CellsPerSide / static_cast<double>(m);
    const double o = 0.5 * CellsPerSide;
    const int iu = std::min(CellsPerSide - 1, static_cast<int>(static_cast<double>(u) * h + o));
    const int iv = std::min(CellsPerSide - 1, static_cast<int>(static_cast<double>(v) * h + o));
    return (face * CellsPerSide + iv) * CellsPerSide + iu;
  }

private:
  int A = 0, P = 0;
  HoughAccumulator Accumulator;
  std::vector<double> Rotations;
  std::vector<std::uint16_t> Tables;
};

struct RHTParameters
{
  double Radius = 6.0;
  int Trials = 648;
  int Accumulators = 5;
  std::uint64_t Seed = 0;
};

/// The trials of one cube-map cell.
struct RHTCellSum
{
  double Sum[3] = { 0, 0, 0 }; // unit normals, largest component positive
  std::int32_t Count = 0;
};

/// Scratch memory of one thread.
struct RHTWorkspace
{
  std::vector<std::int32_t> Points;
  std::vector<RHTCellSum> Slots;      // per cube-map cell; all zero between surfels
  std::vector<std::int32_t> Touched;  // the distinct cells of the trials, first trial first
  std::vector<std::uint16_t> Entries; // per distinct cell: the accumulator's table entry
  std::vector<std::int32_t> Counts;   // per bin; all zero between accumulators
  std::vector<int> Pool;              // rotation indices (the surfel's picks first)
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
/// oriented into the hemisphere of `reference` (unit, docs/method.md section 6's
/// outward direction). With fewer than three points or no valid triplet
/// the estimate is the reference itself (Fallback). The accumulators are
/// `tables` (built for parameters.Accumulators and parameters.Seed).
void EstimateRHT(const std::int32_t* points, int numberOfPoints, const double reference[3],
  const RHTParameters& parameters, std::uint64_t surfelSeed, const HoughTables& tables,
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
