// The world metric of the Ambrosio-Tortorelli operators (dgATMetric.h,
// docs/at-metric.md): its weights on an anisotropic box, the exact scale
// invariance it promises, and the claim that parameters mean the same at
// every resolution.
#include "dgATMetric.h"
#include "dgGroundTruth.h"
#include "dgTestShapes.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace
{
using V3 = Eigen::Vector3d;

// The polygons of a surface as the AT filter hands them to the core.
void Polygons(vtkPolyData* pd, std::vector<std::int64_t>& offsets,
  std::vector<std::int64_t>& connectivity)
{
  vtkCellArray* polys = pd->GetPolys();
  offsets.assign(1, 0);
  connectivity.clear();
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c)
  {
    polys->GetCellAtId(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      connectivity.push_back(ids->GetId(k));
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
}

vtkSmartPointer<vtkPolyData> Surface(vtkImageData* image)
{
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  surface->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(surface->GetOutput());
  return out;
}

// A shape digitised on a grid of the given spacing (origin 0): voxel
// (i, j, k) is inside when its world centre is.
vtkSmartPointer<vtkImageData> DigitizeWorld(
  const dgtest::ImplicitShape& shape, const int n[3], const double spacing[3])
{
  auto image = dgtest::MakeImage(n[0], n[1], n[2], [&](int i, int j, int k) {
    return shape.Inside(V3(i * spacing[0], j * spacing[1], k * spacing[2])) ? 1.0 : 0.0;
  });
  image->SetSpacing(spacing[0], spacing[1], spacing[2]);
  return image;
}

struct ATRun
{
  vtkSmartPointer<vtkPolyData> Surface, Features;
};

// Surface -> II (world radius) -> AT with the given metric and parameters.
ATRun RunAT(vtkImageData* image, double iiRadiusWorld, int metric, double alpha, double lambda,
  double eps1, double eps2, int solver = vtkAmbrosioTortorelliFilter::CONJUGATE_GRADIENT_IC)
{
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadiusUnitsToWorld();
  ii->SetRadius(iiRadiusWorld);
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetInputConnection(ii->GetOutputPort());
  at->SetMetric(metric);
  at->SetAlpha(alpha);
  at->SetLambda(lambda);
  at->SetEpsilonStart(eps1);
  at->SetEpsilonEnd(eps2);
  at->SetLinearSolver(solver);
  at->Update();
  ATRun r;
  r.Surface = vtkSmartPointer<vtkPolyData>::New();
  r.Surface->ShallowCopy(at->GetOutput(0));
  r.Features = vtkSmartPointer<vtkPolyData>::New();
  r.Features->ShallowCopy(at->GetOutput(1));
  return r;
}

} // namespace

TEST(ATMetric, WeightsOfAnAnisotropicBox)
{
  // A 4 x 3 x 2 box of voxels at spacing (1, 1.5, 2): face areas are the
  // products of their two sides, the areas add up to the world surface
  // area, and so do the vertex dual areas; an edge between two coplanar
  // faces has ratio |e| / (distance between the face centres).
  auto image = dgtest::MakeImage(6, 5, 4, [](int i, int j, int k) {
    return i >= 1 && i <= 4 && j >= 1 && j <= 3 && k >= 1 && k <= 2 ? 1.0 : 0.0;
  });
  image->SetSpacing(1, 1.5, 2);
  auto surface = Surface(image);
  std::vector<std::int64_t> offsets, connectivity;
  Polygons(surface, offsets, connectivity);
  dg::ATComplex complex;
  ASSERT_TRUE(complex.Build(surface->GetNumberOfPoints(), offsets, connectivity));
  dg::ATMetric metric;
  std::string error;
  ASSERT_TRUE(dg::ComputeWorldMetric(
    surface->GetPoints(), nullptr, complex, offsets, connectivity, metric, error))
    << error;
  const double X = 4, Y = 3 * 1.5, Z = 2 * 2;
  const double area = 2 * (X * Y + X * Z + Y * Z);
  double faces = 0, vertices = 0;
  for (double a : metric.FaceArea)
  {
    faces += a;
    EXPECT_TRUE(std::abs(a - 1.5) < 1e-12 || std::abs(a - 2) < 1e-12 || std::abs(a - 3) < 1e-12)
      << a;
  }
  for (double a : metric.VertexArea)
  {
    vertices += a;
  }
  EXPECT_NEAR(faces, area, 1e-9);
  EXPECT_NEAR(vertices, area, 1e-9);
  int coplanar = 0;
  for (std::int64_t e = 0; e < complex.NumberOfEdges(); ++e)
  {
    ASSERT_EQ(complex.EdgeFacePtr[e + 1] - complex.EdgeFacePtr[e], 2);
    V3 c[2], nrm[2];
    for (int s = 0; s < 2; ++s)
    {
      const int f = complex.EdgeFaces[complex.EdgeFacePtr[e] + s];
      vtkNew<vtkIdList> ids;
      surface->GetCellPoints(f, ids);
      V3 p[4];
      for (int k = 0; k < 4; ++k)
      {
        surface->GetPoint(ids->GetId(k), p[k].data());
      }
      c[s] = 0.25 * (p[0] + p[1] + p[2] + p[3]);
      nrm[s] = (p[1] - p[0]).cross(p[2] - p[1]).normalized();
    }
    V3 a, b;
    surface->GetPoint(complex.EdgeVertices[2 * e], a.data());
    surface->GetPoint(complex.EdgeVertices[2 * e + 1], b.data());
    if (nrm[0].dot(nrm[1]) > 0.999)
    {
      ++coplanar;
      EXPECT_NEAR(metric.EdgeRatio[e], (b - a).norm() / (c[1] - c[0]).norm(), 1e-12);
    }
    else
    {
      // A box edge: half of each face's side across it.
      const V3 m = 0.5 * (a + b);
      EXPECT_NEAR(
        metric.EdgeRatio[e], (b - a).norm() / ((c[0] - m).norm() + (c[1] - m).norm()), 1e-12);
    }
  }
  EXPECT_GT(coplanar, 20);

  // Degenerate geometry is refused.
  auto flat = dgtest::FlattenedPoints(surface->GetPoints());
  EXPECT_FALSE(
    dg::ComputeWorldMetric(flat, nullptr, complex, offsets, connectivity, metric, error));
  EXPECT_NE(error.find("no"), std::string::npos) << error;
}

TEST(ATMetric, ScalingTheWorldScalesTheParameters)
{
  // The world metric's energy at spacing h with alpha / h^2, lambda / h,
  // eps h is the energy at spacing 1 with alpha, lambda, eps: the same u and
  // v up to rounding (exact solver). The grid metric ignores the spacing,
  // and the world metric with unscaled parameters does not.
  auto cube = dgtest::MakeRotatedCube(V3(12.1, 11.9, 12.2), 7.3, 20, 30, 10);
  auto unit = dgtest::Digitize(*cube, 24);
  auto twice = vtkSmartPointer<vtkImageData>::New();
  twice->DeepCopy(unit);
  const double h = 1.7;
  twice->SetSpacing(h, h, h);
  const int ldlt = vtkAmbrosioTortorelliFilter::SIMPLICIAL_LDLT;
  const int world = vtkAmbrosioTortorelliFilter::METRIC_WORLD;
  const ATRun a = RunAT(unit, 3.0, world, 0.1, 0.01, 2.0, 0.25, ldlt);
  const ATRun b = RunAT(twice, 3.0 * h, world, 0.1 / (h * h), 0.01 / h, 2.0 * h, 0.25 * h, ldlt);
  const ATRun c = RunAT(twice, 3.0 * h, world, 0.1, 0.01, 2.0, 0.25, ldlt);
  const ATRun g1 = RunAT(unit, 3.0, vtkAmbrosioTortorelliFilter::METRIC_GRID, 0.1, 0.01, 2.0, 0.25, ldlt);
  const ATRun g2 = RunAT(twice, 3.0 * h, vtkAmbrosioTortorelliFilter::METRIC_GRID, 0.1, 0.01, 2.0, 0.25, ldlt);
  auto maxDiff = [](vtkDataArray* x, vtkDataArray* y) {
    double d = 0;
    for (vtkIdType i = 0; i < x->GetNumberOfValues(); ++i)
    {
      d = std::max(d, std::abs(x->GetVariantValue(i).ToDouble() - y->GetVariantValue(i).ToDouble()));
    }
    return d;
  };
  auto v = [](const ATRun& r) { return r.Surface->GetPointData()->GetArray("ATFeatureIndicator"); };
  auto u = [](const ATRun& r) { return r.Surface->GetCellData()->GetArray("ATNormals"); };
  ASSERT_EQ(v(a)->GetNumberOfValues(), v(b)->GetNumberOfValues());
  const double dvScaled = maxDiff(v(a), v(b)), duScaled = maxDiff(u(a), u(b));
  const double dvUnscaled = maxDiff(v(a), v(c));
  std::printf("world metric, spacing 1 vs 2 with scaled parameters: max |dv| %.2e, |du| %.2e; "
              "unscaled: max |dv| %.2e; grid metric spacing 1 vs 2: max |dv| %.2e\n",
    dvScaled, duScaled, dvUnscaled, maxDiff(v(g1), v(g2)));
  EXPECT_LT(dvScaled, 1e-8);
  EXPECT_LT(duScaled, 1e-8);
  EXPECT_GT(dvUnscaled, 0.1);
  EXPECT_LT(maxDiff(v(g1), v(g2)), 1e-12);
  // At spacing 1 the two metrics differ only through the dual areas of the
  // vertices where 3 or 5+ faces meet: close, not equal.
  const double dvMetrics = maxDiff(v(a), v(g1));
  std::printf("spacing 1, world vs grid metric: max |dv| %.3f\n", dvMetrics);
  EXPECT_GT(dvMetrics, 0.0);
}

namespace
{
// AT on a digitised shape whose input field is the true normal at each face
// centre (no estimator in between, so the input is the same field at every
// resolution). Returns the world width of the feature band, the integral of
// (1 - v) over the surface per unit of true edge length, and the mean
// normal error beyond `far` of the edges.
struct Band
{
  double Width = 0, FarError = 0;
};
Band OracleBand(const dgtest::ImplicitShape& shape, const int n[3], const double spacing[3],
  int metric, double alpha, double lambda, double eps1, double eps2, double far)
{
  auto image = DigitizeWorld(shape, n, spacing);
  auto surface = Surface(image);
  vtkNew<vtkDoubleArray> truth;
  truth->SetName("TrueNormals");
  truth->SetNumberOfComponents(3);
  truth->SetNumberOfTuples(surface->GetNumberOfCells());
  const std::vector<V3> centres = dgtest::CellCentres(surface);
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    const V3 nn = shape.Normal(centres[c]);
    truth->SetTuple3(c, nn[0], nn[1], nn[2]);
  }
  surface->GetCellData()->SetNormals(truth);
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetInputData(surface);
  at->SetMetric(metric);
  at->SetAlpha(alpha);
  at->SetLambda(lambda);
  at->SetEpsilonStart(eps1);
  at->SetEpsilonEnd(eps2);
  at->Update();
  vtkPolyData* out = at->GetOutput(0);
  vtkDataArray* v = out->GetPointData()->GetArray("ATFeatureIndicator");
  // The dual areas of the vertices (world), as the metric computes them.
  std::vector<std::int64_t> offsets, connectivity;
  Polygons(out, offsets, connectivity);
  dg::ATComplex complex;
  complex.Build(out->GetNumberOfPoints(), offsets, connectivity);
  dg::ATMetric m;
  std::string error;
  dg::ComputeWorldMetric(out->GetPoints(), nullptr, complex, offsets, connectivity, m, error);
  double integral = 0;
  for (vtkIdType p = 0; p < out->GetNumberOfPoints(); ++p)
  {
    integral += m.VertexArea[p] * (1 - v->GetTuple1(p));
  }
  Band b;
  b.Width = integral / (0.25 * static_cast<double>(shape.SharpEdgeSamples(0.25).size()));
  vtkDataArray* u = out->GetCellData()->GetArray("ATNormals");
  double sum = 0;
  int count = 0;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    if (shape.DistanceToSharpEdge(centres[c], 2 * far) >= far)
    {
      V3 x;
      u->GetTuple(c, x.data());
      sum += dgtest::AngleDegrees(x, shape.Normal(centres[c]));
      ++count;
    }
  }
  b.FarError = count ? sum / count : 0.0;
  return b;
}
} // namespace

