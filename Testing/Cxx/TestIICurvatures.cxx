// Integral-invariant curvatures (docs/method.md section 6, with its correction of
// the principal directions): mean and principal curvatures and directions
// on spheres, a plane, a tilted cylinder, a spherical cavity and a torus.
#include "dgGroundTruth.h"
#include "dgIntegralInvariant.h"
#include "dgNoise.h"
#include "dgIITestSupport.h"
#include "dgTestShapes.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <vector>

namespace
{
using V3 = Eigen::Vector3d;
using dgtest::Estimate;
using dgtest::ImageOf;
using dgtest::MaskOf;
using dgtest::Mean;
using dgtest::Percentile;
using dgtest::Tuple;
} // namespace

namespace
{
struct CurvatureMedians
{
  double H, K1, K2, K, HalfSum;
};
CurvatureMedians SphereCurvatures(double R, double r, int reference)
{
  const int n = static_cast<int>(2 * R + 2 * r + 6);
  auto shape = dgtest::MakeSphere(V3(0.5 * n + 0.3, 0.5 * n - 0.2, 0.5 * n + 0.1), R);
  auto out = Estimate(dgtest::Digitize(*shape, n), r, true, reference);
  vtkCellData* cd = out->GetCellData();
  std::vector<double> H, K, k1, k2, halfSum;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    H.push_back(cd->GetArray("IIMeanCurvature")->GetTuple1(c));
    K.push_back(cd->GetArray("IIGaussianCurvature")->GetTuple1(c));
    k1.push_back(cd->GetArray("IIK1")->GetTuple1(c));
    k2.push_back(cd->GetArray("IIK2")->GetTuple1(c));
    halfSum.push_back(0.5 * (k1.back() + k2.back()));
    EXPECT_GE(k1.back(), k2.back());
    // Principal directions: unit, orthogonal to each other and to the normal.
    const V3 d1 = Tuple(cd->GetArray("IIK1Direction"), c);
    const V3 d2 = Tuple(cd->GetArray("IIK2Direction"), c);
    const V3 nn = Tuple(cd->GetArray("IINormals"), c);
    EXPECT_NEAR(d1.norm(), 1.0, 1e-9);
    EXPECT_NEAR(d1.dot(d2), 0.0, 1e-9);
    EXPECT_NEAR(d1.dot(nn), 0.0, 1e-9);
  }
  return { Percentile(H, 0.5),
    Percentile(k1, 0.5),
    Percentile(k2, 0.5),
    Percentile(K, 0.5),
    Percentile(halfSum, 0.5) };
}
} // namespace

