// The sharp-features stage (dgSharpFeatures, vtkSharpFeaturesFilter) and the
// program's whole default pipeline (dgPipeline) against ground truth:
// - the core on a folded sheet with an AT-like ladder band: one line on the
//   fold, exact side normals; a false band on a flat sheet gives no line;
//   a hole's wall cut into strips merges (quadric merges, crease test);
// - the filter's errors on bad input;
// - rotated cubes (two orientations), an octahedron and cube-sphere at 64^3
//   and 128^3, noise k = 0, 0.3, 0.5, two seeds, through the program's
//   defaults, with issue 15's metrics (dgFeatureMetrics.h);
// - sharp edges that end in fillets (issue 39), through the same defaults.
#include "dgFeatureMetrics.h"
#include "dgGroundTruth.h"
#include "dgPipeline.h"
#include "dgSharpFeatures.h"
#include "dgSharpFeaturesRegionFits.h"
#include "dgTestShapes.h"
#include "vtkSharpFeaturesFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

namespace
{
using V3 = Eigen::Vector3d;

// A sheet of nx x ny unit quads in x, y, folded down by `angle` degrees
// along x = fold (points past the fold turn about the y axis). Quads wind
// counter-clockwise seen from +z, so their normals point up on the flat part.
struct Sheet
{
  std::vector<double> Points;
  std::vector<std::int64_t> Offsets{ 0 }, Connectivity;
  std::vector<V3> TrueNormal;
  std::vector<double> FaceX; // x of the face centre before folding
  int NX, NY;
};

Sheet FoldedSheet(int nx, int ny, double fold, double angle)
{
  Sheet s;
  s.NX = nx;
  s.NY = ny;
  const double a = angle * M_PI / 180.0;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
    {
      const double x = i, t = x - fold;
      V3 p(x, j, 0);
      if (t > 0)
        p = V3(fold + t * std::cos(a), j, -t * std::sin(a));
      s.Points.insert(s.Points.end(), { p.x(), p.y(), p.z() });
    }
  const V3 down(std::sin(a), 0, std::cos(a));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const std::int64_t p0 = j * (nx + 1) + i;
      s.Connectivity.insert(s.Connectivity.end(), { p0, p0 + 1, p0 + nx + 2, p0 + nx + 1 });
      s.Offsets.push_back(static_cast<std::int64_t>(s.Connectivity.size()));
      s.FaceX.push_back(i + 0.5);
      s.TrueNormal.push_back(i + 0.5 < fold ? V3(0, 0, 1) : down);
    }
  return s;
}

// What AT leaves: the input estimator's normals blended across the fold over
// `blend` units, and v low on the vertices within `band` of the fold.
void ATLike(const Sheet& s, double fold, double blend, double band, std::vector<double>& g,
  std::vector<double>& v)
{
  g.clear();
  for (std::size_t f = 0; f < s.TrueNormal.size(); ++f)
  {
    const double w = std::clamp(0.5 + (s.FaceX[f] - fold) / (2 * blend), 0.0, 1.0);
    const V3 n = ((1 - w) * s.TrueNormal.front() + w * s.TrueNormal.back()).normalized();
    g.insert(g.end(), { n.x(), n.y(), n.z() });
  }
  v.assign(s.Points.size() / 3, 1.0);
  for (std::size_t p = 0; p < v.size(); ++p)
  {
    const double x = static_cast<double>(p % (s.NX + 1));
    if (std::abs(x - fold) <= band)
      v[p] = 0.05;
  }
}

TEST(SharpFeaturesCore, FoldGivesOneLineAndExactSideNormals)
{
  for (double angle : { 90.0, 40.0 })
  {
    const double fold = 15;
    Sheet s = FoldedSheet(30, 12, fold, angle);
    std::vector<double> g, v;
    ATLike(s, fold, 2.0, 2.0, g, v); // blended within the band, as AT leaves it
    dg::SharpFeatureResult r;
    std::string error;
    ASSERT_TRUE(dg::ComputeSharpFeatures(static_cast<std::int64_t>(v.size()), s.Points.data(),
      s.Offsets, s.Connectivity, g.data(), v.data(), nullptr, dg::SharpFeatureParameters(), r, &error))
      << error;
    EXPECT_EQ(r.NumberOfRegions, 2) << angle;
    // One line: the 12 edges of the fold, all on x = fold.
    ASSERT_EQ(r.FeatureEdges.size(), 12u) << angle;
    for (std::size_t l = 0; l < r.FeatureEdges.size(); ++l)
    {
      for (std::int64_t p : r.FeatureEdges[l])
        EXPECT_NEAR(s.Points[3 * p], fold, 1e-12);
      EXPECT_NEAR(r.FeatureAngle[l], angle, 1e-6);
    }
    // Every face, in the band too, has its own side's normal (the band's
    // input normals were blended by up to angle / 2).
    double worst = 0;
    for (std::size_t f = 0; f < s.TrueNormal.size(); ++f)
      worst = std::max(worst,
        dgtest::AngleDegrees(V3(r.Normals[3 * f], r.Normals[3 * f + 1], r.Normals[3 * f + 2]),
          s.TrueNormal[f]));
    EXPECT_LT(worst, 1e-6) << angle;
  }
}

