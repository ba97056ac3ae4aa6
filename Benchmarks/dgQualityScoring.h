// BenchQuality's scoring: the shapes at grid size n, the ground truth at
// cell centres (normal, signed value, distance to a sharp edge), angle
// statistics per region, feature scores (dgFeatureMetrics) and the CSV rows.
// See BenchQuality.cxx for the definitions of the regions and rows.
#ifndef dgQualityScoring_h
#define dgQualityScoring_h

#include "dgFeatureMetrics.h"
#include "dgGroundTruth.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkSmartPointer.h>

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace dgquality
{
using V3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;
constexpr double NaN = std::numeric_limits<double>::quiet_NaN();
constexpr double NearEdge = 2.0;    // voxels
constexpr double FarEdge = 8.0;     // voxels: beyond the largest II ball
constexpr double SurfaceBand = 2.0; // voxels from the true surface (issue 15)

inline double Seconds(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline std::vector<std::string> Split(const std::string& s)
{
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
  {
    if (!item.empty())
      out.push_back(item);
  }
  return out;
}

// Shapes scaled to the grid size n; the centre is off the grid symmetry by a
// small amount so that no digitisation is exactly symmetric.
inline std::unique_ptr<dgtest::ImplicitShape> MakeShape(const std::string& name, int n)
{
  const V3 c = V3::Constant(0.5 * (n - 1)) + V3(0.13, 0.07, 0.11);
  if (name == "sphere")
    return dgtest::MakeSphere(c, 0.38 * n);
  if (name == "cube")
    return dgtest::MakeRotatedCube(c, 0.26 * n, 20, 30, 10);
  if (name == "cubesphere")
    return dgtest::MakeCubeSphere(c, 0.3 * n, 0.38 * n);
  if (name == "cylinder")
    return dgtest::MakeCylinder(c, 0.32 * n, 0.3 * n);
  if (name == "octahedron")
    return dgtest::MakeOctahedron(c, 0.42 * n);
  if (name == "wedge")
    return dgtest::MakeWedge(c, 0.3 * n);
  // Smooth and filleted shapes (issue 39), as TestSmoothShapes measures
  // them; "ball" is the smooth suite's sphere (0.19 n).
  return dgtest::MakeSmoothShape(name == "ball" ? "sphere" : name, n);
}

struct Stats
{
  std::size_t Count = 0;
  double Mean = NaN, Median = NaN, P95 = NaN;
};

inline Stats Compute(std::vector<double> e)
{
  Stats s;
  s.Count = e.size();
  if (e.empty())
    return s;
  double sum = 0;
  for (double x : e)
    sum += x;
  s.Mean = sum / e.size();
  std::sort(e.begin(), e.end());
  auto q = [&](double p)
  {
    const double pos = p * (e.size() - 1);
    const std::size_t i = static_cast<std::size_t>(std::floor(pos));
    const double f = pos - i;
    return i + 1 < e.size() ? e[i] * (1 - f) + e[i + 1] * f : e[i];
  };
  s.Median = q(0.5);
  s.P95 = q(0.95);
  return s;
}

// Per-cell ground truth: true normal and near/away flag.
struct Truth
{
  std::vector<V3> Normal;
  std::vector<double> Value;        // the shape's signed function at the centre
  std::vector<double> EdgeDistance; // capped: any value > FarEdge means "far"
};

inline Truth MakeTruth(const dgtest::ImplicitShape& shape, const std::vector<V3>& centres)
{
  Truth t;
  t.Normal.resize(centres.size());
  t.Value.resize(centres.size());
  t.EdgeDistance.resize(centres.size());
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(centres.size()),
    [&](vtkIdType b, vtkIdType e)
    {
      for (vtkIdType i = b; i < e; ++i)
      {
        // Near/away is decided on the centre projected onto the true surface
        // along the true normal (exact for planes and spheres; for CSG shapes
        // it lands on the active part): a smoothed mesh that has pulled its
        // cells in from a corner is still judged by where they belong.
        const V3 n = shape.Normal(centres[i]);
        t.Normal[i] = n;
        t.Value[i] = shape.Value(centres[i]);
        const V3 onSurface = centres[i] - t.Value[i] * n;
        t.EdgeDistance[i] = shape.DistanceToSharpEdge(onSurface, FarEdge + 1.0);
      }
    });
  return t;
}

inline std::vector<V3> Normals(vtkPolyData* pd, const char* name)
{
  std::vector<V3> out;
  vtkDataArray* a = pd ? pd->GetCellData()->GetArray(name) : nullptr;
  if (!a)
  {
    std::fprintf(stderr, "missing cell array %s\n", name);
    return out;
  }
  out.resize(a->GetNumberOfTuples());
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    double v[3];
    a->GetTuple(i, v);
    out[i] = V3(v[0], v[1], v[2]);
  }
  return out;
}

