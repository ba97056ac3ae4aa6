#include "dgCorrectedCurvatureSurface.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace dg
{
namespace curvature
{

bool Surface::FlagsSide(std::int64_t f, std::int64_t ka, std::int64_t kb) const
{
  const std::int64_t b = (*this->Offsets)[f], e = (*this->Offsets)[f + 1];
  // The side runs from the corner whose next corner is the other.
  const std::int64_t from = (ka + 1 < e ? ka + 1 : b) == kb ? ka : kb;
  const std::int64_t side = from - b;
  return side < 8 && (this->CreaseSides[f] & (1u << side)) != 0;
}

V3 Surface::CornerNormal(std::int64_t f, std::int64_t p) const
{
  V3 up = V3::Zero();
  for (std::int64_t k = this->Start[p]; k < this->Start[p + 1]; ++k)
    if (this->SameSide(f, this->Around[k], p))
      up += At(this->Normals, this->Around[k]);
  return up.norm() > 0 ? V3(up.normalized()) : At(this->Normals, f);
}

double WholeSurfaceFigures(const Surface& surface, const std::vector<V3>& centre,
  const std::vector<CorrectedMeasures>& measures, CurvatureResult& result,
  std::vector<Crease>& creases)
{
  const std::vector<std::int64_t>& offsets = *surface.Offsets;
  const std::vector<std::int64_t>& connectivity = *surface.Connectivity;
  const double* points = surface.Points;
  const double* normals = surface.Normals;
  const int* region = surface.Region;
  const std::int64_t F = surface.Faces();
  const auto isGhost = [&](std::int64_t f) { return surface.IsGhost(f); };

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
  // Each face's edges at its corners' positions, filled on the threads; the
  // mean edge length summed in that order.
  // Each edge once per face on it, listed from its lower point: the corners
  // around each point give that point's edges at once, so the list comes
  // grouped by A without a sort of the whole (2.7 million edges on
  // octa-flower 512^3), and only each point's few edges are sorted, on the
  // threads.
  const std::int64_t P = static_cast<std::int64_t>(surface.Start.size()) - 1;
  const std::vector<std::int64_t>& corner = surface.AroundCorner;
  const auto next = [&](std::int64_t k, std::int64_t f) {
    return k + 1 < offsets[f + 1] ? k + 1 : offsets[f];
  };
  const auto previous = [&](std::int64_t k, std::int64_t f) {
    return k > offsets[f] ? k - 1 : offsets[f + 1] - 1;
  };
  std::vector<std::int64_t> first(P + 1, 0);
  vtkSMPTools::For(0, P, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t p = begin; p < end; ++p)
      for (std::int64_t j = surface.Start[p]; j < surface.Start[p + 1]; ++j)
      {
        const std::int64_t k = corner[j], f = surface.Around[j];
        if (offsets[f + 1] - offsets[f] < 2)
          continue;
        first[p + 1] += (connectivity[next(k, f)] > p ? 1 : 0) +
          (connectivity[previous(k, f)] > p ? 1 : 0);
      }
  });
  for (std::int64_t p = 0; p < P; ++p)
    first[p + 1] += first[p];
  // Not zeroed (107 MB on octa-flower 512^3, a serial memset and its page
  // faults): every record is written on the threads.
  const std::size_t nEdges = static_cast<std::size_t>(first[P]);
  const std::unique_ptr<EdgeFace[]> edges(new EdgeFace[nEdges]);
  vtkSMPTools::For(0, P, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t p = begin; p < end; ++p)
    {
      std::int64_t e = first[p];
      for (std::int64_t j = surface.Start[p]; j < surface.Start[p + 1]; ++j)
      {
        const std::int64_t k = corner[j], f = surface.Around[j];
        if (offsets[f + 1] - offsets[f] < 2)
          continue;
        const std::int64_t kn = next(k, f), kp = previous(k, f);
        if (connectivity[kn] > p)
          edges[e++] = EdgeFace{ p, connectivity[kn], f, k, kn };
        if (connectivity[kp] > p)
          edges[e++] = EdgeFace{ p, connectivity[kp], f, k, kp };
      }
      std::sort(edges.get() + first[p], edges.get() + first[p + 1]);
    }
  });
  const std::unique_ptr<std::int64_t[]> faceOfCorner(new std::int64_t[connectivity.size()]);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
      for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
        faceOfCorner[k] = f;
  });
  // The mean edge length, each face's edges in order.
  double edgeSum = 0;
  const std::int64_t edgeCount = static_cast<std::int64_t>(connectivity.size());
  for (std::int64_t f = 0; f < F; ++f)
    for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
      edgeSum += (At(points, connectivity[k]) - At(points, connectivity[next(k, f)])).norm();

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
      n += At(points, connectivity[offsets[f] + i])
             .cross(At(points, connectivity[offsets[f] + (i + 1) % m]));
    return n;
  };

  // The Euler characteristic counts each edge and point for the share of
  // its faces owned here, so that pieces' figures add up to the whole's.
  result.BoundaryEdges = 0;
  creases.clear();
  double chi = 0;
  for (std::size_t i = 0; i < nEdges;)
  {
    std::size_t j = i;
    std::int64_t own = 0;
    while (j < nEdges && edges[j].A == edges[i].A && edges[j].B == edges[i].B)
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
            const int shared =
              (isGhost(edges[i + a].F) ? 0 : 1) + (isGhost(edges[i + partner[a]].F) ? 0 : 1);
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
    if (region && n == 2 && region[edges[i].F] != region[edges[i + 1].F] &&
      (!surface.CreaseSides || surface.FlagsSide(edges[i].F, edges[i].KA, edges[i].KB) ||
        surface.FlagsSide(edges[i + 1].F, edges[i + 1].KA, edges[i + 1].KB)))
    {
      std::int64_t f = edges[i].F, g = edges[i + 1].F;
      if (surface.FaceIds ? surface.FaceIds[g] < surface.FaceIds[f] : g < f)
        std::swap(f, g);
      if (!isGhost(f))
        creases.push_back({ edges[i].A, edges[i].B, f, g });
    }
    i = j;
  }
  // Surface points: one per fan, counted for its share of owned corners;
  // each fan's normal is the mean of its faces' (the continuous field).
  // Every corner's fan, the fans numbered in the order of their roots (a
  // parent never has a larger index than its child, so one pass in order
  // resolves every corner); one entry per fan, not per corner, keeps the
  // fresh memory small (on octa-flower 512^3 its zeroing took more than the
  // sums).
  std::vector<std::int64_t>& fan = parent;
  std::int64_t fans = 0;
  for (std::size_t k = 0; k < fan.size(); ++k)
    fan[k] = fan[k] == static_cast<std::int64_t>(k) ? fans++ : fan[fan[k]];
  std::vector<std::int64_t> fanCorners(fans, 0), fanOwned(fans, 0);
  std::vector<V3> fanNormal(fans, V3::Zero());
  for (std::size_t k = 0; k < connectivity.size(); ++k)
  {
    const std::int64_t r = fan[k];
    ++fanCorners[r];
    fanOwned[r] += isGhost(faceOfCorner[k]) ? 0 : 1;
    fanNormal[r] += At(normals, faceOfCorner[k]);
  }
  for (std::int64_t k = 0; k < fans; ++k)
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
  // creases, where the first-order mu2 falls short. Each face's share on
  // the threads, summed in face order.
  const auto solidAngle = [](const V3& a, const V3& b, const V3& c) {
    return 2.0 * std::atan2(a.dot(b.cross(c)), 1.0 + a.dot(b) + b.dot(c) + c.dot(a));
  };
  std::vector<double> faceAngle(F, 0.0), faceVolume(F, 0.0);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      const std::int64_t m = offsets[f + 1] - offsets[f];
      if (isGhost(f) || m < 3)
        continue;
      V3 ub = V3::Zero();
      for (std::int64_t i = 0; i < m; ++i)
        ub += fanNormal[fan[offsets[f] + i]];
      ub = ub.norm() > 0 ? V3(ub.normalized()) : At(normals, f);
      for (std::int64_t i = 0; i < m; ++i)
        faceAngle[f] +=
          solidAngle(ub, fanNormal[fan[offsets[f] + i]], fanNormal[fan[offsets[f] + (i + 1) % m]]);
      const V3 x0 = At(points, connectivity[offsets[f]]);
      for (std::int64_t i = 1; i + 1 < m; ++i)
        faceVolume[f] += x0.dot(At(points, connectivity[offsets[f] + i])
                                  .cross(At(points, connectivity[offsets[f] + i + 1]))) /
          6.0;
    }
  });
  result.Area = result.TotalGaussian = 0;
  double volume = 0;
  for (std::int64_t f = 0; f < F; ++f)
  {
    const std::int64_t m = offsets[f + 1] - offsets[f];
    if (isGhost(f) || m < 3)
      continue;
    result.Area += measures[f].Mu0;
    chi += 1;
    result.TotalGaussian += faceAngle[f];
    volume += faceVolume[f];
  }
  result.EulerShare = chi;
  result.EulerCharacteristic = static_cast<std::int64_t>(std::llround(chi));
  result.Volume = result.BoundaryEdges ? std::nan("") : volume;
  return edgeCount ? edgeSum / edgeCount : 1.0;
}

