#include "dgCorrectedCurvatureRadius.h"

#include <Eigen/Core>

#include <vtkSMPTools.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace dg
{
namespace curvature
{

void GroupFaces(const FaceCells& cells, const std::int64_t* faceIds, FaceGroups& groups)
{
  const std::int64_t nCells = cells.Cells(), blocks = cells.Blocks();
  groups = FaceGroups();
  groups.CellGroupStart.assign(nCells + 1, 0);
  groups.BlockGroupStart.assign(blocks + 1, 0);
  std::vector<std::int64_t>& rep = groups.Rep;
  std::int64_t b = 0;
  for (std::int64_t c = 0; c < nCells; ++c)
  {
    while (b < blocks && cells.BlockStart[b] <= cells.CellStart[c])
      groups.BlockGroupStart[b++] = static_cast<std::int64_t>(rep.size());
    groups.CellGroupStart[c] = static_cast<std::int64_t>(rep.size());
    const auto cc = cells.CellOfPoint(cells.Centre(cells.CellStart[c]));
    const double side = cells.Side;
    const V3 middle((cc[0] + 0.5) * side, (cc[1] + 0.5) * side, (cc[2] + 0.5) * side);
    const std::size_t firstGroup = rep.size();
    for (std::int64_t i = cells.CellStart[c]; i < cells.CellStart[c + 1]; ++i)
    {
      std::size_t g = firstGroup;
      while (g < rep.size() && groups.Region[g] != cells.Region[i])
        ++g;
      if (g == rep.size())
      {
        rep.push_back(i);
        groups.Region.push_back(cells.Region[i]);
        groups.Sums.resize(groups.Sums.size() + SUMS, 0.0);
        groups.Centre.push_back(V3::Zero());
      }
      else
      {
        const std::int64_t j = rep[g];
        const double di = (cells.Centre(i) - middle).squaredNorm();
        const double dj = (cells.Centre(j) - middle).squaredNorm();
        const std::int64_t idi = faceIds ? faceIds[cells.Face[i]] : cells.Face[i];
        const std::int64_t idj = faceIds ? faceIds[cells.Face[j]] : cells.Face[j];
        if (di < dj || (di == dj && idi < idj))
          rep[g] = i;
      }
      if (cells.Inner[i])
      {
        for (int m = 0; m < SUMS; ++m)
          groups.Sums[SUMS * g + m] += cells.Sums[SUMS * i + m];
        groups.Centre[g] += cells.Centre(i);
      }
    }
    for (std::size_t g = firstGroup; g < rep.size(); ++g)
    {
      std::int64_t count = 0;
      for (std::int64_t i = cells.CellStart[c]; i < cells.CellStart[c + 1]; ++i)
        count += (cells.Inner[i] && cells.Region[i] == groups.Region[g]) ? 1 : 0;
      if (count > 0)
        groups.Centre[g] /= static_cast<double>(count);
    }
  }
  while (b <= blocks)
    groups.BlockGroupStart[b++] = static_cast<std::int64_t>(rep.size());
  groups.CellGroupStart[nCells] = static_cast<std::int64_t>(rep.size());
}

namespace
{
// The candidates (one array per coordinate) of region `own` within
// sqrt(reach2) of p: their squared distances in d2 (a loop that
// vectorises), their indices in `inside` in order, chosen without a branch
// (whether a candidate is in is a coin toss); returns how many.
std::int64_t SelectNear(const std::vector<double>& X, const std::vector<double>& Y,
  const std::vector<double>& Z, const std::vector<int>& region, double px, double py, double pz,
  int own, double reach2, std::vector<double>& d2, std::vector<std::int32_t>& inside)
{
  const std::int64_t n = static_cast<std::int64_t>(X.size());
  {
    const double* __restrict gx = X.data();
    const double* __restrict gy = Y.data();
    const double* __restrict gz = Z.data();
    double* __restrict gd2 = d2.data();
    for (std::int64_t j = 0; j < n; ++j)
    {
      const double ex = gx[j] - px, ey = gy[j] - py, ez = gz[j] - pz;
      gd2[j] = ex * ex + ey * ey + ez * ez;
    }
  }
  std::int64_t count = 0;
  for (std::int64_t j = 0; j < n; ++j)
  {
    inside[count] = static_cast<std::int32_t>(j);
    count += (region[j] == own && d2[j] < reach2) ? 1 : 0;
  }
  return count;
}
} // namespace

void ChooseBallRadii(const FaceCells& cells, const FaceGroups& groups,
  const double* firstSums, const std::vector<char>& keepRadius,
  const unsigned char* ghost, double R, CurvatureResult& result)
{
  // The error of H over a ball of radius r is a bias that grows like a r^2
  // where the curvature varies (a = Laplacian(H) / 8 on a flat disc) and a
  // noise whose deviation falls like s r^-3/2 (the ball's mu1 is the flux
  // of the field's tangential error through its rim: a sum along its length
  // ~ r, over its area ~ r^2). Their squared sum is smallest at r* = R (3
  // s_R^2 / (4 a^2 R^4))^(1/7), s_R the noise at R. s_R and a are measured
  // around each face from balls of R, 1.5 R, 2 R and 3 R; r* is kept within
  // [2R/3, 3R] and below the face's smallest curvature radius 1 / max(|k1|,
  // |k2|) (a larger ball reaches round the surface, where the expansion no
  // longer holds).
  const auto isGhost = [&](std::int64_t f) { return ghost && ghost[f] != 0; };
  const std::int64_t nCells = cells.Cells(), blocks = cells.Blocks(), nGroups = groups.Size();
  const double side = cells.Side;
  const std::vector<std::int64_t>& groupRep = groups.Rep;
  const std::vector<int>& groupRegion = groups.Region;
  const double ladder[] = { 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0 };
  constexpr int K = 7, K15 = 2, K2 = 4, K3 = 6;
  double L[K];
  for (int k = 0; k < K; ++k)
    L[k] = ladder[k] * R;
  const double minRadius = kMinRadiusFactor * R, maxRadius = kMaxRadiusFactor * R;
  // Cells' sums count in a ball by their centre's distance with a ramp as
  // wide as a cell (their faces spread over it).
  const double soft = side, ringReach = maxRadius + 0.5 * soft;

  // Rings: for each representative, its cumulative sums C_k over the balls
  // of L[k], from the cells' sums of their region's interior faces, all
  // radii in one pass over the groups near it (each group adds to the ring
  // where its ramp starts, and the rings are summed up after); a face's
  // ball of r > R is its own ball of R plus C(r) - C_0 of the
  // representatives near it, blended.
  // Only the representatives that may give their rings have them (not
  // those that keep R), and they are not zeroed: each is written whole by
  // the threads (40 MB on octa-flower 512^3 were a serial memset and its
  // page faults).
  std::vector<std::int64_t> ringOf(nGroups, -1);
  std::int64_t rings = 0;
  for (std::int64_t g = 0; g < nGroups; ++g)
    if (firstSums[SUMS * groupRep[g]] > 0 && !keepRadius[groupRep[g]])
      ringOf[g] = rings++;
  const std::unique_ptr<double[]> ring(new double[static_cast<std::size_t>(rings) * K * SUMS]);
  std::vector<double> repH(static_cast<std::size_t>(nGroups) * 4, 0.0); // H at R, 1.5R, 2R, 3R
  std::vector<char> repValid(nGroups, 0);
  const double reach2 = ringReach * ringReach;
  // The ladder padded to a vector's length.
  constexpr int KP = 8;
  Eigen::Array<double, KP, 1> LP;
  for (int k = 0; k < KP; ++k)
    LP[k] = k < K ? L[k] : 2 * maxRadius + 2 * soft;
  vtkSMPTools::For(0, blocks, [&](std::int64_t begin, std::int64_t end) {
    // The groups near a block, one array per quantity, so that each
    // representative's distances to all of them are one vectorised loop.
    std::vector<double> nearX, nearY, nearZ, nearQ, nearD2;
    std::vector<int> nearRegion;
    std::vector<std::int32_t> inside;
    for (std::int64_t b = begin; b < end; ++b)
    {
      const std::int64_t g0 = groups.BlockGroupStart[b], g1 = groups.BlockGroupStart[b + 1];
      if (g0 == g1)
        continue;
      // The groups within ringReach of the box of the block's
      // representatives, from the 7 x 7 x 7 blocks around it.
      V3 lo = cells.Centre(groupRep[g0]), hi = lo;
      for (std::int64_t g = g0; g < g1; ++g)
      {
        lo = lo.cwiseMin(cells.Centre(groupRep[g]));
        hi = hi.cwiseMax(cells.Centre(groupRep[g]));
      }
      const auto cc = cells.CellOfPoint(cells.Centre(cells.BlockStart[b]));
      const std::int64_t bx = FaceCells::BlockOfCell(cc[0]), by = FaceCells::BlockOfCell(cc[1]),
                         bz = FaceCells::BlockOfCell(cc[2]);
      nearX.clear();
      nearY.clear();
      nearZ.clear();
      nearQ.clear();
      nearRegion.clear();
      for (int dx = -3; dx <= 3; ++dx)
        for (int dy = -3; dy <= 3; ++dy)
          for (int dz = -3; dz <= 3; ++dz)
          {
            const auto it = cells.BlockOf.find(Pack(bx + dx, by + dy, bz + dz));
            if (it == cells.BlockOf.end())
              continue;
            for (std::int64_t h = groups.BlockGroupStart[it->second];
                 h < groups.BlockGroupStart[it->second + 1]; ++h)
            {
              if (!(groups.Sums[SUMS * h] > 0))
                continue;
              const V3& x = groups.Centre[h];
              const double ex = std::max({ lo.x() - x.x(), 0.0, x.x() - hi.x() });
              const double ey = std::max({ lo.y() - x.y(), 0.0, x.y() - hi.y() });
              const double ez = std::max({ lo.z() - x.z(), 0.0, x.z() - hi.z() });
              if (ex * ex + ey * ey + ez * ez >= reach2)
                continue;
              nearX.push_back(x.x());
              nearY.push_back(x.y());
              nearZ.push_back(x.z());
              nearQ.insert(nearQ.end(), groups.Sums.begin() + SUMS * h,
                groups.Sums.begin() + SUMS * (h + 1));
              nearRegion.push_back(groupRegion[h]);
            }
          }
      const std::int64_t nNear = static_cast<std::int64_t>(nearX.size());
      nearD2.resize(nNear);
      inside.resize(nNear);
      for (std::int64_t g = g0; g < g1; ++g)
      {
        const std::int64_t i = groupRep[g];
        const double* s0 = &firstSums[SUMS * i];
        // A representative that keeps R (its ball of R is not a whole disc)
        // gives neither its noise nor its rings to any face: its rings are
        // not needed.
        if (!(s0[0] > 0) || keepRadius[i])
          continue;
        double* s = &ring[static_cast<std::size_t>(ringOf[g]) * K * SUMS];
        // Each radius's sums in registers (7 x 12 doubles), added to
        // without a load and store per group.
        using Row = Eigen::Array<double, SUMS, 1>;
        Row acc[K];
        for (int k = 0; k < K; ++k)
          acc[k].setZero();
        const V3 x = cells.Centre(i);
        const double px = x.x(), py = x.y(), pz = x.z();
        const int own = groupRegion[g];
        const std::int64_t nInside =
          SelectNear(nearX, nearY, nearZ, nearRegion, px, py, pz, own, reach2, nearD2, inside);
        for (std::int64_t n = 0; n < nInside; ++n)
        {
          const std::int64_t j = inside[n];
          const double d = std::sqrt(nearD2[j]);
          const Row q = Eigen::Map<const Row>(&nearQ[static_cast<std::size_t>(SUMS) * j]);
          // The group adds the rise of its weight from each radius to the
          // next (the weights grow with the radius) to that radius's ring:
          // the same terms in the same order as a loop over the radii that
          // stops at a weight of 1, and rises of 0 to the others, which add
          // nothing; no branch on the distance, which mispredicted half the
          // time. All radii's ramps at once: one vector division.
          const Eigen::Array<double, KP, 1> w = ((LP - d) / soft + 0.5).max(0.0).min(1.0);
          acc[0] += w[0] * q;
          for (int k = 1; k < K; ++k)
            acc[k] += (w[k] - w[k - 1]) * q;
        }
        for (int k = 1; k < K; ++k)
          acc[k] += acc[k - 1];
        for (int k = 0; k < K; ++k)
          Eigen::Map<Row>(s + k * SUMS) = acc[k];
        bool valid = true;
        const int at[4] = { 0, K15, K2, K3 };
        for (int n = 0; n < 4 && valid; ++n)
        {
          const int k = at[n];
          const double mu0 = s0[0] + s[k * SUMS] - s[0],
                       mu1 = s0[M1 - M0] + s[k * SUMS + M1 - M0] - s[M1 - M0];
          valid = mu0 > 0;
          repH[4 * g + n] = valid ? mu1 / (2 * mu0) : 0;
        }
        repValid[g] = valid ? 1 : 0;
      }
    }
  });

  // Per representative whose ball of R is a whole disc: the noise s_R and
  // the bias a from the representatives of the 3 x 3 x 3 cells around it.
  // E = H(R) - 12/7 H(1.5R) + 5/7 H(2R) cancels a constant and a bias in
  // r^2, so it is noise only; D2 = H(2R) - H(R) = 3 a R^2 and D3 = H(3R) -
  // H(R) = 8 a R^2 plus noise (the larger of the two biases counts: the
  // bias is not exactly quadratic). The noise of balls of R, 1.5 R, 2 R,
  // 3 R is independent (their rims differ): Var(E) = s_R^2 (1 + (12/7)^2
  // / 1.5^3 + (5/7)^2 / 2^3), Var(D2) = s_R^2 (1 + 1/2^3), Var(D3) = s_R^2
  // (1 + 1/3^3); the mean of D over the neighbourhood holds about 4
  // independent samples (faces closer than R/2 share the noise of H(R)),
  // whose part is taken off D's square.
  const double varE = 1 + (144.0 / 49.0) / 3.375 + (25.0 / 49.0) / 8.0, var2 = 1.125,
               var3 = 1 + 1.0 / 27, samples = 4, R4 = R * R * R * R;
  std::vector<double> repRadius(nGroups, 0.0);
  vtkSMPTools::For(0, nCells, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t c = begin; c < end; ++c)
    {
      double e2 = 0, d2 = 0, d3 = 0;
      int n = 0;
      bool any = false;
      for (std::int64_t g = groups.CellGroupStart[c]; g < groups.CellGroupStart[c + 1]; ++g)
        any = any || (repValid[g] && !keepRadius[groupRep[g]]);
      if (!any)
        continue;
      for (std::int64_t g = groups.CellGroupStart[c]; g < groups.CellGroupStart[c + 1]; ++g)
      {
        if (!repValid[g] || keepRadius[groupRep[g]])
          continue;
        e2 = d2 = d3 = 0;
        n = 0;
        for (std::int64_t k = cells.NeighbourStart[c]; k < cells.NeighbourStart[c + 1]; ++k)
        {
          if (!cells.NeighbourAdjacent[k])
            continue;
          const std::int64_t nc = cells.Neighbour[k];
          for (std::int64_t h = groups.CellGroupStart[nc]; h < groups.CellGroupStart[nc + 1]; ++h)
            if (groupRegion[h] == groupRegion[g] && repValid[h] && !keepRadius[groupRep[h]])
            {
              const double* H = &repH[4 * h];
              const double E = H[0] - 12.0 / 7.0 * H[1] + 5.0 / 7.0 * H[2];
              e2 += E * E;
              d2 += H[2] - H[0];
              d3 += H[3] - H[0];
              ++n;
            }
        }
        const double noise2 = e2 / n / varE;
        d2 /= n;
        d3 /= n;
        const double a2 = std::max(std::max(d2 * d2 - var2 * noise2 / samples, 0.0) / 9,
                            std::max(d3 * d3 - var3 * noise2 / samples, 0.0) / 64) /
          R4;
        repRadius[g] = a2 > 0 ? R * std::pow(0.75 * noise2 / (a2 * R4), 1.0 / 7.0) : maxRadius;
      }
    }
  });

  // Per face whose ball of R is a whole disc: the representatives within
  // 1.5 cells, weighted 1 - d / 1.5 cells, give the radius (then bounded
  // by the face's own curvature radius and [2R/3, 3R]) and the rings.
  const double blend = 1.5 * side, cellReach = blend + 0.5 * std::sqrt(3.0) * side;
  const double blend2 = blend * blend;
  vtkSMPTools::For(0, nCells, [&](std::int64_t begin, std::int64_t end) {
    Runs runs;
    Candidates candidates;
    bool gathered = false;
    char border;
    // The representatives near a cell, one array per quantity, so that a
    // face's distances to all of them are one vectorised loop.
    std::vector<double> nearX, nearY, nearZ, nearD2;
    std::vector<std::int64_t> nearG;
    std::vector<int> nearRegion;
    std::vector<std::int32_t> inside;
    std::vector<std::pair<std::int64_t, double>> weights;
    double sum[QUANTITIES];
    for (std::int64_t c = begin; c < end; ++c)
    {
      const std::int64_t first = cells.CellStart[c];
      bool any = false;
      for (std::int64_t i = first; i < cells.CellStart[c + 1] && !any; ++i)
        any = !isGhost(cells.Face[i]) && !keepRadius[i] && result.BallRadius[cells.Face[i]] > 0;
      if (!any)
        continue;
      // The representatives that may lie within `blend` of a face of the
      // cell, and the cell's runs, once a face needs a smaller ball.
      const auto cc = cells.CellOfPoint(cells.Centre(first));
      const V3 middle((cc[0] + 0.5) * side, (cc[1] + 0.5) * side, (cc[2] + 0.5) * side);
      nearX.clear();
      nearY.clear();
      nearZ.clear();
      nearG.clear();
      nearRegion.clear();
      for (std::int64_t k = cells.NeighbourStart[c]; k < cells.NeighbourStart[c + 1]; ++k)
      {
        const std::int64_t nc = cells.Neighbour[k];
        for (std::int64_t g = groups.CellGroupStart[nc]; g < groups.CellGroupStart[nc + 1]; ++g)
        {
          const V3 x = cells.Centre(groupRep[g]);
          if (repRadius[g] > 0 && (x - middle).squaredNorm() < cellReach * cellReach)
          {
            nearX.push_back(x.x());
            nearY.push_back(x.y());
            nearZ.push_back(x.z());
            nearG.push_back(g);
            nearRegion.push_back(groupRegion[g]);
          }
        }
      }
      const std::int64_t nNear = static_cast<std::int64_t>(nearX.size());
      nearD2.resize(nNear);
      inside.resize(nNear);
      gathered = false;
      for (std::int64_t i = first; i < cells.CellStart[c + 1]; ++i)
      {
        const std::int64_t f = cells.Face[i];
        if (isGhost(f) || keepRadius[i] || result.BallRadius[f] == 0)
          continue;
        double wSum = 0, r = 0;
        weights.clear();
        const double x = cells.Q[CX][i], y = cells.Q[CY][i], z = cells.Q[CZ][i];
        const std::int64_t nInside = SelectNear(
          nearX, nearY, nearZ, nearRegion, x, y, z, cells.Region[i], blend2, nearD2, inside);
        for (std::int64_t n = 0; n < nInside; ++n)
        {
          const std::int64_t j = inside[n], g = nearG[j];
          const double w = 1 - std::sqrt(nearD2[j]) / blend;
          weights.emplace_back(g, w);
          wSum += w;
          r += w * repRadius[g];
        }
        const auto keep = [&]() {
          std::copy(firstSums + SUMS * i, firstSums + SUMS * (i + 1), sum + M0);
          CurvaturesFromSums(f, sum, true, result);
        };
        if (wSum == 0)
        {
          keep();
          continue;
        }
        r /= wSum;
        const double kappa = std::max(std::abs(result.K1[f]), std::abs(result.K2[f]));
        if (kappa > 0)
          r = std::min(r, 1 / kappa);
        r = std::min(maxRadius, std::max(minRadius, r));
        if (r < R)
        {
          if (!gathered)
            cells.Gather(c, R, runs, candidates);
          gathered = true;
          cells.BallSums(&i, &r, 1, candidates, sum + M0, &border);
          if (CurvaturesFromSums(f, sum, true, result))
            result.BallRadius[f] = r;
          else
            keep();
        }
        else if (r == R)
          keep();
        else
        {
          int k = 0;
          while (k + 2 < K && L[k + 1] < r)
            ++k;
          const double t =
            std::min(1.0, (r * r - L[k] * L[k]) / (L[k + 1] * L[k + 1] - L[k] * L[k]));
          std::copy(firstSums + SUMS * i, firstSums + SUMS * (i + 1), sum + M0);
          for (const auto& w : weights)
          {
            const double* s = &ring[static_cast<std::size_t>(ringOf[w.first]) * K * SUMS];
            const double u = w.second / wSum;
            for (int m = 0; m < SUMS; ++m)
              sum[M0 + m] += u * ((1 - t) * s[k * SUMS + m] + t * s[(k + 1) * SUMS + m] - s[m]);
          }
          if (CurvaturesFromSums(f, sum, true, result))
            result.BallRadius[f] = r;
          else
            keep();
        }
      }
    }
  });
}

} // namespace curvature
} // namespace dg
