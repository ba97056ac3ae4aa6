#include "dgFeatureMetrics.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dgtest
{

namespace
{
constexpr double Tolerance = 1.5;   // voxels from a true edge
constexpr double SurfaceBand = 2.0; // voxels from the true surface
}

std::string FeatureMetrics::Describe() const
{
  char s[256];
  std::snprintf(s, sizeof(s),
    "len %.0f mult %.2f off %.2f P %.3f R %.3f | err mean %.2f <1 %.2f <3 %.2f", this->Length,
    this->Multiplicity, this->Offset, this->Precision, this->Recall, this->MeanError,
    this->Error1, this->Error3);
  return s;
}

FeatureMetrics MeasureFeatures(
  const ImplicitShape& shape, vtkPolyData* surface, const char* normals, vtkPolyData* lines)
{
  using V3 = Eigen::Vector3d;
  FeatureMetrics m;
  const double trueLength = shape.SharpEdges().TotalLength();
  PolylineDistance detected;
  double within = 0, offset = 0;
  vtkCellArray* ca = lines ? lines->GetLines() : nullptr;
  if (ca)
  {
    vtkNew<vtkIdList> ids;
    for (ca->InitTraversal(); ca->GetNextCell(ids);)
      for (vtkIdType j = 0; j + 1 < ids->GetNumberOfIds(); ++j)
      {
        double pa[3], pb[3];
        lines->GetPoint(ids->GetId(j), pa);
        lines->GetPoint(ids->GetId(j + 1), pb);
        const V3 a(pa[0], pa[1], pa[2]), b(pb[0], pb[1], pb[2]);
        const double l = (b - a).norm();
        m.Length += l;
        detected.AddSegment(a, b);
        const double d = shape.DistanceToSharpEdge(0.5 * (a + b), 2 * Tolerance);
        if (d <= Tolerance)
        {
          within += l;
          offset += l * d;
        }
      }
  }
  m.Multiplicity = trueLength > 0 ? within / trueLength : 0;
  m.Offset = within > 0 ? offset / within : 0;
  m.Precision = m.Length > 0 ? within / m.Length : 0;
  const auto samples = shape.SharpEdgeSamples(0.25);
  std::size_t hit = 0;
  for (const auto& p : samples)
    hit += detected.Size() && detected.Distance(p, 2 * Tolerance) <= Tolerance;
  m.Recall = samples.empty() ? 0 : double(hit) / samples.size();

  const auto centres = SurfelCenters(surface);
  vtkDataArray* n = surface ? surface->GetCellData()->GetArray(normals) : nullptr;
  double sum = 0, sum1 = 0, sum3 = 0;
  std::size_t count = 0, count1 = 0, count3 = 0;
  if (n && n->GetNumberOfTuples() == static_cast<vtkIdType>(centres.size()))
  {
    for (std::size_t i = 0; i < centres.size(); ++i)
    {
      const V3& c = centres[i];
      const double value = shape.Value(c);
      if (std::abs(value) > SurfaceBand)
        continue;
      const V3 truth = shape.Normal(c);
      double t[3];
      n->GetTuple(static_cast<vtkIdType>(i), t);
      double a = AngleDegrees(V3(t[0], t[1], t[2]), truth);
      a = std::min(a, 180.0 - a);
      const double d = shape.DistanceToSharpEdge(c - value * truth, 4.0);
      sum += a;
      ++count;
      if (d <= 1.0)
      {
        sum1 += a;
        ++count1;
      }
      if (d <= 3.0)
      {
        sum3 += a;
        ++count3;
      }
    }
  }
  else
  {
    sum = sum1 = sum3 = NAN;
  }
  m.MeanError = count ? sum / count : NAN;
  m.Error1 = count1 ? sum1 / count1 : NAN;
  m.Error3 = count3 ? sum3 / count3 : NAN;
  return m;
}

std::string SmoothMetrics::Describe() const
{
  char s[256];
  std::snprintf(s, sizeof(s),
    "features %.1f/1000 | out mean %.2f p95 %.2f max %.1f | input mean %.2f p95 %.2f | worse %.2f %%",
    this->FeaturesPer1000, this->Mean, this->P95, this->Max, this->InputMean, this->InputP95,
    this->WorseShare);
  return s;
}

SmoothMetrics MeasureSmooth(const ImplicitShape& shape, vtkPolyData* surface,
  const char* outputNormals, const char* inputNormals, vtkPolyData* lines)
{
  SmoothMetrics m;
  vtkDataArray* out = surface->GetCellData()->GetArray(outputNormals);
  vtkDataArray* in = surface->GetCellData()->GetArray(inputNormals);
  const vtkIdType n = surface->GetNumberOfCells();
  if (!out || !in || n == 0)
    return m;
  std::vector<double> eo(n), ei(n);
  vtkNew<vtkIdList> ids;
  std::int64_t worse = 0;
  for (vtkIdType c = 0; c < n; ++c)
  {
    surface->GetCellPoints(c, ids);
    Eigen::Vector3d centre(0, 0, 0);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      Eigen::Vector3d p;
      surface->GetPoint(ids->GetId(k), p.data());
      centre += p / static_cast<double>(ids->GetNumberOfIds());
    }
    const Eigen::Vector3d t = shape.Normal(centre);
    Eigen::Vector3d a, b;
    out->GetTuple(c, a.data());
    in->GetTuple(c, b.data());
    eo[c] = std::min(AngleDegrees(a, t), 180.0 - AngleDegrees(a, t));
    ei[c] = std::min(AngleDegrees(b, t), 180.0 - AngleDegrees(b, t));
    worse += eo[c] >= ei[c] + 10.0;
    m.Mean += eo[c] / n;
    m.InputMean += ei[c] / n;
    m.Max = std::max(m.Max, eo[c]);
  }
  auto p95 = [](std::vector<double> x) {
    std::nth_element(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(0.95 * (x.size() - 1)), x.end());
    return x[static_cast<std::size_t>(0.95 * (x.size() - 1))];
  };
  m.P95 = p95(eo);
  m.InputP95 = p95(ei);
  m.WorseShare = 100.0 * static_cast<double>(worse) / n;
  double length = 0;
  if (vtkCellArray* ca = lines ? lines->GetLines() : nullptr)
    for (ca->InitTraversal(); ca->GetNextCell(ids);)
      for (vtkIdType j = 0; j + 1 < ids->GetNumberOfIds(); ++j)
      {
        Eigen::Vector3d a, b;
        lines->GetPoint(ids->GetId(j), a.data());
        lines->GetPoint(ids->GetId(j + 1), b.data());
        length += (b - a).norm();
      }
  m.FeaturesPer1000 = 1000.0 * length / n;
  return m;
}

} // namespace dgtest