void MeasureCreases(const Surface& surface, const std::vector<V3>& centre,
  const std::vector<Crease>& creases, CurvatureResult& result)
{
  // Each crease edge: the normal's turn from one side's normal at the edge
  // (its corner normals at the edge's two ends) to the other's, convex when
  // the second face's centre lies below the first side's plane more than
  // the first's lies below the second's; its length along the crease
  // (t = n_a x n_b), so that a staircase of voxel edges along a slanted
  // crease counts for the crease's own length.
  result.CreaseEdges.clear();
  result.CreaseAngle.clear();
  result.CreaseLength.clear();
  result.CreaseTotalMean = 0;
  for (const Crease& c : creases)
  {
    const V3 na = (surface.CornerNormal(c.F, c.A) + surface.CornerNormal(c.F, c.B)).normalized();
    const V3 nb = (surface.CornerNormal(c.G, c.A) + surface.CornerNormal(c.G, c.B)).normalized();
    const V3 axis = na.cross(nb);
    const double turn = std::atan2(axis.norm(), na.dot(nb));
    const bool convex = (centre[c.G] - centre[c.F]).dot(na - nb) <= 0;
    const double angle = convex ? turn : -turn;
    const V3 edge = At(surface.Points, c.B) - At(surface.Points, c.A);
    const double length =
      axis.norm() > 1e-6 ? std::abs(edge.dot(axis.normalized())) : edge.norm();
    result.CreaseEdges.push_back(c.A);
    result.CreaseEdges.push_back(c.B);
    result.CreaseAngle.push_back(angle);
    result.CreaseLength.push_back(length);
    result.CreaseTotalMean += 0.5 * angle * length;
  }
}

} // namespace curvature
} // namespace dg
