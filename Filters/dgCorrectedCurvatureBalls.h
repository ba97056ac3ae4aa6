// The ball sums of the corrected curvature stage (dgCorrectedCurvature.h):
// the faces sorted into cubic cells, each quantity one contiguous array in
// cell order, the sums of the measures over the ball around a face, and the
// curvatures of a face from its ball's sums. Internal to that stage.
#ifndef dgCorrectedCurvatureBalls_h
#define dgCorrectedCurvatureBalls_h

#include "dgCorrectedCurvature.h"

#include <Eigen/Core>
#include <Eigen/Geometry> // cross products

#include <vtkSMPTools.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace dg
{
namespace curvature
{
using V3 = Eigen::Vector3d;

inline V3 At(const double* p, std::int64_t i)
{
  return V3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
}

// Cell key of a uniform grid from a cell's integer coordinates (21 bits
// per axis).
inline std::int64_t Pack(std::int64_t x, std::int64_t y, std::int64_t z)
{
  const auto k = [](std::int64_t v) { return (v + (1 << 20)) & ((1 << 21) - 1); };
  return (k(x) << 42) | (k(y) << 21) | k(z);
}

// The per-face quantities in cell order: the centre, then what a ball sums
// (mu0, mu1, mu2, the symmetrised anisotropic measure, the normal).
enum Quantity
{
  CX, CY, CZ, M0, M1, M2, SXX, SYY, SZZ, SXY, SXZ, SYZ, NX, NY, NZ, QUANTITIES
};
constexpr int SUMS = QUANTITIES - M0; // the quantities summed over a ball

using Runs = std::vector<std::pair<std::int64_t, std::int64_t>>;

/// std::sort on the threads: a chunk per thread sorted at once, then merged
/// pairwise.
/// The keys must be unique (a total order), so that the result does not
/// depend on the number of threads.
template <typename T>
void SortInParallel(std::vector<T>& v)
{
  const std::int64_t n = static_cast<std::int64_t>(v.size());
  const std::int64_t chunks = std::max(1, vtkSMPTools::GetEstimatedNumberOfThreads());
  if (n < 4096 || chunks == 1)
  {
    std::sort(v.begin(), v.end());
    return;
  }
  std::vector<std::int64_t> bound(chunks + 1);
  for (std::int64_t k = 0; k <= chunks; ++k)
    bound[k] = n * k / chunks;
  vtkSMPTools::For(0, chunks, 1, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t k = begin; k < end; ++k)
      std::sort(v.begin() + bound[k], v.begin() + bound[k + 1]);
  });
  for (std::int64_t width = 1; width < chunks; width *= 2)
  {
    const std::int64_t merges = (chunks + 2 * width - 1) / (2 * width);
    vtkSMPTools::For(0, merges, 1, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t m = begin; m < end; ++m)
      {
        const std::int64_t a = 2 * width * m, b = std::min(a + width, chunks),
                           c = std::min(a + 2 * width, chunks);
        if (b < c)
          std::inplace_merge(v.begin() + bound[a], v.begin() + bound[b], v.begin() + bound[c]);
      }
    });
  }
}

// The faces a cell's balls may hold, one array per quantity, the summed
// quantities as the columns of a matrix: the sums of all of a cell's balls
// are then one matrix product, weights (a row per ball) times quantities,
// instead of a loop over the candidates per ball.
struct Candidates
{
  // Positions; the region as a double, and the region of interior faces
  // only (NaN for the others), so that the weights' loop is all doubles and
  // vectorises.
  Eigen::ArrayXd X, Y, Z, Region, InnerRegion;
  Eigen::Matrix<double, Eigen::Dynamic, SUMS, Eigen::RowMajor> Q;
  // Scratch of BallSums.
  std::vector<std::int64_t> Index;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> W;
  Eigen::Matrix<double, Eigen::Dynamic, SUMS, Eigen::RowMajor> S;
  Eigen::ArrayXd D2, D;
  Eigen::Index Size() const { return this->X.size(); }
};

