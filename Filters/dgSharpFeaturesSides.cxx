#include "dgSharpFeaturesSides.h"

#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dg
{
namespace sharp
{
namespace
{
// The sample of `region` among a search's samples, added empty if new.
RegionSample& SampleOf(std::vector<RegionSample>& samples, int region)
{
  for (RegionSample& r : samples)
    if (r.Region == region)
      return r;
  samples.emplace_back();
  samples.back().Region = region;
  return samples.back();
}
} // namespace

void ChooseSides(const FaceGraph& graph, const std::vector<std::int64_t>& bandFaces,
  const std::vector<int>& region, const std::vector<RegionPlane>& planes,
  const std::vector<RegionQuadric>& quadrics, const std::vector<double>& quadricDistance,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& polyNormal,
  const std::vector<Vec3>& field, double meanEdge2, const SharpFeatureParameters& par,
  std::vector<int>& assigned, std::vector<Vec3>& out, std::vector<double>& cornerDepth)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  cornerDepth.assign(F, std::numeric_limits<double>::quiet_NaN());
  const double maxResidual2 = std::pow(par.FitResidual * meanEdge2, 2);
  constexpr int MaximumDepth = 64; // bounds the search inside very wide bands
  vtkSMPThreadLocal<SearchScratch> scratch;
  vtkSMPTools::For(0, static_cast<std::int64_t>(bandFaces.size()), [&](std::int64_t b, std::int64_t e) {
    SearchScratch& s = scratch.Local();
    for (std::int64_t i = b; i < e; ++i)
    {
      const std::int64_t f0 = bandFaces[i];
      s.Samples.clear();
      auto all = [](std::int64_t) { return true; };
      Breadth(graph, s, f0, MaximumDepth, all, [&](std::int64_t f, int depth, int limit) {
        if (region[f] < 0)
          return limit;
        if (s.Samples.empty())
          limit = std::min(limit, depth + par.SearchDepth);
        RegionSample* it = &SampleOf(s.Samples, region[f]);
        ++it->Count;
        if (!quadricDistance.empty())
          it->QuadricDistanceSum += quadricDistance[f];
        // Relative to the band face: small numbers for the moments.
        it->AddPosition(centre[f] - centre[f0]);
        it->AddNormal(field[f], centre[f] - centre[f0]);
        return limit;
      });
      if (s.Samples.empty())
        continue;
      // Candidates: enough support, and a normal on the face's own side.
      int maxCount = 0;
      for (const auto& r : s.Samples)
        maxCount = std::max(maxCount, r.Count);
      const int support = std::min(par.MinimumSupport, maxCount);
      bool anyFacing = false;
      for (const auto& r : s.Samples)
        anyFacing |= r.Count >= support && r.NormalSum.Dot(polyNormal[f0]) > 0;
      // Between two sides, the face belongs to the plane that put its
      // outside voxel outside: at a convex edge (each side's centroid below
      // the other's plane) the one with the larger signed distance, at a
      // concave edge the smaller. A tournament over the candidates in region
      // order keeps it deterministic.
      const RegionSample* chosen = nullptr;
      Vec3 chosenN, chosenC;
      double chosenS = 0;
      bool chosenByQuadric = false;
      bool convexCorner = true;
      int compared = 0;
      for (const auto& r : s.Samples)
      {
        if (r.Count < support || (anyFacing && r.NormalSum.Dot(polyNormal[f0]) <= 0))
          continue;
        // Positions are relative to the band face (p = 0).
        const RegionPlane& plane = planes[r.Region];
        const bool flat = plane.Planar;
        const Vec3 n = flat ? plane.Normal : r.NormalSum.Unit();
        const Vec3 c = flat ? plane.Point - centre[f0] : r.CentroidSum * (1.0 / r.Count);
        double sd = n.Dot(c * -1.0);
        // A region's quadric decides where it still passes within an edge
        // length of the faces found here (their mean distance to it): a
        // surface that is no quadric is left to the local model.
        const RegionQuadric& q = quadrics[r.Region];
        const bool byQuadric =
          !flat && q.Valid && std::abs(r.QuadricDistanceSum / r.Count) <= meanEdge2;
        if (byQuadric)
          sd = q.Distance(centre[f0]);
        else if (par.CurvedSides && !flat)
          sd += r.Fall(n, Vec3());
        // Convex or concave is read from the faces found here: a planar
        // region's whole centroid may lie anywhere along the edge, and at
        // the concave circles of the README's shape (a sphere leaving a
        // cube face) it put the sphere's side on the wrong side of the
        // test (their recall 0.90 -> 1.00 with the local centroid).
        const Vec3 local = r.CentroidSum * (1.0 / r.Count);
        bool take = !chosen;
        if (chosen)
        {
          const double convexity = chosenN.Dot(local - chosenC) + n.Dot(chosenC - local);
          take = convexity < 0 ? sd > chosenS : sd < chosenS;
          convexCorner = convexity < 0;
          ++compared;
        }
        if (take)
        {
          chosen = &r;
          chosenN = n;
          chosenC = local;
          chosenS = sd;
          chosenByQuadric = byQuadric;
        }
      }
      if (chosen)
      {
        assigned[f0] = chosen->Region;
        if (compared > 0)
          cornerDepth[f0] = convexCorner ? -chosenS : chosenS;
        out[f0] = par.FitPlanes ? chosen->PlaneNormal(maxResidual2) : chosenN;
        // A side that decided with its quadric (above) gives the quadric's
        // normal at the face: the local plane through curved samples a few
        // faces away is tilted by their curvature.
        if (chosenByQuadric)
        {
          const Vec3 n = quadrics[chosen->Region].Normal(centre[f0]);
          if (n.Norm() > 0 && AngleDegrees(n, out[f0]) < par.StrongFeatureAngle)
            out[f0] = n;
        }
      }
    }
  });
  // Majority smoothing of the band's labels: noise moves single faces to
  // the wrong side, which draws a wiggling line.
  for (int pass = 0; pass < par.SmoothingPasses; ++pass)
  {
    std::vector<int> nextLabel(assigned);
    std::vector<Vec3> nextNormal(out);
    vtkSMPTools::For(0, static_cast<std::int64_t>(bandFaces.size()), [&](std::int64_t b, std::int64_t e) {
      SearchScratch& s = scratch.Local();
      for (std::int64_t i = b; i < e; ++i)
      {
        const std::int64_t f0 = bandFaces[i];
        if (assigned[f0] < 0)
          continue;
        s.Samples.clear();
        auto all = [](std::int64_t) { return true; };
        Breadth(graph, s, f0, par.SmoothingDepth, all, [&](std::int64_t f, int, int limit) {
          if (assigned[f] < 0)
            return limit;
          RegionSample& sample = SampleOf(s.Samples, assigned[f]);
          ++sample.Count;
          sample.NormalSum += out[f];
          return limit;
        });
        const RegionSample* own = nullptr;
        const RegionSample* best = nullptr;
        for (const auto& r : s.Samples)
        {
          if (r.Region == assigned[f0])
            own = &r;
          if (!best || r.Count > best->Count || (r.Count == best->Count && r.Region < best->Region))
            best = &r;
        }
        if (best && own && best != own && best->Count > own->Count)
        {
          nextLabel[f0] = best->Region;
          nextNormal[f0] = best->NormalSum.Unit();
        }
      }
    });
    assigned.swap(nextLabel);
    out.swap(nextNormal);
  }
}

} // namespace sharp
} // namespace dg
