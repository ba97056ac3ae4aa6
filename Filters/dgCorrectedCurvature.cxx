#include "dgCorrectedCurvature.h"

#include <vtkSMPTools.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
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

// Cell key of a uniform grid of cell size h (21 bits per axis).
std::int64_t Key(const V3& c, double h, int dx = 0, int dy = 0, int dz = 0)
{
  const auto k = [&](double v, int d) {
    return (static_cast<std::int64_t>(std::floor(v / h)) + d + (1 << 20)) & ((1 << 21) - 1);
  };
  return (k(c.x(), dx) << 42) | (k(c.y(), dy) << 21) | k(c.z(), dz);
}
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
  const double R = par.Radius, reach = R + 0.5 * l, reach2 = reach * reach;

  // The faces sorted into cubic cells of side reach / 2 and copied in that
  // order, one array per quantity: every ball around a face of a cell lies
  // within the 5 x 5 x 5 cells around it, whose faces are a few contiguous
  // runs that all faces of the cell read (on octa-flower 512^3 this is
  // what made the stage 3 times faster than a hash lookup per face).
  const double side = 0.5 * reach;
  std::vector<std::pair<std::int64_t, std::int64_t>> order(F);
  for (std::int64_t f = 0; f < F; ++f)
    order[f] = { Key(centre[f], side), f };
  std::sort(order.begin(), order.end());
  std::vector<std::int64_t> cellStart;
  std::unordered_map<std::int64_t, std::int64_t> cellOf;
  for (std::int64_t i = 0; i < F; ++i)
    if (i == 0 || order[i].first != order[i - 1].first)
    {
      cellOf.emplace(order[i].first, static_cast<std::int64_t>(cellStart.size()));
      cellStart.push_back(i);
    }
  const std::int64_t cells = static_cast<std::int64_t>(cellStart.size());
  cellStart.push_back(F);
  enum Quantity
  {
    CX, CY, CZ, M0, M1, M2, SXX, SYY, SZZ, SXY, SXZ, SYZ, NX, NY, NZ, QUANTITIES
  };
  std::vector<std::vector<double>> q(QUANTITIES, std::vector<double>(F));
  std::vector<int> side_(F, 0);
  std::vector<char> inner(F, 0);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t i = begin; i < end; ++i)
    {
      const std::int64_t f = order[i].second;
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

  result.Mean.assign(F, 0.0);
  result.BallNormal.assign(3 * F, 0.0);
  result.Gaussian.assign(F, 0.0);
  result.K1.assign(F, 0.0);
  result.K2.assign(F, 0.0);
  result.D1.assign(3 * F, 0.0);
  result.D2.assign(3 * F, 0.0);
  vtkSMPTools::For(0, cells, [&](std::int64_t begin, std::int64_t end) {
    std::vector<std::pair<std::int64_t, std::int64_t>> runs;
    for (std::int64_t c = begin; c < end; ++c)
    {
      runs.clear();
      const std::int64_t first = cellStart[c];
      const V3& anchor = centre[order[first].second];
      for (int dx = -2; dx <= 2; ++dx)
        for (int dy = -2; dy <= 2; ++dy)
          for (int dz = -2; dz <= 2; ++dz)
          {
            const auto it = cellOf.find(Key(anchor, side, dx, dy, dz));
            if (it != cellOf.end())
              runs.emplace_back(cellStart[it->second], cellStart[it->second + 1]);
          }
      for (std::int64_t i = first; i < cellStart[c + 1]; ++i)
      {
        const std::int64_t f = order[i].second;
        if (isGhost(f))
          continue;
        const double x = q[CX][i], y = q[CY][i], z = q[CZ][i];
        const int own = side_[i];
        double sum[QUANTITIES] = {};
        // Interior faces first; all of the region's faces when the ball
        // holds none (a strip narrower than a face ring).
        for (int pass = 0; pass < 2 && !(sum[M0] > 0); ++pass)
          for (const auto& run : runs)
            for (std::int64_t j = run.first; j < run.second; ++j)
            {
              if (side_[j] != own || (pass == 0 && !inner[j]))
                continue;
              const double ex = q[CX][j] - x, ey = q[CY][j] - y, ez = q[CZ][j] - z;
              const double d2 = ex * ex + ey * ey + ez * ez;
              if (d2 >= reach2)
                continue;
              const double w = std::min(1.0, 0.5 + (R - std::sqrt(d2)) / l);
              for (int k = M0; k < QUANTITIES; ++k)
                sum[k] += w * q[k][j];
            }
        V3 n(sum[NX], sum[NY], sum[NZ]);
        const double mu0 = sum[M0], mu1 = sum[M1], mu2 = sum[M2];
        if (!(mu0 > 0) || n.norm() == 0)
          continue;
        n.normalize();
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
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
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
        const Eigen::Vector2d e1 = eig.eigenvectors().col(0), e2 = eig.eigenvectors().col(1);
        const V3 d1 = (e1[0] * t1 + e1[1] * t2).normalized();
        const V3 d2 = (e2[0] * t1 + e2[1] * t2).normalized();
        result.K1[f] = k1;
        result.K2[f] = k2;
        for (int d = 0; d < 3; ++d)
        {
          result.D1[3 * f + d] = d1[d];
          result.D2[3 * f + d] = d2[d];
        }
      }
    }
  });

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
