#include "dgSharpFeaturesCreases.h"

#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace dg
{
namespace sharp
{
namespace
{

constexpr double Degrees = 180.0 / M_PI;

double Median(std::vector<double> x)
{
  if (x.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
  return x[x.size() / 2];
}

double Angle(const Vec3& a, const Vec3& b)
{
  const double c = a.Unit().Dot(b.Unit());
  return std::acos(std::max(-1.0, std::min(1.0, c))) * Degrees;
}

// An edge between two groups' faces, A in the smaller group.
struct LineEdge
{
  std::int64_t A, B;
};

struct FitScratch : BreadthScratch
{
  std::vector<std::int64_t> Faces, Turn, Line;
};

// One side's area vectors summed near the line and farther out, within a
// slab across it.
struct TurnSums
{
  Vec3 Near, Far;
  int NearCount = 0, FarCount = 0;
};

// A side's input normals as a linear function of the position, fitted to
// `faces` and evaluated at x0; the rate at which they turn when moving from
// the faces towards x0 (per unit length) and the fit's RMS residual.
struct SideFit
{
  Vec3 Normal, Rate;
  double Residual = 0;
  bool Valid = false;
};

SideFit FitSide(const std::vector<std::int64_t>& faces, const std::vector<Vec3>& centre,
  const std::vector<Vec3>& input, const Vec3& x0)
{
  SideFit out;
  Vec3 xbar;
  for (std::int64_t f : faces)
    xbar += centre[f];
  xbar = xbar * (1.0 / faces.size());
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 4, 3> atb = Eigen::Matrix<double, 4, 3>::Zero();
  for (std::int64_t f : faces)
  {
    const Vec3 d = centre[f] - xbar;
    const Eigen::Vector4d m(1.0, d.x, d.y, d.z);
    ata += m * m.transpose();
    atb += m * Eigen::RowVector3d(input[f].x, input[f].y, input[f].z);
  }
  // A small ridge on the slopes: the faces barely spread along the normal.
  const double ridge = 1e-3 * (ata(1, 1) + ata(2, 2) + ata(3, 3));
  for (int k = 1; k < 4; ++k)
    ata(k, k) += ridge;
  Eigen::LDLT<Eigen::Matrix4d> ldlt(ata);
  if (ldlt.info() != Eigen::Success)
    return out;
  const Eigen::Matrix<double, 4, 3> coef = ldlt.solve(atb);
  auto at = [&](const Vec3& x) {
    const Vec3 d = x - xbar;
    const Eigen::RowVector3d u = Eigen::RowVector4d(1.0, d.x, d.y, d.z) * coef;
    return Vec3(u(0), u(1), u(2));
  };
  out.Normal = at(x0);
  if (!(out.Normal.Norm() > 0) || !std::isfinite(out.Normal.Norm()))
    return out;
  const Vec3 n = out.Normal.Unit();
  const Vec3 d = x0 - xbar;
  const Vec3 towards = (d - n * d.Dot(n)).Unit();
  const Eigen::Vector3d rate =
    coef.block<3, 3>(1, 0).transpose() * Eigen::Vector3d(towards.x, towards.y, towards.z);
  out.Rate = Vec3(rate(0), rate(1), rate(2));
  double r2 = 0;
  for (std::int64_t f : faces)
  {
    const Vec3 e = input[f] - at(centre[f]);
    r2 += e.Dot(e);
  }
  out.Residual = std::sqrt(r2 / faces.size()) * Degrees;
  out.Valid = true;
  return out;
}

// The line's direction near x0 (the principal axis of the line faces'
// centres), then each side face within TurnSlab of x0 along it, summed by
// its distance across.
TurnSums MeasureTurn(const std::vector<Vec3>& centre, const std::vector<Vec3>& area, const Vec3& x0,
  const std::vector<std::int64_t>& line, const std::vector<std::int64_t>& faces,
  const CreaseTestSettings& settings)
{
  TurnSums out;
  if (line.size() < 3)
    return out;
  Vec3 mean;
  for (std::int64_t f : line)
    mean += centre[f];
  mean = mean * (1.0 / line.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::int64_t f : line)
  {
    const Vec3 d = centre[f] - mean;
    const Eigen::Vector3d v(d.x, d.y, d.z);
    cov += v * v.transpose();
  }
  const Eigen::Vector3d t =
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(2);
  const Vec3 tangent(t(0), t(1), t(2));
  for (std::int64_t f : faces)
  {
    const Vec3 d = centre[f] - x0;
    const double along = d.Dot(tangent);
    if (std::abs(along) > settings.TurnSlab)
      continue;
    const double across = (d - tangent * along).Norm();
    if (across <= settings.TurnNear)
    {
      out.Near += area[f];
      ++out.NearCount;
    }
    else if (across >= settings.TurnFarFrom && across <= settings.TurnFar)
    {
      out.Far += area[f];
      ++out.FarCount;
    }
  }
  return out;
}

// The verdict on the line between groups a and b (edges, A on a's side)
// from its seeds' fits and turns (by slot), the stage's side normals and the
// band faces' corner depths (dgSharpFeaturesCreases.h says what makes a
// crease).
CreaseVerdict Decide(int a, int b, const std::vector<LineEdge>& edges,
  const std::vector<std::int64_t>& seeds, const std::vector<int>& slot,
  const std::vector<SideFit>& fits, const std::vector<TurnSums>& turns,
  const std::vector<Vec3>& sides, const std::vector<double>& cornerDepth,
  const CreaseTestSettings& settings)
{
  CreaseVerdict v;
  v.A = a;
  v.B = b;
  v.Edges = static_cast<int>(edges.size());
  std::vector<double> jumps, rateA, rateB, residuals, depths, nearTurns, farTurns;
  for (const LineEdge& be : edges)
  {
    const TurnSums &ta = turns[slot[be.A]], &tb = turns[slot[be.B]];
    if (ta.NearCount >= 3 && tb.NearCount >= 3 && ta.FarCount >= 3 && tb.FarCount >= 3)
    {
      nearTurns.push_back(Angle(ta.Near, tb.Near));
      farTurns.push_back(Angle(ta.Far, tb.Far));
    }
    const SideFit &fa = fits[slot[be.A]], &fb = fits[slot[be.B]];
    if (!fa.Valid || !fb.Valid)
      continue;
    jumps.push_back(Angle(fa.Normal, fb.Normal));
    // How fast each side turns towards the other as it nears the line.
    const Vec3 j = (fb.Normal.Unit() - fa.Normal.Unit()).Unit();
    rateA.push_back(fa.Rate.Dot(j) * Degrees);
    rateB.push_back(-fb.Rate.Dot(j) * Degrees);
  }
  for (std::size_t i = 0; i < seeds.size(); ++i)
  {
    const std::int64_t f = seeds[i];
    if (fits[i].Valid)
      residuals.push_back(fits[i].Residual);
    if (std::isfinite(cornerDepth[f]))
      depths.push_back(cornerDepth[f]);
  }
  v.Jump = Median(jumps);
  v.Depth = Median(depths);
  const double farTurn = Median(farTurns);
  v.TurnShare = farTurn > 0 ? Median(nearTurns) / farTurn : std::numeric_limits<double>::quiet_NaN();
  const double curvature = jumps.empty()
    ? 0.0
    : std::max(0.0, std::max(Median(rateA), Median(rateB))) * settings.Near;
  v.Allowance = curvature + settings.NoiseFactor * (residuals.empty() ? 0.0 : Median(residuals));
  // Two sides facing apart (the two faces of a slab thinner than AT's
  // band, their normals 150-180 degrees apart) make no corner to cut.
  std::vector<double> sideJumps;
  for (const LineEdge& be : edges)
    sideJumps.push_back(Angle(sides[be.A], sides[be.B]));
  const double sideJump = Median(sideJumps);
  const bool deep = static_cast<int>(depths.size()) >= settings.MinimumSamples &&
    v.Depth > settings.CornerDepth && sideJump < 120;
  // Sides too narrow to be fitted beyond the blur (a slab a few voxels
  // thick): a crease when the stage's own side normals jump by a sure
  // angle across the line and its voxels reach the corner.
  const bool fitted = static_cast<int>(jumps.size()) >= settings.MinimumSamples;
  // A slab's two faces (sides facing apart) make no turn to measure.
  const bool turning = static_cast<int>(nearTurns.size()) >= settings.MinimumSamples &&
    sideJump < 120 && v.TurnShare < settings.MinimumTurnShare;
  v.Crease = fitted && !deep && !turning && v.Jump >= settings.MinimumAngle + v.Allowance;
  return v;
}

} // namespace

std::vector<CreaseVerdict> TestCreases(const FaceGraph& graph, const std::vector<Vec3>& centre,
  const std::vector<Vec3>& area, const std::vector<Vec3>& input, const std::vector<Vec3>& sides,
  const std::vector<int>& group, const std::vector<double>& cornerDepth, const CreaseTestSettings& settings,
  const std::map<std::pair<int, int>, CreaseVerdict>& known)
{
  const std::int64_t F = static_cast<std::int64_t>(group.size());
  std::map<std::pair<int, int>, std::vector<LineEdge>> lines;
  const std::int64_t E = static_cast<std::int64_t>(graph.Edges.size());
  for (std::int64_t e = 0; e < E; ++e)
    for (std::int64_t a = graph.EdgeFacePtr[e]; a < graph.EdgeFacePtr[e + 1]; ++a)
      for (std::int64_t b = a + 1; b < graph.EdgeFacePtr[e + 1]; ++b)
      {
        std::int64_t fa = graph.EdgeFaces[a], fb = graph.EdgeFaces[b];
        if (group[fa] < 0 || group[fb] < 0 || group[fa] == group[fb])
          continue;
        if (group[fa] > group[fb])
          std::swap(fa, fb);
        lines[{ group[fa], group[fb] }].push_back({ fa, fb });
      }

  // Per line: every face within Far of it (nearest line face in face steps)
  // knows its side and its distance to that face; the arrays are reset
  // after each line, so the work is the faces near the lines.
  std::vector<std::int64_t> seedOf(F, -1);
  std::vector<signed char> side(F, 0);
  std::vector<float> distance(F, -1.0f);
  std::vector<std::int64_t> reached;
  // A line's fits and turns, by the rank of its face in `seeds` (slot):
  // arrays the size of the surface would be most of the test's time.
  std::vector<int> slot(F, -1);
  std::vector<SideFit> fits;
  std::vector<TurnSums> turns;
  std::vector<char> turnSeed(F, 0);
  constexpr std::size_t TurnSamples = 16;
  vtkSMPThreadLocal<FitScratch> scratch;
  std::vector<CreaseVerdict> verdicts;
  const bool turn = settings.MinimumTurnShare > 0;
  const double reach = turn ? std::max(settings.Far, settings.TurnFar) : settings.Far;
  // A face is searched within this many face steps for its side's fit
  // faces, and within `steps` for the voxel-scale turn (lengths over the
  // edge length: the spacing changes nothing; degenerate lengths, from a
  // surface whose edges all have length 0 or non-finite points, give the
  // smallest search).
  const auto stepsFor = [&](double length) {
    const double s = std::ceil(1.5 * length / settings.EdgeLength);
    return (std::isfinite(s) ? static_cast<int>(std::min(std::max(s, 0.0), 1e6)) : 0) + 2;
  };
  const int fitSteps = stepsFor(settings.Far);
  const int steps =
    turn ? std::max(fitSteps, stepsFor(std::hypot(settings.TurnFar, settings.TurnSlab))) : fitSteps;
  // The line's direction at a face: from the line faces within this length.
  const double tangentReach = 4 * settings.EdgeLength;
  for (const auto& line : lines)
  {
    const auto was = known.find(line.first);
    if (was != known.end())
    {
      verdicts.push_back(was->second);
      continue;
    }
    const int ga = line.first.first;
    reached.clear();
    for (const LineEdge& be : line.second)
      for (std::int64_t f : { be.A, be.B })
        if (seedOf[f] < 0)
        {
          seedOf[f] = f;
          side[f] = group[f] == ga ? 1 : -1;
          distance[f] = 0.0f;
          reached.push_back(f);
        }
    const std::vector<std::int64_t> seeds(reached);
    for (std::size_t i = 0; i < seeds.size(); ++i)
      slot[seeds[i]] = static_cast<int>(i);
    fits.assign(seeds.size(), SideFit());
    turns.assign(seeds.size(), TurnSums());
    // The turn's medians need no more than about TurnSamples edges per
    // line: every stride-th edge's two faces measure it.
    if (turn)
    {
      const std::size_t stride = std::max<std::size_t>(1, line.second.size() / TurnSamples);
      for (std::size_t k = 0; k < line.second.size(); k += stride)
        turnSeed[line.second[k].A] = turnSeed[line.second[k].B] = 1;
    }
    for (std::size_t h = 0; h < reached.size(); ++h)
    {
      const std::int64_t f = reached[h];
      if (distance[f] > reach + settings.EdgeLength)
        continue;
      for (std::int64_t k = graph.FaceEdgePtr[f]; k < graph.FaceEdgePtr[f + 1]; ++k)
      {
        const std::int64_t e = graph.FaceEdges[k];
        for (std::int64_t j = graph.EdgeFacePtr[e]; j < graph.EdgeFacePtr[e + 1]; ++j)
        {
          const std::int64_t g = graph.EdgeFaces[j];
          if (seedOf[g] >= 0)
            continue;
          seedOf[g] = seedOf[f];
          side[g] = side[f];
          distance[g] = static_cast<float>((centre[g] - centre[seedOf[f]]).Norm());
          reached.push_back(g);
        }
      }
    }
    vtkSMPTools::For(0, static_cast<std::int64_t>(seeds.size()), [&](std::int64_t b, std::int64_t e) {
      FitScratch& s = scratch.Local();
      for (std::int64_t i = b; i < e; ++i)
      {
        const std::int64_t f0 = seeds[i];
        s.Faces.clear();
        s.Turn.clear();
        s.Line.clear();
        const bool measure = turnSeed[f0] != 0;
        Breadth(graph, s, f0, measure ? steps : fitSteps, [&](std::int64_t g) { return seedOf[g] >= 0; },
          [&](std::int64_t f, int depth, int limit) {
            // Faces turned away from the line face (the far side of a part
            // thinner than the window) are not this side's surface.
            const bool facing = input[f].Dot(input[f0]) > 0;
            if (depth <= fitSteps && side[f] == side[f0] && distance[f] >= settings.Near &&
              distance[f] <= settings.Far && facing)
              s.Faces.push_back(f);
            // Only the side's own part: past a narrow side another part
            // (across its other line) is not the surface that turns here.
            if (measure && group[f] == group[f0] && distance[f] <= settings.TurnFar && facing)
              s.Turn.push_back(f);
            if (measure && seedOf[f] == f && (centre[f] - centre[f0]).Norm() <= tangentReach)
              s.Line.push_back(f);
            return limit;
          });
        if (static_cast<int>(s.Faces.size()) >= settings.MinimumFit)
          fits[i] = FitSide(s.Faces, centre, input, centre[f0]);
        if (measure)
          turns[i] = MeasureTurn(centre, area, centre[f0], s.Line, s.Turn, settings);
      }
    });

    verdicts.push_back(Decide(line.first.first, line.first.second, line.second, seeds, slot, fits,
      turns, sides, cornerDepth, settings));
    for (std::int64_t f : reached)
    {
      seedOf[f] = -1;
      side[f] = 0;
      distance[f] = -1.0f;
      turnSeed[f] = 0;
    }
    for (std::int64_t f : seeds)
      slot[f] = -1;
  }
  return verdicts;
}

} // namespace sharp
} // namespace dg
