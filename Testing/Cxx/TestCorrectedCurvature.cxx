// Issue 37, the core of the corrected curvature measures
// (dgCorrectedCurvature.h) on ground truth: closed-form measures of single
// polygons, spheres' mean and Gaussian curvature, Gauss-Bonnet on shapes of
// genus 0 and 1, and a torus's principal curvatures and directions, all with
// the true normals as the corrected field on the digital surface's voxel
// faces.
#include "dgCorrectedCurvature.h"
#include "dgGroundTruth.h"
#include "dgPipeline.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
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

struct Mesh
{
  std::vector<double> Points;
  std::vector<std::int64_t> Offsets, Connectivity;
  std::vector<V3> Centres;
};

Mesh Surface(const dgtest::ImplicitShape& shape, int n)
{
  auto image = dgtest::Digitize(shape, n);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  surface->Update();
  vtkPolyData* pd = surface->GetOutput();
  Mesh m;
  m.Points.resize(3 * pd->GetNumberOfPoints());
  for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
    pd->GetPoint(i, &m.Points[3 * i]);
  vtkCellArray* polys = pd->GetPolys();
  vtkNew<vtkIdTypeArray> offsets, conn;
  polys->ExportLegacyFormat(conn);
  m.Offsets.push_back(0);
  for (vtkIdType k = 0; k < conn->GetNumberOfValues();)
  {
    const vtkIdType npts = conn->GetValue(k++);
    V3 c = V3::Zero();
    for (vtkIdType j = 0; j < npts; ++j)
    {
      const vtkIdType id = conn->GetValue(k++);
      m.Connectivity.push_back(id);
      c += V3(m.Points[3 * id], m.Points[3 * id + 1], m.Points[3 * id + 2]);
    }
    m.Offsets.push_back(static_cast<std::int64_t>(m.Connectivity.size()));
    m.Centres.push_back(c / npts);
  }
  return m;
}

std::vector<double> TrueNormals(const dgtest::ImplicitShape& shape, const Mesh& m)
{
  std::vector<double> u;
  for (const V3& c : m.Centres)
  {
    const V3 n = shape.Normal(c).normalized();
    u.insert(u.end(), { n.x(), n.y(), n.z() });
  }
  return u;
}

dg::CurvatureResult Measure(const Mesh& m, const std::vector<double>& u, double radius)
{
  dg::CurvatureParameters p;
  p.Radius = radius;
  dg::CurvatureResult r;
  std::string error;
  EXPECT_TRUE(dg::ComputeCorrectedCurvatures(static_cast<std::int64_t>(m.Points.size() / 3),
    m.Points.data(), m.Offsets, m.Connectivity, u.data(), nullptr, p, r, &error))
    << error;
  return r;
}

double Median(std::vector<double> v)
{
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
} // namespace

// A flat unit square with its own normal: area 1, no curvature; a square on
// a unit sphere's cap with the sphere's normals: mu1 = 2 H area, mu2 = G
// area to first order.
TEST(CorrectedCurvatureCore, PolygonMeasures)
{
  const double x[12] = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 };
  const double u[12] = { 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 };
  const dg::CorrectedMeasures flat = dg::PolygonMeasures(4, x, u);
  EXPECT_NEAR(flat.Mu0, 1, 1e-12);
  EXPECT_NEAR(flat.Mu1, 0, 1e-12);
  EXPECT_NEAR(flat.Mu2, 0, 1e-12);
  const double h = 0.01, R = 1;
  double y[12], w[12];
  const double corners[4][2] = { { -h, -h }, { h, -h }, { h, h }, { -h, h } };
  for (int i = 0; i < 4; ++i)
  {
    const V3 p(corners[i][0], corners[i][1], R);
    const V3 q = p.normalized() * R;
    for (int d = 0; d < 3; ++d)
    {
      y[3 * i + d] = q[d];
      w[3 * i + d] = q[d] / R;
    }
  }
  const dg::CorrectedMeasures cap = dg::PolygonMeasures(4, y, w);
  EXPECT_NEAR(cap.Mu1 / (2 * cap.Mu0), 1 / R, 1e-3);
  EXPECT_NEAR(cap.Mu2 / cap.Mu0, 1 / (R * R), 1e-3);
}

