#include "dgCorrectedCurvatureBalls.h"

#include <vtkSMPTools.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dg
{
namespace curvature
{

std::array<std::int64_t, 3> FaceCells::CellOfPoint(const V3& c) const
{
  return { static_cast<std::int64_t>(std::floor(c.x() / this->Side)),
    static_cast<std::int64_t>(std::floor(c.y() / this->Side)),
    static_cast<std::int64_t>(std::floor(c.z() / this->Side)) };
}

void SortIntoCells(const std::vector<V3>& centre, const std::vector<CorrectedMeasures>& measures,
  const double* normals, const int* region, const std::vector<char>& interior, double radius,
  double edgeLength, bool blocks, FaceCells& cells)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  cells.EdgeLength = edgeLength;
  cells.Side = 0.5 * (radius + 0.5 * edgeLength);
  struct Sorted
  {
    std::int64_t Block, Cell, F;
    bool operator<(const Sorted& o) const
    {
      return Block != o.Block ? Block < o.Block : (Cell != o.Cell ? Cell < o.Cell : F < o.F);
    }
  };
  std::vector<Sorted> order(F);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      const auto c = cells.CellOfPoint(centre[f]);
      order[f] = { Pack(FaceCells::BlockOfCell(c[0]), FaceCells::BlockOfCell(c[1]),
                     FaceCells::BlockOfCell(c[2])),
        Pack(c[0], c[1], c[2]), f };
    }
  });
  SortInParallel(order);
  cells.CellStart.clear();
  cells.BlockStart.clear();
  cells.CellOf.clear();
  cells.BlockOf.clear();
  for (std::int64_t i = 0; i < F; ++i)
  {
    if (i == 0 || order[i].Cell != order[i - 1].Cell)
    {
      cells.CellOf.emplace(order[i].Cell, static_cast<std::int64_t>(cells.CellStart.size()));
      cells.CellStart.push_back(i);
    }
    if (blocks && (i == 0 || order[i].Block != order[i - 1].Block))
    {
      cells.BlockOf.emplace(order[i].Block, static_cast<std::int64_t>(cells.BlockStart.size()));
      cells.BlockStart.push_back(i);
    }
  }
  cells.CellStart.push_back(F);
  cells.BlockStart.push_back(F);
  cells.Face.resize(F);
  cells.Q.assign(M0, std::vector<double>(F));
  cells.Sums.reset(new double[static_cast<std::size_t>(SUMS) * F]);
  cells.Region.assign(F, 0);
  cells.Inner.assign(F, 0);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      const std::int64_t f = order[i].F;
      const CorrectedMeasures& m = measures[f];
      const double values[QUANTITIES] = { centre[f].x(), centre[f].y(), centre[f].z(), m.Mu0, m.Mu1,
        m.Mu2, m.MuXY[0], m.MuXY[4], m.MuXY[8], 0.5 * (m.MuXY[1] + m.MuXY[3]),
        0.5 * (m.MuXY[2] + m.MuXY[6]), 0.5 * (m.MuXY[5] + m.MuXY[7]), normals[3 * f],
        normals[3 * f + 1], normals[3 * f + 2] };
      for (int k = 0; k < M0; ++k)
        cells.Q[k][i] = values[k];
      std::copy(values + M0, values + QUANTITIES, cells.Sums.get() + SUMS * i);
      cells.Face[i] = f;
      cells.Region[i] = region ? region[f] : 0;
      cells.Inner[i] = interior[f];
    }
  });
  const std::int64_t nCells = cells.Cells();
  std::vector<std::vector<std::int64_t>> found(nCells);
  vtkSMPTools::For(0, nCells, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t c = begin; c < end; ++c)
    {
      const auto cc = cells.CellOfPoint(cells.Centre(cells.CellStart[c]));
      for (int dx = -2; dx <= 2; ++dx)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dz = -2; dz <= 2; ++dz)
          {
            const auto it = cells.CellOf.find(Pack(cc[0] + dx, cc[1] + dy, cc[2] + dz));
            if (it != cells.CellOf.end())
            {
              const bool adjacent = std::abs(dx) <= 1 && std::abs(dy) <= 1 && std::abs(dz) <= 1;
              found[c].push_back(2 * it->second + (adjacent ? 1 : 0));
            }
          }
    }
  });
  cells.NeighbourStart.assign(nCells + 1, 0);
  for (std::int64_t c = 0; c < nCells; ++c)
    cells.NeighbourStart[c + 1] = cells.NeighbourStart[c] + static_cast<std::int64_t>(found[c].size());
  cells.Neighbour.resize(cells.NeighbourStart[nCells]);
  cells.NeighbourAdjacent.resize(cells.NeighbourStart[nCells]);
  vtkSMPTools::For(0, nCells, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t c = begin; c < end; ++c)
    {
      std::int64_t k = cells.NeighbourStart[c];
      for (const std::int64_t v : found[c])
      {
        cells.Neighbour[k] = v / 2;
        cells.NeighbourAdjacent[k++] = static_cast<char>(v % 2);
      }
      std::vector<std::int64_t>().swap(found[c]);
    }
  });
}