TEST(SharpFeaturesCore, FalseBandOnAFlatSheetGivesNoLine)
{
  Sheet s = FoldedSheet(30, 12, 1e9, 0.0); // never folds
  std::vector<double> g(3 * s.TrueNormal.size()), v;
  for (std::size_t f = 0; f < s.TrueNormal.size(); ++f)
  {
    // Noisy input normals, a few degrees off.
    const double e = 0.05 * std::sin(1.7 * f);
    g[3 * f] = e;
    g[3 * f + 1] = -e;
    g[3 * f + 2] = 1;
  }
  v.assign(s.Points.size() / 3, 1.0);
  for (std::size_t p = 0; p < v.size(); ++p)
    if (std::abs(static_cast<double>(p % 31) - 15) <= 2)
      v[p] = 0.1; // a band across the sheet, splitting it in two
  // A closed loop around a bump inside the right half: a tiny region.
  for (int j = 4; j <= 8; ++j)
    for (int i = 22; i <= 26; ++i)
      if (j == 4 || j == 8 || i == 22 || i == 26)
        v[j * 31 + i] = 0.1;
  dg::SharpFeatureResult r;
  std::string error;
  ASSERT_TRUE(dg::ComputeSharpFeatures(static_cast<std::int64_t>(v.size()), s.Points.data(),
    s.Offsets, s.Connectivity, g.data(), v.data(), nullptr, dg::SharpFeatureParameters(), r, &error))
    << error;
  EXPECT_EQ(r.FeatureEdges.size(), 0u);
  EXPECT_EQ(r.NumberOfRegions, 1);
  EXPECT_GE(r.NumberOfDissolvedRegions, 1);
  EXPECT_EQ(r.NumberOfMergedBoundaries, 1);
}

