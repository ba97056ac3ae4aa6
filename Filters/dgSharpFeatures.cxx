#include "dgSharpFeatures.h"

#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <utility>

namespace dg
{
namespace
{

struct Vec3
{
  double x = 0, y = 0, z = 0;
  Vec3() = default;
  Vec3(double a, double b, double c)
    : x(a)
    , y(b)
    , z(c)
  {
  }
  Vec3 operator+(const Vec3& o) const { return { x + o.x, y + o.y, z + o.z }; }
  Vec3 operator-(const Vec3& o) const { return { x - o.x, y - o.y, z - o.z }; }
  Vec3 operator*(double s) const { return { x * s, y * s, z * s }; }
  Vec3& operator+=(const Vec3& o)
  {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  double Dot(const Vec3& o) const { return x * o.x + y * o.y + z * o.z; }
  Vec3 Cross(const Vec3& o) const
  {
    return { y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x };
  }
  double Norm() const { return std::sqrt(this->Dot(*this)); }
  Vec3 Unit() const
  {
    const double n = this->Norm();
    return n > 0 ? *this * (1.0 / n) : Vec3();
  }
};

double AngleDegrees(const Vec3& a, const Vec3& b)
{
  // atan2 of |a x b| and a.b: accurate for small angles, unlike acos.
  return std::atan2(a.Cross(b).Norm(), a.Dot(b)) * 180.0 / M_PI;
}

// Faces around each edge (CSR) and edges of each face, from the polygons'
// sides; an edge is an unordered point pair.
struct FaceGraph
{
  std::vector<std::array<std::int64_t, 2>> Edges;
  std::vector<std::int64_t> EdgeFacePtr;
  std::vector<std::int64_t> EdgeFaces;
  std::vector<std::int64_t> FaceEdgePtr;
  std::vector<std::int64_t> FaceEdges;

  void Build(const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& conn)
  {
    const std::int64_t F = static_cast<std::int64_t>(offsets.size()) - 1;
    struct Side
    {
      std::int64_t A, B, Face;
    };
    std::vector<Side> sides;
    sides.reserve(conn.size());
    for (std::int64_t f = 0; f < F; ++f)
    {
      const std::int64_t b = offsets[f], e = offsets[f + 1];
      for (std::int64_t k = b; k < e; ++k)
      {
        const std::int64_t p = conn[k], q = conn[k + 1 < e ? k + 1 : b];
        if (p != q)
          sides.push_back({ std::min(p, q), std::max(p, q), f });
      }
    }
    std::sort(sides.begin(), sides.end(), [](const Side& s, const Side& t) {
      return s.A != t.A ? s.A < t.A : s.B != t.B ? s.B < t.B : s.Face < t.Face;
    });
    this->EdgeFacePtr.assign(1, 0);
    std::vector<std::int64_t> faceEdgeCount(F + 1, 0);
    std::vector<std::pair<std::int64_t, std::int64_t>> faceEdge; // (face, edge)
    faceEdge.reserve(sides.size());
    for (std::size_t i = 0; i < sides.size();)
    {
      std::size_t j = i;
      const std::int64_t e = static_cast<std::int64_t>(this->Edges.size());
      this->Edges.push_back({ sides[i].A, sides[i].B });
      for (; j < sides.size() && sides[j].A == sides[i].A && sides[j].B == sides[i].B; ++j)
      {
        // A face that runs twice along the same edge counts once.
        if (j == i || sides[j].Face != sides[j - 1].Face)
        {
          this->EdgeFaces.push_back(sides[j].Face);
          faceEdge.emplace_back(sides[j].Face, e);
          ++faceEdgeCount[sides[j].Face + 1];
        }
      }
      this->EdgeFacePtr.push_back(static_cast<std::int64_t>(this->EdgeFaces.size()));
      i = j;
    }
    std::partial_sum(faceEdgeCount.begin(), faceEdgeCount.end(), faceEdgeCount.begin());
    this->FaceEdgePtr = faceEdgeCount;
    this->FaceEdges.assign(faceEdge.size(), 0);
    std::vector<std::int64_t> fill(faceEdgeCount.begin(), faceEdgeCount.end() - 1);
    for (const auto& fe : faceEdge)
      this->FaceEdges[fill[fe.first]++] = fe.second;
  }
};

struct UnionFind
{
  std::vector<int> Parent;
  explicit UnionFind(int n)
    : Parent(n)
  {
    std::iota(this->Parent.begin(), this->Parent.end(), 0);
  }
  int Find(int a)
  {
    while (this->Parent[a] != a)
      a = this->Parent[a] = this->Parent[this->Parent[a]];
    return a;
  }
  bool Unite(int a, int b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a == b)
      return false;
    this->Parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

// What a band face's search found of one region.
struct RegionSample
{
  int Region;
  int Count = 0;
  Vec3 CentroidSum, NormalSum;
  double Moment[6] = { 0, 0, 0, 0, 0, 0 }; // sums of xx, xy, xz, yy, yz, zz
  Eigen::Matrix3d NormalMoment = Eigen::Matrix3d::Zero(); // sum of u x^T
  double NormalSquares = 0;                                // sum of |u|^2