TEST(CorrectedCurvatureCore, SpheresMeanAndGaussianCurvature)
{
  for (double radius : { 10.0, 20.0, 40.0 })
  {
    const int n = static_cast<int>(2 * radius + 8);
    auto shape = dgtest::MakeSphere(V3(n / 2.0 + 0.3, n / 2.0 + 0.1, n / 2.0 + 0.2), radius);
    const Mesh m = Surface(*shape, n);
    const dg::CurvatureResult r = Measure(m, TrueNormals(*shape, m), 3.0);
    std::vector<double> hr, gr, k1, k2;
    for (std::size_t f = 0; f < m.Centres.size(); ++f)
    {
      hr.push_back(r.Mean[f] * radius);
      gr.push_back(r.Gaussian[f] * radius * radius);
      k1.push_back(r.K1[f] * radius);
      k2.push_back(r.K2[f] * radius);
    }
    const double area = 4 * M_PI * radius * radius;
    std::printf("sphere R %.0f: median H R %.4f, K R^2 %.4f, k1 R %.4f, k2 R %.4f; area %.4f of "
                "the true, int G / 2 pi %.4f\n",
      radius, Median(hr), Median(gr), Median(k1), Median(k2), r.Area / area,
      r.TotalGaussian / (2 * M_PI));
    EXPECT_NEAR(Median(hr), 1, 0.01) << radius;
    EXPECT_NEAR(Median(gr), 1, 0.01) << radius;
    // The principal curvatures come from the anisotropic measure, whose
    // tangential trace falls short of mu1 on small spheres: measured k R
    // 0.975-0.979 at R = 10, 0.992-0.996 at 20, 0.997-1.001 at 40 (ball
    // radius 3); H from mu1 is within 0.05 % at all three.
    EXPECT_NEAR(Median(k1), 1, 0.03) << radius;
    EXPECT_NEAR(Median(k2), 1, 0.03) << radius;
    EXPECT_NEAR(r.Area / area, 1, 0.005) << radius;
    EXPECT_NEAR(r.TotalGaussian / (2 * M_PI), 2, 0.01) << radius;
  }
}

// On a torus (major radius a, minor b) the outer equator has k = 1/b around
// the tube and 1/(a + b) along the equator, the inner one 1/b and
// -1/(a - b): k1 is the tube's, its direction orthogonal to the equator.
TEST(CorrectedCurvatureCore, TorusPrincipalCurvaturesAndGaussBonnet)
{
  const double a = 24, b = 10;
  const int n = 80;
  const V3 c(n / 2.0 + 0.2, n / 2.0 + 0.3, n / 2.0 + 0.1);
  auto shape = dgtest::MakeTorus(c, a, b, 0, 0, 0);
  const Mesh m = Surface(*shape, n);
  const dg::CurvatureResult r = Measure(m, TrueNormals(*shape, m), 3.0);
  std::printf("torus: int G / 2 pi %.4f\n", r.TotalGaussian / (2 * M_PI));
  EXPECT_NEAR(r.TotalGaussian / (2 * M_PI), 0, 0.01);
  std::vector<double> outer1, outer2, inner1, inner2, outerDir, innerDir;
  for (std::size_t f = 0; f < m.Centres.size(); ++f)
  {
    const V3 p = m.Centres[f] - c;
    const double rho = std::hypot(p.x(), p.y());
    if (std::abs(p.z()) > 1.5)
      continue;
    const V3 tangent = V3(-p.y(), p.x(), 0).normalized(); // along the equator
    const V3 d1(r.D1[3 * f], r.D1[3 * f + 1], r.D1[3 * f + 2]);
    if (rho > a + b - 1)
    {
      outer1.push_back(r.K1[f] * b);
      outer2.push_back(r.K2[f] * (a + b));
      outerDir.push_back(std::abs(d1.dot(tangent)));
    }
    else if (rho < a - b + 1)
    {
      inner1.push_back(r.K1[f] * b);
      inner2.push_back(r.K2[f] * (a - b));
      innerDir.push_back(std::abs(d1.dot(tangent)));
    }
  }
  ASSERT_FALSE(outer1.empty());
  ASSERT_FALSE(inner1.empty());
  std::printf("torus outer: k1 b %.3f k2 (a+b) %.3f |d1.t| %.3f; inner: k1 b %.3f k2 (a-b) %.3f "
              "|d1.t| %.3f\n",
    Median(outer1), Median(outer2), Median(outerDir), Median(inner1), Median(inner2),
    Median(innerDir));
  EXPECT_NEAR(Median(outer1), 1, 0.05);
  EXPECT_NEAR(Median(outer2), 1, 0.1);
  EXPECT_NEAR(Median(inner1), 1, 0.05);
  EXPECT_NEAR(Median(inner2), -1, 0.1);
  EXPECT_LT(Median(outerDir), 0.1);
  EXPECT_LT(Median(innerDir), 0.1);
}

