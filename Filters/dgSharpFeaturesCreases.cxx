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

// An edge between two groups' faces, A in the smaller group; E the graph
// edge.
struct LineEdge
{
  std::int64_t A, B, E;
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

// What a verdict reads: per edge of a line (or of a stretch of it), the
// extrapolated jump and each side's turn rate towards the other, the
// voxel-scale turn, the stage's side normals' angle; per face at the line,
// its fit's residual and its corner depth.
struct Evidence
{
  std::vector<double> Jumps, RateA, RateB, Residuals, Depths, NearTurns, FarTurns, SideJumps;
  void Clear()
  {
    for (auto* v : { &Jumps, &RateA, &RateB, &Residuals, &Depths, &NearTurns, &FarTurns, &SideJumps })
      v->clear();
  }
};

// One edge's share of the evidence (turn: whether its voxel-scale turn is
// read).
void AddEdge(Evidence& ev, const LineEdge& be, const std::vector<int>& slot,
  const std::vector<SideFit>& fits, const std::vector<TurnSums>& turns, const std::vector<Vec3>& sides,
  bool turn)
{
  const TurnSums &ta = turns[slot[be.A]], &tb = turns[slot[be.B]];
  if (turn && ta.NearCount >= 3 && tb.NearCount >= 3 && ta.FarCount >= 3 && tb.FarCount >= 3)
  {
    ev.NearTurns.push_back(Angle(ta.Near, tb.Near));
    ev.FarTurns.push_back(Angle(ta.Far, tb.Far));
  }
  ev.SideJumps.push_back(Angle(sides[be.A], sides[be.B]));
  const SideFit &fa = fits[slot[be.A]], &fb = fits[slot[be.B]];
  if (!fa.Valid || !fb.Valid)
    return;
  ev.Jumps.push_back(Angle(fa.Normal, fb.Normal));
  // How fast each side turns towards the other as it nears the line.
  const Vec3 j = (fb.Normal.Unit() - fa.Normal.Unit()).Unit();
  ev.RateA.push_back(fa.Rate.Dot(j) * Degrees);
  ev.RateB.push_back(-fb.Rate.Dot(j) * Degrees);
}

// One face's share (a face at the line).
void AddFace(Evidence& ev, std::int64_t f, const SideFit& fit, const std::vector<double>& cornerDepth)
{
  if (fit.Valid)
    ev.Residuals.push_back(fit.Residual);
  if (std::isfinite(cornerDepth[f]))
    ev.Depths.push_back(cornerDepth[f]);
}

// The verdict on the evidence (dgSharpFeaturesCreases.h says what makes a
// crease); A, B and Edges are the caller's.
CreaseVerdict Judge(const Evidence& ev, const CreaseTestSettings& settings)
{
  CreaseVerdict v;
  v.Jump = Median(ev.Jumps);
  v.Depth = Median(ev.Depths);
  const double farTurn = Median(ev.FarTurns);
  v.TurnShare = farTurn > 0 ? Median(ev.NearTurns) / farTurn : std::numeric_limits<double>::quiet_NaN();
  const double curvature = ev.Jumps.empty()
    ? 0.0
    : std::max(0.0, std::max(Median(ev.RateA), Median(ev.RateB))) * settings.Near;
  v.Allowance =
    curvature + settings.NoiseFactor * (ev.Residuals.empty() ? 0.0 : Median(ev.Residuals));
  // Two sides facing apart (the two faces of a slab thinner than AT's
  // band, their normals 150-180 degrees apart) make no corner to cut.
  const double sideJump = Median(ev.SideJumps);
  const bool deep = static_cast<int>(ev.Depths.size()) >= settings.MinimumSamples &&
    v.Depth > settings.CornerDepth && sideJump < 120;
  // Sides too narrow to be fitted beyond the blur (a slab a few voxels
  // thick) show no crease.
  const bool fitted = static_cast<int>(ev.Jumps.size()) >= settings.MinimumSamples;
  // A slab's two faces (sides facing apart) make no turn to measure.
  const bool turning = static_cast<int>(ev.NearTurns.size()) >= settings.MinimumSamples &&
    sideJump < 120 && v.TurnShare < settings.MinimumTurnShare;
  v.Crease = fitted && !deep && !turning && v.Jump >= settings.MinimumAngle + v.Allowance;
  v.Deep = deep;
  return v;
}

enum StretchClass : char
{
  StretchDeep = -1, // its voxels cut the corner: a bend
  StretchOther = 0,
  StretchCrease = 1,
  StretchClear = 2 // a crease by twice the margins
};

// Each edge of a line judged on the line's edges within Stretch of it
// (their midpoints), in the edges' order; the faces' evidence counts once
// per stretch.
// Returns each edge's StretchClass.
std::vector<char> JudgeStretches(const std::vector<LineEdge>& edges, const std::vector<Vec3>& centre,
  const std::vector<int>& slot, const std::vector<SideFit>& fits, const std::vector<TurnSums>& turns,
  const std::vector<Vec3>& sides, const std::vector<double>& cornerDepth,
  const CreaseTestSettings& settings)
{
  const std::size_t n = edges.size();
  std::vector<Vec3> mid(n);
  for (std::size_t i = 0; i < n; ++i)
    mid[i] = (centre[edges[i].A] + centre[edges[i].B]) * 0.5;
  // The midpoints in cells of Stretch: a stretch is the 27 cells around.
  const double cell = settings.Stretch;
  auto key = [&](const Vec3& x, int dx, int dy, int dz) {
    const auto c = [&](double v, int d) {
      return (static_cast<std::int64_t>(std::floor(v / cell)) + d) & 0x1FFFFF;
    };
    return (c(x.x, dx) << 42) | (c(x.y, dy) << 21) | c(x.z, dz);
  };
  std::vector<std::pair<std::int64_t, std::uint32_t>> cells(n);
  for (std::size_t i = 0; i < n; ++i)
    cells[i] = { key(mid[i], 0, 0, 0), static_cast<std::uint32_t>(i) };
  std::sort(cells.begin(), cells.end());
  // Calls visit(j) for every edge j within Stretch of edge i (i included).
  auto around = [&](std::size_t i, const auto& visit) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
        {
          const std::int64_t k = key(mid[i], dx, dy, dz);
          auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(k, std::uint32_t(0)));
          for (; it != cells.end() && it->first == k; ++it)
            if ((mid[it->second] - mid[i]).Norm() <= settings.Stretch)
              visit(it->second);
        }
  };
  std::vector<char> kind(n, 0);
  vtkSMPThreadLocal<std::pair<Evidence, std::vector<std::int64_t>>> scratch;
  vtkSMPTools::For(0, static_cast<std::int64_t>(n), [&](std::int64_t b, std::int64_t e) {
    auto& local = scratch.Local();
    Evidence& ev = local.first;
    std::vector<std::int64_t>& faces = local.second;
    for (std::int64_t i = b; i < e; ++i)
    {
      ev.Clear();
      faces.clear();
      around(i, [&](std::uint32_t j) {
        AddEdge(ev, edges[j], slot, fits, turns, sides, true);
        faces.push_back(edges[j].A);
        faces.push_back(edges[j].B);
      });
      std::sort(faces.begin(), faces.end());
      faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
      for (std::int64_t f : faces)
        AddFace(ev, f, fits[slot[f]], cornerDepth);
      const CreaseVerdict jv = Judge(ev, settings);
      // Clear: a crease with twice the margins a whole line needs.
      const bool clear = jv.Crease && jv.Jump >= 2 * settings.MinimumAngle + jv.Allowance &&
        jv.Depth <= 0.5 * settings.CornerDepth &&
        jv.TurnShare >= 0.5 * (1 + settings.MinimumTurnShare);
      kind[i] = static_cast<char>(jv.Deep ? StretchDeep
          : clear                          ? StretchClear
          : jv.Crease                      ? StretchCrease
                                           : StretchOther);
    }
  });
  // A bend or a clear crease only as a stretch of its kind at least
  // MinimumStretchEdges long: a few edges' windows tip either way under
  // noise.
  std::vector<char> kept(kind);
  vtkSMPTools::For(0, static_cast<std::int64_t>(n), [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t i = b; i < e; ++i)
    {
      if (kind[i] != StretchDeep && kind[i] != StretchClear)
        continue;
      int same = 0;
      around(i, [&](std::uint32_t j) { same += kind[j] == kind[i]; });
      if (same < settings.MinimumStretchEdges)
        kept[i] = kind[i] == StretchDeep ? StretchOther : StretchCrease;
    }
  });
  kind.swap(kept);
  return kind;
}