  void AddPosition(const Vec3& p)
  {
    this->CentroidSum += p;
    this->Moment[0] += p.x * p.x;
    this->Moment[1] += p.x * p.y;
    this->Moment[2] += p.x * p.z;
    this->Moment[3] += p.y * p.y;
    this->Moment[4] += p.y * p.z;
    this->Moment[5] += p.z * p.z;
  }

  void AddNormal(const Vec3& u, const Vec3& p)
  {
    this->NormalSum += u;
    this->NormalMoment += Eigen::Vector3d(u.x, u.y, u.z) * Eigen::RowVector3d(p.x, p.y, p.z);
    this->NormalSquares += u.Dot(u);
  }

  Eigen::Matrix3d Covariance() const
  {
    const double n = this->Count;
    const Vec3 c = this->CentroidSum * (1.0 / n);
    Eigen::Matrix3d cov;
    cov(0, 0) = this->Moment[0] / n - c.x * c.x;
    cov(0, 1) = cov(1, 0) = this->Moment[1] / n - c.x * c.y;
    cov(0, 2) = cov(2, 0) = this->Moment[2] / n - c.x * c.z;
    cov(1, 1) = this->Moment[3] / n - c.y * c.y;
    cov(1, 2) = cov(2, 1) = this->Moment[4] / n - c.y * c.z;
    cov(2, 2) = this->Moment[5] / n - c.z * c.z;
    return cov;
  }

  // How far the side's surface falls below its plane (centroid c, unit
  // normal m) at p, relative to its mean fall over the samples (the plane
  // passes through their centroid): 1/2 k (|d|^2 - tr Cov_t), d = p - c in
  // the plane, k the side's curvature along the edge, taken as isotropic.
  // k is the slope along the edge of the normal field's linear fit
  // u(x) = mean + S (x - c): the normals, because a digital plane's
  // staircase bends the positions but not the regularised normals; along
  // the edge, because the normals next to AT's band still lean towards the
  // other side (a slope across the edge, which a flat side must not read as
  // curvature), and that lean does not change along the edge. The fall is
  // shrunk to nothing when k is not significant against the fit's residual
  // (James-Stein-like factor 1 - z^2 se^2 / fall^2, z = 3): noise alone
  // must not bend a plane.
  // The linear fit u(x) = mean + S (x - c) of the normals to the positions
  // (cov: the positions' covariance): S, and the normals' cross-covariance
  // with the positions, cux. A small ridge: the samples barely spread along
  // the normal.
  Eigen::Matrix3d NormalSlope(const Eigen::Matrix3d& cov, Eigen::Matrix3d& cux) const
  {
    const double n = this->Count;
    const Eigen::Vector3d c(
      this->CentroidSum.x / n, this->CentroidSum.y / n, this->CentroidSum.z / n);
    const Eigen::Vector3d ubar(
      this->NormalSum.x / n, this->NormalSum.y / n, this->NormalSum.z / n);
    cux = this->NormalMoment / n - ubar * c.transpose();
    const Eigen::Matrix3d reg = cov + 1e-3 * cov.trace() * Eigen::Matrix3d::Identity();
    return cux * reg.inverse();
  }