// A zone of a sphere (radius 20, latitudes 30-150 degrees, 3-degree quads)
// where AT flattened a cap of 28 degrees' radius into a facet, as it does
// under noise: the cap's normals are all its axis, v is low on a ring around
// its rim. The cap's faces lie on the sphere: it merges across its jump (a
// medium one, between MinimumFeatureAngle and StrongFeatureAngle) on the
// quadric test (QuadricMergeFactor) and leaves no line; without the test,
// its rim stays a closed loop. A true facet (the cap cut flat) keeps its
// loop with the test.
TEST(SharpFeaturesCore, FlattenedCapOnASphereMergesOnTheQuadric)
{
  const double radius = 20, step = 3 * M_PI / 180, cap = 28 * M_PI / 180;
  const int rows = 40, columns = 120;
  const V3 axis(1, 0, 0);
  auto point = [&](int j, int i)
  {
    const double t = M_PI / 6 + j * step, p = (i % columns) * step;
    return V3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
  };
  // cut: the cap's points moved onto its plane, a true facet with a sharp
  // rim (28 degrees), whose faces lie up to 2.3 units inside the sphere.
  for (bool cut : { false, true })
  {
    std::vector<double> points, v;
    for (int j = 0; j <= rows; ++j)
      for (int i = 0; i < columns; ++i)
      {
        const V3 u = point(j, i);
        V3 x = radius * u;
        if (cut && u.dot(axis) > std::cos(cap))
          x -= (x.dot(axis) - radius * std::cos(cap)) * axis;
        points.insert(points.end(), { x.x(), x.y(), x.z() });
        const double angle = std::acos(std::clamp(u.dot(axis), -1.0, 1.0));
        v.push_back(std::abs(angle - cap) <= 3.5 * M_PI / 180 ? 0.05 : 1.0);
      }
    std::vector<std::int64_t> offsets{ 0 }, connectivity;
    std::vector<double> g;
    std::vector<V3> sphereNormal;
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < columns; ++i)
      {
        // (theta, phi) -> (theta + 1, phi) -> (theta + 1, phi + 1): outward.
        const std::int64_t a = j * columns + i, b = (j + 1) * columns + i,
                           c = (j + 1) * columns + (i + 1) % columns,
                           d = j * columns + (i + 1) % columns;
        connectivity.insert(connectivity.end(), { a, b, c, d });
        offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
        const V3 n =
          (point(j, i) + point(j + 1, i) + point(j + 1, i + 1) + point(j, i + 1)).normalized();
        const V3 m = std::acos(std::clamp(n.dot(axis), -1.0, 1.0)) < cap ? axis : n;
        g.insert(g.end(), { m.x(), m.y(), m.z() });
        sphereNormal.push_back(n);
      }
    // (quadric merge factor, minimum turn share): the stage's defaults, no
    // quadric merge, neither.
    const dg::SharpFeatureParameters defaults;
    const std::pair<double, double> settings[] = { { defaults.QuadricMergeFactor,
                                                     defaults.MinimumTurnShare },
      { 0.0, defaults.MinimumTurnShare }, { 0.0, 0.0 } };
    for (const auto& setting : settings)
    {
      const double factor = setting.first, turnShare = setting.second;
      dg::SharpFeatureParameters par;
      par.QuadricMergeFactor = factor;
      par.MinimumTurnShare = turnShare;
      dg::SharpFeatureResult r;
      std::string error;
      ASSERT_TRUE(dg::ComputeSharpFeatures(static_cast<std::int64_t>(v.size()),
        points.data(),
        offsets,
        connectivity,
        g.data(),
        v.data(), nullptr,
        par,
        r,
        &error))
        << error;
      EXPECT_GE(r.NumberOfQuadricRegions, 1) << factor;
      // The worst angle to the sphere's normal: the merged cap's faces take
      // the quadric's normal (what is left, 3-7 degrees, is on the band's
      // faces, whose side normals are local fits); unmerged, the cap keeps
      // the facet's normal, up to 28 degrees off.
      double worst = 0;
      for (std::size_t f = 0; f < sphereNormal.size(); ++f)
      {
        const double e = dgtest::AngleDegrees(
            V3(r.Normals[3 * f], r.Normals[3 * f + 1], r.Normals[3 * f + 2]), sphereNormal[f]);
        worst = std::max(worst, e);
      }
      if (factor > 0 && !cut)
      {
        EXPECT_EQ(r.NumberOfQuadricMerges, 1);
        EXPECT_EQ(r.NumberOfRegions, 1);
        EXPECT_EQ(r.FeatureEdges.size(), 0u);
        EXPECT_LT(worst, 8.0);
      }
      else if (!cut && turnShare > 0)
      {
        // Without the quadric merge the crease test still sees the faces
        // themselves turn smoothly across the cap's rim (a bend), however
        // flat the field.
        EXPECT_EQ(r.NumberOfQuadricMerges, 0);
        EXPECT_EQ(r.NumberOfRegions, 1);
        EXPECT_EQ(r.FeatureEdges.size(), 0u);
      }
      else if (!cut)
      {
        EXPECT_GT(worst, 15.0);
      }
      if (cut || (factor == 0 && turnShare == 0))
      {
        EXPECT_EQ(r.NumberOfQuadricMerges, 0) << cut;
        EXPECT_EQ(r.NumberOfRegions, 2) << cut;
        // A closed loop around the cap: 2 pi R sin(28) / 1.05 ~ 56 edges for
        // a smooth circle, a staircase on the quads up to 1.5 times that.
        EXPECT_GE(r.FeatureEdges.size(), 50u) << cut;
        EXPECT_LE(r.FeatureEdges.size(), 90u) << cut;
      }
    }
  }
}