struct Row
{
  std::string Shape;
  int N;
  double K;
  int Seed;
};

struct Output
{
  std::ofstream NormalsCsv, FeaturesCsv, TimesCsv;
  bool CheckFailed = false;
};

inline void WriteErrors(Output& out,
  const Row& row,
  const std::string& method,
  const Truth& truth,
  const std::vector<V3>& normals,
  std::map<std::string, Stats>* keep = nullptr)
{
  std::vector<double> all, nearE, away, mid, far, band, edge1, edge3;
  if (normals.size() != truth.Normal.size())
  {
    std::fprintf(stderr,
      "%s: %zu normals for %zu cells\n",
      method.c_str(),
      normals.size(),
      truth.Normal.size());
    out.CheckFailed = true;
    return;
  }
  for (std::size_t i = 0; i < normals.size(); ++i)
  {
    const double a = dgtest::AngleDegrees(normals[i], truth.Normal[i]);
    all.push_back(a);
    const double d = truth.EdgeDistance[i];
    (d <= NearEdge ? nearE : away).push_back(a);
    if (d > NearEdge)
      (d <= FarEdge ? mid : far).push_back(a);
    // Issue 15 (dgFeatureMetrics.h): unoriented, near the true surface only.
    if (std::abs(truth.Value[i]) <= SurfaceBand)
    {
      const double u = std::min(a, 180.0 - a);
      band.push_back(u);
      if (d <= 1.0)
        edge1.push_back(u);
      if (d <= 3.0)
        edge3.push_back(u);
    }
  }
  const std::pair<const char*, std::vector<double>*> regions[] = { { "all", &all },
    { "near", &nearE },
    { "away", &away },
    { "mid", &mid },
    { "far", &far },
    { "surface2", &band },
    { "edge1", &edge1 },
    { "edge3", &edge3 } };
  for (const auto& r : regions)
  {
    const Stats s = Compute(*r.second);
    out.NormalsCsv << row.Shape << ',' << row.N << ',' << row.K << ',' << row.Seed << ',' << method
                   << ',' << r.first << ',' << s.Count << ',' << s.Mean << ',' << s.Median << ','
                   << s.P95 << '\n';
    if (keep)
      (*keep)[r.first] = s;
  }
}

struct FeatureScore
{
  double Length = 0, Precision = NaN, Recall = NaN, F1 = NaN;
  double Multiplicity = NaN, Offset = NaN;
  int Iterations = 0; // AT: (u, v) step pairs made
};

// Line cells of `lines` (2-point segments or polylines) against the shape's
// sharp edges, with issue 15's definitions (dgtest::MeasureFeatures). NaN
// where a figure is undefined: every figure but the length on a shape
// without sharp edges, precision with no line at all, offset with no line
// near an edge.
inline FeatureScore ScoreFeatures(vtkPolyData* lines, const dgtest::ImplicitShape& shape)
{
  const dgtest::FeatureMetrics m = dgtest::MeasureFeatures(shape, nullptr, nullptr, lines);
  FeatureScore f;
  f.Length = m.Length;
  if (shape.SharpEdges().Size() == 0)
    return f;
  f.Multiplicity = m.Multiplicity;
  f.Offset = m.Multiplicity > 0 ? m.Offset : NaN;
  f.Precision = m.Length > 0 ? m.Precision : NaN;
  f.Recall = m.Recall;
  const double p = std::isnan(f.Precision) ? 0.0 : f.Precision;
  f.F1 = p + f.Recall > 0 ? 2 * p * f.Recall / (p + f.Recall) : 0.0;
  return f;
}