  // S restricted to the plane of unit normal m and symmetrised, as a shape
  // operator is.
  static Eigen::Matrix3d InPlane(const Eigen::Matrix3d& S, const Eigen::Vector3d& m)
  {
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - m * m.transpose();
    const Eigen::Matrix3d St = P * S * P;
    return 0.5 * (St + St.transpose());
  }

  double Fall(const Vec3& m, const Vec3& p) const
  {
    if (this->Count < 6)
      return 0;
    const double n = this->Count;
    const Eigen::Vector3d c(
      this->CentroidSum.x / n, this->CentroidSum.y / n, this->CentroidSum.z / n);
    const Eigen::Vector3d ubar(
      this->NormalSum.x / n, this->NormalSum.y / n, this->NormalSum.z / n);
    const Eigen::Matrix3d cov = this->Covariance();
    Eigen::Matrix3d cux;
    const Eigen::Matrix3d S = this->NormalSlope(cov, cux);
    const Eigen::Vector3d mm(m.x, m.y, m.z);
    const Eigen::Vector3d d0 = Eigen::Vector3d(p.x, p.y, p.z) - c;
    const Eigen::Vector3d d = d0 - mm * mm.dot(d0);
    if (!S.allFinite() || !(d.norm() > 1e-9))
      return 0;
    const Eigen::Vector3d e = mm.cross(d).normalized();
    const double k = e.dot(S * e);
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - mm * mm.transpose();
    const double spread = d.squaredNorm() - (P * cov * P).trace();
    const double fall = 0.5 * k * spread;
    // The slope's standard error: sigma / sqrt(n var_e(x)), sigma^2 the
    // residual variance per tangent component around the fit restricted to
    // the plane and symmetrised, as a shape operator is: what the raw fit
    // explains beyond it (the lean across the edge, a twist) is scatter.
    const Eigen::Matrix3d St = InPlane(S, mm);
    const double cuu = this->NormalSquares / n - ubar.squaredNorm();
    const double rss = std::max(
      0.0, cuu - 2 * (St * cux.transpose()).trace() + (St * cov * St.transpose()).trace());
    const double sigma2 = rss * n / std::max(1.0, 2.0 * (n - 4));
    const double se =
      0.5 * std::abs(spread) * std::sqrt(sigma2 / (n * std::max(e.dot(cov * e), 1e-12)));
    constexpr double z = 3.0;
    const double shrink = std::max(0.0, 1.0 - z * z * se * se / std::max(fall * fall, 1e-300));
    return std::isfinite(fall * shrink) ? fall * shrink : 0.0;
  }

  // The normal of the least-squares plane through the positions (the
  // covariance's smallest eigenvector), turned to the side of the mean field
  // normal; the mean field normal itself when the positions do not span a
  // plane.
  Vec3 PlaneNormal(double maxResidual2) const
  {
    const Vec3 mean = this->NormalSum.Unit();
    if (this->Count < 3)
      return mean;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(this->Covariance());
    const Eigen::Vector3d ev = eig.eigenvalues();
    // A line of faces (second eigenvalue ~ 0) does not fix a plane.
    if (!(ev(1) > 1e-3 * std::max(ev(2), 1e-300)) || !(ev(0) <= maxResidual2))
      return mean;
    const Eigen::Vector3d e = eig.eigenvectors().col(0);
    Vec3 nrm(e(0), e(1), e(2));
    return nrm.Dot(mean) < 0 ? nrm * -1.0 : nrm;
  }
};

// Per-thread scratch of the band faces' searches.
struct SearchScratch
{
  std::vector<std::uint32_t> Stamp;
  std::uint32_t Current = 0;
  std::vector<std::pair<std::int64_t, int>> Queue;
  std::vector<RegionSample> Samples;
  std::vector<std::int64_t> Fit;
};


// Breadth-first search over the face graph from f0, through the faces that
// pass(face) accepts, at most `limit` steps; visit(face, depth, limit) sees
// every face reached in order of depth and returns the limit (it may lower
// it). The scratch's stamps make each search O(faces reached).
template<class Pass, class Visit>
void Breadth(const FaceGraph& graph, SearchScratch& s, std::int64_t f0, int limit,
  const Pass& pass, const Visit& visit)
{
  if (s.Stamp.empty())
    s.Stamp.assign(graph.FaceEdgePtr.size() - 1, 0);
  if (++s.Current == 0)
  {
    std::fill(s.Stamp.begin(), s.Stamp.end(), 0);
    s.Current = 1;
  }
  s.Queue.assign(1, { f0, 0 });
  s.Stamp[f0] = s.Current;
  for (std::size_t head = 0; head < s.Queue.size(); ++head)
  {
    const std::int64_t f = s.Queue[head].first;
    const int depth = s.Queue[head].second;
    if (depth > limit)
      break;
    limit = visit(f, depth, limit);
    if (depth >= limit)
      continue;
    for (std::int64_t k = graph.FaceEdgePtr[f]; k < graph.FaceEdgePtr[f + 1]; ++k)
    {
      const std::int64_t e = graph.FaceEdges[k];
      for (std::int64_t j = graph.EdgeFacePtr[e]; j < graph.EdgeFacePtr[e + 1]; ++j)
      {
        const std::int64_t g = graph.EdgeFaces[j];
        if (s.Stamp[g] != s.Current && pass(g))
        {
          s.Stamp[g] = s.Current;
          s.Queue.emplace_back(g, depth + 1);
        }
      }
    }
  }
}

} // namespace

bool ComputeSharpFeatures(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* normals, const double* v, const SharpFeatureParameters& par,
  SharpFeatureResult& result, std::string* error, const std::function<bool(double)>& progress)
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
  std::vector<Vec3> centre(F), polyNormal(F), field(F);
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
      field[f] = Vec3(normals[3 * f], normals[3 * f + 1], normals[3 * f + 2]).Unit();
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
  const double maxResidual2 = std::pow(par.FitResidual * meanEdge2, 2);

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