TEST(IIEstimator, CurvaturesOnSpheresAndPlane)
{
  // Asserted with the default reference (digital tangent plane); the others
  // are printed for comparison. Per surfel, k1 - k2 carries lattice noise
  // (the lens between a sphere of radius 40 and its tangent plane holds
  // about 25 voxels at r = 6); sorting k1 >= k2 turns that noise into a
  // spread of the medians, so k2 is bounded by 20%, the rest by 10%.
  const char* refNames[] = { "continuous", "digital ball", "tangent plane" };
  for (int reference : { 0, 1, 2 })
  {
    for (double R : { 20.0, 40.0 })
    {
      const auto m = SphereCurvatures(R, 6.0, reference);
      std::printf("%-13s ref., sphere R=%.0f, r=6: median H*R %.3f  k1*R %.3f  k2*R %.3f  "
                  "(k1+k2)/2*R %.3f  K*R^2 %.3f\n",
        refNames[reference],
        R,
        m.H * R,
        m.K1 * R,
        m.K2 * R,
        m.HalfSum * R,
        m.K * R * R);
      if (reference == 2)
      {
        EXPECT_NEAR(m.H * R, 1.0, 0.1);
        EXPECT_NEAR(m.K1 * R, 1.0, 0.1);
        EXPECT_NEAR(m.K2 * R, 1.0, 0.2);
        EXPECT_NEAR(m.HalfSum * R, 1.0, 0.1);
      }
    }
    // A plane: the top face of a slab, away from the image borders.
    const int n = 48;
    auto image = dgtest::MakeImage(n, n, n, [](int, int, int k) { return k <= 20 ? 1.0 : 0.0; });
    auto out = Estimate(image, 6.0, true, reference);
    const auto centres = dgtest::SurfelCenters(out);
    vtkCellData* cd = out->GetCellData();
    double worst = 0;
    int count = 0;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      const V3& p = centres[c];
      if (p[2] != 20.5 || p[0] < 8 || p[0] > n - 9 || p[1] < 8 || p[1] > n - 9)
      {
        continue;
      }
      ++count;
      for (const char* name : { "IIMeanCurvature", "IIK1", "IIK2", "IIGaussianCurvature" })
      {
        worst = std::max(worst, std::abs(cd->GetArray(name)->GetTuple1(c)));
      }
    }
    std::printf("%-13s ref., plane, r=6: largest |H|, |k1|, |k2|, |K| over %d surfels: %.2e\n",
      refNames[reference],
      count,
      worst);
    EXPECT_GT(count, 500);
    if (reference >= 1)
    {
      EXPECT_LT(worst, 1e-12);
    }
  }
  // A tilted plane (normal (1, 2, 3) / sqrt(14)): per surfel the curvatures
  // carry the digitisation noise, their medians are ~0.
  {
    const int n = 64;
    const V3 nrm = V3(1, 2, 3).normalized();
    const V3 mid(31.6, 32.2, 31.9);
    auto image = dgtest::MakeImage(
      n, n, n, [&](int i, int j, int k) { return (V3(i, j, k) - mid).dot(nrm) <= 0 ? 1.0 : 0.0; });
    auto out = Estimate(image, 6.0, true);
    const auto centres = dgtest::SurfelCenters(out);
    vtkCellData* cd = out->GetCellData();
    std::vector<double> H, k1, k2;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      const V3& p = centres[c];
      if (std::abs((p - mid).dot(nrm)) > 2 || p.minCoeff() < 8 || p.maxCoeff() > n - 9)
      {
        continue;
      }
      H.push_back(cd->GetArray("IIMeanCurvature")->GetTuple1(c));
      k1.push_back(cd->GetArray("IIK1")->GetTuple1(c));
      k2.push_back(cd->GetArray("IIK2")->GetTuple1(c));
    }
    const double mH = Percentile(H, 0.5), m1 = Percentile(k1, 0.5), m2 = Percentile(k2, 0.5);
    std::printf(
      "tilted plane, r=6, %zu surfels: median H %.4f  k1 %.4f  k2 %.4f\n", H.size(), mH, m1, m2);
    EXPECT_GT(H.size(), 1000u);
    EXPECT_LT(std::abs(mH), 0.003);
    EXPECT_LT(std::abs(0.5 * (m1 + m2)), 0.003);
  }
  // Other balls: the spread shrinks as r grows (printed only; docs/curvatures.md).
  for (double R : { 20.0, 40.0 })
  {
    for (double r : { 4.0, 8.0, 10.0 })
    {
      const auto m = SphereCurvatures(R, r, 2);
      std::printf("tangent plane ref., sphere R=%.0f, r=%.0f: median H*R %.3f  k1*R %.3f  k2*R "
                  "%.3f\n",
        R,
        r,
        m.H * R,
        m.K1 * R,
        m.K2 * R);
    }
  }
}

