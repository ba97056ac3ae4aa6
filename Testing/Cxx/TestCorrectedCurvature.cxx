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

// The ball radius per face (AdaptiveRadius), with the true normals tilted
// by a smooth noise so that the rule has something to weigh: every radius
// in [2R/3, 3R]; on a torus, none beyond the tube's radius (the face's
// smallest curvature radius) by more than the first pass's error; with two
// regions, the faces whose ball of R reaches the other region keep R; and a
// piece holding its own faces plus the faces within CurvatureReach of them
// (as ghosts, with global ids) gives its faces exactly the whole surface's
// radii and curvatures.
TEST(CorrectedCurvatureCore, AdaptiveRadius)
{
  const double a = 24, b = 10, R = 6;
  const int n = 80;
  const V3 c(n / 2.0 + 0.2, n / 2.0 + 0.3, n / 2.0 + 0.1);
  auto shape = dgtest::MakeTorus(c, a, b, 0, 0, 0);
  const Mesh m = Surface(*shape, n);
  std::vector<double> u = TrueNormals(*shape, m);
  for (std::size_t f = 0; f < m.Centres.size(); ++f)
  {
    const V3 p = m.Centres[f];
    V3 t(std::sin(0.7 * p.y() + 0.3 * p.z()), std::sin(0.9 * p.z() + 0.2 * p.x()),
      std::sin(0.8 * p.x() + 0.4 * p.y()));
    V3 v = V3(u[3 * f], u[3 * f + 1], u[3 * f + 2]) + 0.05 * t;
    v.normalize();
    for (int d = 0; d < 3; ++d)
      u[3 * f + d] = v[d];
  }
  const std::int64_t F = static_cast<std::int64_t>(m.Centres.size());
  const std::int64_t P = static_cast<std::int64_t>(m.Points.size() / 3);
  dg::CurvatureParameters p;
  p.Radius = R;
  p.EdgeLength = 1;
  p.AdaptiveRadius = true;
  std::vector<std::int64_t> ids(F);
  for (std::int64_t f = 0; f < F; ++f)
    ids[f] = f;
  dg::CurvatureResult whole;
  std::string error;
  ASSERT_TRUE(dg::ComputeCorrectedCurvatures(P, m.Points.data(), m.Offsets, m.Connectivity, u.data(),
    nullptr, p, whole, &error, nullptr, ids.data()))
    << error;
  std::vector<double> radii(whole.BallRadius);
  std::sort(radii.begin(), radii.end());
  std::printf("torus, adaptive: radius min %.2f median %.2f max %.2f\n", radii.front(),
    Median(radii), radii.back());
  EXPECT_GE(radii.front(), 2 * R / 3 - 1e-12);
  EXPECT_LE(radii.back(), 3 * R + 1e-12);
  EXPECT_LE(radii.back(), 1.1 * b);
  EXPECT_NE(radii.front(), radii.back());

  // Two regions: the half-space x < c.x and the rest.
  std::vector<int> region(F);
  for (std::int64_t f = 0; f < F; ++f)
    region[f] = m.Centres[f].x() < c.x() ? 0 : 1;
  dg::CurvatureResult sides;
  ASSERT_TRUE(dg::ComputeCorrectedCurvatures(P, m.Points.data(), m.Offsets, m.Connectivity, u.data(),
    region.data(), p, sides, &error, nullptr, ids.data()))
    << error;
  int nearBorder = 0, kept = 0;
  for (std::int64_t f = 0; f < F; ++f)
    if (std::abs(m.Centres[f].x() - c.x()) < R - 1)
    {
      ++nearBorder;
      kept += sides.BallRadius[f] == R ? 1 : 0;
    }
  EXPECT_GT(nearBorder, 0);
  EXPECT_EQ(kept, nearBorder);

  // A piece: the faces with y < c.y - 20, and as ghosts the other faces
  // whose centre lies within CurvatureReach of the piece's box.
  const double reach = dg::CurvatureReach(p, 1.0);
  double top = -1e300;
  for (std::int64_t f = 0; f < F; ++f)
    if (m.Centres[f].y() < c.y() - 20)
      top = std::max(top, m.Centres[f].y());
  std::vector<std::int64_t> keep, offsets{ 0 }, conn, pieceIds;
  std::vector<double> pu;
  std::vector<unsigned char> ghost;
  for (std::int64_t f = 0; f < F; ++f)
  {
    const bool own = m.Centres[f].y() < c.y() - 20;
    if (!own && m.Centres[f].y() > top + reach)
      continue;
    keep.push_back(f);
    ghost.push_back(own ? 0 : 1);
    pieceIds.push_back(f);
    for (std::int64_t k = m.Offsets[f]; k < m.Offsets[f + 1]; ++k)
      conn.push_back(m.Connectivity[k]);
    offsets.push_back(static_cast<std::int64_t>(conn.size()));
    pu.insert(pu.end(), { u[3 * f], u[3 * f + 1], u[3 * f + 2] });
  }
  ASSERT_LT(keep.size(), static_cast<std::size_t>(F));
  dg::CurvatureResult piece;
  ASSERT_TRUE(dg::ComputeCorrectedCurvatures(P, m.Points.data(), offsets, conn, pu.data(), nullptr, p,
    piece, &error, ghost.data(), pieceIds.data()))
    << error;
  double worst = 0, worstRadius = 0;
  for (std::size_t k = 0; k < keep.size(); ++k)
    if (!ghost[k])
    {
      worst = std::max({ worst, std::abs(piece.Mean[k] - whole.Mean[keep[k]]),
        std::abs(piece.Gaussian[k] - whole.Gaussian[keep[k]]),
        std::abs(piece.K1[k] - whole.K1[keep[k]]), std::abs(piece.K2[k] - whole.K2[keep[k]]) });
      worstRadius = std::max(worstRadius, std::abs(piece.BallRadius[k] - whole.BallRadius[keep[k]]));
    }
  std::printf("piece of %zu faces (reach %.2f): curvatures within %.3g, radii within %.3g of the "
              "whole's\n",
    keep.size(), reach, worst, worstRadius);
  EXPECT_LE(worst, 1e-12);
  EXPECT_LE(worstRadius, 1e-12);
}