// The wall of a cylindrical hole of radius 11.5 (the built-in shape's),
// half way round, 2.5-degree quads, which AT cut into nine strips of 20
// degrees: each strip's normals turn by 5.6 degrees across it (AT's all but
// constant facet normals; the extrapolated jumps are 15.2 degrees, medium),
// v is low on a band of four quads across each cut. Each strip's own quadric
// is nearly a plane, on which its neighbour does not lie (the rule before,
// one region's quadric, merged four cuts of eight); the quadric of the strips already
// merged follows the wall, and every cut merges: one region, no line.
// Without the quadric merges the eight cuts stay lines.
TEST(SharpFeaturesCore, HoleWallCutIntoStripsMergesOnTheMergedQuadric)
{
  const double radius = 11.5, step = 2.5 * M_PI / 180, strip = 20 * M_PI / 180;
  const int columns = 72, rows = 30; // 180 degrees, 30 units along the axis
  auto inward = [](double a) { return V3(-std::cos(a), -std::sin(a), 0); };
  std::vector<double> points, v;
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= columns; ++i)
    {
      const double a = i * step;
      points.insert(points.end(), { radius * std::cos(a), radius * std::sin(a), double(j) });
      const double cut = std::round(a / strip) * strip; // the nearest cut
      const bool interior = cut > 0.5 * strip && cut < M_PI - 0.5 * strip;
      v.push_back(interior && std::abs(a - cut) <= 2.6 * M_PI / 180 ? 0.05 : 1.0);
    }
  std::vector<std::int64_t> offsets{ 0 }, connectivity;
  std::vector<double> g;
  std::vector<V3> wallNormal;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i)
    {
      // Wound so that the normal points into the hole, towards the axis.
      const std::int64_t a = j * (columns + 1) + i, b = a + 1, c = a + columns + 2,
                         d = a + columns + 1;
      connectivity.insert(connectivity.end(), { a, d, c, b });
      offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
      const double mid = (i + 0.5) * step, middle = (std::floor(mid / strip) + 0.5) * strip;
      const V3 m = inward(middle + 0.28 * (mid - middle));
      g.insert(g.end(), { m.x(), m.y(), m.z() });
      wallNormal.push_back(inward(mid));
    }
  for (double factor : { dg::SharpFeatureParameters().QuadricMergeFactor, 0.0 })
  {
    dg::SharpFeatureParameters par;
    par.QuadricMergeFactor = factor;
    dg::SharpFeatureResult r;
    std::string error;
    ASSERT_TRUE(dg::ComputeSharpFeatures(static_cast<std::int64_t>(v.size()), points.data(),
      offsets, connectivity, g.data(), v.data(), nullptr, par, r, &error))
      << error;
    double worst = 0, mean = 0;
    for (std::size_t f = 0; f < wallNormal.size(); ++f)
    {
      const double e = dgtest::AngleDegrees(
        V3(r.Normals[3 * f], r.Normals[3 * f + 1], r.Normals[3 * f + 2]), wallNormal[f]);
      worst = std::max(worst, e);
      mean += e / static_cast<double>(wallNormal.size());
    }
    std::printf("hole wall, QuadricMergeFactor %g: %d regions, %d quadric merges, %zu feature "
                "edges, normal error mean %.2f worst %.2f deg\n",
      factor, r.NumberOfRegions, r.NumberOfQuadricMerges, r.FeatureEdges.size(), mean, worst);
    if (factor > 0)
    {
      EXPECT_EQ(r.NumberOfRegions, 1);
      EXPECT_EQ(r.NumberOfQuadricMerges, 8);
      EXPECT_EQ(r.FeatureEdges.size(), 0u);
      // The merged faces take the quadric's normal, which leans on AT's
      // facet normals (measured: mean 4.6, worst 15.7 degrees; the strips'
      // own 3.7 and 7.0).
      EXPECT_LT(mean, 6.0);
      EXPECT_LT(worst, 20.0);
    }
    else
    {
      // Without the quadric merges the crease test (step 7) merges the
      // eight cuts: beyond 0.75 InputRadius from each cut the strips'
      // normals, fitted and extrapolated, agree across it (before that
      // test: 9 regions and 8 * rows line edges, one line per cut).
      EXPECT_EQ(r.NumberOfRegions, 1);
      EXPECT_EQ(r.NumberOfBends, 8);
      EXPECT_EQ(r.FeatureEdges.size(), 0u);
    }
  }
}

