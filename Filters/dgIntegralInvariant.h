// Integral-invariant covariance kernel (docs/method.md section 6).
//
// Plain C++ core of vtkIINormalEstimator. For a surfel with centre c and a
// radius r (grid units) it sums, over the inside voxel centres p of the ball
// |p - c| <= r, the moments 1, p - c and (p - c)(p - c)^T.
//
// How the ball sum avoids visiting every voxel:
// - the ball is a list of x-rows (dy, dz, [x0, x1]) relative to the surfel's
//   lower voxel. The list depends only on the surfel's axis (which coordinate
//   of c is half-integer), so three tables serve every surfel;
// - the volume is stored as runs of inside voxels per x-row, each run with
//   the prefix sums (count, sum x, sum x^2) of the runs before it. The sums of
//   1, x, x^2 over the inside voxels of any x-interval then take two binary
//   searches (one comparison for the common single-run row) and closed-form
//   sums over integer ranges. Within a row y and z are constant, so the ten
//   moments of the row follow from those three numbers.
// Cost per surfel: O(number of ball rows) = O(pi r^2) row look-ups, each
// O(log runs in the row); measured on octa-flower 512^3 about 7.5 ns of CPU
// per row at every radius (25 rows at r = 3, 193 at r = 8, 793 at r = 16).
// Memory: 32 bytes per run (about one run per two x-surfels) plus 8 bytes
// per x-row of the grid (4.7 MiB for octa-flower 512^3); no per-voxel arrays.
//
// Exactness: all sums are integers in doubled coordinates u = 2 (p - c)
// (c is a half-integer along one axis), so the moments are exact; the
// covariance is formed in double from exact integers, relative to the
// surfel centre, so there is no cancellation from large absolute positions.
//
// Anisotropic voxels (docs/curvatures.md, "Anisotropic spacing"): with a
// scale s (the spacing divided by its smallest component) the ball is
// |diag(s) (p - c)| <= r, a ball of world space and an ellipsoid of index
// space. It is still a list of x-rows, so the sums stay exact integers in
// index coordinates; EstimateFromMoments maps them to the scaled frame
// (covariance S C S, volumes times s_x s_y s_z), where the formulas of
// docs/method.md section 6 hold unchanged, and returns the normal as a grid
// covector and the principal directions as grid vectors, as in the
// isotropic case. With s = (1, 1, 1) every result is bitwise the old one.
#ifndef dgIntegralInvariant_h
#define dgIntegralInvariant_h

#include <cstdint>
#include <functional>
#include <vector>

namespace dg
{

/// Exact moments of the inside voxel centres p in a ball, in doubled
/// coordinates u = 2 (p - c) relative to the surfel centre c.
struct IIMoments
{
  std::int64_t Count = 0;
  std::int64_t Sum[3] = { 0, 0, 0 };           // sum of u
  std::int64_t Sum2[6] = { 0, 0, 0, 0, 0, 0 }; // sum of u u^T: xx, xy, xz, yy, yz, zz

  /// C = sum (p - b)(p - b)^T (b the barycentre), row-major 3x3, and the
  /// barycentre relative to the surfel centre, b - c (grid units).
  void Covariance(double cov[9], double barycentreOffset[3]) const;
};

/// The inside voxels of an nx*ny*nz grid as runs along x.
class RowRuns
{
public:
  /// mask[(k * ny + j) * rowStride + rowOffset + i] != 0 marks voxel (i, j, k)
  /// inside. Parallel (vtkSMPTools).
  void Build(const std::uint8_t* mask, const int dims[3], std::int64_t rowStride, int rowOffset);
  int Dims[3] = { 0, 0, 0 };

  /// Sums of 1, x, x^2 over the inside voxels x in [x0, x1] of row (j, k);
  /// x0, x1 already clipped to [0, nx - 1], x0 <= x1.
  void RowSums(int j, int k, int x0, int x1, std::int64_t& n, std::int64_t& s1,
    std::int64_t& s2) const;
  bool Inside(int i, int j, int k) const;
  std::int64_t NumberOfRuns() const { return static_cast<std::int64_t>(this->Start.size()); }
  std::size_t MemoryBytes() const;