//------------------------------------------------------------------------------
TEST(IIEstimator, PrincipalCurvaturesAndDirectionsOnTiltedCylinder)
{
  // An infinite cylinder of radius R along a = (1, 2, 3)/sqrt(14): k1 = 1/R
  // around it (direction perpendicular to a and to the normal), k2 = 0 along
  // a. Curving away more along a direction removes more of the ball's inside
  // near the rim in that direction, so k1 belongs to the smaller tangent
  // eigenvalue of the covariance matrix (Pottmann et al. 2007; docs/method.md section
  // 6 pairs them the other way).
  const int n = 64;
  const double R = 14;
  const V3 a = V3(1, 2, 3).normalized();
  const V3 mid(31.6, 32.2, 31.9);
  auto image = dgtest::MakeImage(n,
    n,
    n,
    [&](int i, int j, int k)
    {
      const V3 d = V3(i, j, k) - mid;
      return (d - d.dot(a) * a).norm() <= R ? 1.0 : 0.0;
    });
  for (double r : { 4.0, 6.0 })
  {
    auto out = Estimate(image, r, true);
    const auto centres = dgtest::SurfelCenters(out);
    vtkCellData* cd = out->GetCellData();
    std::vector<double> k1, k2, along1, along2, around1;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      const V3& p = centres[c];
      if (p.minCoeff() < r + 3 || p.maxCoeff() > n - 4 - r)
      {
        continue; // the image border cuts the cylinder there
      }
      const V3 d = p - mid;
      const V3 radial = (d - d.dot(a) * a).normalized();
      const V3 around = a.cross(radial);
      const V3 d1 = Tuple(cd->GetArray("IIK1Direction"), c);
      const V3 d2 = Tuple(cd->GetArray("IIK2Direction"), c);
      k1.push_back(cd->GetArray("IIK1")->GetTuple1(c));
      k2.push_back(cd->GetArray("IIK2")->GetTuple1(c));
      along1.push_back(std::abs(d1.dot(a)));
      along2.push_back(std::abs(d2.dot(a)));
      around1.push_back(std::abs(d1.dot(around)));
    }
    const double m1 = Percentile(k1, 0.5), m2 = Percentile(k2, 0.5);
    const double a1 = Percentile(along1, 0.5), a2 = Percentile(along2, 0.5);
    const double c1 = Percentile(around1, 0.5), a1p95 = Percentile(along1, 0.95);
    std::printf("tilted cylinder R=%.0f, r=%.0f, %zu surfels: median k1*R %.3f  k2*R %.3f  "
                "|d1.axis| median %.3f p95 %.3f  |d1.around| %.3f  |d2.axis| %.3f\n",
      R,
      r,
      k1.size(),
      m1 * R,
      m2 * R,
      a1,
      a1p95,
      c1,
      a2);
    EXPECT_GT(k1.size(), 2000u);
    EXPECT_NEAR(m1 * R, 1.0, 0.1);
    EXPECT_NEAR(m2 * R, 0.0, 0.1);
    // Measured: median |d1.a| 0.108 (r 4) and 0.081 (r 6), p95 0.305 and
    // 0.178; with the directions swapped both medians are above 0.99.
    EXPECT_LT(a1, r < 5 ? 0.13 : 0.1);
    EXPECT_LT(a1p95, r < 5 ? 0.35 : 0.22);
    EXPECT_GT(c1, 0.99);
    EXPECT_GT(a2, 0.99);
  }
}
//------------------------------------------------------------------------------
TEST(IIEstimator, ConcaveSphericalCavity)
{
  // A ball-shaped hole in a block: the surface's outward normals point into
  // the hole, and with "convex is positive" every curvature is -1/R there.
  const int n = 64;
  const double R = 20;
  const V3 mid(31.7, 32.2, 31.4);
  auto image = dgtest::MakeImage(n,
    n,
    n,
    [&](int i, int j, int k)
    {
      const bool inBlock = std::min({ i, j, k }) >= 2 && std::max({ i, j, k }) <= n - 3;
      return inBlock && (V3(i, j, k) - mid).norm() > R ? 1.0 : 0.0;
    });
  auto out = Estimate(image, 6.0, true);
  const auto centres = dgtest::SurfelCenters(out);
  vtkCellData* cd = out->GetCellData();
  std::vector<double> H, k1, k2, inward;
  for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
  {
    const V3 d = centres[c] - mid;
    if (d.norm() > R + 2)
    {
      continue; // the block's outer faces
    }
    H.push_back(cd->GetArray("IIMeanCurvature")->GetTuple1(c) * R);
    k1.push_back(cd->GetArray("IIK1")->GetTuple1(c) * R);
    k2.push_back(cd->GetArray("IIK2")->GetTuple1(c) * R);
    inward.push_back(-Tuple(cd->GetArray("IINormals"), c).dot(d.normalized()));
  }
  const double mH = Percentile(H, 0.5), m1 = Percentile(k1, 0.5), m2 = Percentile(k2, 0.5);
  std::printf("spherical cavity R=%.0f, r=6, %zu surfels: median H*R %.3f  k1*R %.3f  k2*R %.3f; "
              "smallest cos(normal, towards the centre) %.3f\n",
    R,
    H.size(),
    mH,
    m1,
    m2,
    *std::min_element(inward.begin(), inward.end()));
  EXPECT_GT(H.size(), 5000u);
  EXPECT_NEAR(mH, -1.0, 0.1);
  EXPECT_NEAR(0.5 * (m1 + m2), -1.0, 0.1);
  EXPECT_LT(m1, 0.0);
  EXPECT_GT(*std::min_element(inward.begin(), inward.end()), 0.9);
}