// The faces sorted into cubic cells of side (R + l/2) / 2 and copied in that
// order, one array per quantity: every ball of radius up to R around a face
// of a cell lies within the 5 x 5 x 5 cells around it, whose faces are a few
// contiguous runs that all faces of the cell read (on octa-flower 512^3
// this is what made the stage 3 times faster than a hash lookup per face).
// The cells are ordered by blocks of 3 x 3 x 3, so that the per-face
// radius's larger balls read whole blocks in the same way.
struct FaceCells
{
  double Side = 0;       // a cell's side
  double EdgeLength = 0; // the ramp's width l
  std::vector<std::int64_t> Face; // the face at each position
  std::vector<std::int64_t> CellStart, BlockStart; // positions, one past the last at the end
  std::unordered_map<std::int64_t, std::int64_t> CellOf, BlockOf; // by Pack key
  // The cells of the 5 x 5 x 5 around each cell that hold faces (CSR), in
  // the order of their offsets (dx, dy, dz), and whether they are among the
  // 3 x 3 x 3: looked up once, as every pass reads them.
  std::vector<std::int64_t> NeighbourStart, Neighbour;
  std::vector<char> NeighbourAdjacent;
  std::vector<std::vector<double>> Q; // the centres (CX, CY, CZ), an array each, in cell order
  // SUMS per position: what a ball sums, one face's contiguous; not zeroed
  // when made (every position is written on the threads).
  std::unique_ptr<double[]> Sums;
  std::vector<int> Region;            // per position (0 without regions)
  std::vector<char> Inner;            // per position: all corners inside its region

  std::int64_t Cells() const { return static_cast<std::int64_t>(this->CellStart.size()) - 1; }
  std::int64_t Blocks() const { return static_cast<std::int64_t>(this->BlockStart.size()) - 1; }
  V3 Centre(std::int64_t i) const { return V3(this->Q[CX][i], this->Q[CY][i], this->Q[CZ][i]); }
  std::array<std::int64_t, 3> CellOfPoint(const V3& c) const;
  static std::int64_t BlockOfCell(std::int64_t v) { return v >= 0 ? v / 3 : -((2 - v) / 3); }

  /// The runs of faces in the 5 x 5 x 5 cells around cell c.
  void NeighbourRuns(std::int64_t c, Runs& runs) const;
  /// The faces cell c's balls of radius r <= R may hold: those of the 5 x 5
  /// x 5 cells around it whose centre lies within r + l/2 of the box of the
  /// cell's face centres, in the cells' order.
  void Gather(std::int64_t c, double r, Runs& runs, Candidates& candidates) const;
  /// The ball sums around the faces at positions faces[0..n) of the cell
  /// whose candidates these are, radius radius[k] <= R each, into sums (n
  /// rows of SUMS, mu0 first): the interior faces of its region first, all
  /// of its region's faces when the ball holds none (a strip narrower than
  /// a face ring). border[k]: the ball is not a whole disc of interior faces
  /// of the face's region: it reaches a face of another region or a face
  /// along a crease, or it had to take all of its region's faces.
  void BallSums(const std::int64_t* faces, const double* radius, std::int64_t n,
    Candidates& candidates, double* sums, char* border) const;
};

/// Sorts the faces into cells (blocks: also index the blocks of 3 x 3 x 3
/// cells) and copies their quantities in that order.
void SortIntoCells(const std::vector<V3>& centre, const std::vector<CorrectedMeasures>& measures,
  const double* normals, const int* region, const std::vector<char>& interior, double radius,
  double edgeLength, bool blocks, FaceCells& cells);

/// The curvatures of face f from its ball sums (sum[M0..NZ]) into result;
/// false when the ball has no area (the face keeps zeros). directions
/// false: H, G, k1 and k2 only (a first pass whose face will be measured
/// again).
bool CurvaturesFromSums(std::int64_t f, const double* sum, bool directions, CurvatureResult& result);

} // namespace curvature
} // namespace dg

#endif