  std::vector<std::int64_t> RowFirst;     // ny*nz + 1: first run of each row
  std::vector<std::int32_t> Start, End;   // run [Start, End)
  std::vector<std::int64_t> Before;       // 3 per run: count, sum x, sum x^2 of the earlier runs of its row
};

/// The ball of radius r around a surfel centre, as x-rows.
class BallRows
{
public:
  /// axis: the surfel's axis (its centre is lower voxel + 0.5 e_axis).
  /// scale: per-axis weights of the ball's metric, |diag(scale) (p - c)| <= radius
  /// (null: all 1, the Euclidean ball of the grid).
  void Build(double radius, int axis, const double* scale = nullptr);
  /// The ball test in doubled coordinates u = 2 (p - c), the same
  /// arithmetic as Build's rows (so that references agree to the voxel).
  static bool Contains(double radius, const double scale[3], std::int64_t ux, std::int64_t uy,
    std::int64_t uz);
  struct Row
  {
    int Dy, Dz;          // row offset from the lower voxel
    int X0, X1;          // x offsets from the lower voxel, inclusive
    std::int64_t Uy, Uz; // doubled offsets of the row from the centre
  };
  std::vector<Row> Rows; // sorted by Dz, then Dy
  int Axis = 0;
  int MinDy = 0, MaxDy = 0, MinDz = 0, MaxDz = 0, MinX = 0, MaxX = 0; // bounding box
  std::int64_t Voxels = 0; // voxel centres in the (unclipped) ball
  /// Second moment of the ball's voxel centres along one axis tangent to the
  /// surfel, sum of (p_t - c_t)^2 (the same for both tangent axes).
  double TangentMoment = 0.0;
  double Scale[3] = { 1, 1, 1 };
  bool Scaled = false; // Scale is not (1, 1, 1)
  /// Second moments of the ball's voxel centres along each axis in the
  /// scaled frame, sum of (scale_a (p_a - c_a))^2 (the digital ball reference
  /// of an anisotropic grid).
  double AxisMoment[3] = { 0, 0, 0 };
};

/// The zero-curvature reference of the curvature formulas: the volume of
/// the half ball and its second moments along the tangent directions.
/// - Continuous: the Euclidean half ball of docs/method.md section 6, 2 pi r^3 / 3
///   and 2 pi r^5 / 15.
/// - DigitalBall: half of the digital ball's voxel count and tangent moment
///   (a plane through the surfel centre perpendicular to the surfel's axis
///   cuts the digital ball into two mirror halves): exact for axis-aligned
///   planes.
/// - DigitalTangentPlane: the digital ball's voxels on the inner side of the
///   estimated tangent plane through the surfel centre, and their covariance
///   along the two eigenvectors: removes the lattice bias of the digital ball
///   for every orientation, at the cost of one more O(r^2) row sum per
///   surfel (only when curvatures are computed).
enum class IICurvatureReference
{
  Continuous = 0,
  DigitalBall = 1,
  DigitalTangentPlane = 2
};

/// Moments (as IIMoments) of the voxels u of the ball (unclipped) with
/// u . n <= 0, u in doubled coordinates relative to the surfel centre.
IIMoments HalfBallMoments(const BallRows& ball, const double n[3]);

/// The fast kernel: runs of the volume plus the three ball tables.
class IntegralInvariantKernel
{
public:
  void SetVolume(const std::uint8_t* mask, const int dims[3], std::int64_t rowStride, int rowOffset);
  /// scale: see BallRows::Build (null: isotropic).
  void SetRadius(double radius, const double* scale = nullptr);
  double GetRadius() const { return this->Radius; }
  const RowRuns& GetRuns() const { return this->Runs; }
  const BallRows& GetBall(int axis) const { return this->Balls[axis]; }

  /// Moments of the ball around the surfel of inside voxel (i, j, k) (grid
  /// indices from 0) in direction d (0..5 = -x, +x, -y, +y, -z, +z).
  /// Voxels beyond the grid are outside.
  IIMoments Moments(int i, int j, int k, int direction) const;

private:
  RowRuns Runs;
  BallRows Balls[3];
  double Radius = 0.0;
};

/// Reference: visits every voxel of the ball's bounding box. For tests.
IIMoments BruteForceMoments(const std::uint8_t* mask, const int dims[3], double radius, int i,
  int j, int k, int direction, const double* scale = nullptr);
/// Reference covariance computed in double, two passes (barycentre, then
/// sum of (p - b)(p - b)^T). For tests.
void BruteForceCovariance(const std::uint8_t* mask, const int dims[3], double radius, int i, int j,
  int k, int direction, double cov[9], std::int64_t& count, const double* scale = nullptr);

/// What the II estimator derives from the moments: curvatures in the units
/// of the radius (grid units, or units of the smallest spacing on a scaled
/// grid); Normal is a unit grid covector (world normal: M^-T Normal
/// normalised, M = direction * diag(spacing)), Direction1/2 unit grid
/// vectors (world: M Direction normalised). With an isotropic grid these
/// are the plain grid-frame normal and directions.
struct IIEstimate
{
  double Normal[3];
  bool TrivialFallback; // orientation (or the whole normal) from the surfel's axis
  double Mean, Gaussian, K1, K2;
  double Direction1[3], Direction2[3];
};

/// Normal (eigenvector of the smallest eigenvalue of the covariance, oriented
/// from the ball's barycentre to the surfel centre) and, when curvatures is
/// true, the curvatures of docs/method.md section 6. The orientation falls back to
/// the trivial normal only when the barycentre offset is (nearly) zero or
/// perpendicular to the eigenvector; the whole normal falls back when the
/// covariance is degenerate (fewer than two non-zero eigenvalues).
/// ball: the kernel's ball for the surfel's axis; required unless the
/// reference is Continuous, and its Scale is used (the grid is isotropic
/// without a ball).
void EstimateFromMoments(const IIMoments& m, int direction, double radius, bool curvatures,
  IIEstimate& out, IICurvatureReference reference = IICurvatureReference::Continuous,
  const BallRows* ball = nullptr);

} // namespace dg

#endif
