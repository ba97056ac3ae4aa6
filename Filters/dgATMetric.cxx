#include "dgATMetric.h"

#include <vtkPoints.h>
#include <vtkSMPTools.h>

#include <cmath>
#include <sstream>

namespace dg
{
namespace
{
struct V3
{
  double x, y, z;
};
inline V3 P(const double* points, std::int64_t i)
{
  return { points[3 * i], points[3 * i + 1], points[3 * i + 2] };
}
inline double Norm(double x, double y, double z)
{
  return std::sqrt(x * x + y * y + z * z);
}
} // namespace

bool ATMetric::Compute(const ATComplex& K, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity, const double* points, std::string* error)
{
  const std::int64_t nf = K.NumberOfFaces(), ne = K.NumberOfEdges(), nv = K.NumberOfVertices();
  this->FaceArea.assign(nf, 0.0);
  this->EdgeRatio.assign(ne, 0.0);
  this->VertexArea.assign(nv, 0.0);
  std::vector<double> centre(3 * nf);
  std::vector<int> corners(nf);
  // Faces: the vector area (exact for planar polygons, the projected area
  // of the best plane otherwise) and the vertex mean as centre, over the
  // distinct consecutive vertices, as ATComplex::Build reads the polygons.
  vtkSMPTools::For(0, nf, [&](std::int64_t f0, std::int64_t f1) {
    for (std::int64_t f = f0; f < f1; ++f)
    {
      const std::int64_t b = offsets[f], e = offsets[f + 1];
      double a[3] = { 0, 0, 0 }, c[3] = { 0, 0, 0 };
      int k = 0;
      for (std::int64_t i = b; i < e; ++i)
      {
        const std::int64_t p = connectivity[i], q = connectivity[i + 1 < e ? i + 1 : b];
        if (p == q)
        {
          continue;
        }
        const V3 x = P(points, p), y = P(points, q);
        a[0] += x.y * y.z - x.z * y.y;
        a[1] += x.z * y.x - x.x * y.z;
        a[2] += x.x * y.y - x.y * y.x;
        c[0] += x.x;
        c[1] += x.y;
        c[2] += x.z;
        ++k;
      }
      this->FaceArea[f] = 0.5 * Norm(a[0], a[1], a[2]);
      corners[f] = k;
      for (int d = 0; d < 3; ++d)
      {
        centre[3 * f + d] = k ? c[d] / k : 0.0;
      }
    }
  });
  for (std::int64_t f = 0; f < nf; ++f)
  {
    if (!(this->FaceArea[f] > 0))
    {
      if (error)
      {
        *error = "face " + std::to_string(f) + " has no area";
      }
      return false;
    }
    const std::int64_t b = offsets[f], e = offsets[f + 1];
    for (std::int64_t i = b; i < e; ++i)
    {
      if (connectivity[i] != connectivity[i + 1 < e ? i + 1 : b])
      {
        this->VertexArea[connectivity[i]] += this->FaceArea[f] / corners[f];
      }
    }
  }
  // A point in no polygon (faces have positive area, so only those are at
  // 0) is not on the surface: weight 1 as with the grid metric, so that its
  // row stays regular and its v stays 1.
  for (double& a : this->VertexArea)
  {
    a = a > 0 ? a : 1.0;
  }
  // Edges: |e| over the dual length. A manifold edge's dual edge runs from
  // one face centre to the edge midpoint to the other centre; on k faces
  // (boundary k = 1, non-manifold k > 2) the dual length is 2/k times the
  // sum of the k half dual edges, so that each face pair counts as one
  // dual edge on average.
  std::int64_t bad = -1;
  for (std::int64_t e = 0; e < ne && bad < 0; ++e)
  {
    const V3 a = P(points, K.EdgeVertices[2 * e]), b = P(points, K.EdgeVertices[2 * e + 1]);
    const double length = Norm(b.x - a.x, b.y - a.y, b.z - a.z);
    const double m[3] = { 0.5 * (a.x + b.x), 0.5 * (a.y + b.y), 0.5 * (a.z + b.z) };
    double dual = 0;
    const std::int64_t f0 = K.EdgeFacePtr[e], f1 = K.EdgeFacePtr[e + 1];
    for (std::int64_t i = f0; i < f1; ++i)
    {
      const double* c = centre.data() + 3 * K.EdgeFaces[i];
      dual += Norm(c[0] - m[0], c[1] - m[1], c[2] - m[2]);
    }
    dual *= f1 > f0 ? 2.0 / static_cast<double>(f1 - f0) : 0.0;
    if (!(length > 0) || !(dual > 0) || !std::isfinite(length / dual))
    {
      bad = e;
      break;
    }
    this->EdgeRatio[e] = length / dual;
  }
  if (bad >= 0)
  {
    if (error)
    {
      std::ostringstream s;
      s << "edge " << bad << " (points " << K.EdgeVertices[2 * bad] << ", "
        << K.EdgeVertices[2 * bad + 1] << ") has no length or no dual length";
      *error = s.str();
    }
    return false;
  }
  return true;
}

bool ComputeWorldMetric(vtkPoints* points, const std::vector<std::int64_t>* rows,
  const ATComplex& complex, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity, ATMetric& metric, std::string& error)
{
  const std::int64_t n = complex.NumberOfVertices();
  if (!points || (!rows && points->GetNumberOfPoints() < n))
  {
    error = "the input has no points";
    return false;
  }
  std::vector<double> xyz(3 * n);
  vtkSMPTools::For(0, n, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t k = b; k < e; ++k)
    {
      points->GetPoint(rows ? (*rows)[k] : k, xyz.data() + 3 * k);
    }
  });
  return metric.Compute(complex, offsets, connectivity, xyz.data(), &error);
}

} // namespace dg