// The verdict on the line between groups a and b (edges, A on a's side)
// from its seeds' fits and turns (by slot; the turn on the edges `sampled`
// marks), the stage's side normals and the band faces' corner depths.
CreaseVerdict Decide(int a, int b, const std::vector<LineEdge>& edges,
  const std::vector<std::int64_t>& seeds, const std::vector<int>& slot,
  const std::vector<SideFit>& fits, const std::vector<TurnSums>& turns,
  const std::vector<Vec3>& sides, const std::vector<double>& cornerDepth,
  const std::vector<char>& sampled, const CreaseTestSettings& settings)
{
  Evidence ev;
  for (std::size_t i = 0; i < edges.size(); ++i)
    AddEdge(ev, edges[i], slot, fits, turns, sides, sampled[i] != 0);
  for (std::size_t i = 0; i < seeds.size(); ++i)
    AddFace(ev, seeds[i], fits[i], cornerDepth);
  CreaseVerdict v = Judge(ev, settings);
  v.A = a;
  v.B = b;
  v.Edges = static_cast<int>(edges.size());
  return v;
}

} // namespace

std::vector<CreaseVerdict> TestCreases(const FaceGraph& graph, const std::vector<Vec3>& centre,
  const std::vector<Vec3>& area, const std::vector<Vec3>& input, const std::vector<Vec3>& sides,
  const std::vector<int>& group, const std::vector<double>& cornerDepth, const CreaseTestSettings& settings,
  const std::map<std::pair<int, int>, CreaseVerdict>& known, std::vector<signed char>& edgeCrease)
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
        lines[{ group[fa], group[fb] }].push_back({ fa, fb, e });
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
  std::vector<char> turnSeed(F, 0), sampled;
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
    // Every line face measures the turn for the stretches; the line's own
    // medians read about TurnSamples edges, every stride-th.
    sampled.assign(line.second.size(), 0);
    if (turn)
    {
      for (std::int64_t f : seeds)
        turnSeed[f] = 1;
      const std::size_t stride = std::max<std::size_t>(1, line.second.size() / TurnSamples);
      for (std::size_t k = 0; k < line.second.size(); k += stride)
        sampled[k] = 1;
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

    CreaseVerdict v = Decide(line.first.first, line.first.second, line.second, seeds, slot, fits,
      turns, sides, cornerDepth, sampled, settings);
    // The line's stretches: where a crease runs on into a bend (a sharp
    // edge ending in a fillet), only the crease's stretch is one; a line
    // that the whole reads as a bend still keeps its sides apart when a
    // long enough stretch of it is a crease.
    const std::vector<char> stretch =
      JudgeStretches(line.second, centre, slot, fits, turns, sides, cornerDepth, settings);
    const int creaseEdges = static_cast<int>(std::count(stretch.begin(), stretch.end(), StretchClear));
    const bool whole = v.Crease;
    v.Crease = whole || creaseEdges >= settings.MinimumStretchEdges;
    for (std::size_t i = 0; i < line.second.size(); ++i)
      edgeCrease[line.second[i].E] =
        static_cast<signed char>(whole ? stretch[i] != StretchDeep : stretch[i] == StretchClear);
    verdicts.push_back(v);
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
