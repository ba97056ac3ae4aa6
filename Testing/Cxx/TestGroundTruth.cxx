// The ground truth used by the other tests and the benchmarks is computed,
// not assumed: check its normals and sharp edges at hand-computed points.
#include "dgGroundTruth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using Eigen::Vector3d;
using namespace dgtest;

namespace
{
void ExpectVec(const Vector3d& a, const Vector3d& b, double tol = 1e-9)
{
  EXPECT_NEAR((a - b).norm(), 0.0, tol) << a.transpose() << " vs " << b.transpose();
}

// The rotation of the rotated test shapes, (20, 30, 10) degrees, R = Rz Ry Rx.
Eigen::Matrix3d TestRotation()
{
  const double d = M_PI / 180;
  return (Eigen::AngleAxisd(10 * d, Vector3d::UnitZ()) * Eigen::AngleAxisd(30 * d, Vector3d::UnitY()) *
    Eigen::AngleAxisd(20 * d, Vector3d::UnitX()))
    .toRotationMatrix();
}
} // namespace

TEST(GroundTruth, Sphere)
{
  const Vector3d c(10, 11, 12);
  auto s = MakeSphere(c, 5);
  EXPECT_TRUE(s->Inside(c));
  EXPECT_FALSE(s->Inside(c + Vector3d(5.01, 0, 0)));
  ExpectVec(s->Normal(c + Vector3d(0, 0, 4.9)), Vector3d(0, 0, 1));
  ExpectVec(s->Normal(c + Vector3d(3, -4, 0)), Vector3d(0.6, -0.8, 0));
  EXPECT_TRUE(std::isinf(s->DistanceToSharpEdge(c)));
}

TEST(GroundTruth, AxisAlignedAndRotatedCube)
{
  const Vector3d c(20, 20, 20);
  auto cube = MakeRotatedCube(c, 8, 0, 0, 0);
  ExpectVec(cube->Normal(c + Vector3d(7.9, 1, -2)), Vector3d(1, 0, 0));
  ExpectVec(cube->Normal(c + Vector3d(1, -8.2, 3)), Vector3d(0, -1, 0));
  EXPECT_NEAR(cube->DistanceToSharpEdge(c + Vector3d(8, 8, 3)), 0.0, 1e-9);
  EXPECT_NEAR(cube->DistanceToSharpEdge(c + Vector3d(8, 5, 0)), 3.0, 1e-9);
  EXPECT_NEAR(cube->SharpEdges().TotalLength(), 12 * 16.0, 1e-6);
  EXPECT_EQ(cube->EdgePolylines.size(), 12u);

  // Rotated by (20, 30, 10) degrees: the face normals are R's columns, the
  // corners R (+-h, +-h, +-h), and the edges still total 12 * 2h.
  auto rc = MakeRotatedCube(c, 8, 20, 30, 10);
  const Eigen::Matrix3d R = TestRotation();
  ExpectVec(rc->Normal(c + R * Vector3d(0.5, 0.2, 7.9)), R.col(2));
  ExpectVec(rc->Normal(c + R * Vector3d(-8.1, 0.2, 1)), -R.col(0));
  EXPECT_NEAR(rc->DistanceToSharpEdge(c + R * Vector3d(8, -8, 8)), 0.0, 1e-9);
  EXPECT_NEAR(rc->DistanceToSharpEdge(c + R * Vector3d(8, 0, 0)), 8.0, 1e-9);
  EXPECT_NEAR(rc->DistanceToSharpEdge(c + R * Vector3d(8, 6, 2)), 2.0, 1e-9);
  EXPECT_NEAR(rc->SharpEdges().TotalLength(), 12 * 16.0, 1e-6);
  EXPECT_TRUE(rc->Inside(c + R * Vector3d(7.9, 7.9, 7.9)));
  EXPECT_FALSE(rc->Inside(c + R * Vector3d(8.1, 0, 0)));
}

TEST(GroundTruth, CubeSphereHasSixCircularEdges)
{
  const Vector3d c(0, 0, 0);
  const double h = 10, r = 13;
  const double rho = std::sqrt(r * r - h * h);
  auto s = MakeCubeSphere(c, h, r);
  EXPECT_EQ(s->EdgePolylines.size(), 6u);
  EXPECT_NEAR(s->SharpEdges().TotalLength(), 6 * 2 * M_PI * rho, 0.01 * rho);
  EXPECT_NEAR(s->DistanceToSharpEdge(Vector3d(h, 0, rho)), 0.0, 0.01);
  EXPECT_NEAR(s->DistanceToSharpEdge(Vector3d(h, 0, 0)), rho, 0.01);
  ExpectVec(s->Normal(Vector3d(9.9, 1, 1)), Vector3d(1, 0, 0));
  // On the spherical part (beyond the circle) the normal is radial.
  const Vector3d p = Vector3d(8, 8, 3).normalized() * r;
  ExpectVec(s->Normal(p), p.normalized());
  // The cube's own edges lie outside the sphere: not features of the shape.
  EXPECT_GT(s->DistanceToSharpEdge(Vector3d(h, h, 0), 10.0), 1.0);
}

