// Issue 37, vtkCorrectedCurvatureFilter through the program's pipeline
// (dg::Pipeline with Curvature: II -> AT -> sharp features -> curvature,
// every default) on ground truth: spheres and noisy spheres, a torus's
// principal curvatures and directions, Gauss-Bonnet and V - E + F on
// genus 0, 1 and 2, specific surface area, each side of a cube's and a
// cube-sphere's creases measured on its own, the creases' angles, and bad
// input.
#include "dgGroundTruth.h"
#include "dgTestShapes.h"
#include "dgPipeline.h"
#include "vtkCorrectedCurvatureFilter.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdList.h>
#include <vtkUnsignedCharArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <vector>

namespace
{
using V3 = Eigen::Vector3d;

double Median(std::vector<double> v)
{
  if (v.empty())
    return std::nan("");
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double Quantile(std::vector<double> v, double q)
{
  if (v.empty())
    return std::nan("");
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

double Field(vtkPolyData* pd, const char* name)
{
  vtkDataArray* a = pd->GetFieldData()->GetArray(name);
  EXPECT_NE(a, nullptr) << name;
  return a ? a->GetComponent(0, 0) : std::nan("");
}

V3 CellCentre(vtkPolyData* pd, vtkIdType c)
{
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  pd->GetCellPoints(c, n, ids);
  V3 s = V3::Zero();
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    pd->GetPoint(ids[i], p);
    s += V3(p[0], p[1], p[2]);
  }
  return s / static_cast<double>(n);
}

// The program's pipeline with --curvature, run to its end.
struct ProgramRun
{
  dg::Pipeline P;
  vtkPolyData* Surface = nullptr;
  vtkPolyData* Creases = nullptr;
  ProgramRun(const dgtest::ImplicitShape& shape, int n, double k = 0, int seed = 0)
  {
    auto image = k > 0 ? dgtest::NoisyDigitize(shape, n, k, static_cast<std::uint64_t>(seed))
                       : dgtest::Digitize(shape, n);
    dg::PipelineSettings s;
    s.Curvature = true;
    this->P.Build(image, s);
    this->P.Stages.back().Algorithm->Update();
    this->Surface = this->P.Result();
    this->Creases = this->P.Creases();
  }
  vtkDataArray* Array(const char* name) { return this->Surface->GetCellData()->GetArray(name); }
};

// Two tori side by side, overlapping: genus 2.
class TwoTori : public dgtest::ImplicitShape
{
public:
  TwoTori(const V3& c, double major, double minor, double gap)
    : A(dgtest::MakeTorus(c - V3(gap / 2, 0, 0), major, minor, 0, 0, 0))
    , B(dgtest::MakeTorus(c + V3(gap / 2, 0, 0), major, minor, 0, 0, 0))
  {
  }
  std::string Name() const override { return "two tori"; }
  double Value(const V3& p) const override { return std::min(A->Value(p), B->Value(p)); }
  V3 Normal(const V3& p) const override
  {
    return A->Value(p) < B->Value(p) ? A->Normal(p) : B->Normal(p);
  }

private:
  std::unique_ptr<dgtest::ImplicitShape> A, B;
};
// The box whose four sharp edges end in fillets: the sharp stage draws the
// edges and leaves undrawn the stretches of its region boundaries along the
// fillets. The creases reported are the drawn edges, and their integral of
// H is the sharp edges' (4 edges of length 2 (c - R) turning by pi / 2,
// halved) more closely than when every region boundary is a crease (the
// same surface without "CreaseSides").
TEST(CorrectedCurvatureFilter, MixedBoxCreasesAreTheDrawnEdges)
{
  const int n = 64;
  const double radius = 6;
  const V3 c = V3::Constant(0.5 * (n - 1)) + V3(0.13, 0.07, 0.11);
  const V3 half = V3(0.3, 0.22, 0.18) * n;
  auto shape = dgtest::MakeMixedBox(c, half, radius, 20, 30, 10);
  ProgramRun run(*shape, n);
  using Edge = std::pair<vtkIdType, vtkIdType>;
  auto edges = [](vtkPolyData* lines)
  {
    std::set<Edge> e;
    for (vtkIdType l = 0; l < lines->GetNumberOfCells(); ++l)
    {
      vtkNew<vtkIdList> ids;
      lines->GetCellPoints(l, ids);
      e.insert({ std::min(ids->GetId(0), ids->GetId(1)), std::max(ids->GetId(0), ids->GetId(1)) });
    }
    return e;
  };
  const std::set<Edge> drawn = edges(run.P.Features());
  EXPECT_EQ(edges(run.Creases), drawn);

  vtkNew<vtkPolyData> regionsOnly;
  regionsOnly->ShallowCopy(run.Surface);
  regionsOnly->GetCellData()->RemoveArray("CreaseSides");
  vtkNew<vtkCorrectedCurvatureFilter> byRegions;
  byRegions->SetInputData(regionsOnly);
  byRegions->Update();
  const double truth = 0.5 * 4 * 2 * (half.z() - radius) * M_PI / 2;
  const double withSides = Field(run.Surface, "CreaseIntegralMeanCurvature");
  const double withRegions = Field(byRegions->GetOutput(), "CreaseIntegralMeanCurvature");
  std::printf("mixed box 64, R 6: %zu drawn edges, %lld crease edges by regions; crease integral "
              "of H %.2f (by regions %.2f), the sharp edges' %.2f; integral of H %.2f (by regions "
              "%.2f)\n",
    drawn.size(), static_cast<long long>(byRegions->GetOutput(1)->GetNumberOfCells()), withSides,
    withRegions, truth, Field(run.Surface, "IntegralMeanCurvature"),
    Field(byRegions->GetOutput(), "IntegralMeanCurvature"));
  ASSERT_GT(byRegions->GetOutput(1)->GetNumberOfCells(), static_cast<vtkIdType>(drawn.size()));
  EXPECT_LT(std::abs(withSides - truth), std::abs(withRegions - truth));

  // Corners reordered after the sharp stage, the bits kept: an error and
  // empty outputs.
  vtkNew<vtkCorrectedCurvatureFilter> stale;
  stale->SetInputData(dgtest::ReversedKeepingCellData(run.Surface));
  std::string why;
  EXPECT_TRUE(dgtest::RefusedWith(stale, "crease sides do not match", &why)) << why;
}

} // namespace

// Spheres R = 10-50: median H R and K R^2 within 1 % of 1 (the issue's
// criterion), Gauss-Bonnet and V - E + F agree on 2, the specific surface
// area within 0.5 % of 3 / R (the voxel faces' own area is about 1.5 times
// the sphere's: that row is printed).
TEST(CorrectedCurvatureFilter, Spheres)
{
  for (double radius : { 10.0, 25.0, 50.0 })
  {
    const int n = static_cast<int>(2 * radius + 8);
    auto shape = dgtest::MakeSphere(V3(n / 2.0 + 0.3, n / 2.0 + 0.1, n / 2.0 + 0.2), radius);
    ProgramRun run(*shape, n);
    vtkDataArray* H = run.Array("CorrectedMeanCurvature");
    vtkDataArray* G = run.Array("CorrectedGaussianCurvature");
    ASSERT_NE(H, nullptr);
    ASSERT_NE(G, nullptr);
    std::vector<double> hr, gr;
    for (vtkIdType f = 0; f < H->GetNumberOfTuples(); ++f)
    {
      hr.push_back(H->GetComponent(f, 0) * radius);
      gr.push_back(G->GetComponent(f, 0) * radius * radius);
    }
    const double ssa = Field(run.Surface, "SpecificSurfaceArea");
    const double faces = static_cast<double>(run.Surface->GetNumberOfPolys());
    std::printf("sphere R %.0f: median H R %.4f, K R^2 %.4f; SSA %.5f of 3/R (voxel faces: %.3f); "
                "Gauss-Bonnet %.4f, V - E + F %.0f\n",
      radius, Median(hr), Median(gr), ssa * radius / 3,
      faces / Field(run.Surface, "EnclosedVolume") * radius / 3,
      Field(run.Surface, "GaussBonnetCharacteristic"), Field(run.Surface, "EulerCharacteristic"));
    EXPECT_NEAR(Median(hr), 1, 0.01) << radius;
    // K R^2: 0.9985 / 1.0078 / 1.0092 at R 10 / 25 / 50 with a ball radius
    // per face (medians 9.8 / 11.2 / 14.1 voxels); 1.0026 / 1.0148 / 1.0121
    // with one ball of 6, where the field's terraces on large clean spheres
    // skew the per-face distribution (with the true normals it is 1.0008,
    // TestCorrectedCurvature). The 1 %.
    EXPECT_NEAR(Median(gr), 1, 0.01) << radius;
    EXPECT_NEAR(ssa * radius / 3, 1, 0.005) << radius;
    EXPECT_NEAR(Field(run.Surface, "GaussBonnetCharacteristic"), 2, 0.01) << radius;
    EXPECT_EQ(Field(run.Surface, "EulerCharacteristic"), 2) << radius;
    EXPECT_EQ(run.Creases->GetNumberOfLines(), 0) << radius;
  }
}

// The paper's noise k = 0.3, two seeds: the median relative H error <= 5 %
// on spheres of radius 10-50 voxels.
TEST(CorrectedCurvatureFilter, NoisySpheres)
{
  for (double radius : { 10.0, 15.0, 25.0, 50.0 })
    for (int seed : { 1, 2 })
    {
      const int n = static_cast<int>(2 * radius + 10);
      auto shape = dgtest::MakeSphere(V3(n / 2.0 + 0.3, n / 2.0 + 0.1, n / 2.0 + 0.2), radius);
      ProgramRun run(*shape, n, 0.3, seed);
      vtkDataArray* H = run.Array("CorrectedMeanCurvature");
      ASSERT_NE(H, nullptr);
      std::vector<double> err;
      for (vtkIdType f = 0; f < H->GetNumberOfTuples(); ++f)
        err.push_back(std::abs(H->GetComponent(f, 0) * radius - 1));
      std::printf("noisy sphere R %.0f seed %d: median |H R - 1| %.4f, median H R %.4f\n", radius,
        seed, Median(err), Median([&] {
          std::vector<double> v;
          for (vtkIdType f = 0; f < H->GetNumberOfTuples(); ++f)
            v.push_back(H->GetComponent(f, 0) * radius);
          return v;
        }()));
      // With a ball radius per face: 0.7 / 0.5 / 1.1 / 2.7 % at R 10 / 15 /
      // 25 / 50 (the worse seed). One ball of 6 voxels gave 1.9 / 2.5 / 5.2
      // / 9.7 %: the absolute error, about 0.002 per voxel, does not grow
      // with R, so the relative error did (docs/curvature-measures.md).
      EXPECT_LE(Median(err), 0.05) << radius << " " << seed;
    }
}

// Torus (major 24, minor 10): k1 = 1/b across the tube on both equators,
// k2 = cos(theta) / (a + b cos(theta)): positive outside, negative inside;
// Gauss-Bonnet 0; the specific surface area 2 / b within 0.5 %.
TEST(CorrectedCurvatureFilter, TorusSignsDirectionsAndFigures)
{
  const double a = 24, b = 10;
  const int n = 80;
  const V3 c(n / 2.0 + 0.3, n / 2.0 + 0.2, n / 2.0 + 0.1);
  auto shape = dgtest::MakeTorus(c, a, b, 0, 0, 0);
  ProgramRun run(*shape, n);
  vtkDataArray* K1 = run.Array("CorrectedK1");
  vtkDataArray* K2 = run.Array("CorrectedK2");
  vtkDataArray* D1 = run.Array("CorrectedK1Direction");
  ASSERT_TRUE(K1 && K2 && D1);
  std::vector<double> outer1, outer2, inner1, inner2, outerDir, innerDir;
  for (vtkIdType f = 0; f < K1->GetNumberOfTuples(); ++f)
  {
    const V3 x = CellCentre(run.Surface, f) - c;
    if (std::abs(x.z()) > 1.0)
      continue;
    const double rho = std::hypot(x.x(), x.y());
    const V3 t = V3(-x.y(), x.x(), 0).normalized(); // along the equator
    const V3 d(D1->GetComponent(f, 0), D1->GetComponent(f, 1), D1->GetComponent(f, 2));
    if (std::abs(rho - (a + b)) < 1.0)
    {
      outer1.push_back(K1->GetComponent(f, 0) * b);
      outer2.push_back(K2->GetComponent(f, 0) * (a + b));
      outerDir.push_back(std::abs(d.dot(t)));
    }
    else if (std::abs(rho - (a - b)) < 1.0)
    {
      inner1.push_back(K1->GetComponent(f, 0) * b);
      inner2.push_back(K2->GetComponent(f, 0) * (a - b));
      innerDir.push_back(std::abs(d.dot(t)));
    }
  }
  const double ssa = Field(run.Surface, "SpecificSurfaceArea");
  std::printf("torus: outer k1 b %.3f, k2 (a+b) %.3f, |d1.t| %.3f; inner k1 b %.3f, k2 (a-b) %.3f, "
              "|d1.t| %.3f; SSA %.5f of 2/b; Gauss-Bonnet %.4f, V - E + F %.0f\n",
    Median(outer1), Median(outer2), Median(outerDir), Median(inner1), Median(inner2),
    Median(innerDir), ssa * b / 2, Field(run.Surface, "GaussBonnetCharacteristic"),
    Field(run.Surface, "EulerCharacteristic"));
  ASSERT_FALSE(outer1.empty());
  ASSERT_FALSE(inner1.empty());
  // Signs and directions are the criterion; sizes measured 0.965 / 1.054 /
  // 0.959 / -0.870 (the inner k2, -1/14, is the smallest curvature here;
  // one ball of 6: 0.966 / 1.051 / 0.955 / -0.843).
  EXPECT_NEAR(Median(outer1), 1, 0.1);
  EXPECT_NEAR(Median(outer2), 1, 0.1);
  EXPECT_NEAR(Median(inner1), 1, 0.1);
  EXPECT_NEAR(Median(inner2), -1, 0.3);
  EXPECT_LT(Median(inner2), 0);
  EXPECT_LT(Median(outerDir), 0.1);
  EXPECT_LT(Median(innerDir), 0.1);
  EXPECT_NEAR(ssa * b / 2, 1, 0.005);
  EXPECT_NEAR(Field(run.Surface, "GaussBonnetCharacteristic"), 0, 0.01);
  EXPECT_EQ(Field(run.Surface, "EulerCharacteristic"), 0);
}

TEST(CorrectedCurvatureFilter, GenusTwo)
{
  const int n = 72;
  TwoTori shape(V3(n / 2.0 + 0.3, n / 2.0 + 0.2, n / 2.0 + 0.1), 14, 6, 30);
  ProgramRun run(shape, n);
  std::printf("two tori: Gauss-Bonnet %.4f, V - E + F %.0f\n",
    Field(run.Surface, "GaussBonnetCharacteristic"), Field(run.Surface, "EulerCharacteristic"));
  EXPECT_NEAR(Field(run.Surface, "GaussBonnetCharacteristic"), -2, 0.01);
  EXPECT_EQ(Field(run.Surface, "EulerCharacteristic"), -2);
}

// A rotated cube, per side: every face up to the edges is flat (|H| <= 0.01
// per voxel), the creases turn by 90 degrees (convex), and the surface's
// integral of H is what its creases hold (their angle times their length).
TEST(CorrectedCurvatureFilter, CubePerSide)
{
  const int n = 64;
  const double h = 18;
  auto shape = dgtest::MakeRotatedCube(V3(n / 2.0 + 0.3, n / 2.0 + 0.2, n / 2.0 + 0.1), h, 20, 30, 10);
  ProgramRun run(*shape, n);
  vtkDataArray* H = run.Array("CorrectedMeanCurvature");
  ASSERT_NE(H, nullptr);
  std::vector<double> absH, nearEdge;
  for (vtkIdType f = 0; f < H->GetNumberOfTuples(); ++f)
  {
    absH.push_back(std::abs(H->GetComponent(f, 0)));
    if (shape->DistanceToSharpEdge(CellCentre(run.Surface, f)) <= 1.0)
      nearEdge.push_back(std::abs(H->GetComponent(f, 0)));
  }
  vtkDataArray* angle = run.Creases->GetCellData()->GetArray("CreaseAngle");
  ASSERT_NE(angle, nullptr);
  std::vector<double> dev;
  for (vtkIdType e = 0; e < angle->GetNumberOfTuples(); ++e)
    dev.push_back(std::abs(angle->GetComponent(e, 0) - 90));
  // The cube's edges hold all of its integral of H: 12 edges of length 2h
  // turning by pi/2, halved.
  const double truth = 0.5 * 12 * 2 * h * M_PI / 2;
  std::printf("cube per side: |H| median %.4f p99 %.4f max %.4f, within 1 voxel of an edge p99 %.4f "
              "max %.4f; %lld crease edges, |angle - 90| median %.2f p90 %.2f max %.2f; "
              "integral of H %.1f, creases %.1f, truth %.1f; Gauss-Bonnet %.4f\n",
    Median(absH), Quantile(absH, 0.99), Quantile(absH, 1.0), Quantile(nearEdge, 0.99),
    Quantile(nearEdge, 1.0), static_cast<long long>(angle->GetNumberOfTuples()), Median(dev),
    Quantile(dev, 0.9), Quantile(dev, 1.0), Field(run.Surface, "IntegralMeanCurvature"),
    Field(run.Surface, "CreaseIntegralMeanCurvature"), truth,
    Field(run.Surface, "GaussBonnetCharacteristic"));
  EXPECT_LE(Quantile(absH, 0.99), 0.01);
  EXPECT_LE(Quantile(nearEdge, 0.99), 0.01);
  EXPECT_LE(Median(dev), 3);
  EXPECT_NEAR(Field(run.Surface, "CreaseIntegralMeanCurvature") / truth, 1, 0.05);
  EXPECT_NEAR(Field(run.Surface, "IntegralMeanCurvature") / truth, 1, 0.02);
  EXPECT_NEAR(Field(run.Surface, "GaussBonnetCharacteristic"), 2, 0.01);
}

// Cube-sphere, per side: the spherical parts' H R within 3 % up to the
// circles, the flat discs' H near 0, the circles convex.
TEST(CorrectedCurvatureFilter, CubeSpherePerSide)
{
  const int n = 64;
  const double h = 20, r = 25;
  const V3 c(n / 2.0 + 0.3, n / 2.0 + 0.2, n / 2.0 + 0.1);
  auto shape = dgtest::MakeCubeSphere(c, h, r);
  ProgramRun run(*shape, n);
  vtkDataArray* H = run.Array("CorrectedMeanCurvature");
  ASSERT_NE(H, nullptr);
  std::vector<double> sphere, sphereNear, flat;
  for (vtkIdType f = 0; f < H->GetNumberOfTuples(); ++f)
  {
    const V3 x = CellCentre(run.Surface, f) - c;
    const bool onSphere = x.cwiseAbs().maxCoeff() < h - 0.5;
    const double d = shape->DistanceToSharpEdge(x + c);
    if (onSphere)
    {
      sphere.push_back(std::abs(H->GetComponent(f, 0) * r - 1));
      if (d <= 1.0)
        sphereNear.push_back(std::abs(H->GetComponent(f, 0) * r - 1));
    }
    else if (x.cwiseAbs().maxCoeff() > h + 0.5 || d > 1.5)
      flat.push_back(std::abs(H->GetComponent(f, 0)));
  }
  vtkDataArray* angle = run.Creases->GetCellData()->GetArray("CreaseAngle");
  ASSERT_NE(angle, nullptr);
  std::vector<double> angles;
  for (vtkIdType e = 0; e < angle->GetNumberOfTuples(); ++e)
    angles.push_back(angle->GetComponent(e, 0));
  // Where the sphere meets a face at distance h: cos(turn) = h / r.
  const double truth = std::acos(h / r) * 180 / M_PI;
  std::printf("cube-sphere per side: |H R - 1| on the sphere median %.4f p90 %.4f, within 1 voxel "
              "of the circles median %.4f p90 %.4f; flat |H| median %.4f; crease angle median "
              "%.2f (truth %.2f)\n",
    Median(sphere), Quantile(sphere, 0.9), Median(sphereNear), Quantile(sphereNear, 0.9),
    Median(flat), Median(angles), truth);
  // The 3 %, up to the circles. Measured 1.6 % (1.75 % within a
  // voxel of the circles); 4.5 % and 7.1 % while the strips (at most 5.6
  // voxels wide between the discs) kept AT's flattened normals up to the
  // circles instead of their quadric's (docs/sharp-features.md, step 10).
  EXPECT_LE(Median(sphere), 0.03);
  EXPECT_LE(Median(sphereNear), 0.03);
  EXPECT_NEAR(Median(angles), truth, 3);
}

// Bad input: one error, empty outputs.
TEST(CorrectedCurvatureFilter, RejectsBadInput)
{
  const int n = 24;
  auto shape = dgtest::MakeSphere(V3(12.3, 12.1, 12.2), 8);
  auto image = dgtest::Digitize(*shape, n);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  surface->Update();
  vtkNew<vtkPolyData> noNormals;
  noNormals->ShallowCopy(surface->GetOutput());
  noNormals->GetCellData()->SetNormals(nullptr);
  vtkNew<vtkPolyData> half;
  half->ShallowCopy(surface->GetOutput());
  vtkNew<vtkDoubleArray> halves;
  halves->SetName("Half");
  halves->SetNumberOfComponents(3);
  halves->SetNumberOfTuples(half->GetNumberOfCells());
  for (vtkIdType f = 0; f < half->GetNumberOfCells(); ++f)
    halves->SetTuple3(f, 0, 0, 0.5);
  half->GetCellData()->AddArray(halves);
  half->GetCellData()->SetNormals(halves);
  vtkNew<vtkPolyData> empty;
  struct Case
  {
    vtkPolyData* Input;
    double Radius;
    const char* Why;
  };
  const Case cases[] = { { noNormals, 5, "no normals" }, { half, 5, "non-unit" },
    { surface->GetOutput(), 0, "radius 0" }, { surface->GetOutput(), -1, "radius < 0" },
    { surface->GetOutput(), 1000, "radius > surface" }, { empty, 5, "empty" } };
  for (const Case& c : cases)
  {
    vtkNew<vtkCorrectedCurvatureFilter> filter;
    filter->SetInputData(c.Input);
    filter->SetRadius(c.Radius);
    filter->GlobalWarningDisplayOff();
    filter->Update();
    EXPECT_EQ(filter->GetOutput(0)->GetNumberOfCells(), 0) << c.Why;
    EXPECT_EQ(filter->GetOutput(1)->GetNumberOfCells(), 0) << c.Why;
    EXPECT_EQ(filter->GetOutput(0)->GetCellData()->GetArray("CorrectedMeanCurvature"), nullptr)
      << c.Why;
  }
  vtkObject::GlobalWarningDisplayOn();
  // The same surface with its own (trivial) normals is fine: a surface whose
  // normals take six values has all its curvature at its edges.
  vtkNew<vtkCorrectedCurvatureFilter> ok;
  ok->SetInputData(surface->GetOutput());
  ok->Update();
  EXPECT_EQ(ok->GetOutput(0)->GetNumberOfCells(), surface->GetOutput()->GetNumberOfCells());
}

// Ghost cells in the input (a downstream request for ghost levels reaches
// the producers upstream, e.g. ParaView's parallel writer asks for one) are
// left out: the output holds the own cells in input order, with only the
// points they use, and no ghost array.
TEST(CorrectedCurvatureFilter, GhostCellsAreLeftOut)
{
  const int n = 24;
  auto shape = dgtest::MakeSphere(V3(12.3, 12.1, 12.2), 8);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(dgtest::Digitize(*shape, n));
  surface->Update();
  vtkNew<vtkPolyData> marked;
  marked->ShallowCopy(surface->GetOutput());
  const vtkIdType nCells = marked->GetNumberOfCells();
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  ghosts->SetNumberOfTuples(nCells);
  std::vector<vtkIdType> own;
  std::vector<char> usedPoint(marked->GetNumberOfPoints(), 0);
  vtkNew<vtkIdList> pts;
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    double b[6];
    marked->GetCellBounds(c, b);
    const bool ghost = b[4] > 14.0; // a cap of the sphere
    ghosts->SetValue(c, ghost ? vtkDataSetAttributes::DUPLICATECELL : 0);
    if (ghost)
      continue;
    own.push_back(c);
    marked->GetCellPoints(c, pts);
    for (vtkIdType k = 0; k < pts->GetNumberOfIds(); ++k)
      usedPoint[pts->GetId(k)] = 1;
  }
  ASSERT_GT(own.size(), 0u);
  ASSERT_LT(static_cast<vtkIdType>(own.size()), nCells);
  marked->GetCellData()->AddArray(ghosts);
  vtkNew<vtkCorrectedCurvatureFilter> filter;
  filter->SetInputData(marked);
  filter->SetRadius(3);
  filter->Update();
  vtkPolyData* out = filter->GetOutput(0);
  ASSERT_EQ(out->GetNumberOfCells(), static_cast<vtkIdType>(own.size()));
  EXPECT_EQ(out->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()), nullptr);
  EXPECT_EQ(out->GetNumberOfPoints(),
    static_cast<vtkIdType>(std::count(usedPoint.begin(), usedPoint.end(), 1)));
  vtkDataArray* inVoxel = marked->GetCellData()->GetArray("InsideVoxel");
  vtkDataArray* outVoxel = out->GetCellData()->GetArray("InsideVoxel");
  vtkDataArray* h = out->GetCellData()->GetArray("CorrectedMeanCurvature");
  ASSERT_NE(outVoxel, nullptr);
  ASSERT_NE(h, nullptr);
  for (std::size_t i = 0; i < own.size(); ++i)
  {
    for (int c = 0; c < inVoxel->GetNumberOfComponents(); ++c)
      ASSERT_EQ(outVoxel->GetComponent(static_cast<vtkIdType>(i), c), inVoxel->GetComponent(own[i], c));
    ASSERT_TRUE(std::isfinite(h->GetComponent(static_cast<vtkIdType>(i), 0)));
  }
}
