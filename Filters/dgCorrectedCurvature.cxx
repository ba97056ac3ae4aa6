#include "dgCorrectedCurvature.h"

#include <vtkSMPTools.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

namespace dg
{
namespace
{
using V3 = Eigen::Vector3d;

V3 At(const double* p, std::int64_t i)
{
  return V3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
}

void AddTriangle(const V3& a, const V3& b, const V3& c, const V3& ua, const V3& ub,
  const V3& uc, CorrectedMeasures& m)
{
  const V3 um = (ua + ub + uc) / 3.0;
  m.Mu0 += 0.5 * um.dot((b - a).cross(c - a));
  m.Mu1 += 0.5 * (um.dot((uc - ub).cross(a)) + um.dot((ua - uc).cross(b)) + um.dot((ub - ua).cross(c)));
  m.Mu2 += 0.5 * ua.dot(ub.cross(uc));
  // det(um, <Y, uc - ua> X, b - a) = <Y, uc - ua> <X, (b - a) x um>.
  const V3 w1 = (b - a).cross(um), w2 = (c - a).cross(um);
  const V3 d1 = uc - ua, d2 = ub - ua;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m.MuXY[3 * i + j] += 0.5 * (w1[i] * d1[j] - w2[i] * d2[j]);
}

// Cell key of a uniform grid from a cell's integer coordinates (21 bits
// per axis).
std::int64_t Pack(std::int64_t x, std::int64_t y, std::int64_t z)
{
  const auto k = [](std::int64_t v) { return (v + (1 << 20)) & ((1 << 21) - 1); };
  return (k(x) << 42) | (k(y) << 21) | k(z);
}

enum Quantity
{
  CX, CY, CZ, M0, M1, M2, SXX, SYY, SZZ, SXY, SXZ, SYZ, NX, NY, NZ, QUANTITIES
};
constexpr int SUMS = QUANTITIES - M0; // the quantities summed over a ball
} // namespace

CorrectedMeasures PolygonMeasures(int corners, const double* x, const double* u)
{
  CorrectedMeasures m;
  if (corners < 3)
    return m;
  if (corners == 3)
  {
    AddTriangle(At(x, 0), At(x, 1), At(x, 2), At(u, 0), At(u, 1), At(u, 2), m);
    return m;
  }
  V3 b = V3::Zero(), ub = V3::Zero();
  for (int i = 0; i < corners; ++i)
  {
    b += At(x, i);
    ub += At(u, i).normalized();
  }
  b /= corners;
  ub = ub.norm() > 0 ? ub.normalized() : ub;
  for (int i = 0; i < corners; ++i)
  {
    const int j = (i + 1) % corners;
    AddTriangle(b, At(x, i), At(x, j), ub, At(u, i), At(u, j), m);
  }
  return m;
}

double CurvatureReach(const CurvatureParameters& parameters, double edgeLength)
{
  // A ball and its ramp, and the ring of faces around a ball face's corners
  // (its corner normals). With the per-face radius, in cells of side s =
  // (R + l/2) / 2: a face blends the representatives within 1.5 s of it,
  // whose radius comes from the representatives of the 3 x 3 x 3 cells
  // around theirs (within 2 sqrt(3) s), whose balls of up to 3 R (their
  // cells' sums counted with a ramp of s / 2 each side) take the sums of
  // whole cells (faces within sqrt(3) s of their cell's mean centre): 3 R
  // + (1.5 + 2 sqrt(3) + 0.5 + sqrt(3)) s < 3 R + 8 s.
  const double s = 0.5 * (parameters.Radius + 0.5 * edgeLength);
  const double ball = parameters.AdaptiveRadius
    ? kMaxRadiusFactor * parameters.Radius + 8 * s
    : parameters.Radius;
  return ball + 3 * edgeLength;
}

bool ComputeCorrectedCurvatures(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* normals, const int* region, const CurvatureParameters& par,
  CurvatureResult& result, std::string* error, const unsigned char* ghost,
  const std::int64_t* faceIds)
{
  auto fail = [&](const std::string& message) {
    if (error)
      *error = message;
    return false;
  };
  if (offsets.empty() || offsets.front() != 0 ||
    offsets.back() != static_cast<std::int64_t>(connectivity.size()))
    return fail("inconsistent polygon offsets");
  if (!(par.Radius > 0) || !std::isfinite(par.Radius))
    return fail("the ball radius must be a positive number");
  const std::int64_t F = static_cast<std::int64_t>(offsets.size()) - 1;
  for (std::int64_t id : connectivity)
    if (id < 0 || id >= numberOfPoints)
      return fail("a polygon refers to a point that does not exist");
  for (std::int64_t f = 0; f < F; ++f)
  {
    const double n = At(normals, f).norm();
    if (!(std::abs(n - 1) < 1e-3))
      return fail("the normal field is not made of unit vectors (face " + std::to_string(f) + ")");
  }

  // Faces around each point (CSR).
  std::vector<std::int64_t> start(numberOfPoints + 1, 0), around(connectivity.size());
  for (std::int64_t id : connectivity)
    ++start[id + 1];
  for (std::int64_t p = 0; p < numberOfPoints; ++p)
    start[p + 1] += start[p];
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::int64_t f = 0; f < F; ++f)
      for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
        around[fill[connectivity[k]]++] = f;
  }
  const auto sameSide = [&](std::int64_t f, std::int64_t g) {
    return !region || region[f] == region[g];
  };
  const auto isGhost = [&](std::int64_t f) { return ghost && ghost[f] != 0; };

  // Each face's measures, with corner normals from the faces around each
  // corner: all of them (perSide false), or those of the face's own region.
  std::vector<V3> centre(F);
  const auto faceMeasures = [&](bool perSide, std::vector<CorrectedMeasures>& measures) {
    measures.assign(F, CorrectedMeasures());
    vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
      std::vector<double> x, u;
      for (std::int64_t f = begin; f < end; ++f)
      {
        const int m = static_cast<int>(offsets[f + 1] - offsets[f]);
        x.assign(3 * m, 0.0);
        u.assign(3 * m, 0.0);
        V3 c = V3::Zero();
        for (int i = 0; i < m; ++i)
        {
          const std::int64_t p = connectivity[offsets[f] + i];
          const V3 xp = At(points, p);
          c += xp;
          V3 up = V3::Zero();
          for (std::int64_t k = start[p]; k < start[p + 1]; ++k)
            if (!perSide || sameSide(f, around[k]))
              up += At(normals, around[k]);
          up = up.norm() > 0 ? up.normalized() : At(normals, f);
          for (int d = 0; d < 3; ++d)
          {
            x[3 * i + d] = xp[d];
            u[3 * i + d] = up[d];
          }
        }
        centre[f] = m > 0 ? V3(c / m) : c;
        measures[f] = PolygonMeasures(m, x.data(), u.data());
      }
    });
  };
  std::vector<CorrectedMeasures> measures;
  faceMeasures(region != nullptr, measures);
  // Per side, a face with a corner on another region's face has corner
  // normals from one side of that corner only, which understate how the
  // normal turns across it: such faces lend no measures to balls that hold
  // faces whose corners are all inside their region (their ball still
  // measures them, from those faces).
  std::vector<char> interior(F, 1);
  if (region)
    for (std::int64_t f = 0; f < F; ++f)
      for (std::int64_t k = offsets[f]; k < offsets[f + 1] && interior[f]; ++k)
      {
        const std::int64_t p = connectivity[k];
        for (std::int64_t j = start[p]; j < start[p + 1]; ++j)
          if (!sameSide(f, around[j]))
          {
            interior[f] = 0;
            break;
          }
      }
  // The normal of side `f` at point p: the mean of f's region's faces
  // around p.
  const auto cornerNormal = [&](std::int64_t f, std::int64_t p) {
    V3 up = V3::Zero();
    for (std::int64_t k = start[p]; k < start[p + 1]; ++k)
      if (sameSide(f, around[k]))
        up += At(normals, around[k]);
    return up.norm() > 0 ? V3(up.normalized()) : At(normals, f);
  };

  // The faces' own complex: each edge with the faces on it, from the sorted
  // (low point, high point, face) triples, with the corners (positions in
  // `connectivity`) of the edge's two points in that face.
  struct EdgeFace
  {
    std::int64_t A, B, F, KA, KB;
    bool operator<(const EdgeFace& o) const
    {
      return A != o.A ? A < o.A : (B != o.B ? B < o.B : F < o.F);
    }
  };
  std::vector<EdgeFace> edges;
  edges.reserve(connectivity.size());
  std::vector<std::int64_t> faceOfCorner(connectivity.size());
  double edgeSum = 0;
  std::int64_t edgeCount = 0;
  for (std::int64_t f = 0; f < F; ++f)
  {
    const std::int64_t m = offsets[f + 1] - offsets[f];
    for (std::int64_t i = 0; i < m; ++i)
    {
      const std::int64_t ki = offsets[f] + i, kj = offsets[f] + (i + 1) % m;
      const std::int64_t p = connectivity[ki], q = connectivity[kj];
      faceOfCorner[ki] = f;
      edges.push_back(p < q ? EdgeFace{ p, q, f, ki, kj } : EdgeFace{ q, p, f, kj, ki });
      edgeSum += (At(points, p) - At(points, q)).norm();
      ++edgeCount;
    }
  }
  std::sort(edges.begin(), edges.end());

  // The surface as a 2-manifold: two faces on an edge are joined there; at
  // an edge of four faces (two voxels touching along an edge only) each
  // face is joined to the one it makes a convex fold with (the faces of one
  // inside voxel: inside voxels are 6-connected, as everywhere in the
  // module). A point is one surface point per fan of faces joined around it
  // (two at a pinch). Corners are the nodes of a union-find.
  std::vector<std::int64_t> parent(connectivity.size());
  for (std::size_t k = 0; k < parent.size(); ++k)
    parent[k] = static_cast<std::int64_t>(k);
  const auto find = [&](std::int64_t k) {
    while (parent[k] != k)
      k = parent[k] = parent[parent[k]];
    return k;
  };
  const auto unite = [&](std::int64_t a, std::int64_t b) {
    a = find(a);
    b = find(b);
    if (a != b)
      parent[std::max(a, b)] = std::min(a, b);
  };
  const auto faceNormal = [&](std::int64_t f) {
    V3 n = V3::Zero();
    const std::int64_t m = offsets[f + 1] - offsets[f];
    for (std::int64_t i = 0; i < m; ++i)
      n += At(points, connectivity[offsets[f] + i]).cross(At(points, connectivity[offsets[f] + (i + 1) % m]));
    return n;
  };

  // Whole-surface figures over the faces this call owns (not ghost). The
  // Euler characteristic counts each edge and point for the share of its
  // faces owned here, so that pieces' figures add up to the whole's.
  result.BoundaryEdges = 0;
  result.CreaseEdges.clear();
  result.CreaseAngle.clear();
  result.CreaseLength.clear();
  struct Crease
  {
    std::int64_t A, B, F, G;
  };
  std::vector<Crease> creases;
  double chi = 0;
  for (std::size_t i = 0; i < edges.size();)
  {
    std::size_t j = i;
    std::int64_t own = 0;
    while (j < edges.size() && edges[j].A == edges[i].A && edges[j].B == edges[i].B)
      own += isGhost(edges[j++].F) ? 0 : 1;
    const std::int64_t n = static_cast<std::int64_t>(j - i);
    const auto join = [&](std::size_t a, std::size_t b) {
      unite(edges[a].KA, edges[b].KA);
      unite(edges[a].KB, edges[b].KB);
    };
    bool paired = false;
    if (n == 4)
    {
      const V3 mid = 0.5 * (At(points, edges[i].A) + At(points, edges[i].B));
      int partner[4] = { -1, -1, -1, -1 };
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          if (a != b && faceNormal(edges[i + a].F).dot(centre[edges[i + b].F] - mid) < 0 &&
            faceNormal(edges[i + b].F).dot(centre[edges[i + a].F] - mid) < 0)
            partner[a] = partner[a] == -1 ? b : -2;
      paired = true;
      for (int a = 0; a < 4; ++a)
        paired = paired && partner[a] >= 0 && partner[partner[a]] == a;
      if (paired)
        for (int a = 0; a < 4; ++a)
          if (a < partner[a])
          {
            join(i + a, i + partner[a]);
            const int shared = (isGhost(edges[i + a].F) ? 0 : 1) + (isGhost(edges[i + partner[a]].F) ? 0 : 1);
            chi -= 0.5 * shared;
          }
    }
    if (!paired)
    {
      // A manifold edge, a boundary edge, or a junction this rule does not
      // resolve (three label sheets): one edge joining all its faces.
      for (std::size_t k = i + 1; k < j; ++k)
        join(i, k);
      chi -= static_cast<double>(own) / static_cast<double>(n);
    }
    if (own > 0 && n == 1)
      ++result.BoundaryEdges;
    // A crease edge is reported once, by the piece owning its face of
    // smaller id, and oriented from that face.
    if (region && n == 2 && region[edges[i].F] != region[edges[i + 1].F])
    {
      std::int64_t f = edges[i].F, g = edges[i + 1].F;
      if (faceIds ? faceIds[g] < faceIds[f] : g < f)
        std::swap(f, g);
      if (!isGhost(f))
        creases.push_back({ edges[i].A, edges[i].B, f, g });
    }
    i = j;
  }
  // Surface points: one per fan, counted for its share of owned corners;
  // each fan's normal is the mean of its faces' (the continuous field).
  std::vector<std::int64_t> fanCorners(connectivity.size(), 0), fanOwned(connectivity.size(), 0);
  std::vector<V3> fanNormal(connectivity.size(), V3::Zero());
  for (std::size_t k = 0; k < connectivity.size(); ++k)
  {
    const std::int64_t r = find(static_cast<std::int64_t>(k));
    ++fanCorners[r];
    fanOwned[r] += isGhost(faceOfCorner[k]) ? 0 : 1;
    fanNormal[r] += At(normals, faceOfCorner[k]);
  }
  for (std::size_t k = 0; k < connectivity.size(); ++k)
    if (fanCorners[k] > 0)
    {
      chi += static_cast<double>(fanOwned[k]) / static_cast<double>(fanCorners[k]);
      if (fanNormal[k].norm() > 0)
        fanNormal[k].normalize();
    }

  // The integral of G over the whole surface: the area the continuous field
  // (corner normals: the mean over the corner's fan) sweeps on the unit
  // sphere, each triangle (b, x_i, x_{i+1}) of a face as the exact solid
  // angle of its three unit normals. Summed over a closed surface this is
  // 2 pi times its Euler characteristic whatever the field, even across
  // creases, where the first-order mu2 falls short.
  const auto solidAngle = [](const V3& a, const V3& b, const V3& c) {
    return 2.0 * std::atan2(a.dot(b.cross(c)), 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
  };
  result.Area = result.TotalGaussian = 0;
  double volume = 0;
  for (std::int64_t f = 0; f < F; ++f)
  {
    const std::int64_t m = offsets[f + 1] - offsets[f];
    if (isGhost(f) || m < 3)
      continue;
    result.Area += measures[f].Mu0;
    chi += 1;
    V3 ub = V3::Zero();
    for (std::int64_t i = 0; i < m; ++i)
      ub += fanNormal[find(offsets[f] + i)];
    ub = ub.norm() > 0 ? V3(ub.normalized()) : At(normals, f);
    for (std::int64_t i = 0; i < m; ++i)
      result.TotalGaussian += solidAngle(ub, fanNormal[find(offsets[f] + i)],
        fanNormal[find(offsets[f] + (i + 1) % m)]);
    const V3 x0 = At(points, connectivity[offsets[f]]);
    for (std::int64_t i = 1; i + 1 < m; ++i)
      volume += x0.dot(At(points, connectivity[offsets[f] + i])
                         .cross(At(points, connectivity[offsets[f] + i + 1]))) / 6.0;
  }
  result.EulerShare = chi;
  result.EulerCharacteristic = static_cast<std::int64_t>(std::llround(chi));
  result.Volume = result.BoundaryEdges ? std::nan("") : volume;

  // A face cut by the ball's sphere counts for the share of it inside,
  // estimated from its centre's distance d: 1/2 + (R - d) / l, clamped to
  // [0, 1], l the mean edge length (exact for a square face of side l moving
  // across a plane, and the sphere is locally a plane for R >> l).
  const double l = par.EdgeLength > 0 ? par.EdgeLength : (edgeCount ? edgeSum / edgeCount : 1.0);
  const double R = par.Radius, reach = R + 0.5 * l;
  const bool adaptive = par.AdaptiveRadius;

  // The faces sorted into cubic cells of side reach / 2 and copied in that
  // order, one array per quantity: every ball around a face of a cell lies
  // within the 5 x 5 x 5 cells around it, whose faces are a few contiguous
  // runs that all faces of the cell read (on octa-flower 512^3 this is
  // what made the stage 3 times faster than a hash lookup per face). The
  // cells are ordered by blocks of 3 x 3 x 3 (the per-face radius's
  // representative balls, up to 3 R, read the 5 x 5 x 5 blocks around
  // theirs in the same way).
  const double side = 0.5 * reach;
  const auto cellOfPoint = [&](const V3& c) {
    return std::array<std::int64_t, 3>{ static_cast<std::int64_t>(std::floor(c.x() / side)),
      static_cast<std::int64_t>(std::floor(c.y() / side)),
      static_cast<std::int64_t>(std::floor(c.z() / side)) };
  };
  const auto block = [](std::int64_t v) { return v >= 0 ? v / 3 : -((2 - v) / 3); };
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
      const auto c = cellOfPoint(centre[f]);
      order[f] = { Pack(block(c[0]), block(c[1]), block(c[2])), Pack(c[0], c[1], c[2]), f };
    }
  });
  std::sort(order.begin(), order.end());
  std::vector<std::int64_t> cellStart, blockStart;
  std::unordered_map<std::int64_t, std::int64_t> cellOf, blockOf;
  for (std::int64_t i = 0; i < F; ++i)
  {
    if (i == 0 || order[i].Cell != order[i - 1].Cell)
    {
      cellOf.emplace(order[i].Cell, static_cast<std::int64_t>(cellStart.size()));
      cellStart.push_back(i);
    }
    if (adaptive && (i == 0 || order[i].Block != order[i - 1].Block))
    {
      blockOf.emplace(order[i].Block, static_cast<std::int64_t>(blockStart.size()));
      blockStart.push_back(i);
    }
  }
  const std::int64_t cells = static_cast<std::int64_t>(cellStart.size());
  const std::int64_t blocks = static_cast<std::int64_t>(blockStart.size());
  cellStart.push_back(F);
  blockStart.push_back(F);
  std::vector<std::vector<double>> q(QUANTITIES, std::vector<double>(F));
  std::vector<int> side_(F, 0);
  std::vector<char> inner(F, 0);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      const std::int64_t f = order[i].F;
      const CorrectedMeasures& m = measures[f];
      const double values[QUANTITIES] = { centre[f].x(), centre[f].y(), centre[f].z(), m.Mu0, m.Mu1,
        m.Mu2, m.MuXY[0], m.MuXY[4], m.MuXY[8], 0.5 * (m.MuXY[1] + m.MuXY[3]),
        0.5 * (m.MuXY[2] + m.MuXY[6]), 0.5 * (m.MuXY[5] + m.MuXY[7]), normals[3 * f],
        normals[3 * f + 1], normals[3 * f + 2] };
      for (int k = 0; k < QUANTITIES; ++k)
        q[k][i] = values[k];
      side_[i] = region ? region[f] : 0;
      inner[i] = interior[f];
    }
  });
  using Runs = std::vector<std::pair<std::int64_t, std::int64_t>>;
  // The runs of faces in the 5 x 5 x 5 cells around a cell.
  const auto neighbourRuns = [&](const std::array<std::int64_t, 3>& c, Runs& runs) {
    runs.clear();
    for (int dx = -2; dx <= 2; ++dx)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dz = -2; dz <= 2; ++dz)
        {
          const auto it = cellOf.find(Pack(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it != cellOf.end())
            runs.emplace_back(cellStart[it->second], cellStart[it->second + 1]);
        }
  };

  // The faces a cell's balls of radius r <= R may hold, copied together
  // (position, region, interior, the summed quantities): the faces of the
  // 5 x 5 x 5 cells around it whose centre lies within r + l/2 of the box
  // of the cell's face centres, in the cells' order.
  struct Candidate
  {
    double X, Y, Z, Q[SUMS];
    int Region, Inner;
  };
  const auto gather = [&](std::int64_t c, double r, Runs& runs, std::vector<Candidate>& candidates) {
    V3 lo = centre[order[cellStart[c]].F], hi = lo;
    for (std::int64_t i = cellStart[c]; i < cellStart[c + 1]; ++i)
    {
      lo = lo.cwiseMin(centre[order[i].F]);
      hi = hi.cwiseMax(centre[order[i].F]);
    }
    neighbourRuns(cellOfPoint(lo), runs);
    const double rr = r + 0.5 * l, rr2 = rr * rr;
    candidates.clear();
    for (const auto& run : runs)
      for (std::int64_t j = run.first; j < run.second; ++j)
      {
        const double x = q[CX][j], y = q[CY][j], z = q[CZ][j];
        const double ex = std::max({ lo.x() - x, 0.0, x - hi.x() });
        const double ey = std::max({ lo.y() - y, 0.0, y - hi.y() });
        const double ez = std::max({ lo.z() - z, 0.0, z - hi.z() });
        if (ex * ex + ey * ey + ez * ez >= rr2)
          continue;
        Candidate cand;
        cand.X = x;
        cand.Y = y;
        cand.Z = z;
        for (int m = 0; m < SUMS; ++m)
          cand.Q[m] = q[M0 + m][j];
        cand.Region = side_[j];
        cand.Inner = inner[j];
        candidates.push_back(cand);
      }
  };

  // The ball sums (q[M0..NZ]) around the face at position i of `order`,
  // radius r <= R, over its cell's candidates: the interior faces of its
  // region first, all of its region's faces when the ball holds none (a
  // strip narrower than a face ring). Returns true when the ball is not a
  // whole disc of interior faces of the face's region: it reaches a face of
  // another region or a face along a crease, or it had to take all of its
  // region's faces.
  const auto ballSums = [&](std::int64_t i, double r, const std::vector<Candidate>& candidates,
                          double* sum) {
    const double x = q[CX][i], y = q[CY][i], z = q[CZ][i];
    const double rr = r + 0.5 * l, rr2 = rr * rr;
    const double full = std::max(r - 0.5 * l, 0.0), full2 = full * full; // weight 1 within
    const int own = side_[i];
    std::fill(sum, sum + QUANTITIES, 0.0);
    double* total = sum + M0;
    bool border = false;
    int pass = 0;
    for (; pass < 2 && !(sum[M0] > 0); ++pass)
      for (const Candidate& cand : candidates)
      {
        const bool skip = cand.Region != own || (pass == 0 && !cand.Inner);
        if (skip && border)
          continue;
        const double ex = cand.X - x, ey = cand.Y - y, ez = cand.Z - z;
        const double d2 = ex * ex + ey * ey + ez * ez;
        if (d2 >= rr2)
          continue;
        if (skip)
        {
          border = true;
          continue;
        }
        const double w = d2 <= full2 ? 1.0 : std::min(1.0, 0.5 + (r - std::sqrt(d2)) / l);
        for (int m = 0; m < SUMS; ++m)
          total[m] += w * cand.Q[m];
      }
    return border || pass == 2;
  };

  result.Mean.assign(F, 0.0);
  result.BallNormal.assign(3 * F, 0.0);
  result.Gaussian.assign(F, 0.0);
  result.K1.assign(F, 0.0);
  result.K2.assign(F, 0.0);
  result.D1.assign(3 * F, 0.0);
  result.D2.assign(3 * F, 0.0);
  result.BallRadius.assign(F, 0.0);
  // The curvatures of face f from its ball sums; false when the ball has no
  // area (the face keeps zeros). directions false: H, G, k1 and k2 only
  // (a first pass whose face will be measured again).
  const auto finish = [&](std::int64_t f, const double* sum, bool directions = true) {
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
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(
      A, directions ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
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
  };

  // With the per-face radius: the faces of each cell and region are a
  // group, with their interior faces' sums and mean centre, and a
  // representative face, the one nearest the cell's centre (ties: the
  // smaller global id), whose balls of R to 3R give the noise and the
  // variation of the curvature around it (below).
  std::vector<std::int64_t> cellGroupStart, blockGroupStart, groupRep;
  std::vector<int> groupRegion;
  std::vector<double> groupSums;
  std::vector<V3> groupCentre;
  if (adaptive)
  {
    cellGroupStart.assign(cells + 1, 0);
    blockGroupStart.assign(blocks + 1, 0);
    std::int64_t b = 0;
    for (std::int64_t c = 0; c < cells; ++c)
    {
      while (b < blocks && blockStart[b] <= cellStart[c])
        blockGroupStart[b++] = static_cast<std::int64_t>(groupRep.size());
      cellGroupStart[c] = static_cast<std::int64_t>(groupRep.size());
      const auto cc = cellOfPoint(centre[order[cellStart[c]].F]);
      const V3 middle((cc[0] + 0.5) * side, (cc[1] + 0.5) * side, (cc[2] + 0.5) * side);
      const std::size_t firstGroup = groupRep.size();
      for (std::int64_t i = cellStart[c]; i < cellStart[c + 1]; ++i)
      {
        std::size_t g = firstGroup;
        while (g < groupRep.size() && groupRegion[g] != side_[i])
          ++g;
        if (g == groupRep.size())
        {
          groupRep.push_back(i);
          groupRegion.push_back(side_[i]);
          groupSums.resize(groupSums.size() + SUMS, 0.0);
          groupCentre.push_back(V3::Zero());
        }
        else
        {
          const std::int64_t j = groupRep[g];
          const double di = (centre[order[i].F] - middle).squaredNorm();
          const double dj = (centre[order[j].F] - middle).squaredNorm();
          const std::int64_t idi = faceIds ? faceIds[order[i].F] : order[i].F;
          const std::int64_t idj = faceIds ? faceIds[order[j].F] : order[j].F;
          if (di < dj || (di == dj && idi < idj))
            groupRep[g] = i;
        }
        if (inner[i])
        {
          for (int m = 0; m < SUMS; ++m)
            groupSums[SUMS * g + m] += q[M0 + m][i];
          groupCentre[g] += centre[order[i].F];
        }
      }
      for (std::size_t g = firstGroup; g < groupRep.size(); ++g)
      {
        std::int64_t count = 0;
        for (std::int64_t i = cellStart[c]; i < cellStart[c + 1]; ++i)
          count += (inner[i] && side_[i] == groupRegion[g]) ? 1 : 0;
        if (count > 0)
          groupCentre[g] /= static_cast<double>(count);
      }
    }
    while (b <= blocks)
      blockGroupStart[b++] = static_cast<std::int64_t>(groupRep.size());
    cellGroupStart[cells] = static_cast<std::int64_t>(groupRep.size());
  }
  const std::int64_t nGroups = static_cast<std::int64_t>(groupRep.size());
  std::vector<char> isRep(adaptive ? F : 0, 0);
  for (const std::int64_t i : groupRep)
    isRep[i] = 1;

  // First pass: every face's ball of radius R. With the per-face radius,
  // its sums are kept (the larger balls add to them), and whether the ball
  // is a whole disc of its region's interior faces: a face whose ball of R
  // reaches its region's border keeps R (the rule below assumes a disc; on
  // a strip narrower than the ball, a cube's side near its edges, the noise
  // and the bias grow otherwise with r).
  std::vector<double> firstSums(adaptive ? static_cast<std::size_t>(SUMS) * F : 0);
  std::vector<char> keepRadius(adaptive ? F : 0, 0);
  vtkSMPTools::For(0, cells, [&](std::int64_t begin, std::int64_t end) {
    Runs runs;
    std::vector<Candidate> candidates;
    double sum[QUANTITIES];
    for (std::int64_t c = begin; c < end; ++c)
    {
      const std::int64_t first = cellStart[c];
      candidates.clear();
      for (std::int64_t i = first; i < cellStart[c + 1]; ++i)
      {
        const std::int64_t f = order[i].F;
        if (isGhost(f) && !(adaptive && isRep[i]))
          continue;
        if (candidates.empty())
          gather(c, R, runs, candidates);
        const bool border = ballSums(i, R, candidates, sum);
        // A face that will be measured again needs only its k1, k2 here.
        if (!isGhost(f) && finish(f, sum, !adaptive || border))
          result.BallRadius[f] = R;
        if (adaptive)
        {
          std::copy(sum + M0, sum + QUANTITIES, firstSums.begin() + SUMS * i);
          keepRadius[i] = border ? 1 : 0;
        }
      }
    }
  });

  if (adaptive)
  {
    // The ball radius per face (docs/curvature-measures.md, "The ball radius
    // per face"). The error of H over a ball of radius r is a bias that
    // grows like a r^2 where the curvature varies (a = Laplacian(H) / 8 on
    // a flat disc) and a noise whose deviation falls like s r^-3/2 (the
    // ball's mu1 is the flux of the field's tangential error through its
    // rim: a sum along its length ~ r, over its area ~ r^2). Their squared
    // sum is smallest at r* = R (3 s_R^2 / (4 a^2 R^4))^(1/7), s_R the
    // noise at R. s_R and a are measured around each face from balls of R,
    // 1.5 R, 2 R and 3 R; r* is kept within [2R/3, 3R] and below the face's
    // smallest curvature radius 1 / max(|k1|, |k2|) (a larger ball reaches
    // round the surface, where the expansion no longer holds).
    const double ladder[] = { 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0 };
    constexpr int K = 7, K15 = 2, K2 = 4, K3 = 6;
    double L[K];
    for (int k = 0; k < K; ++k)
      L[k] = ladder[k] * R;
    const double minRadius = kMinRadiusFactor * R, maxRadius = kMaxRadiusFactor * R;
    // Cells' sums count in a ball by their centre's distance with a ramp as
    // wide as a cell (their faces spread over it).
    const double soft = side, ringReach = maxRadius + 0.5 * soft;

    // Rings: for each representative (below), its cumulative sums C_k over
    // the balls of L[k], from the cells' sums of their region's interior
    // faces; a face's ball of r > R is its own ball of R plus C(r) - C_0 of
    // the representatives near it, blended.
    std::vector<double> ring(static_cast<std::size_t>(nGroups) * K * SUMS, 0.0);
    std::vector<double> repH(static_cast<std::size_t>(nGroups) * 4, 0.0); // H at R, 1.5R, 2R, 3R
    std::vector<char> repValid(nGroups, 0);
    struct GroupCandidate
    {
      double X, Y, Z, Q[SUMS];
      int Region;
    };
    vtkSMPTools::For(0, blocks, [&](std::int64_t begin, std::int64_t end) {
      std::vector<GroupCandidate> near;
      for (std::int64_t b = begin; b < end; ++b)
      {
        const std::int64_t g0 = blockGroupStart[b], g1 = blockGroupStart[b + 1];
        if (g0 == g1)
          continue;
        // The groups within ringReach of the box of the block's
        // representatives, from the 7 x 7 x 7 blocks around it.
        V3 lo = centre[order[groupRep[g0]].F], hi = lo;
        for (std::int64_t g = g0; g < g1; ++g)
        {
          lo = lo.cwiseMin(centre[order[groupRep[g]].F]);
          hi = hi.cwiseMax(centre[order[groupRep[g]].F]);
        }
        const auto cc = cellOfPoint(centre[order[blockStart[b]].F]);
        const std::int64_t bx = block(cc[0]), by = block(cc[1]), bz = block(cc[2]);
        near.clear();
        for (int dx = -3; dx <= 3; ++dx)
          for (int dy = -3; dy <= 3; ++dy)
            for (int dz = -3; dz <= 3; ++dz)
            {
              const auto it = blockOf.find(Pack(bx + dx, by + dy, bz + dz));
              if (it == blockOf.end())
                continue;
              for (std::int64_t h = blockGroupStart[it->second]; h < blockGroupStart[it->second + 1]; ++h)
              {
                if (!(groupSums[SUMS * h] > 0))
                  continue;
                const V3& x = groupCentre[h];
                const double ex = std::max({ lo.x() - x.x(), 0.0, x.x() - hi.x() });
                const double ey = std::max({ lo.y() - x.y(), 0.0, x.y() - hi.y() });
                const double ez = std::max({ lo.z() - x.z(), 0.0, x.z() - hi.z() });
                if (ex * ex + ey * ey + ez * ez >= ringReach * ringReach)
                  continue;
                GroupCandidate cand;
                cand.X = x.x();
                cand.Y = x.y();
                cand.Z = x.z();
                for (int m = 0; m < SUMS; ++m)
                  cand.Q[m] = groupSums[SUMS * h + m];
                cand.Region = groupRegion[h];
                near.push_back(cand);
              }
            }
        for (std::int64_t g = g0; g < g1; ++g)
        {
          const std::int64_t i = groupRep[g];
          const double* s0 = &firstSums[SUMS * i];
          if (!(s0[0] > 0))
            continue;
          double* s = &ring[static_cast<std::size_t>(g) * K * SUMS];
          const V3 x = centre[order[i].F];
          for (const GroupCandidate& cand : near)
          {
            if (cand.Region != groupRegion[g])
              continue;
            const double ex = cand.X - x.x(), ey = cand.Y - x.y(), ez = cand.Z - x.z();
            const double d2 = ex * ex + ey * ey + ez * ez;
            if (d2 >= ringReach * ringReach)
              continue;
            const double d = std::sqrt(d2);
            double before = 0;
            for (int k = 0; k < K && before < 1; ++k)
            {
              const double w = std::min(1.0, std::max(0.0, 0.5 + (L[k] - d) / soft));
              if (w > before)
              {
                double* sk = s + k * SUMS;
                for (int m = 0; m < SUMS; ++m)
                  sk[m] += (w - before) * cand.Q[m];
                before = w;
              }
            }
          }
          for (int k = 1; k < K; ++k)
            for (int m = 0; m < SUMS; ++m)
              s[k * SUMS + m] += s[(k - 1) * SUMS + m];
          bool valid = true;
          const int at[4] = { 0, K15, K2, K3 };
          for (int n = 0; n < 4 && valid; ++n)
          {
            const int k = at[n];
            const double mu0 = s0[0] + s[k * SUMS] - s[0], mu1 = s0[M1 - M0] + s[k * SUMS + M1 - M0] - s[M1 - M0];
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
    vtkSMPTools::For(0, cells, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t c = begin; c < end; ++c)
      {
        const auto cc = cellOfPoint(centre[order[cellStart[c]].F]);
        double e2 = 0, d2 = 0, d3 = 0;
        int n = 0;
        bool any = false;
        for (std::int64_t g = cellGroupStart[c]; g < cellGroupStart[c + 1]; ++g)
          any = any || (repValid[g] && !keepRadius[groupRep[g]]);
        if (!any)
          continue;
        for (std::int64_t g = cellGroupStart[c]; g < cellGroupStart[c + 1]; ++g)
        {
          if (!repValid[g] || keepRadius[groupRep[g]])
            continue;
          e2 = d2 = d3 = 0;
          n = 0;
          for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dz = -1; dz <= 1; ++dz)
              {
                const auto it = cellOf.find(Pack(cc[0] + dx, cc[1] + dy, cc[2] + dz));
                if (it == cellOf.end())
                  continue;
                for (std::int64_t h = cellGroupStart[it->second]; h < cellGroupStart[it->second + 1]; ++h)
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
                              std::max(d3 * d3 - var3 * noise2 / samples, 0.0) / 64) / R4;
          repRadius[g] = a2 > 0 ? R * std::pow(0.75 * noise2 / (a2 * R4), 1.0 / 7.0) : maxRadius;
        }
      }
    });

    // Per face whose ball of R is a whole disc: the representatives within
    // 1.5 cells, weighted 1 - d / 1.5 cells, give the radius (then bounded
    // by the face's own curvature radius and [2R/3, 3R]) and the rings.
    const double blend = 1.5 * side, cellReach = blend + 0.5 * std::sqrt(3.0) * side;
    struct NearRep
    {
      double X, Y, Z;
      std::int64_t G;
      int Region;
    };
    vtkSMPTools::For(0, cells, [&](std::int64_t begin, std::int64_t end) {
      Runs runs;
      std::vector<Candidate> candidates;
      std::vector<NearRep> nearGroups;
      std::vector<std::pair<std::int64_t, double>> weights;
      double sum[QUANTITIES];
      for (std::int64_t c = begin; c < end; ++c)
      {
        const std::int64_t first = cellStart[c];
        bool any = false;
        for (std::int64_t i = first; i < cellStart[c + 1] && !any; ++i)
          any = !isGhost(order[i].F) && !keepRadius[i] && result.BallRadius[order[i].F] > 0;
        if (!any)
          continue;
        // The representatives that may lie within `blend` of a face of the
        // cell, and the cell's runs, once a face needs a smaller ball.
        const auto cc = cellOfPoint(centre[order[first].F]);
        const V3 middle((cc[0] + 0.5) * side, (cc[1] + 0.5) * side, (cc[2] + 0.5) * side);
        nearGroups.clear();
        for (int dx = -2; dx <= 2; ++dx)
          for (int dy = -2; dy <= 2; ++dy)
            for (int dz = -2; dz <= 2; ++dz)
            {
              const auto it = cellOf.find(Pack(cc[0] + dx, cc[1] + dy, cc[2] + dz));
              if (it != cellOf.end())
                for (std::int64_t g = cellGroupStart[it->second]; g < cellGroupStart[it->second + 1]; ++g)
                {
                  const V3& x = centre[order[groupRep[g]].F];
                  if (repRadius[g] > 0 && (x - middle).squaredNorm() < cellReach * cellReach)
                    nearGroups.push_back({ x.x(), x.y(), x.z(), g, groupRegion[g] });
                }
            }
        candidates.clear();
        for (std::int64_t i = first; i < cellStart[c + 1]; ++i)
        {
          const std::int64_t f = order[i].F;
          if (isGhost(f) || keepRadius[i] || result.BallRadius[f] == 0)
            continue;
          double wSum = 0, r = 0;
          weights.clear();
          const double x = q[CX][i], y = q[CY][i], z = q[CZ][i];
          for (const NearRep& near : nearGroups)
          {
            const double ex = near.X - x, ey = near.Y - y, ez = near.Z - z;
            const double d2 = ex * ex + ey * ey + ez * ez;
            if (near.Region != side_[i] || d2 >= blend * blend)
              continue;
            const double w = 1 - std::sqrt(d2) / blend;
            weights.emplace_back(near.G, w);
            wSum += w;
            r += w * repRadius[near.G];
          }
          const auto keep = [&]() {
            std::copy(firstSums.begin() + SUMS * i, firstSums.begin() + SUMS * (i + 1), sum + M0);
            finish(f, sum);
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
            if (candidates.empty())
              gather(c, R, runs, candidates);
            ballSums(i, r, candidates, sum);
            if (finish(f, sum))
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
            const double t = std::min(1.0, (r * r - L[k] * L[k]) / (L[k + 1] * L[k + 1] - L[k] * L[k]));
            std::copy(firstSums.begin() + SUMS * i, firstSums.begin() + SUMS * (i + 1), sum + M0);
            for (const auto& w : weights)
            {
              const double* s = &ring[static_cast<std::size_t>(w.first) * K * SUMS];
              const double u = w.second / wSum;
              for (int m = 0; m < SUMS; ++m)
                sum[M0 + m] += u * ((1 - t) * s[k * SUMS + m] + t * s[(k + 1) * SUMS + m] - s[m]);
            }
            if (finish(f, sum))
              result.BallRadius[f] = r;
            else
              keep();
          }
        }
      }
    });
  }

  // The integral of H: per side, each interior face's own measure and each
  // boundary face's ball estimate over its area, plus what the creases hold;
  // with one region, the faces' measures.
  result.TotalMean = 0;
  for (std::int64_t f = 0; f < F; ++f)
    if (!isGhost(f))
      result.TotalMean += interior[f] ? 0.5 * measures[f].Mu1 : result.Mean[f] * measures[f].Mu0;

  // Each crease edge: the normal's turn from one side's normal at the edge
  // (its corner normals at the edge's two ends) to the other's, convex when
  // the second face's centre lies below the first side's plane more than
  // the first's lies below the second's; its length along the crease
  // (t = n_a x n_b), so that a staircase of voxel edges along a slanted
  // crease counts for the crease's own length.
  result.CreaseTotalMean = 0;
  for (const Crease& c : creases)
  {
    const V3 na = (cornerNormal(c.F, c.A) + cornerNormal(c.F, c.B)).normalized();
    const V3 nb = (cornerNormal(c.G, c.A) + cornerNormal(c.G, c.B)).normalized();
    const V3 axis = na.cross(nb);
    const double turn = std::atan2(axis.norm(), na.dot(nb));
    const bool convex = (centre[c.G] - centre[c.F]).dot(na - nb) <= 0;
    const double angle = convex ? turn : -turn;
    const V3 edge = At(points, c.B) - At(points, c.A);
    const double length = axis.norm() > 1e-6 ? std::abs(edge.dot(axis.normalized())) : edge.norm();
    result.CreaseEdges.push_back(c.A);
    result.CreaseEdges.push_back(c.B);
    result.CreaseAngle.push_back(angle);
    result.CreaseLength.push_back(length);
    result.CreaseTotalMean += 0.5 * angle * length;
  }
  result.TotalMean += result.CreaseTotalMean;
  return true;
}

} // namespace dg