TEST(GroundTruth, CylinderOctahedronWedge)
{
  auto cyl = MakeCylinder(Vector3d(0, 0, 0), 6, 9);
  ExpectVec(cyl->Normal(Vector3d(2.97, 3.96, 0)), Vector3d(0.6, 0.8, 0));
  ExpectVec(cyl->Normal(Vector3d(1, 1, 8.95)), Vector3d(0, 0, 1));
  EXPECT_NEAR(cyl->DistanceToSharpEdge(Vector3d(0, 6, 9)), 0.0, 0.01);
  EXPECT_NEAR(cyl->DistanceToSharpEdge(Vector3d(0, 6, 0), 12.0), 9.0, 0.01);
  EXPECT_TRUE(std::isinf(cyl->DistanceToSharpEdge(Vector3d(0, 6, 0)))) << "beyond the default reach";
  EXPECT_NEAR(cyl->SharpEdges().TotalLength(), 2 * 2 * M_PI * 6, 0.05);

  const double a = 12;
  auto oct = MakeOctahedron(Vector3d(0, 0, 0), a);
  EXPECT_EQ(oct->EdgePolylines.size(), 12u);
  EXPECT_NEAR(oct->SharpEdges().TotalLength(), 12 * a * std::sqrt(2.0), 1e-6);
  ExpectVec(oct->Normal(Vector3d(a / 3, a / 3, a / 3)), Vector3d(1, 1, 1).normalized());
  ExpectVec(oct->Normal(Vector3d(-a / 3, a / 3, -a / 3)), Vector3d(-1, 1, -1).normalized());
  EXPECT_NEAR(oct->DistanceToSharpEdge(Vector3d(a, 0, 0)), 0.0, 1e-9);
  EXPECT_NEAR(oct->DistanceToSharpEdge(Vector3d(a / 3, a / 3, a / 3), 10), a / std::sqrt(6.0), 1e-9);

  const double h = 10, t = std::tan(15 * M_PI / 180);
  auto w = MakeWedge(Vector3d(0, 0, 0), h);
  EXPECT_NEAR(w->DistanceToSharpEdge(Vector3d(0, 3, h)), 0.0, 1e-9);
  ExpectVec(w->Normal(Vector3d(h / 2, 0, h - t * h / 2 - 0.01)), Vector3d(t, 0, 1).normalized());
  ExpectVec(w->Normal(Vector3d(-h / 2, 1, h - t * h / 2 - 0.01)), Vector3d(-t, 0, 1).normalized());
  // The ridge's dihedral angle is 150 degrees: the two roof normals are 30 apart.
  EXPECT_NEAR(AngleDegrees(Vector3d(t, 0, 1), Vector3d(-t, 0, 1)), 30.0, 1e-9);
  // Ridge (2h), the two eaves where a roof meets x = +-h (2h each), four
  // sloped roof/gable edges (h / cos 15), four bottom edges (2h) and four
  // vertical edges from z = -h to z = h - t h.
  const double roof = h / std::cos(15 * M_PI / 180);
  const double side = 2 * h - t * h;
  const double expected = 2 * h + 2 * (2 * h) + 4 * roof + 4 * (2 * h) + 4 * side;
  EXPECT_NEAR(w->SharpEdges().TotalLength(), expected, 1e-6);
}

TEST(GroundTruth, DigitizeAndSurfelCenters)
{
  auto s = MakeSphere(Vector3d(7.3, 7.1, 6.9), 4);
  auto image = Digitize(*s, 16);
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 16);
  EXPECT_EQ(image->GetScalarComponentAsDouble(7, 7, 7, 0), 1.0);
  EXPECT_EQ(image->GetScalarComponentAsDouble(0, 0, 0, 0), 0.0);
  EXPECT_EQ(image->GetScalarComponentAsDouble(11, 7, 7, 0), 1.0);  // 3.7 from the centre
  EXPECT_EQ(image->GetScalarComponentAsDouble(12, 7, 7, 0), 0.0);  // 4.7
}