  // Planar regions: a region whose normal field turns by less than
  // PlanarRegionAngle across it is a plane, and its side in step 3 is the
  // least-squares plane through all its faces instead of the few found near
  // the band face: on a noisy or staircased plane that is the plane the
  // voxels show, not a local tilt of it (cube and sphere at k = 0.3: recall
  // 0.90-0.94 -> 0.95-0.97). The turn is the slope of a linear fit of the
  // normals to the positions, u(x) = mean + S (x - c), its largest
  // in-plane curvature times the region's extent; AT's normals still lean
  // towards the other side next to the band, so true planes measure 3-5
  // degrees (cube and sphere's discs, 64^3, k = 0.3), their curved
  // neighbours 9 and more.
  std::vector<char> planar(regions, 0);
  std::vector<Vec3> planeNormal(regions), planePoint(regions);
  if (par.PlanarRegionAngle > 0)
  {
    std::vector<RegionSample> whole(regions);
    std::vector<Vec3> origin(regions);
    std::vector<char> started(regions, 0);
    for (std::int64_t f = 0; f < F; ++f)
    {
      const int r = region[f];
      if (r < 0)
        continue;
      if (!started[r])
      {
        started[r] = 1;
        origin[r] = centre[f]; // small numbers for the moments
      }
      ++whole[r].Count;
      whole[r].AddPosition(centre[f] - origin[r]);
      whole[r].AddNormal(field[f], centre[f] - origin[r]);
    }
    vtkSMPTools::For(0, regions, [&](int b, int e) {
      for (int r = b; r < e; ++r)
      {
        const RegionSample& w = whole[r];
        planar[r] = 0;
        if (w.Count < par.MinimumRegionSize)
          continue;
        const Eigen::Matrix3d cov = w.Covariance();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        const Eigen::Vector3d ev = eig.eigenvalues();
        // Only regions that reach beyond a band face's own search: in a
        // smaller one the local fit sees the whole region anyway, and a
        // plane through a few dozen noisy faces is less sure of its normal
        // than their mean (measured: admitting them cost cube and sphere
        // 128^3 at k = 0.3 a whole circle, recall 0.97 -> 0.82).
        if (!(ev(1) > 1e-3 * std::max(ev(2), 1e-300)) ||
          !(std::sqrt(ev(2)) >= par.SearchDepth * meanEdge2))
          continue;
        const Eigen::Vector3d m = eig.eigenvectors().col(0);
        Eigen::Matrix3d cux;
        const Eigen::Matrix3d S = RegionSample::InPlane(w.NormalSlope(cov, cux), m);
        const Eigen::Vector3d k = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S).eigenvalues();
        const double turn = std::max(std::abs(k(0)), std::abs(k(2))) * 2.0 * std::sqrt(ev(2));
        if (!(turn * 180.0 / 3.14159265358979323846 < par.PlanarRegionAngle))
          continue;
        Vec3 nrm(m(0), m(1), m(2));
        planeNormal[r] = nrm.Dot(w.NormalSum) < 0 ? nrm * -1.0 : nrm;
        planePoint[r] = origin[r] + w.CentroidSum * (1.0 / w.Count);
        planar[r] = 1;
      }
    });
    for (int r = 0; r < regions; ++r)
      result.NumberOfPlanarRegions += planar[r];
  }