inline void WriteFeatures(Output& out,
  const Row& row,
  const std::string& method,
  const FeatureScore& f)
{
  out.FeaturesCsv << row.Shape << ',' << row.N << ',' << row.K << ',' << row.Seed << ',' << method
                  << ',' << f.Length << ',' << f.Precision << ',' << f.Recall << ',' << f.F1 << ','
                  << f.Iterations << ',' << f.Multiplicity << ',' << f.Offset << '\n';
}

inline void WriteTime(Output& out,
  const Row& row,
  const std::string& stage,
  double s,
  vtkIdType cells)
{
  out.TimesCsv << row.Shape << ',' << row.N << ',' << row.K << ',' << row.Seed << ',' << stage
               << ',' << s << ',' << cells << '\n';
}

inline std::vector<V3> CellCentres(vtkPolyData* pd)
{
  std::vector<V3> c(pd->GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  for (vtkIdType i = 0; i < pd->GetNumberOfCells(); ++i)
  {
    pd->GetCellPoints(i, ids);
    V3 s = V3::Zero();
    for (vtkIdType j = 0; j < ids->GetNumberOfIds(); ++j)
    {
      double p[3];
      pd->GetPoint(ids->GetId(j), p);
      s += V3(p[0], p[1], p[2]);
    }
    c[i] = ids->GetNumberOfIds() ? V3(s / ids->GetNumberOfIds()) : s;
  }
  return c;
}

// The VCM feature score as feature lines: the surface edges all of whose
// surfels (two on a manifold edge, four on a non-manifold one) have a score
// >= T; a boundary edge (one surfel) is never a feature edge. The lines
// are 2-point segments on the surface's points.
inline vtkSmartPointer<vtkPolyData> ScoreEdges(vtkPolyData* surface,
  const char* scoreName,
  double T)
{
  auto lines = vtkSmartPointer<vtkPolyData>::New();
  lines->SetPoints(surface->GetPoints());
  vtkNew<vtkCellArray> cells;
  vtkDataArray* score = surface->GetCellData()->GetArray(scoreName);
  if (!score)
  {
    std::fprintf(stderr, "missing cell array %s\n", scoreName);
    lines->SetLines(cells);
    return lines;
  }
  // edge (smaller point id, larger) -> (surfels, surfels at or above T)
  std::unordered_map<std::uint64_t, std::pair<int, int>> edges;
  edges.reserve(2 * surface->GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    surface->GetCellPoints(c, ids);
    const vtkIdType n = ids->GetNumberOfIds();
    const bool above = score->GetComponent(c, 0) >= T;
    for (vtkIdType j = 0; j < n; ++j)
    {
      std::uint64_t a = ids->GetId(j), b = ids->GetId((j + 1) % n);
      if (a > b)
        std::swap(a, b);
      auto& e = edges[(a << 32) | b];
      ++e.first;
      e.second += above;
    }
  }
  std::vector<std::uint64_t> keys;
  for (const auto& e : edges)
    if (e.second.first >= 2 && e.second.second == e.second.first)
      keys.push_back(e.first);
  std::sort(keys.begin(), keys.end()); // a deterministic cell order
  for (std::uint64_t k : keys)
  {
    const vtkIdType pts[2] = { static_cast<vtkIdType>(k >> 32),
      static_cast<vtkIdType>(k & 0xffffffffu) };
    cells->InsertNextCell(2, pts);
  }
  lines->SetLines(cells);
  return lines;
}

constexpr double VCMThresholds[] = { 0.1, 0.2, 0.3 };

inline std::string ThresholdName(double T)
{
  std::ostringstream s;
  s << "VCM-T" << T;
  return s.str();
}
} // namespace dgquality

#endif