// The rounded prisms (shallow fillets: the edges of an n-gon prism turn by
// 360 / n degrees): Value is the signed distance (so its gradient is the
// normal, of unit length, near the surface) and Normal agrees with it; the
// flat faces' normals and the fillet's width are the polygon's.
TEST(GroundTruth, MixedBoxHasItsNormalAndItsSharpEdges)
{
  // Half sides 19.2, 14.08, 11.52 (0.3, 0.22, 0.18 of 64), radius 6.
  const Vector3d c = Vector3d::Constant(31.5) + Vector3d(0.13, 0.07, 0.11);
  const Eigen::Matrix3d R = TestRotation();
  auto shape = MakeMixedBox(c, Vector3d(19.2, 14.08, 11.52), 6, 20, 30, 10);
  // Away from the sharp edges the value is a distance near the surface and
  // the normal its gradient.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> offset(-22, 22);
  int checked = 0;
  for (int i = 0; i < 4000 && checked < 400; ++i)
  {
    const Vector3d p = c + Vector3d(offset(rng), offset(rng), offset(rng));
    if (std::abs(shape->Value(p)) > 1.0 || shape->DistanceToSharpEdge(p) < 2.0)
      continue;
    const Vector3d l = R.transpose() * (p - c);
    // Near the corners' fading creases (both fillets within a voxel) the
    // gradient is the larger side's: left out like the edges.
    if (std::abs(std::abs(l.x()) - 19.2) < 8 && std::abs(std::abs(l.y()) - 14.08) < 8)
      continue;
    const double h = 1e-5;
    Vector3d g;
    for (int k = 0; k < 3; ++k)
      g[k] = (shape->Value(p + h * Vector3d::Unit(k)) - shape->Value(p - h * Vector3d::Unit(k))) / (2 * h);
    EXPECT_NEAR(g.norm(), 1.0, 1e-4) << p.transpose();
    ExpectVec(shape->Normal(p), g.normalized(), 1e-4);
    ++checked;
  }
  EXPECT_GE(checked, 100);
  // Four sharp edges along z, on the surface, 2 (11.52 - 6) long each; on
  // either side of one, the two faces' normals.
  ASSERT_EQ(shape->EdgePolylines.size(), 4u);
  EXPECT_NEAR(shape->SharpEdges().TotalLength(), 4 * 2 * (11.52 - 6), 1e-9);
  for (const Vector3d& p : shape->SharpEdgeSamples(0.5))
    EXPECT_NEAR(shape->Value(p), 0.0, 1e-9);
  ExpectVec(shape->Normal(c + R * Vector3d(19.2, 13, 1)), R.col(0));
  ExpectVec(shape->Normal(c + R * Vector3d(18, 14.08, 1)), R.col(1));
  // A rounded edge's middle (between the +x face and the +z face) and a
  // z face's middle.
  const double s = std::sqrt(0.5);
  const Vector3d mid(19.2 - 6 + 6 * s, 0, 11.52 - 6 + 6 * s);
  EXPECT_NEAR(shape->Value(c + R * mid), 0.0, 1e-9);
  ExpectVec(shape->Normal(c + R * mid), R * Vector3d(s, 0, s));
  EXPECT_NEAR(shape->Value(c + R * Vector3d(1, 2, 11.52)), 0.0, 1e-9);
  ExpectVec(shape->Normal(c + R * Vector3d(1, 2, 11.52)), R.col(2));
}

TEST(GroundTruth, RoundedPrismIsADistanceWithItsNormal)
{
  // MakeSmoothShape's centre at 64^3.
  const Vector3d c = Vector3d::Constant(31.5) + Vector3d(0.13, 0.07, 0.11);
  for (const char* name : { "prism6r6", "prism8r6", "prism12r10" })
  {
    auto shape = MakeSmoothShape(name, 64);
    ASSERT_NE(shape, nullptr) << name;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> offset(-26, 26);
    int checked = 0;
    for (int i = 0; i < 4000 && checked < 400; ++i)
    {
      const Vector3d p = c + Vector3d(offset(rng), offset(rng), offset(rng));
      if (std::abs(shape->Value(p)) > 1.5)
        continue;
      const double h = 1e-5;
      Vector3d g;
      for (int k = 0; k < 3; ++k)
        g[k] = (shape->Value(p + h * Vector3d::Unit(k)) - shape->Value(p - h * Vector3d::Unit(k))) / (2 * h);
      EXPECT_NEAR(g.norm(), 1.0, 1e-4) << name << " at " << p.transpose();
      ExpectVec(shape->Normal(p), g.normalized(), 1e-4);
      ++checked;
    }
    EXPECT_GE(checked, 100) << name;
  }
  // In the prism's own frame (the rotation undone): a hexagon of apothem
  // 0.3 n = 19.2 and half height 0.22 n = 14.08, rounded with 6. A face's
  // middle, a cap's and a rounded edge's lie on the surface with the
  // polygon's and the cap's normals.
  auto hex = MakeSmoothShape("prism6r6", 64);
  const Eigen::Matrix3d R = TestRotation();
  const double d = M_PI / 180;
  EXPECT_NEAR(hex->Value(c + R * Vector3d(19.2, 0, 0)), 0.0, 1e-9);
  EXPECT_NEAR(hex->Value(c + R * Vector3d(0, 0, 14.08)), 0.0, 1e-9);
  ExpectVec(hex->Normal(c + R * Vector3d(19.2, 1, 2)), R.col(0));
  ExpectVec(hex->Normal(c + R * Vector3d(1, 2, 14.08)), R.col(2));
  // The middle of the rounded edge between the faces at 0 and 60 degrees.
  const Vector3d mid(std::cos(30 * d), std::sin(30 * d), 0);
  const double toApex = (19.2 - 6) / std::cos(30 * d) + 6;
  EXPECT_NEAR(hex->Value(c + R * (toApex * mid)), 0.0, 1e-9);
  ExpectVec(hex->Normal(c + R * (toApex * mid)), R * mid);
}