void FaceCells::NeighbourRuns(std::int64_t c, Runs& runs) const
{
  runs.clear();
  for (std::int64_t k = this->NeighbourStart[c]; k < this->NeighbourStart[c + 1]; ++k)
    runs.emplace_back(this->CellStart[this->Neighbour[k]], this->CellStart[this->Neighbour[k] + 1]);
}

void FaceCells::Gather(std::int64_t c, double r, Runs& runs, Candidates& candidates) const
{
  const std::vector<double>&X = this->Q[CX], &Y = this->Q[CY], &Z = this->Q[CZ];
  V3 lo = this->Centre(this->CellStart[c]), hi = lo;
  for (std::int64_t i = this->CellStart[c]; i < this->CellStart[c + 1]; ++i)
  {
    lo = lo.cwiseMin(this->Centre(i));
    hi = hi.cwiseMax(this->Centre(i));
  }
  this->NeighbourRuns(c, runs);
  const double rr = r + 0.5 * this->EdgeLength, rr2 = rr * rr;
  std::vector<std::int64_t>& index = candidates.Index;
  std::size_t total = 0;
  for (const auto& run : runs)
    total += static_cast<std::size_t>(run.second - run.first);
  index.resize(total);
  // Without a branch (most faces of the runs are in, the others a coin toss
  // along the runs' edges): every face is written, the count moves on for
  // those within reach.
  std::int64_t* out = index.data();
  std::int64_t found = 0;
  const double lx = lo.x(), ly = lo.y(), lz = lo.z(), hx = hi.x(), hy = hi.y(), hz = hi.z();
  for (const auto& run : runs)
    for (std::int64_t j = run.first; j < run.second; ++j)
    {
      const double x = X[j], y = Y[j], z = Z[j];
      const double ex = std::max(std::max(lx - x, 0.0), x - hx);
      const double ey = std::max(std::max(ly - y, 0.0), y - hy);
      const double ez = std::max(std::max(lz - z, 0.0), z - hz);
      out[found] = j;
      found += ex * ex + ey * ey + ez * ez < rr2 ? 1 : 0;
    }
  index.resize(found);
  const Eigen::Index n = static_cast<Eigen::Index>(found);
  candidates.X.resize(n);
  candidates.Y.resize(n);
  candidates.Z.resize(n);
  candidates.Region.resize(n);
  candidates.InnerRegion.resize(n);
  candidates.Q.resize(n, SUMS);
  for (Eigen::Index k = 0; k < n; ++k)
  {
    const std::int64_t j = index[k];
    candidates.X[k] = X[j];
    candidates.Y[k] = Y[j];
    candidates.Z[k] = Z[j];
    candidates.Region[k] = this->Region[j];
    candidates.InnerRegion[k] =
      this->Inner[j] ? candidates.Region[k] : std::numeric_limits<double>::quiet_NaN();
  }
  // A fixed-size copy per row (std::copy called memmove for each).
  using Row = Eigen::Matrix<double, 1, SUMS>;
  for (Eigen::Index k = 0; k < n; ++k)
    candidates.Q.row(k) = Eigen::Map<const Row>(this->Sums.get() + SUMS * index[k]);
}

namespace
{
// The weights of the candidates in the ball of radius r around (x, y, z)
// whose `side` equals own (NaN never does): 1/2 + (r - d) / l clamped to 1,
// 0 from r + l/2 on (the ball's ramp). Returns whether a candidate of
// another side lies in the ball. Written with doubles only and no branch,
// so that it vectorises.
bool BallWeights(const Candidates& cand, const Eigen::ArrayXd& side, double own, double x,
  double y, double z, double r, double l, Eigen::ArrayXd& d2, Eigen::ArrayXd& d, double* w)
{
  const Eigen::Index n = cand.Size();
  const double rr = r + 0.5 * l, rr2 = rr * rr;
  const double full = std::max(r - 0.5 * l, 0.0), full2 = full * full; // weight 1 within
  d2 = (cand.X - x).square() + (cand.Y - y).square() + (cand.Z - z).square();
  d = d2.sqrt();
  const double* D2 = d2.data();
  const double* D = d.data();
  const double* S = side.data();
  int other = 0;
  for (Eigen::Index j = 0; j < n; ++j)
  {
    const bool in = D2[j] < rr2, mine = S[j] == own;
    const double ramp = std::min(1.0, 0.5 + (r - D[j]) / l);
    const double v = D2[j] <= full2 ? 1.0 : ramp;
    w[j] = in && mine ? v : 0.0;
    other |= (in && !mine) ? 1 : 0;
  }
  return other != 0;
}
} // namespace