// The whole-region quadric (QuadricSides) against brute force: faces
// sampled on a sphere and on a tilted cylinder with their exact normals.
// Q / |grad Q| is the first-order distance: on a sphere of radius R it is
// (rho^2 - R^2) / 2 rho at distance rho from the centre, which the fit must
// give to rounding; signs follow the normals (a cavity flips them).
TEST(SharpFeaturesCore, RegionQuadricsFitSpheresAndCylinders)
{
  const V3 centre(3.2, -2.1, 5.3), axis = V3(1, 2, 2).normalized();
  const double R = 20;
  auto sample = [&](bool cylinder, double sign, std::vector<dg::sharp::Vec3>& pos,
                  std::vector<dg::sharp::Vec3>& nrm) {
    pos.clear();
    nrm.clear();
    const V3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
    for (int i = 0; i < 40; ++i)
      for (int j = 0; j < 40; ++j)
      {
        const double a = 2 * M_PI * i / 40.0, t = -0.6 + 1.2 * j / 39.0;
        V3 n, p;
        if (cylinder)
        {
          n = std::cos(a) * e1 + std::sin(a) * e2;
          p = centre + R * n + 15.0 * t * axis;
        }
        else
        {
          n = std::cos(t * 2) * (std::cos(a) * e1 + std::sin(a) * e2) + std::sin(t * 2) * axis;
          p = centre + R * n;
        }
        pos.push_back({ p.x(), p.y(), p.z() });
        n *= sign;
        nrm.push_back({ n.x(), n.y(), n.z() });
      }
  };
  for (bool cylinder : { false, true })
    for (double sign : { 1.0, -1.0 })
    {
      std::vector<dg::sharp::Vec3> pos, nrm;
      sample(cylinder, sign, pos, nrm);
      const std::vector<int> region(pos.size(), 0);
      const auto q = dg::sharp::FitRegionQuadrics(region, 1, pos, nrm, { 0 }, 30, 10.0, 1.0);
      ASSERT_TRUE(q[0].Valid) << cylinder << sign;
      double worst = 0;
      for (std::size_t f = 0; f < pos.size(); f += 7)
        for (double d : { -1.0, 0.0, 0.5, 2.0 })
        {
          const V3 p(pos[f].x, pos[f].y, pos[f].z), n(nrm[f].x, nrm[f].y, nrm[f].z);
          const V3 x = p + d * n; // d along the normal: outside when sign = 1
          V3 radial = x - centre;
          if (cylinder)
            radial -= axis * axis.dot(radial);
          const double rho = radial.norm();
          const double expected = sign * (rho * rho - R * R) / (2 * rho);
          worst = std::max(worst, std::abs(q[0].Distance({ x.x(), x.y(), x.z() }) - expected));
        }
      EXPECT_LT(worst, 1e-6) << "cylinder " << cylinder << " sign " << sign;
    }
  // Regions that are skipped (planar), too small or too short get none.
  std::vector<dg::sharp::Vec3> pos, nrm;
  sample(false, 1.0, pos, nrm);
  const std::vector<int> region(pos.size(), 0);
  EXPECT_FALSE(dg::sharp::FitRegionQuadrics(region, 1, pos, nrm, { 1 }, 30, 10.0, 1.0)[0].Valid);
  EXPECT_FALSE(
    dg::sharp::FitRegionQuadrics(region, 1, pos, nrm, { 0 }, 2000, 10.0, 1.0)[0].Valid);
  EXPECT_FALSE(dg::sharp::FitRegionQuadrics(region, 1, pos, nrm, { 0 }, 30, 30.0, 1.0)[0].Valid);
}

TEST(SharpFeaturesCore, RejectsInconsistentInput)
{
  Sheet s = FoldedSheet(4, 4, 2, 90);
  std::vector<double> g, v;
  ATLike(s, 2, 1, 1, g, v);
  dg::SharpFeatureResult r;
  std::string error;
  std::vector<std::int64_t> bad = s.Connectivity;
  bad[3] = 1000;
  EXPECT_FALSE(dg::ComputeSharpFeatures(static_cast<std::int64_t>(v.size()), s.Points.data(),
    s.Offsets, bad, g.data(), v.data(), nullptr, dg::SharpFeatureParameters(), r, &error));
  EXPECT_NE(error.find("point"), std::string::npos) << error;
  dg::SharpFeatureParameters p;
  p.MinimumRegionSize = 0;
  EXPECT_FALSE(dg::ComputeSharpFeatures(static_cast<std::int64_t>(v.size()), s.Points.data(),
    s.Offsets, s.Connectivity, g.data(), v.data(), nullptr, p, r, &error));
}

