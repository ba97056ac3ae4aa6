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

} // namespace dgtest