void FaceCells::BallSums(const std::int64_t* faces, const double* radius, std::int64_t n,
  Candidates& cand, double* sums, char* border) const
{
  // A face cut by the ball's sphere counts for the share of it inside,
  // estimated from its centre's distance d: 1/2 + (r - d) / l, clamped to
  // [0, 1] (exact for a square face of side l moving across a plane, and
  // the sphere is locally a plane for r >> l).
  const double l = this->EdgeLength;
  const Eigen::Index nc = cand.Size();
  cand.W.resize(n, nc);
  for (std::int64_t k = 0; k < n; ++k)
  {
    const std::int64_t i = faces[k];
    border[k] = BallWeights(cand, cand.InnerRegion, this->Region[i], this->Q[CX][i],
                  this->Q[CY][i], this->Q[CZ][i], radius[k], l, cand.D2, cand.D, cand.W.row(k).data())
      ? 1
      : 0;
  }
  cand.S.noalias() = cand.W * cand.Q;
  for (std::int64_t k = 0; k < n; ++k)
  {
    if (!(cand.S(k, 0) > 0))
    {
      // No interior face of the region in the ball: all of its faces.
      const std::int64_t i = faces[k];
      Eigen::RowVectorXd w(nc);
      BallWeights(cand, cand.Region, this->Region[i], this->Q[CX][i], this->Q[CY][i],
        this->Q[CZ][i], radius[k], l, cand.D2, cand.D, w.data());
      cand.S.row(k) += w * cand.Q;
      border[k] = 1;
    }
    std::copy(cand.S.row(k).data(), cand.S.row(k).data() + SUMS, sums + SUMS * k);
  }
}

bool CurvaturesFromSums(std::int64_t f, const double* sum, bool directions, CurvatureResult& result)
{
  V3 n(sum[NX], sum[NY], sum[NZ]);
  const double mu0 = sum[M0], mu1 = sum[M1], mu2 = sum[M2];
  if (!(mu0 > 0) || n.norm() == 0)
    return false;
  n.normalize();
  if (directions)
    for (int d = 0; d < 3; ++d)
      result.BallNormal[3 * f + d] = n[d];
  result.Mean[f] = mu1 / (2 * mu0);
  result.Gaussian[f] = mu2 / mu0;
  // Principal curvatures: the symmetrised anisotropic measure in the
  // tangent plane of the ball's mean normal.
  Eigen::Matrix3d T;
  T << sum[SXX], sum[SXY], sum[SXZ], sum[SXY], sum[SYY], sum[SYZ], sum[SXZ], sum[SYZ], sum[SZZ];
  T /= mu0;
  const V3 t1 = n.unitOrthogonal();
  const V3 t2 = n.cross(t1);
  Eigen::Matrix2d A;
  A << t1.dot(T * t1), t1.dot(T * t2), t2.dot(T * t1), t2.dot(T * t2);
  // The 2 x 2 problem in closed form: compute()'s QR iterations were a
  // third of this function's time, called twice for most faces.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig;
  eig.computeDirect(A, directions ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
  // The measure's tangential eigenvalues are the principal curvatures
  // with the opposite sign (muXY pairs the normal's change along Y
  // with X x u, a quarter turn away), so the smallest is k1.
  // The ball's faces turn away from its mean normal's plane, so the
  // projected measure falls short of the curvature along each
  // direction by about the mean cos^2 of that direction's turn (12 %
  // for a ball of 7 on a tube of radius 10): most along the more
  // curved direction. mu1 is exact, so the trace's deficit is given
  // back to k1 and k2 in proportion to their size.
  double k1 = -eig.eigenvalues()[0], k2 = -eig.eigenvalues()[1];
  const double deficit = mu1 / mu0 - (k1 + k2), size = std::abs(k1) + std::abs(k2);
  const double share1 = size > 0 ? std::abs(k1) / size : 0.5;
  k1 += deficit * share1;
  k2 += deficit * (1 - share1);
  result.K1[f] = k1;
  result.K2[f] = k2;
  if (!directions)
    return true;
  const Eigen::Vector2d e1 = eig.eigenvectors().col(0), e2 = eig.eigenvectors().col(1);
  const V3 d1 = (e1[0] * t1 + e1[1] * t2).normalized();
  const V3 d2 = (e2[0] * t1 + e2[1] * t2).normalized();
  for (int d = 0; d < 3; ++d)
  {
    result.D1[3 * f + d] = d1[d];
    result.D2[3 * f + d] = d2[d];
  }
  return true;
}

} // namespace curvature
} // namespace dg