  // 3. Band faces join the region whose local plane is nearest.
  std::vector<std::int64_t> bandFaces;
  for (std::int64_t f = 0; f < F; ++f)
    if (band[f])
      bandFaces.push_back(f);
  result.NumberOfBandFaces = static_cast<std::int64_t>(bandFaces.size());
  std::vector<Vec3> out(field);
  std::vector<int> assigned(region);
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
        auto it = std::find_if(s.Samples.begin(), s.Samples.end(),
          [&](const RegionSample& r) { return r.Region == region[f]; });
        if (it == s.Samples.end())
        {
          s.Samples.emplace_back();
          s.Samples.back().Region = region[f];
          it = s.Samples.end() - 1;
        }
        ++it->Count;
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
      for (const auto& r : s.Samples)
      {
        if (r.Count < support || (anyFacing && r.NormalSum.Dot(polyNormal[f0]) <= 0))
          continue;
        // Positions are relative to the band face (p = 0).
        const bool flat = planar[r.Region] != 0;
        const Vec3 n = flat ? planeNormal[r.Region] : r.NormalSum.Unit();
        const Vec3 c = flat ? planePoint[r.Region] - centre[f0] : r.CentroidSum * (1.0 / r.Count);
        double sd = n.Dot(c * -1.0);
        if (par.CurvedSides && !flat)
          sd += r.Fall(n, Vec3());
        bool take = !chosen;
        if (chosen)
        {
          const double convexity = chosenN.Dot(c - chosenC) + n.Dot(chosenC - c);
          take = convexity < 0 ? sd > chosenS : sd < chosenS;
        }
        if (take)
        {
          chosen = &r;
          chosenN = n;
          chosenC = c;
          chosenS = sd;
        }
      }
      if (chosen)
      {
        assigned[f0] = chosen->Region;
        out[f0] = par.FitPlanes ? chosen->PlaneNormal(maxResidual2) : chosenN;
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
          auto it = std::find_if(s.Samples.begin(), s.Samples.end(),
            [&](const RegionSample& r) { return r.Region == assigned[f]; });
          if (it == s.Samples.end())
          {
            s.Samples.emplace_back();
            s.Samples.back().Region = assigned[f];
            it = s.Samples.end() - 1;
          }
          ++it->Count;
          it->NormalSum += out[f];
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
  for (const auto& w : weak)
  {
    int ra = uf.Find(w.second.first), rb = uf.Find(w.second.second);
    if (ra == rb)
      continue;
    if (apart[ra].size() > apart[rb].size())
      std::swap(ra, rb);
    bool separated = false;
    for (int other : apart[ra])
      separated |= uf.Find(other) == rb;
    if (separated)
    {
      ++result.NumberOfRefusedMerges;
      continue;
    }
    uf.Unite(ra, rb);
    ++result.NumberOfMergedBoundaries;
    const int root = uf.Find(ra), gone = root == ra ? rb : ra;
    if (apart[root].size() < apart[gone].size())
      apart[root].swap(apart[gone]); // the shorter list is the one copied
    apart[root].insert(apart[root].end(), apart[gone].begin(), apart[gone].end());
    std::vector<int>().swap(apart[gone]);
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

  // 5. Feature edges: between faces of different regions.
  for (std::int64_t e = 0; e < E; ++e)
  {
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
      result.FeatureEdges.push_back(graph.Edges[e]);
      result.FeatureAngle.push_back(angle);
    }
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