// The core's sheet as a vtkPolyData with AT's arrays.
vtkSmartPointer<vtkPolyData> SheetPolyData(const Sheet& s, const std::vector<double>& g,
  const std::vector<double>& v)
{
  vtkNew<vtkPoints> pts;
  for (std::size_t p = 0; p < s.Points.size() / 3; ++p)
    pts->InsertNextPoint(&s.Points[3 * p]);
  vtkNew<vtkCellArray> polys;
  for (std::size_t f = 0; f + 1 < s.Offsets.size(); ++f)
  {
    vtkIdType ids[4];
    for (int k = 0; k < 4; ++k)
      ids[k] = s.Connectivity[s.Offsets[f] + k];
    polys->InsertNextCell(4, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  vtkNew<vtkDoubleArray> n;
  n->SetName("ATNormals");
  n->SetNumberOfComponents(3);
  for (std::size_t f = 0; f < g.size() / 3; ++f)
    n->InsertNextTuple(&g[3 * f]);
  pd->GetCellData()->AddArray(n);
  vtkNew<vtkDoubleArray> va;
  va->SetName("ATFeatureIndicator");
  for (double x : v)
    va->InsertNextValue(x);
  pd->GetPointData()->AddArray(va);
  return pd;
}

TEST(SharpFeaturesFilter, OutputsAndBadInput)
{
  Sheet s = FoldedSheet(20, 6, 10, 90);
  std::vector<double> g, v;
  ATLike(s, 10, 3, 2, g, v);
  auto pd = SheetPolyData(s, g, v);
  vtkNew<vtkSharpFeaturesFilter> f;
  f->SetInputData(pd);
  f->Update();
  vtkPolyData* out = f->GetOutput(0);
  ASSERT_NE(out->GetCellData()->GetNormals(), nullptr);
  EXPECT_STREQ(out->GetCellData()->GetNormals()->GetName(), "SharpNormals");
  EXPECT_NE(out->GetCellData()->GetArray("ATNormals"), nullptr) << "input arrays are kept";
  EXPECT_NE(out->GetCellData()->GetArray("FeatureRegion"), nullptr);
  EXPECT_EQ(f->GetOutput(1)->GetNumberOfLines(), 6);
  EXPECT_EQ(f->GetNumberOfRegions(), 2);
  ASSERT_NE(f->GetOutput(1)->GetCellData()->GetArray("FeatureAngle"), nullptr);
  EXPECT_NEAR(f->GetOutput(1)->GetCellData()->GetArray("FeatureAngle")->GetTuple1(0), 90, 1e-6);

  auto expectFailure = [&](vtkPolyData* input, const char* what, auto&& configure) {
    vtkNew<vtkSharpFeaturesFilter> bad;
    vtkNew<dgtest::ErrorObserver> obs;
    obs->Observe(bad);
    bad->SetInputData(input);
    configure(bad.Get());
    bad->Update();
    EXPECT_GE(obs->Errors, 1) << what;
    EXPECT_NE(obs->Messages.find(what), std::string::npos) << obs->Messages;
    EXPECT_EQ(bad->GetOutput(0)->GetNumberOfCells(), 0) << what;
    EXPECT_EQ(bad->GetOutput(1)->GetNumberOfCells(), 0) << what;
  };
  expectFailure(pd, "PlanarRegionAngle", [](vtkSharpFeaturesFilter* b) { b->SetPlanarRegionAngle(-1); });
  auto none = [](vtkSharpFeaturesFilter*) {};
  vtkNew<vtkPolyData> empty;
  expectFailure(empty, "no polygons", none);
  auto noV = SheetPolyData(s, g, v);
  noV->GetPointData()->RemoveArray("ATFeatureIndicator");
  expectFailure(noV, "ATFeatureIndicator", none);
  auto noN = SheetPolyData(s, g, v);
  noN->GetCellData()->RemoveArray("ATNormals");
  expectFailure(noN, "ATNormals", none);
  expectFailure(pd, "MinimumRegionSize", [](vtkSharpFeaturesFilter* b) { b->SetMinimumRegionSize(0); });
  expectFailure(pd, "FeatureThreshold", [](vtkSharpFeaturesFilter* b) { b->SetFeatureThreshold(1.5); });
  expectFailure(pd, "StrongFeatureAngle", [](vtkSharpFeaturesFilter* b) { b->SetStrongFeatureAngle(200); });
  expectFailure(pd, "QuadricMergeFactor", [](vtkSharpFeaturesFilter* b) { b->SetQuadricMergeFactor(-1); });
  expectFailure(pd, "QuadricMergeDistance", [](vtkSharpFeaturesFilter* b) { b->SetQuadricMergeDistance(-1); });
  expectFailure(pd, "InputRadius", [](vtkSharpFeaturesFilter* b) { b->SetInputRadius(0); });
  expectFailure(pd, "CornerDepth", [](vtkSharpFeaturesFilter* b) { b->SetCornerDepth(-1); });
  expectFailure(pd, "InputNormalsName", [](vtkSharpFeaturesFilter* b) { b->SetInputNormalsName("NoSuchNormals"); });
  auto nan = SheetPolyData(s, g, v);
  nan->GetCellData()->GetArray("ATNormals")->SetComponent(3, 0, NAN);
  expectFailure(nan, "NaN", none);
}

// --- the program's default pipeline on ground-truth shapes -----------------

std::unique_ptr<dgtest::ImplicitShape> Shape(const std::string& name, int n)
{
  // The quality benchmark's shapes (off the grid's symmetry).
  const V3 c = V3::Constant(0.5 * (n - 1)) + V3(0.13, 0.07, 0.11);
  if (name == "cube")
    return dgtest::MakeRotatedCube(c, 0.26 * n, 20, 30, 10);
  if (name == "cube2")
    return dgtest::MakeRotatedCube(c, 0.26 * n, 35, 10, 50);
  if (name == "octahedron")
    return dgtest::MakeOctahedron(c, 0.42 * n);
  return dgtest::MakeCubeSphere(c, 0.3 * n, 0.38 * n);
}

struct PipelineRun
{
  dgtest::FeatureMetrics Sharp, Plain, Input; // Input: the input normals with the stage's lines
  int PlanarRegions = 0;
  int QuadricRegions = 0;
};

PipelineRun RunProgramDefaults(const dgtest::ImplicitShape& shape, int n, double k, int seed)
{
  auto image = dgtest::NoisyDigitize(shape, n, k, static_cast<std::uint64_t>(seed));
  dg::Pipeline p;
  p.Build(image, dg::PipelineSettings());
  p.Stages.back().Algorithm->Update();
  PipelineRun r;
  r.Sharp = dgtest::MeasureFeatures(shape, p.Result(), p.NormalsName(), p.Features());
  r.Plain = dgtest::MeasureFeatures(shape, p.AT->GetOutput(0), "ATNormals", p.AT->GetOutput(1));
  r.Input = dgtest::MeasureFeatures(shape, p.Result(), p.InputNormalsName(), p.Features());
  r.PlanarRegions = p.Sharp->GetNumberOfPlanarRegions();
  r.QuadricRegions = p.Sharp->GetNumberOfQuadricRegions();
  return r;
}

class ProgramDefaults : public ::testing::TestWithParam<std::tuple<std::string, int>>
{
};

TEST_P(ProgramDefaults, FeaturesAndNormalsOnGroundTruth)
{
  const std::string name = std::get<0>(GetParam());
  const int n = std::get<1>(GetParam());
  auto shape = Shape(name, n);
  // cube-sphere's 38-degree circles are the hardest edges here; issue 15's
  // targets are not all met on them (docs/sharp-features.md): where one is
  // missed the bound is the worst measured figure (64^3 and 128^3, both
  // seeds) with a margin (0.06 voxel, 0.03 in P and R, 1.35 degrees within
  // one voxel, 0.5 degree for the mean), and says so; where one is met the
  // target itself is asserted.
  const bool cs = name == "cubesphere";

  const PipelineRun clean = RunProgramDefaults(*shape, n, 0.0, 1);
  std::printf("%s %d k 0   sharp %s\n%s %d k 0   plain %s\n", name.c_str(), n,
    clean.Sharp.Describe().c_str(), name.c_str(), n, clean.Plain.Describe().c_str());
  const auto& c = clean.Sharp;
  EXPECT_LE(c.Multiplicity, 2.0);
  EXPECT_LE(c.Offset, cs ? 0.70 : 0.5);    // cube-sphere measured 0.45-0.64
  EXPECT_GE(c.Precision, 0.97);
  EXPECT_GE(c.Recall, 0.97);
  EXPECT_LE(c.Error1, cs ? 14.0 : 8.0);    // cube-sphere measured 9.0-11.9
  EXPECT_LE(c.MeanError, 3.0);
  // The flat faces are found flat (PlanarRegionAngle), the sphere is not.
  EXPECT_EQ(clean.PlanarRegions, name == "octahedron" ? 8 : 6);
  // Only curved regions get a quadric (QuadricSides); at 128^3 the sphere
  // reaches beyond three searches.
  if (!cs)
  {
    EXPECT_EQ(clean.QuadricRegions, 0);
  }
  else if (n == 128)
  {
    EXPECT_GE(clean.QuadricRegions, 1);
  }
  // What the stage is for: fewer, better placed lines than AT's ladders.
  EXPECT_LT(c.Multiplicity, clean.Plain.Multiplicity);
  if (!cs)
  {
    EXPECT_LE(c.Error1, clean.Plain.Error1 + 1.0);
  }

  for (int seed : { 1, 2 })
  {
    const PipelineRun noisy = RunProgramDefaults(*shape, n, 0.3, seed);
    std::printf("%s %d k 0.3 s %d sharp %s\n%s %d k 0.3 s %d plain %s\n", name.c_str(), n, seed,
      noisy.Sharp.Describe().c_str(), name.c_str(), n, seed, noisy.Plain.Describe().c_str());
    const auto& m = noisy.Sharp;
    EXPECT_LE(m.Multiplicity, 2.5) << seed;
    EXPECT_GE(m.Precision, 0.85) << seed; // cube-sphere measured 0.852-0.877
    EXPECT_GE(m.Recall, 0.95) << seed;
    EXPECT_LE(m.MeanError, 6.0) << seed;
    EXPECT_LE(m.Error3, 12.0) << seed;
    EXPECT_GT(m.Precision, noisy.Plain.Precision - 0.02) << seed;

    // k = 0.5 has no target in the issue: the stage must not be worse than
    // AT's own output where it matters.
    const PipelineRun heavy = RunProgramDefaults(*shape, n, 0.5, seed);
    std::printf("%s %d k 0.5 s %d sharp %s\n%s %d k 0.5 s %d plain %s\n", name.c_str(), n, seed,
      heavy.Sharp.Describe().c_str(), name.c_str(), n, seed, heavy.Plain.Describe().c_str());
    EXPECT_LT(heavy.Sharp.Multiplicity, heavy.Plain.Multiplicity) << seed;
    EXPECT_LE(heavy.Sharp.MeanError, heavy.Plain.MeanError + 0.5) << seed;
    // No chain of weak merges erases a strong edge (StrongFeatureAngle):
    // measured 0.62-0.99 (cube-sphere 128^3 seed 2 the lowest, where the
    // noisy local convexity test lets one circle go); cube-sphere 128^3
    // gave 0.19-0.20 without it.
    EXPECT_GE(heavy.Sharp.Recall, 0.55) << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, ProgramDefaults,
  ::testing::Combine(::testing::Values("cube", "cube2", "octahedron", "cubesphere"),
    ::testing::Values(64, 128)),
  [](const auto& info) {
    return std::get<0>(info.param) + std::to_string(std::get<1>(info.param));
  });

// Issue 39, the other way round: sharp edges that end in fillets, as on a
// machined part. A rotated box whose four edges along its z axis are sharp
// and whose eight other edges are rounded with radius 6 voxels
// (MakeMixedBox). Each sharp edge's two sides merge with the fillets at its
// ends, so the line between them also runs along fillets: judged whole it
// is a bend, and before the crease test judged stretches the program drew
// no line there and blurred the four edges. 64^3 and 128^3, clean and at
// k = 0.3 (two seeds); the bounds are the measured figures with a margin
// (docs/sharp-features.md, step 7).
class MixedEdges : public ::testing::TestWithParam<std::tuple<int, double, int>>
{
};

TEST_P(MixedEdges, SharpEdgesIntoFilletsAreKept)
{
  const int n = std::get<0>(GetParam());
  const double k = std::get<1>(GetParam());
  const int seed = std::get<2>(GetParam());
  const V3 c = V3::Constant(0.5 * (n - 1)) + V3(0.13, 0.07, 0.11);
  const auto shape = dgtest::MakeMixedBox(c, V3(0.3, 0.22, 0.18) * n, 6, 20, 30, 10);
  const PipelineRun run = RunProgramDefaults(*shape, n, k, seed);
  const dgtest::FeatureMetrics& out = run.Sharp;
  std::printf("mixed6 %d^3 k %.1f seed %d: %s; II within 1 voxel of the edges %.2f\n", n, k, seed,
    out.Describe().c_str(), run.Input.Error1);
  if (k == 0)
  {
    // Measured: recall 1.000 / 0.998, precision 0.918 / 1.000 (the rest
    // runs on along the corners' fading creases), within 1 voxel of the
    // edges 0.76 / 0.36 of II's error (before: no line, 1.08 / 1.06).
    EXPECT_GE(out.Recall, 0.95);
    EXPECT_GE(out.Precision, 0.85);
    EXPECT_LT(out.Error1, 0.85 * run.Input.Error1);
  }
  else
  {
    // Measured: recall 0.69 / 0.50 at 64^3 (seeds 1 / 2; before 0.50 /
    // 0.50), where the edges run 11 voxels between the fillets, and 0.998
    // at 128^3.
    EXPECT_GE(out.Recall, n >= 128 ? 0.95 : 0.45);
    EXPECT_LT(out.Error1, run.Input.Error1);
  }
}

INSTANTIATE_TEST_SUITE_P(Defaults, MixedEdges,
  ::testing::Values(std::make_tuple(64, 0.0, 1), std::make_tuple(128, 0.0, 1),
    std::make_tuple(64, 0.3, 1), std::make_tuple(64, 0.3, 2), std::make_tuple(128, 0.3, 1),
    std::make_tuple(128, 0.3, 2)));

} // namespace
