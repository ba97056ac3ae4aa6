#include "dgCorrectedCurvature.h"

#include "dgCorrectedCurvatureBalls.h"
#include "dgCorrectedCurvatureRadius.h"
#include "dgCorrectedCurvatureSurface.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace dg
{
namespace
{
using curvature::At;
using curvature::V3;

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
  const std::int64_t* faceIds, const unsigned char* creaseSides)
{
  using namespace curvature;
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

  Surface surface;
  surface.Points = points;
  surface.Offsets = &offsets;
  surface.Connectivity = &connectivity;
  surface.Normals = normals;
  surface.Region = region;
  surface.CreaseSides = region ? creaseSides : nullptr;
  if (surface.CreaseSides)
  {
    surface.OnCrease.assign(numberOfPoints, 0);
    for (std::int64_t f = 0; f < F; ++f)
    {
      const std::int64_t m = offsets[f + 1] - offsets[f];
      for (std::int64_t i = 0; i < m && i < 8; ++i)
        if (creaseSides[f] & (1u << i))
        {
          surface.OnCrease[connectivity[offsets[f] + i]] = 1;
          surface.OnCrease[connectivity[offsets[f] + (i + 1) % m]] = 1;
        }
    }
  }
  surface.Ghost = ghost;
  surface.FaceIds = faceIds;
  // Faces around each point (CSR).
  std::vector<std::int64_t>& start = surface.Start;
  std::vector<std::int64_t>& around = surface.Around;
  start.assign(numberOfPoints + 1, 0);
  around.resize(connectivity.size());
  surface.AroundCorner.resize(connectivity.size());
  for (std::int64_t id : connectivity)
    ++start[id + 1];
  for (std::int64_t p = 0; p < numberOfPoints; ++p)
    start[p + 1] += start[p];
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::int64_t f = 0; f < F; ++f)
      for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
      {
        const std::int64_t slot = fill[connectivity[k]]++;
        around[slot] = f;
        surface.AroundCorner[slot] = k;
      }
  }
  const auto isGhost = [&](std::int64_t f) { return surface.IsGhost(f); };
  // The sharp stage flags a drawn edge on every face along it: an edge of
  // two faces that one flags and the other does not means the flags no
  // longer match the corners (a filter reordered them in between).
  if (surface.CreaseSides)
  {
    std::int64_t oneSided = 0;
    for (std::int64_t f = 0; f < F; ++f)
      for (std::int64_t ka = offsets[f]; ka < offsets[f + 1] && creaseSides[f]; ++ka)
      {
        const std::int64_t kb = ka + 1 < offsets[f + 1] ? ka + 1 : offsets[f];
        if (!surface.FlagsSide(f, ka, kb))
          continue;
        // The other faces on the edge, by their corner at a.
        const std::int64_t a = connectivity[ka], b = connectivity[kb];
        int others = 0;
        bool flagged = false;
        for (std::int64_t j = start[a]; j < start[a + 1]; ++j)
        {
          const std::int64_t g = around[j], kg = surface.AroundCorner[j];
          if (g == f)
            continue;
          const std::int64_t gn = kg + 1 < offsets[g + 1] ? kg + 1 : offsets[g];
          const std::int64_t gp = kg > offsets[g] ? kg - 1 : offsets[g + 1] - 1;
          for (std::int64_t kc : { gn, gp })
            if (connectivity[kc] == b)
            {
              ++others;
              flagged = flagged || surface.FlagsSide(g, kg, kc);
            }
        }
        oneSided += others == 1 && !flagged;
      }
    if (oneSided > 0)
      return fail("the crease sides do not match the faces' corners (" + std::to_string(oneSided) +
        " edges flagged by one of their two faces only): a filter after the sharp stage reordered "
        "the corners; drop the CreaseSides array or remap its bits");
  }

  // Each face's measures, with corner normals from the faces around each
  // corner: all of them (perSide false), or those of the face's own region.
  std::vector<V3> centre(F);
  std::vector<CorrectedMeasures> measures(F);
  const bool perSide = region != nullptr;
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
          if (!perSide || surface.SameSide(f, around[k], p))
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
  // Per side, a face with a corner on another region's face has corner
  // normals from one side of that corner only, which understate how the
  // normal turns across it: such faces lend no measures to balls that hold
  // faces whose corners are all inside their region (their ball still
  // measures them, from those faces).
  std::vector<char> interior(F, 1);
  if (region)
    vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t f = begin; f < end; ++f)
        for (std::int64_t k = offsets[f]; k < offsets[f + 1] && interior[f]; ++k)
        {
          const std::int64_t p = connectivity[k];
          for (std::int64_t j = start[p]; j < start[p + 1]; ++j)
            if (!surface.SameSide(f, around[j], p))
            {
              interior[f] = 0;
              break;
            }
        }
    });

  std::vector<Crease> creases;
  const double meanEdge = WholeSurfaceFigures(surface, centre, measures, result, creases);

  // The ramp's width: the mean edge length, or the whole surface's when a
  // piece is given it.
  const double l = par.EdgeLength > 0 ? par.EdgeLength : meanEdge;
  const double R = par.Radius;
  const bool adaptive = par.AdaptiveRadius;
  FaceCells cells;
  SortIntoCells(centre, measures, normals, region, interior, R, l, adaptive, cells);
  const std::int64_t nCells = cells.Cells();

  result.Mean.assign(F, 0.0);
  result.BallNormal.assign(3 * F, 0.0);
  result.Gaussian.assign(F, 0.0);
  result.K1.assign(F, 0.0);
  result.K2.assign(F, 0.0);
  result.D1.assign(3 * F, 0.0);
  result.D2.assign(3 * F, 0.0);
  result.BallRadius.assign(F, 0.0);

  FaceGroups groups;
  std::vector<char> isRep(adaptive ? F : 0, 0);
  if (adaptive)
  {
    GroupFaces(cells, faceIds, groups);
    for (const std::int64_t i : groups.Rep)
      isRep[i] = 1;
  }

  // First pass: every face's ball of radius R. With the per-face radius,
  // its sums are kept (the larger balls add to them), and whether the ball
  // is a whole disc of its region's interior faces: a face whose ball of R
  // reaches its region's border keeps R (the rule assumes a disc; on a
  // strip narrower than the ball, a cube's side near its edges, the noise
  // and the bias grow otherwise with r). A ghost representative is measured
  // too: its balls tell its neighbours' radii.
  // Not zeroed: the pass writes every position it measures, the only ones
  // read, and a first touch on the threads costs less than a serial memset
  // (64 MB on octa-flower 512^3).
  std::unique_ptr<double[]> firstSums(
    adaptive ? new double[static_cast<std::size_t>(SUMS) * F] : nullptr);
  std::vector<char> keepRadius(adaptive ? F : 0, 0);
  vtkSMPTools::For(0, nCells, [&](std::int64_t begin, std::int64_t end) {
    Runs runs;
    Candidates candidates;
    std::vector<std::int64_t> faces;
    std::vector<double> radius, sums;
    std::vector<char> border;
    double sum[QUANTITIES];
    for (std::int64_t c = begin; c < end; ++c)
    {
      faces.clear();
      for (std::int64_t i = cells.CellStart[c]; i < cells.CellStart[c + 1]; ++i)
        if (!isGhost(cells.Face[i]) || (adaptive && isRep[i]))
          faces.push_back(i);
      if (faces.empty())
        continue;
      const std::int64_t n = static_cast<std::int64_t>(faces.size());
      cells.Gather(c, R, runs, candidates);
      radius.assign(n, R);
      sums.resize(SUMS * n);
      border.resize(n);
      cells.BallSums(faces.data(), radius.data(), n, candidates, sums.data(), border.data());
      for (std::int64_t k = 0; k < n; ++k)
      {
        const std::int64_t i = faces[k], f = cells.Face[i];
        std::copy(sums.begin() + SUMS * k, sums.begin() + SUMS * (k + 1), sum + M0);
        // A face that will be measured again needs only its k1, k2 here.
        if (!isGhost(f) && CurvaturesFromSums(f, sum, !adaptive || border[k], result))
          result.BallRadius[f] = R;
        if (adaptive)
        {
          std::copy(sum + M0, sum + QUANTITIES, firstSums.get() + SUMS * i);
          keepRadius[i] = border[k];
        }
      }
    }
  });
  if (adaptive)
    ChooseBallRadii(cells, groups, firstSums.get(), keepRadius, ghost, R, result);

  // The integral of H: per side, each interior face's own measure and each
  // boundary face's ball estimate over its area, plus what the creases hold;
  // with one region, the faces' measures.
  result.TotalMean = 0;
  for (std::int64_t f = 0; f < F; ++f)
    if (!isGhost(f))
      result.TotalMean += interior[f] ? 0.5 * measures[f].Mu1 : result.Mean[f] * measures[f].Mu0;
  MeasureCreases(surface, centre, creases, result);
  result.TotalMean += result.CreaseTotalMean;
  return true;
}

} // namespace dg