//------------------------------------------------------------------------------
TEST(IIEstimator, CurvatureSignsOnTorus)
{
  // A torus (axis z, tube radius a around a circle of radius Rt): at the angle
  // phi around the tube (0 on the outer equator) the curvature across the
  // tube is 1/a and along the circle cos(phi) / (Rt + a cos(phi)), negative on
  // the inner half: the saddle points that spheres and cylinders never test.
  const int n = 88;
  const double Rt = 26, a = 12;
  const V3 mid(43.6, 44.2, 43.9);
  auto image = dgtest::MakeImage(n,
    n,
    n,
    [&](int i, int j, int k)
    {
      const V3 d = V3(i, j, k) - mid;
      return std::hypot(std::hypot(d.x(), d.y()) - Rt, d.z()) <= a ? 1.0 : 0.0;
    });
  // r = 4 is printed for comparison: per surfel its curvatures are too noisy
  // for signs (a centre 0.3 voxel off the surface moves H by 4 * 0.3 / r^2).
  for (double r : { 4.0, 6.0 })
  {
    auto out = Estimate(image, r, true);
    const auto centres = dgtest::SurfelCenters(out);
    vtkCellData* cd = out->GetCellData();
    std::vector<double> e1, e2, eH, abs2, azimuth1, azimuth2;
    int saddles = 0, saddlesFound = 0, elliptic = 0, ellipticFound = 0;
    for (vtkIdType c = 0; c < out->GetNumberOfCells(); ++c)
    {
      const V3 d = centres[c] - mid;
      const double rho = std::hypot(d.x(), d.y());
      const double cosPhi = (rho - Rt) / std::hypot(rho - Rt, d.z());
      const double t1 = 1 / a, t2 = cosPhi / (Rt + a * cosPhi);
      const V3 around = V3(-d.y(), d.x(), 0) / rho;
      const double k1 = cd->GetArray("IIK1")->GetTuple1(c);
      const double k2 = cd->GetArray("IIK2")->GetTuple1(c);
      const double K = cd->GetArray("IIGaussianCurvature")->GetTuple1(c);
      e1.push_back((k1 - t1) * a);
      e2.push_back((k2 - t2) * a);
      abs2.push_back(std::abs(k2 - t2) * a);
      eH.push_back((cd->GetArray("IIMeanCurvature")->GetTuple1(c) - 0.5 * (t1 + t2)) * a);
      azimuth1.push_back(std::abs(Tuple(cd->GetArray("IIK1Direction"), c).dot(around)));
      azimuth2.push_back(std::abs(Tuple(cd->GetArray("IIK2Direction"), c).dot(around)));
      // Signs where K = t1 t2 is clearly away from 0.
      if (t2 < -0.5 / (Rt - a))
      {
        ++saddles;
        saddlesFound += K < 0;
      }
      else if (t2 > 0.5 / (Rt + a))
      {
        ++elliptic;
        ellipticFound += K > 0;
      }
    }
    const double m1 = Percentile(e1, 0.5), m2 = Percentile(e2, 0.5), mH = Percentile(eH, 0.5);
    const double az1 = Percentile(azimuth1, 0.5), az2 = Percentile(azimuth2, 0.5);
    std::printf("torus Rt=%.0f a=%.0f, r=%.0f, %zu surfels: median (k1 - true)*a %.3f  (k2 - "
                "true)*a %.3f (|.| %.3f)  (H - true)*a %.3f; median |d1.azimuth| %.3f  "
                "|d2.azimuth| %.3f; K < 0 on %d of %d saddle surfels, K > 0 on %d of %d "
                "elliptic ones\n",
      Rt,
      a,
      r,
      e1.size(),
      m1,
      m2,
      Percentile(abs2, 0.5),
      mH,
      az1,
      az2,
      saddlesFound,
      saddles,
      ellipticFound,
      elliptic);
    ASSERT_GT(saddles, 2000);
    ASSERT_GT(elliptic, 5000);
    if (r < 5)
    {
      continue;
    }
    // Measured at r = 6: -0.065, 0.003, -0.018; 0.050, 0.999; 100% and 88%.
    EXPECT_LT(std::abs(m1), 0.09);
    EXPECT_LT(std::abs(m2), 0.03);
    EXPECT_LT(std::abs(mH), 0.03);
    EXPECT_LT(az1, 0.07);
    EXPECT_GT(az2, 0.99);
    EXPECT_GE(saddlesFound, 0.98 * saddles);
    EXPECT_GE(ellipticFound, 0.85 * elliptic);
  }
}
