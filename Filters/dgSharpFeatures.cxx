#include "dgSharpFeatures.h"

#include "dgSharpFeaturesCreases.h"
#include "dgSharpFeaturesField.h"
#include "dgSharpFeaturesGraph.h"
#include "dgSharpFeaturesRegionFits.h"
#include "dgSharpFeaturesSides.h"

#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <utility>

namespace dg
{
using namespace sharp;
bool ComputeSharpFeatures(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* normals, const double* v, const double* inputNormals,
  const SharpFeatureParameters& par, SharpFeatureResult& result, std::string* error,
  const std::function<bool(double)>& progress)
{
  auto fail = [&](const std::string& m) {
    if (error)
      *error = m;
    return false;
  };
  result = SharpFeatureResult();
  if (offsets.empty() || offsets.front() != 0 ||
    offsets.back() != static_cast<std::int64_t>(connectivity.size()))
    return fail("inconsistent polygon offsets");
  for (std::int64_t id : connectivity)
    if (id < 0 || id >= numberOfPoints)
      return fail("a polygon refers to a point that does not exist");
  if (par.MinimumRegionSize < 1 || par.SearchDepth < 0 || par.SmoothingPasses < 0 || par.SmoothingDepth < 1 || par.MinimumSupport < 1 ||
    !(par.MinimumFeatureAngle >= 0) || !(par.StrongFeatureAngle >= 0) || !(par.PlanarRegionAngle >= 0))
    return fail("invalid sharp-feature parameters");
  auto report = [&](double f) { return !progress || progress(f); };
  auto aborted = [&]() {
    if (error)
      error->clear();
    return false;
  };

  const std::int64_t F = static_cast<std::int64_t>(offsets.size()) - 1;
  FaceGraph graph;
  graph.Build(offsets, connectivity);

  // Face centres, polygon normals (Newell) and unit field normals.
  std::vector<Vec3> centre(F), polyNormal(F), areaVector(F), field(F), input(F);
  vtkSMPTools::For(0, F, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t f = b; f < e; ++f)
    {
      Vec3 c, n;
      const std::int64_t o = offsets[f], m = offsets[f + 1] - o;
      for (std::int64_t k = 0; k < m; ++k)
      {
        const double* p = points + 3 * connectivity[o + k];
        const double* q = points + 3 * connectivity[o + (k + 1) % m];
        c += Vec3(p[0], p[1], p[2]);
        n += Vec3(p[0], p[1], p[2]).Cross(Vec3(q[0], q[1], q[2]));
      }
      centre[f] = m > 0 ? c * (1.0 / m) : c;
      polyNormal[f] = n.Unit();
      areaVector[f] = n * 0.5;
      field[f] = Vec3(normals[3 * f], normals[3 * f + 1], normals[3 * f + 2]).Unit();
      input[f] = inputNormals
        ? Vec3(inputNormals[3 * f], inputNormals[3 * f + 1], inputNormals[3 * f + 2]).Unit()
        : field[f];
    }
  });

  // Plane fits count as planar when their RMS residual is below
  // FitResidual edge lengths (noise-free digital planes: about 0.3).
  double meanEdge2 = 0;
  for (const auto& e : graph.Edges)
  {
    const double* p = points + 3 * e[0];
    const double* q = points + 3 * e[1];
    meanEdge2 += (Vec3(p[0], p[1], p[2]) - Vec3(q[0], q[1], q[2])).Norm();
  }
  meanEdge2 = graph.Edges.empty() ? 1.0 : meanEdge2 / graph.Edges.size();

  // 1. Band faces.
  std::vector<char> band(F, 0);
  for (std::int64_t f = 0; f < F; ++f)
    for (std::int64_t k = offsets[f]; k < offsets[f + 1] && !band[f]; ++k)
      band[f] = v[connectivity[k]] < par.FeatureThreshold;

  // 2. Regions: components of the non-band faces; small ones join the band.
  std::vector<int> region(F, -1);
  int regions = 0;
  {
    std::vector<std::int64_t> members;
    std::vector<Vec3> reference(F);
    for (std::int64_t seed = 0; seed < F; ++seed)
    {
      if (band[seed] || region[seed] >= 0)
        continue;
      // Breadth-first growth; each face carries a reference normal that
      // follows the region's own normals with a lag, so that a region does
      // not creep around the end of a gap in AT's band, where the normal
      // turns over a few faces with no single large jump.
      members.clear();
      members.push_back(seed);
      region[seed] = regions;
      reference[seed] = field[seed];
      for (std::size_t head = 0; head < members.size(); ++head)
      {
        const std::int64_t f = members[head];
        for (std::int64_t k = graph.FaceEdgePtr[f]; k < graph.FaceEdgePtr[f + 1]; ++k)
        {
          const std::int64_t e = graph.FaceEdges[k];
          for (std::int64_t j = graph.EdgeFacePtr[e]; j < graph.EdgeFacePtr[e + 1]; ++j)
          {
            const std::int64_t g = graph.EdgeFaces[j];
            if (!band[g] && region[g] < 0 &&
              AngleDegrees(reference[f], field[g]) <= par.RegionEdgeAngle)
            {
              region[g] = regions;
              reference[g] = (reference[f] * (1.0 - par.ReferenceWeight) +
                field[g] * par.ReferenceWeight).Unit();
              members.push_back(g);
            }
          }
        }
      }
      if (static_cast<int>(members.size()) < par.MinimumRegionSize)
      {
        for (std::int64_t f : members)
        {
          region[f] = -1;
          band[f] = 1;
        }
        ++result.NumberOfDissolvedRegions;
      }
      else
      {
        ++regions;
      }
    }
  }
  if (!report(0.3))
    return aborted();

  // Whole-region models for the choice of side (step 3): a plane for the
  // regions whose normals turn by less than PlanarRegionAngle across them,
  // a quadric for the other large ones (QuadricSides). Both only for
  // regions that reach beyond a band face's own search: in a smaller one
  // the local fit sees the whole region anyway, and a model of a few dozen
  // noisy faces is less sure than their mean (measured: planes admitted
  // below that cost cube and sphere 128^3 at k = 0.3 a whole circle, recall
  // 0.97 -> 0.82; quadrics below 3 searches cost it at 64^3, recall
  // 0.97 -> 0.95).
  std::vector<RegionPlane> planes(regions);
  if (par.PlanarRegionAngle > 0)
    planes = FindPlanarRegions(region, regions, centre, field, par.MinimumRegionSize,
      par.SearchDepth * meanEdge2, par.PlanarRegionAngle);
  std::vector<char> planar(regions, 0);
  for (int r = 0; r < regions; ++r)
  {
    planar[r] = planes[r].Planar;
    result.NumberOfPlanarRegions += planar[r];
  }
  std::vector<RegionQuadric> quadrics(regions);
  std::vector<double> quadricDistance;
  if (par.QuadricSides)
  {
    quadrics = FitRegionQuadrics(region, regions, centre, field, planar, par.MinimumRegionSize,
      3.0 * par.SearchDepth * meanEdge2, meanEdge2);
    quadricDistance.assign(F, 0.0);
    vtkSMPTools::For(0, F, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t f = b; f < e; ++f)
        if (region[f] >= 0 && quadrics[region[f]].Valid)
          quadricDistance[f] = quadrics[region[f]].Distance(centre[f]);
    });
    for (const auto& q : quadrics)
      result.NumberOfQuadricRegions += q.Valid;
  }

  // 3. Band faces join the region whose local plane is nearest
  // (dgSharpFeaturesSides.h).
  std::vector<std::int64_t> bandFaces;
  for (std::int64_t f = 0; f < F; ++f)
    if (band[f])
      bandFaces.push_back(f);
  result.NumberOfBandFaces = static_cast<std::int64_t>(bandFaces.size());
  std::vector<Vec3> out(field);
  std::vector<int> assigned(region);
  std::vector<double> cornerDepth;
  ChooseSides(graph, bandFaces, region, planes, quadrics, quadricDistance, centre, polyNormal, field,
    meanEdge2, par, assigned, out, cornerDepth);
  vtkSMPThreadLocal<SearchScratch> scratch;
  if (!report(0.7))
    return aborted();

  // 4. Merge regions whose common boundary has a weak mean normal jump.
  const std::int64_t E = static_cast<std::int64_t>(graph.Edges.size());
  // A boundary's normal jump is the median over its edges of the angle
  // between the two sides' input normal fields extrapolated to the edge
  // (below): single faces' normals are noisy, a mean over the whole boundary
  // would cancel on a curved one, and the input normals are continuous
  // across a false band on a smooth part, where two local plane fits a few
  // faces apart are not.
  struct BoundaryEdge
  {
    std::int64_t A, B;
  };
  std::vector<BoundaryEdge> boundaryEdges;
  std::vector<char> onBoundary(F, 0);
  for (std::int64_t e = 0; e < E; ++e)
  {
    for (std::int64_t a = graph.EdgeFacePtr[e]; a < graph.EdgeFacePtr[e + 1]; ++a)
      for (std::int64_t b = a + 1; b < graph.EdgeFacePtr[e + 1]; ++b)
      {
        const std::int64_t fa = graph.EdgeFaces[a], fb = graph.EdgeFaces[b];
        if (assigned[fa] < 0 || assigned[fb] < 0 || assigned[fa] == assigned[fb])
          continue;
        boundaryEdges.push_back({ fa, fb });
        onBoundary[fa] = onBoundary[fb] = 1;
      }
  }
  std::vector<std::int64_t> boundaryFaces;
  for (std::int64_t f = 0; f < F; ++f)
    if (onBoundary[f])
      boundaryFaces.push_back(f);
  std::vector<Vec3> localMean(F);

  vtkSMPTools::For(0, static_cast<std::int64_t>(boundaryFaces.size()), [&](std::int64_t b, std::int64_t e) {
    SearchScratch& s = scratch.Local();
    for (std::int64_t i = b; i < e; ++i)
    {
      const std::int64_t f0 = boundaryFaces[i];
      // The side's normal field extrapolated to this face: a linear fit
      // u(x) = a + B (x - xbar) to the side's faces outside the band (their
      // normals are not blended across the edge), evaluated at the face. On
      // a smooth part cut by a false band both sides extrapolate to the same
      // normal, however curved; across a true edge they differ by its angle.
      Vec3 sum, xbar;
      int count = 0;
      s.Fit.clear();
      Breadth(graph, s, f0, par.SearchDepth,
        [&](std::int64_t g) { return assigned[g] == assigned[f0]; },
        [&](std::int64_t f, int, int limit) {
          sum += field[f];
          if (!band[f] || !par.ExtrapolateSides)
          {
            s.Fit.push_back(f);
            xbar += centre[f];
            ++count;
          }
          return limit;
        });
      localMean[f0] = sum;
      if (!par.ExtrapolateSides || count < 12)
        continue;
      xbar = xbar * (1.0 / count);
      Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
      Eigen::Matrix<double, 4, 3> atb = Eigen::Matrix<double, 4, 3>::Zero();
      for (std::int64_t f : s.Fit)
      {
        const Vec3 d = centre[f] - xbar;
        const Eigen::Vector4d m(1.0, d.x, d.y, d.z);
        ata += m * m.transpose();
        atb += m * Eigen::RowVector3d(field[f].x, field[f].y, field[f].z);
      }
      // A small ridge on the slopes: the faces barely spread along the
      // surface normal.
      const double ridge = 1e-3 * (ata(1, 1) + ata(2, 2) + ata(3, 3));
      for (int k = 1; k < 4; ++k)
        ata(k, k) += ridge;
      Eigen::LDLT<Eigen::Matrix4d> ldlt(ata);
      if (ldlt.info() != Eigen::Success)
        continue;
      const Eigen::Matrix<double, 4, 3> coef = ldlt.solve(atb);
      const Vec3 d = centre[f0] - xbar;
      const Eigen::RowVector3d u = Eigen::RowVector4d(1.0, d.x, d.y, d.z) * coef;
      const Vec3 extrapolated(u(0), u(1), u(2));
      if (extrapolated.Norm() > 0 && std::isfinite(extrapolated.Norm()))
        localMean[f0] = extrapolated;
    }
  });
  std::map<std::pair<int, int>, std::vector<double>> boundary;
  for (const auto& be : boundaryEdges)
  {
    const int ra = assigned[be.A], rb = assigned[be.B];
    boundary[{ std::min(ra, rb), std::max(ra, rb) }].push_back(
      AngleDegrees(localMean[be.A], localMean[be.B]));
  }
  auto median = [](std::vector<double> a) {
    std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
    return a[a.size() / 2];
  };
  // Weak boundaries merge, weakest first, unless the union would join two
  // regions that meet along a strong boundary: under heavy noise a sliver
  // of one smooth part, cut off by AT's bands, meets both sides of a true
  // edge along weak boundaries, and merging through it would erase the
  // edge (cube and sphere at k = 0.5, 128^3: recall 0.20 -> 0.81). Each
  // root keeps the regions it must not join; the shorter list is checked.
  std::vector<std::pair<double, std::pair<int, int>>> weak;
  std::vector<std::vector<int>> apart(regions);
  const double strongAngle = std::max(par.StrongFeatureAngle, par.MinimumFeatureAngle);
  for (const auto& b : boundary)
  {
    const double m = median(b.second);
    if (m < par.MinimumFeatureAngle)
      weak.push_back({ m, b.first });
    else if (m >= strongAngle)
    {
      apart[b.first.first].push_back(b.first.second);
      apart[b.first.second].push_back(b.first.first);
    }
  }
  std::sort(weak.begin(), weak.end());
  UnionFind uf(regions);
  // Joins the merged regions ra and rb unless a strong boundary lies
  // between them.
  auto unite = [&](int ra, int rb)
  {
    if (apart[ra].size() > apart[rb].size())
      std::swap(ra, rb);
    for (int other : apart[ra])
      if (uf.Find(other) == rb)
        return false;
    uf.Unite(ra, rb);
    const int root = uf.Find(ra), gone = root == ra ? rb : ra;
    if (apart[root].size() < apart[gone].size())
      apart[root].swap(apart[gone]); // the shorter list is the one copied
    apart[root].insert(apart[root].end(), apart[gone].begin(), apart[gone].end());
    std::vector<int>().swap(apart[gone]);
    return true;
  };
  for (const auto& w : weak)
  {
    const int ra = uf.Find(w.second.first), rb = uf.Find(w.second.second);
    if (ra == rb)
      continue;
    if (!unite(ra, rb))
    {
      ++result.NumberOfRefusedMerges;
      continue;
    }
    ++result.NumberOfMergedBoundaries;
  }

  // Then the boundaries of medium jump (between the weak and the strong
  // angle) where one side lies on the other's quadric: under noise AT
  // flattens part of a curved region into a facet (a patch of a sphere),
  // whose normals jump at its rim, but whose faces lie on the curved
  // neighbour's surface as closely as that neighbour's own faces do.
  // - The quadric is fitted to everything already merged with the larger
  //   side, not to one region: AT cuts a tight curved part (the built-in
  //   shape's hole, radius 11.5 voxels) into strips a few faces wide whose
  //   own quadrics are nearly planes (AT's normals are all but constant
  //   across each), while the strips merged so far pin the curvature down.
  //   The fit leans on the normals more than step 3's (a position residual
  //   of 3 edge lengths weighs as much as one radian): a quadric fitted to
  //   the noisy positions of a 60-degree arc extrapolates badly over the
  //   next one (cylinder 64^3, k = 0.1 and 0.2: precision 0.55-0.59 with 0.3
  //   edge lengths, 0.62-0.97 with 3). Passes repeat until nothing merges, so a
  //   boundary refused while its larger side was one strip is tested again
  //   once its neighbours have merged (built-in shape, clean: precision
  //   0.76 -> 1.00).
  // - The test takes everything already merged with the smaller side: a
  //   sliver of the sphere that a weak boundary joined to a disc carries the
  //   disc's faces, far from the sphere, and stays apart (cube and sphere
  //   128^3, k = 0.3: a circle lost otherwise).
  // - Beyond QuadricMergeDistance edge lengths (RMS) no side is on a
  //   quadric, however rough the quadric's own faces: under heavy noise
  //   (cube and sphere 128^3, k = 0.4) the sphere's own RMS reaches 2 and a
  //   whole disc, 4.5 from it, would merge.
  if (par.QuadricMergeFactor > 0 && !quadrics.empty())
  {
    std::vector<std::vector<std::int64_t>> faces(regions);
    for (std::int64_t f = 0; f < F; ++f)
      if (assigned[f] >= 0)
        faces[assigned[f]].push_back(f);
    struct Candidate
    {
      double Angle;
      int A, B; // two regions, one of them a quadric region
      bool Refused = false;
      std::size_t TestedSizes = 0; // the two sides' face counts when last tested
    };
    std::vector<Candidate> candidates;
    for (const auto& b : boundary)
    {
      const double m = median(b.second);
      if (m < par.MinimumFeatureAngle || m >= strongAngle)
        continue;
      const int a = b.first.first, c = b.first.second;
      if (quadrics[a].Valid || quadrics[c].Valid)
        candidates.push_back({ m, a, c });
    }
    std::sort(candidates.begin(),
      candidates.end(),
      [](const Candidate& x, const Candidate& y)
      { return std::tie(x.Angle, x.A, x.B) < std::tie(y.Angle, y.A, y.B); });
    // The merged groups' members, kept up to date as they merge.
    std::vector<std::vector<int>> members(regions);
    for (int r = 0; r < regions; ++r)
      members[uf.Find(r)].push_back(r);
    std::vector<std::size_t> groupSize(regions, 0); // faces, at the roots
    for (int r = 0; r < regions; ++r)
      groupSize[uf.Find(r)] += faces[r].size();
    auto groupFaces = [&](int root) {
      std::vector<std::int64_t> out;
      for (int r : members[root])
        out.insert(out.end(), faces[r].begin(), faces[r].end());
      return out;
    };
    auto rms = [&](const RegionQuadric& q, const std::vector<std::int64_t>& fs) {
      double sum = 0;
      for (std::int64_t f : fs)
      {
        const double d = q.Distance(centre[f]);
        sum += d * d;
      }
      return std::sqrt(sum / static_cast<double>(std::max<std::size_t>(1, fs.size())));
    };
    // A group's quadric and own RMS, refitted only when the group has grown.
    struct GroupFit
    {
      std::size_t Members = 0;
      RegionQuadric Quadric;
      double Own = 0;
    };
    std::vector<GroupFit> fits(regions);
    // Passes until nothing merges: a boundary refused while its larger side
    // was one strip may pass once the strips beside it have merged.
    for (bool merged = true; merged;)
    {
      merged = false;
      for (auto& c : candidates)
      {
        int ra = uf.Find(c.A), rb = uf.Find(c.B);
        if (ra == rb)
          continue;
        // Sides only grow: the same total means the same two sides, and
        // the same answer as last time.
        if (groupSize[ra] + groupSize[rb] == c.TestedSizes)
          continue;
        c.TestedSizes = groupSize[ra] + groupSize[rb];
        // The larger merged side's quadric; the smaller side is tested.
        if (groupSize[ra] > groupSize[rb])
          std::swap(ra, rb);
        GroupFit& g = fits[rb];
        if (g.Members != members[rb].size())
        {
          const std::vector<std::int64_t> own = groupFaces(rb);
          g.Members = members[rb].size();
          g.Quadric = FitQuadric(own, centre, field, 3.0 * meanEdge2);
          g.Own = g.Quadric.Valid ? rms(g.Quadric, own) : 0.0;
        }
        if (!g.Quadric.Valid)
          continue;
        const std::vector<std::int64_t> side = groupFaces(ra);
        const double other = rms(g.Quadric, side);
        const double limit = std::min(par.QuadricMergeFactor * std::max(g.Own, 0.25 * meanEdge2),
          par.QuadricMergeDistance * meanEdge2);
        if (other > limit)
          continue;
        const RegionQuadric q = g.Quadric; // the union below may move fits[rb]
        if (!unite(ra, rb))
        {
          result.NumberOfRefusedMerges += !c.Refused;
          c.Refused = true;
          continue;
        }
        ++result.NumberOfQuadricMerges;
        merged = true;
        const int root = uf.Find(ra), gone = root == ra ? rb : ra;
        members[root].insert(members[root].end(), members[gone].begin(), members[gone].end());
        groupSize[root] += groupSize[gone];
        std::vector<int>().swap(members[gone]);
        // AT's normals on a flattened facet are the facet's; its faces take
        // the normal of the surface they were found to lie on, where that
        // turns them by less than a sure edge would (under heavy noise a
        // merged piece may reach where the quadric no longer describes it).
        for (std::int64_t f : side)
        {
          const Vec3 n = q.Normal(centre[f]);
          if (n.Norm() > 0 && AngleDegrees(n, out[f]) < strongAngle)
            out[f] = n;
        }
      }
    }
  }

  // Per graph edge: whether the line through it is drawn, from its last
  // test (-1: never tested, drawn if it separates two regions).
  std::vector<signed char> edgeCrease;
  // 7. Creases and bends (dgSharpFeaturesCreases.h): every line left
  // between two merged parts is tested against the input normals beyond
  // their blur and against the corner its sides make. AT's normals jump
  // across its false lines on curved parts as much as across real edges,
  // so from here on only this test's creases keep parts apart; bends merge
  // smallest jump first (a sliver cut off a curved part joins the side it
  // continues before the side across a crease can reach it through it).
  // Merged bends make larger sides, whose fits and turns reach farther
  // from the lines left: those lines are tested again (at most
  // CreaseRounds times, until no bend merges); a line between two groups
  // that did not change keeps its verdict.
  {
    CreaseTestSettings cs;
    cs.Near = 0.75 * par.InputRadius * meanEdge2;
    cs.Far = cs.Near + 5.0 * meanEdge2;
    cs.Stretch = cs.Far;
    cs.MinimumAngle = par.MinimumFeatureAngle;
    cs.CornerDepth = par.CornerDepth * meanEdge2;
    cs.MinimumTurnShare = par.MinimumTurnShare;
    cs.EdgeLength = meanEdge2;
    cs.TurnNear *= meanEdge2;
    cs.TurnFarFrom *= meanEdge2;
    cs.TurnFar *= meanEdge2;
    cs.TurnSlab *= meanEdge2;
    const auto creaseStart = std::chrono::steady_clock::now();
    constexpr int CreaseRounds = 3;
    std::vector<int> group(F, -1);
    std::map<std::pair<int, int>, CreaseVerdict> known;
    edgeCrease.assign(E, -1);
    for (int round = 0; round < CreaseRounds; ++round)
    {
      for (std::int64_t f = 0; f < F; ++f)
        group[f] = assigned[f] >= 0 ? uf.Find(assigned[f]) : -1;
      const std::vector<CreaseVerdict> verdicts =
        TestCreases(graph, centre, areaVector, input, out, group, cornerDepth, cs, known, edgeCrease);
      known.clear();
      for (const CreaseVerdict& c : verdicts)
        known[{ c.A, c.B }] = c;
      for (auto& a : apart)
        a.clear();
      result.NumberOfCreases = 0;
      std::vector<std::pair<double, std::pair<int, int>>> bends;
      for (const CreaseVerdict& c : verdicts)
      {
        if (c.Crease)
        {
          apart[c.A].push_back(c.B);
          apart[c.B].push_back(c.A);
          ++result.NumberOfCreases;
        }
        else
        {
          bends.push_back({ std::isnan(c.Jump) ? -1.0 : c.Jump, { c.A, c.B } });
        }
      }
      std::sort(bends.begin(), bends.end());
      int merged = 0;
      std::set<int> changed;
      for (const auto& b : bends)
      {
        const int ra = uf.Find(b.second.first), rb = uf.Find(b.second.second);
        if (ra != rb && unite(ra, rb))
        {
          ++result.NumberOfBends;
          ++merged;
          changed.insert(ra);
          changed.insert(rb);
        }
      }
      if (merged == 0)
        break;
      for (auto k = known.begin(); k != known.end();)
        k = changed.count(k->first.first) || changed.count(k->first.second) ? known.erase(k) : std::next(k);
    }
    result.CreaseTestSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - creaseStart).count();
  }

  // Renumber the merged regions in order of first appearance.
  std::vector<int> relabel(regions, -1);
  result.Region.assign(F, -1);
  for (std::int64_t f = 0; f < F; ++f)
  {
    if (assigned[f] < 0)
    {
      result.NumberOfUnassignedFaces += band[f] != 0;
      continue;
    }
    int& r = relabel[uf.Find(assigned[f])];
    if (r < 0)
      r = result.NumberOfRegions++;
    result.Region[f] = r;
  }

  // Piecewise smoothing: every face takes the mean normal of its own
  // region's faces within NormalSmoothingDepth steps, which never reaches
  // across a feature line. On a noisy surface AT's u keeps some of the
  // noise (its data term); a short mean over one side removes most of it.
  if (par.NormalSmoothingDepth > 0)
  {
    std::vector<Vec3> smooth(out);
    vtkSMPTools::For(0, F, [&](std::int64_t b, std::int64_t e) {
      SearchScratch& s = scratch.Local();
      for (std::int64_t f0 = b; f0 < e; ++f0)
      {
        const int r0 = result.Region[f0];
        if (r0 < 0)
          continue;
        Vec3 sum;
        Breadth(graph, s, f0, par.NormalSmoothingDepth,
          [&](std::int64_t g) { return result.Region[g] == r0; },
          [&](std::int64_t f, int, int limit) {
            sum += out[f];
            return limit;
          });
        const Vec3 m = sum.Unit();
        if (m.Norm() > 0)
          smooth[f0] = m;
      }
    });
    out.swap(smooth);
  }

  // 5. Feature edges: between faces of different regions, but for the
  // stretches step 7 found to be bends. The output field keeps to their
  // sides (crease).
  std::vector<char> crease(E, 0);
  for (std::int64_t e = 0; e < E; ++e)
  {
    if (edgeCrease[e] == 0)
      continue;
    double angle = -1;
    for (std::int64_t a = graph.EdgeFacePtr[e]; a < graph.EdgeFacePtr[e + 1]; ++a)
      for (std::int64_t b = a + 1; b < graph.EdgeFacePtr[e + 1]; ++b)
      {
        const std::int64_t fa = graph.EdgeFaces[a], fb = graph.EdgeFaces[b];
        const int ra = result.Region[fa], rb = result.Region[fb];
        if (ra >= 0 && rb >= 0 && ra != rb)
          angle = std::max(angle, AngleDegrees(out[fa], out[fb]));
      }
    if (angle >= 0)
    {
      crease[e] = 1;
      result.FeatureEdges.push_back(graph.Edges[e]);
      result.FeatureAngle.push_back(angle);
    }
  }
  // The same edges as each face's sides: the mesh stage's creases. Regions
  // cannot say it, since a line may be drawn on some stretches only.
  result.CreaseSides.assign(F, 0);
  for (std::int64_t f = 0; f < F; ++f)
  {
    const std::int64_t b = offsets[f], m = offsets[f + 1] - b;
    for (std::int64_t i = 0; i < m && i < 8; ++i)
    {
      const std::int64_t p = connectivity[b + i], q = connectivity[b + (i + 1) % m];
      const std::array<std::int64_t, 2> key{ std::min(p, q), std::max(p, q) };
      for (std::int64_t k = graph.FaceEdgePtr[f]; k < graph.FaceEdgePtr[f + 1]; ++k)
        if (crease[graph.FaceEdges[k]] && graph.Edges[graph.FaceEdges[k]] == key)
          result.CreaseSides[f] |= static_cast<unsigned char>(1u << i);
    }
  }
  // 10. The output field (dgSharpFeaturesField.h): a twiced Gaussian of the
  // input normals within each side of the kept creases (blended with AT's u
  // away from the lines and AT's band, as much as the surface is noisy), or
  // of the side normals found above within SearchDepth of a crease, where
  // the input blends the two sides. The noise the surface shows is the
  // share of faces that face away from their input normal (a voxel face
  // turned more than 90 degrees from the surface), 0 on a clean digital
  // surface of any shape and 0.22-0.23 at the paper's noise k = 0.3; it
  // sets the Gaussian's width too, and where the input's blur leans
  // nothing (an evenly curved part) the field is 1.4 times as wide.
  if (inputNormals && par.FieldWidth >= 0)
  {
    std::int64_t away = 0;
    for (std::int64_t f = 0; f < F; ++f)
      away += polyNormal[f].Dot(input[f]) < 0;
    result.NoiseShare = static_cast<double>(away) / static_cast<double>(F);
    const double noise = std::min(1.0, result.NoiseShare / 0.22);
    // The width near the lines, and away from them at least 2 edges while
    // the input's blur is undone below (the step doubles the
    // digitisation's wiggle, and the Gaussian takes it out). Near a line
    // the window is one-sided, and a wider one bends a curved side's
    // normals: cube-sphere's spherical strips between the discs (5.6
    // voxels wide at most) measured H R 1.6 % off with 1 edge, 3.8 % with 2.
    double nearWidth = par.FieldWidth, width = par.FieldWidth;
    if (par.FieldWidth == 0)
    {
      nearWidth = 1.0 + 1.5 * std::min(1.5, result.NoiseShare / 0.22);
      width = std::max(par.UndoInputBlur ? 2.0 : 1.0, nearWidth);
    }
    result.FieldWidth = width;
    std::vector<int> steps(F, -1);
    std::vector<std::int64_t> queue;
    for (std::int64_t e = 0; e < E; ++e)
    {
      if (crease[e])
        for (std::int64_t a = graph.EdgeFacePtr[e]; a < graph.EdgeFacePtr[e + 1]; ++a)
          if (steps[graph.EdgeFaces[a]] < 0)
          {
            steps[graph.EdgeFaces[a]] = 0;
            queue.push_back(graph.EdgeFaces[a]);
          }
    }
    for (std::size_t h = 0; h < queue.size(); ++h)
    {
      const std::int64_t f = queue[h];
      if (steps[f] >= 2 * par.SearchDepth)
        continue;
      for (std::int64_t k = graph.FaceEdgePtr[f]; k < graph.FaceEdgePtr[f + 1]; ++k)
      {
        const std::int64_t e = graph.FaceEdges[k];
        for (std::int64_t j = graph.EdgeFacePtr[e]; j < graph.EdgeFacePtr[e + 1]; ++j)
        {
          const std::int64_t g = graph.EdgeFaces[j];
          if (steps[g] < 0)
          {
            steps[g] = steps[f] + 1;
            queue.push_back(g);
          }
        }
      }
    }
    // Within SearchDepth of a line (the steps go on to twice that for the
    // field's width below).
    auto nearLine = [&](std::int64_t f) { return steps[f] >= 0 && steps[f] <= par.SearchDepth; };
    // Within twice that: where the field stays narrow.
    auto nearField = [&](std::int64_t f) {
      return steps[f] >= 0 && steps[f] < std::max(1, 2 * par.SearchDepth);
    };
    // Curved sides up to a crease: AT's normals there are flatter than the
    // surface (its smoothing shrinks curvature), and the input blends the
    // two sides. A side that is a quadric to within the staircase gives its
    // normal to its faces near a crease that lie on it, where that normal
    // turns them by less than a feature angle (the two describe the same
    // surface).
    std::vector<RegionQuadric> sideQuadrics;
    if (par.QuadricSides)
    {
      std::vector<char> nearCrease(result.NumberOfRegions, 0);
      for (std::int64_t f = 0; f < F; ++f)
        if (nearLine(f) && result.Region[f] >= 0)
          nearCrease[result.Region[f]] = 1;
      sideQuadrics = FitQuadricSides(result.Region, result.NumberOfRegions, centre, out, nearCrease,
        par.MinimumRegionSize, 3.0 * par.SearchDepth * meanEdge2, meanEdge2,
        par.FitResidual * meanEdge2);
    }
    std::vector<Vec3> data(F);
    vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t f = begin; f < end; ++f)
      {
        // A side normal is data only where it is a side's: near a crease
        // the input blends the two sides, so it lies within about half the
        // crease's angle of either; a side normal farther than 60 degrees
        // from the input came from a region beyond a band wider than the
        // search (measured on organic volumes, whose bands cover more than
        // half the surface).
        data[f] = nearLine(f) && AngleDegrees(out[f], input[f]) <= 60 ? out[f] : input[f];
        // Away from the lines and from AT's band, AT's u has averaged the
        // noise over its whole smooth part, the Gaussian only over its
        // width; on a clean surface u is flatter than the surface (AT's
        // smoothing shrinks curvature) and the input is the better datum.
        // The two are blended by the noise the surface shows.
        if (!nearLine(f) && !band[f] && noise > 0)
        {
          const Vec3 u(normals[3 * f], normals[3 * f + 1], normals[3 * f + 2]);
          const Vec3 mix = input[f] * (1 - noise) + u.Unit() * noise;
          if (mix.Norm() > 0)
            data[f] = mix.Unit();
        }
        const int r = result.Region[f];
        if (nearLine(f) && r >= 0 && !sideQuadrics.empty() && sideQuadrics[r].Valid &&
          std::abs(sideQuadrics[r].Distance(centre[f])) <= meanEdge2)
        {
          const Vec3 n = sideQuadrics[r].Normal(centre[f]);
          if (AngleDegrees(n, data[f]) < par.MinimumFeatureAngle)
            data[f] = n;
        }
      }
    });
    // The input's blur undone on a clean surface: the input normals are
    // the surface's blurred over the estimator's ball, which leans them
    // towards the more curved side wherever the curvature changes (a
    // fillet meeting a plane). One Van Cittert step, d + (d - G d) with G a
    // Gaussian of 0.375 InputRadius (about the ball's own spread), takes
    // out the blur's leading term; the field's Gaussian then smooths what
    // the step amplifies. Near a crease the data are side normals and stay
    // as they are. Under noise the raw correction is mostly noise (and AT's
    // terraces, which the step would sharpen): as the square of the noise
    // gauge, the step takes the correction averaged over the gate's
    // Gaussian three times instead, with the gate's thresholds 1.5 times as
    // high at k = 0.3 (measured, 64^3 and 128^3: the fillets of radius 6
    // 0.62 / 0.61 of II's mean error -> 0.58 / 0.57, the blobs 0.52 ->
    // 0.51, the sphere, ellipsoid and torus within 0.02 degrees).
    const auto fieldStart = std::chrono::steady_clock::now();
    // The undo step and the field's two passes read the same searches
    // when the step's Gaussian reaches no farther than the field's.
    FieldSearches searches;
    if (!FindFieldSearches(graph, crease, centre, width * meanEdge2, searches))
      return fail("the output field needs a positive width, fewer than 2^32 faces and a surface "
                  "narrower than 2^21 field widths");
    const double averaged = 1.0 - (1.0 - noise) * (1.0 - noise);
    std::vector<double> lean;
    if (par.UndoInputBlur && par.InputRadius > 0)
    {
      std::vector<char> away(F);
      for (std::int64_t f = 0; f < F; ++f)
        away[f] = !nearLine(f);
      // The step's Gaussian: about the spread of the estimator's ball
      // (0.375 r), with a floor that matters at small radii only (measured:
      // at r = 4, 2 edges instead of 1.5 took the clean fillets' 95th
      // percentile from 8.2 to 6.6 degrees at 64^3; at r = 16 the floor
      // adds 2.4 %, where 0.5 r cost goursat half its accuracy). The gate's
      // thresholds were measured with a Gaussian of 0.375 r; the correction
      // where the curvature changes grows as the Gaussian's variance, and so
      // do they (docs/sharp-features.md, step 10).
      const double spread = 0.375 * par.InputRadius;
      const double stepWidth = std::sqrt(spread * spread + 1.75);
      const double gateScale = 4.0 / par.InputRadius * (stepWidth * stepWidth) / (spread * spread);
      std::vector<Vec3> sharpened;
      UndoBlurWithinSides(graph, crease, centre, data, stepWidth * meanEdge2, 1.0, sharpened,
        &away, &searches, width * meanEdge2, &lean, gateScale, averaged);
      data.swap(sharpened);
      // Near a line the window is one-sided (and under noise the line may
      // be a false one between AT's facets): there the field stays narrow,
      // as if the surface leaned.
      for (std::int64_t f = 0; f < F; ++f)
        if (nearField(f))
          lean[f] = std::max(lean[f], 2 * WideFullDegrees);
    }
    SmoothFieldWithinSides(graph, crease, centre, data, width * meanEdge2, out, nullptr, 1.0,
      &searches, lean.empty() ? nullptr : &lean);
    if (nearWidth != width)
    {
      // From the near width within SearchDepth of a line to the full width
      // at twice that, linearly in face steps.
      std::vector<char> close(F);
      for (std::int64_t f = 0; f < F; ++f)
        close[f] = nearField(f);
      std::vector<Vec3> narrow;
      SmoothFieldWithinSides(
        graph, crease, centre, data, nearWidth * meanEdge2, narrow, &close, meanEdge2, &searches);
      vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
        for (std::int64_t f = begin; f < end; ++f)
        {
          const double t = steps[f] < 0
            ? 1.0
            : std::max(0.0,
                std::min(1.0, static_cast<double>(steps[f] - par.SearchDepth) / std::max(1, par.SearchDepth)));
          const Vec3 m = narrow[f] * (1.0 - t) + out[f] * t;
          if (m.Norm() > 0)
            out[f] = m.Unit();
        }
      });
    }
    result.FieldSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - fieldStart).count();
  }
  result.Normals.resize(3 * F);
  for (std::int64_t f = 0; f < F; ++f)
  {
    result.Normals[3 * f] = out[f].x;
    result.Normals[3 * f + 1] = out[f].y;
    result.Normals[3 * f + 2] = out[f].z;
  }
  if (!report(1.0))
    return aborted();
  return true;
}

} // namespace dg