TEST(ATMetric, SameParametersSameBandAtEveryResolution)
{
  // One rotated cube (world half side 40) digitised at spacing 1 (128^3),
  // spacing 2 (64^3) and spacing (1, 1, 2); the input field is the true
  // normal, so only AT differs. Same numbers under both metrics (alpha
  // 0.05, lambda 0.01, eps 4 -> 2, large enough to be resolved at spacing
  // 2). The band's world width must be the same on the three grids with the
  // world metric; with the grid metric eps is in voxels, so the band is
  // about twice as wide in world units at spacing 2.
  auto cube = dgtest::MakeRotatedCube(V3(64.3, 63.7, 64.1), 40, 20, 30, 10);
  struct Grid
  {
    const char* name;
    int n[3];
    double spacing[3];
  };
  const Grid grids[] = { { "128^3, spacing 1", { 128, 128, 128 }, { 1, 1, 1 } },
    { "64^3, spacing 2", { 64, 64, 64 }, { 2, 2, 2 } },
    { "128x128x64, spacing (1, 1, 2)", { 128, 128, 64 }, { 1, 1, 2 } } };
  Band bands[2][3];
  for (int metric : { vtkAmbrosioTortorelliFilter::METRIC_GRID,
         vtkAmbrosioTortorelliFilter::METRIC_WORLD })
  {
    for (int g = 0; g < 3; ++g)
    {
      bands[metric][g] =
        OracleBand(*cube, grids[g].n, grids[g].spacing, metric, 0.05, 0.01, 4.0, 2.0, 8.0);
      std::printf("%s metric, %-30s band width %.3f (world), normals beyond 8 of the edges "
                  "%.3f deg\n",
        metric ? "world" : "grid ", grids[g].name, bands[metric][g].Width,
        bands[metric][g].FarError);
    }
  }
  const Band* w = bands[vtkAmbrosioTortorelliFilter::METRIC_WORLD];
  const Band* q = bands[vtkAmbrosioTortorelliFilter::METRIC_GRID];
  const double worldSpread = std::max({ w[0].Width, w[1].Width, w[2].Width }) /
    std::min({ w[0].Width, w[1].Width, w[2].Width });
  std::printf("band width max/min over the grids: world metric %.3f; grid metric spacing 2 / "
              "spacing 1 %.3f\n",
    worldSpread, q[1].Width / q[0].Width);
  EXPECT_LT(worldSpread, 1.2);
  EXPECT_GT(q[1].Width / q[0].Width, 1.6);
}