TEST(CorrectedCurvatureCore, RejectsBadInput)
{
  const std::vector<double> points = { 0, 0, 0, 1, 0, 0, 1, 1, 0 };
  const std::vector<std::int64_t> offsets = { 0, 3 }, conn = { 0, 1, 2 };
  const double unit[3] = { 0, 0, 1 }, half[3] = { 0, 0, 0.5 };
  dg::CurvatureParameters p;
  dg::CurvatureResult r;
  std::string error;
  EXPECT_TRUE(dg::ComputeCorrectedCurvatures(3, points.data(), offsets, conn, unit, nullptr, p, r, &error));
  EXPECT_FALSE(dg::ComputeCorrectedCurvatures(3, points.data(), offsets, conn, half, nullptr, p, r, &error));
  EXPECT_NE(error.find("unit"), std::string::npos) << error;
  p.Radius = 0;
  EXPECT_FALSE(dg::ComputeCorrectedCurvatures(3, points.data(), offsets, conn, unit, nullptr, p, r, &error));
  p.Radius = 3;
  const std::vector<std::int64_t> bad = { 0, 1, 5 };
  EXPECT_FALSE(dg::ComputeCorrectedCurvatures(3, points.data(), offsets, bad, unit, nullptr, p, r, &error));
}

// The module's own field (the program's defaults: SharpNormals) as u, per
// side (FeatureRegion), clean spheres: what a user gets.
TEST(CorrectedCurvatureCore, SpheresWithTheProgramsNormals)
{
  for (double radius : { 10.0, 20.0, 40.0 })
  {
    const int n = static_cast<int>(2 * radius + 8);
    auto shape = dgtest::MakeSphere(V3(n / 2.0 + 0.3, n / 2.0 + 0.1, n / 2.0 + 0.2), radius);
    auto image = dgtest::Digitize(*shape, n);
    dg::Pipeline p;
    p.Build(image, dg::PipelineSettings());
    p.Stages.back().Algorithm->Update();
    vtkPolyData* pd = p.Result();
    Mesh m;
    m.Points.resize(3 * pd->GetNumberOfPoints());
    for (vtkIdType i = 0; i < pd->GetNumberOfPoints(); ++i)
      pd->GetPoint(i, &m.Points[3 * i]);
    vtkNew<vtkIdTypeArray> conn;
    pd->GetPolys()->ExportLegacyFormat(conn);
    m.Offsets.push_back(0);
    for (vtkIdType k = 0; k < conn->GetNumberOfValues();)
    {
      const vtkIdType npts = conn->GetValue(k++);
      for (vtkIdType j = 0; j < npts; ++j)
        m.Connectivity.push_back(conn->GetValue(k++));
      m.Offsets.push_back(static_cast<std::int64_t>(m.Connectivity.size()));
    }
    vtkDataArray* normals = pd->GetCellData()->GetArray(p.NormalsName());
    ASSERT_NE(normals, nullptr);
    std::vector<double> u(3 * normals->GetNumberOfTuples());
    for (vtkIdType f = 0; f < normals->GetNumberOfTuples(); ++f)
    {
      V3 v(normals->GetComponent(f, 0), normals->GetComponent(f, 1), normals->GetComponent(f, 2));
      v.normalize();
      for (int d = 0; d < 3; ++d)
        u[3 * f + d] = v[d];
    }
    for (double ball : { 3.0, 5.0 })
    {
      const dg::CurvatureResult r = Measure(m, u, ball);
      std::vector<double> hr, gr;
      for (std::size_t f = 0; f < r.Mean.size(); ++f)
      {
        hr.push_back(r.Mean[f] * radius);
        gr.push_back(r.Gaussian[f] * radius * radius);
      }
      std::printf("sphere R %.0f, program's normals, ball %.0f: median H R %.4f, K R^2 %.4f; "
                  "area %.4f of the true, int G / 2 pi %.4f\n",
        radius, ball, Median(hr), Median(gr), r.Area / (4 * M_PI * radius * radius),
        r.TotalGaussian / (2 * M_PI));
      EXPECT_NEAR(r.Area / (4 * M_PI * radius * radius), 1, 0.005) << radius << " " << ball;
      EXPECT_NEAR(r.TotalGaussian / (2 * M_PI), 2, 0.01) << radius << " " << ball;
      if (ball == 5)
      {
        // The 1 % holds for H at ball radius 5 (measured 1.0015-1.0076;
        // 1.0068-1.0121 at 3); K R^2 measured 1.0029-1.0121 at 5: bound 1.5 %.
        EXPECT_NEAR(Median(hr), 1, 0.01) << radius;
        EXPECT_NEAR(Median(gr), 1, 0.015) << radius;
      }
    }
  }
}
