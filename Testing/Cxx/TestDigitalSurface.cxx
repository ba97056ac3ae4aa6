// vtkDigitalSurfaceFilter and its core: counts, topology (Euler
// characteristic, edge incidences), orientation against the image, geometry
// (origin, spacing), selection modes, determinism and bad input.
#include "dgTestShapes.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <set>

namespace
{
using Edge = std::pair<vtkIdType, vtkIdType>;

vtkSmartPointer<vtkPolyData> Extract(vtkImageData* image, vtkDigitalSurfaceFilter* f = nullptr)
{
  vtkNew<vtkDigitalSurfaceFilter> local;
  if (!f)
  {
    f = local;
  }
  f->SetInputData(image);
  f->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

// Undirected edge -> list of (quad, +1 if the quad runs along it low->high).
std::map<Edge, std::vector<std::pair<vtkIdType, int>>> EdgeIncidence(vtkPolyData* pd)
{
  std::map<Edge, std::vector<std::pair<vtkIdType, int>>> edges;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    pd->GetCellPoints(c, ids);
    const vtkIdType n = ids->GetNumberOfIds();
    for (vtkIdType a = 0; a < n; ++a)
    {
      const vtkIdType p = ids->GetId(a), q = ids->GetId((a + 1) % n);
      edges[{ std::min(p, q), std::max(p, q) }].push_back({ c, p < q ? 1 : -1 });
    }
  }
  return edges;
}

long EulerCharacteristic(vtkPolyData* pd)
{
  return static_cast<long>(pd->GetNumberOfPoints()) - static_cast<long>(EdgeIncidence(pd).size()) +
    static_cast<long>(pd->GetNumberOfPolys());
}

std::array<double, 3> QuadNormal(vtkPolyData* pd, vtkIdType c, double* centroid = nullptr)
{
  vtkNew<vtkIdList> ids;
  pd->GetCellPoints(c, ids);
  double p[4][3];
  for (int a = 0; a < 4; ++a)
  {
    pd->GetPoint(ids->GetId(a), p[a]);
  }
  // Newell's normal: area-weighted, sign by winding.
  std::array<double, 3> n = { 0, 0, 0 };
  for (int a = 0; a < 4; ++a)
  {
    const double* u = p[a];
    const double* v = p[(a + 1) % 4];
    n[0] += (u[1] - v[1]) * (u[2] + v[2]);
    n[1] += (u[2] - v[2]) * (u[0] + v[0]);
    n[2] += (u[0] - v[0]) * (u[1] + v[1]);
  }
  for (int a = 0; a < 3; ++a)
  {
    n[a] *= 0.5;
  }
  if (centroid)
  {
    for (int a = 0; a < 3; ++a)
    {
      centroid[a] = 0.25 * (p[0][a] + p[1][a] + p[2][a] + p[3][a]);
    }
  }
  return n;
}

// Every quad: unit area, geometric normal == "Normals" == axis of
// SurfelDirection, the voxel behind it inside and the one in front outside.
void CheckOrientation(vtkImageData* image, vtkPolyData* pd)
{
  auto* normals = pd->GetCellData()->GetNormals();
  auto* voxels = vtkIntArray::SafeDownCast(pd->GetCellData()->GetArray("InsideVoxel"));
  auto* dirs = pd->GetCellData()->GetArray("SurfelDirection");
  ASSERT_NE(normals, nullptr);
  ASSERT_NE(voxels, nullptr);
  ASSERT_NE(dirs, nullptr);
  double origin[3], spacing[3];
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  int ext[6];
  image->GetExtent(ext);
  auto inside = [&](int i, int j, int k) {
    if (i < ext[0] || i > ext[1] || j < ext[2] || j > ext[3] || k < ext[4] || k > ext[5])
    {
      return false;
    }
    return image->GetScalarComponentAsDouble(i, j, k, 0) != 0.0;
  };
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    double centroid[3];
    auto n = QuadNormal(pd, c, centroid);
    const int d = static_cast<int>(dirs->GetTuple1(c));
    const int axis = d / 2;
    const double sign = (d & 1) ? 1.0 : -1.0;
    double expectedArea = 1.0;
    for (int a = 0; a < 3; ++a)
    {
      expectedArea *= a == axis ? 1.0 : spacing[a];
    }
    for (int a = 0; a < 3; ++a)
    {
      ASSERT_NEAR(n[a], a == axis ? sign * expectedArea : 0.0, 1e-9) << "quad " << c;
      ASSERT_NEAR(normals->GetComponent(c, a), a == axis ? sign : 0.0, 1e-6);
    }
    int v[3] = { voxels->GetTypedComponent(c, 0), voxels->GetTypedComponent(c, 1),
      voxels->GetTypedComponent(c, 2) };
    // The quad's centre lies half a voxel from the inside voxel's centre.
    for (int a = 0; a < 3; ++a)
    {
      const double expected = origin[a] + spacing[a] * (v[a] + (a == axis ? 0.5 * sign : 0.0));
      ASSERT_NEAR(centroid[a], expected, 1e-9);
    }
    ASSERT_TRUE(inside(v[0], v[1], v[2])) << "quad " << c;
    v[axis] += static_cast<int>(sign);
    ASSERT_FALSE(inside(v[0], v[1], v[2])) << "quad " << c;
  }
}

std::array<double, 3> NormalSum(vtkPolyData* pd)
{
  std::array<double, 3> sum = { 0, 0, 0 };
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    auto n = QuadNormal(pd, c);
    for (int a = 0; a < 3; ++a)
    {
      sum[a] += n[a];
    }
  }
  return sum;
}

// Each point used by some quad, no two points at the same place.
void CheckPointsUnique(vtkPolyData* pd)
{
  std::set<std::array<long long, 3>> seen;
  for (vtkIdType p = 0; p < pd->GetNumberOfPoints(); ++p)
  {
    double x[3];
    pd->GetPoint(p, x);
    std::array<long long, 3> key = { std::llround(x[0] * 1024), std::llround(x[1] * 1024),
      std::llround(x[2] * 1024) };
    ASSERT_TRUE(seen.insert(key).second) << "duplicate point " << p;
  }
  std::vector<int> used(pd->GetNumberOfPoints(), 0);
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    pd->GetCellPoints(c, ids);
    for (vtkIdType a = 0; a < ids->GetNumberOfIds(); ++a)
    {
      used[ids->GetId(a)] = 1;
    }
  }
  for (int u : used)
  {
    ASSERT_EQ(u, 1);
  }
}
} // namespace

TEST(DigitalSurface, OneVoxelGivesSixOutwardQuads)
{
  auto image = dgtest::MakeImage(3, 3, 3, [](int i, int j, int k) {
    return (i == 1 && j == 1 && k == 1) ? 128.0 : 0.0;
  });
  auto pd = Extract(image);
  EXPECT_EQ(pd->GetNumberOfPolys(), 6);
  EXPECT_EQ(pd->GetNumberOfPoints(), 8);
  CheckOrientation(image, pd);
  CheckPointsUnique(pd);
  // All normals point away from the voxel centre (1, 1, 1).
  for (vtkIdType c = 0; c < 6; ++c)
  {
    double centroid[3];
    auto n = QuadNormal(pd, c, centroid);
    EXPECT_GT(n[0] * (centroid[0] - 1) + n[1] * (centroid[1] - 1) + n[2] * (centroid[2] - 1), 0.4);
  }
  EXPECT_EQ(EulerCharacteristic(pd), 2);
}

TEST(DigitalSurface, TwoVoxelsSharingAnEdgeKeepTheNonManifoldEdge)
{
  auto image = dgtest::MakeImage(4, 4, 4, [](int i, int j, int k) {
    return ((i == 1 && j == 1 && k == 1) || (i == 2 && j == 2 && k == 1)) ? 1.0 : 0.0;
  });
  auto pd = Extract(image);
  EXPECT_EQ(pd->GetNumberOfPolys(), 12);
  EXPECT_EQ(pd->GetNumberOfPoints(), 14); // 16 corners, 2 shared along the edge
  int fourWay = 0;
  for (const auto& e : EdgeIncidence(pd))
  {
    if (e.second.size() == 4)
    {
      ++fourWay;
      int sum = 0;
      for (auto& q : e.second)
      {
        sum += q.second;
      }
      EXPECT_EQ(sum, 0) << "orientations along the non-manifold edge must cancel";
    }
    else
    {
      EXPECT_EQ(e.second.size(), 2u);
    }
  }
  EXPECT_EQ(fourWay, 1);
  CheckOrientation(image, pd);
}

TEST(DigitalSurface, BlockOfNCubedVoxelsHasSixNSquaredQuads)
{
  for (int n = 1; n <= 6; ++n)
  {
    auto image = dgtest::MakeImage(n + 4, n + 3, n + 2, [n](int i, int j, int k) {
      return (i >= 2 && i < 2 + n && j >= 1 && j < 1 + n && k >= 1 && k < 1 + n) ? 1.0 : 0.0;
    });
    auto pd = Extract(image);
    EXPECT_EQ(pd->GetNumberOfPolys(), 6 * n * n) << "n = " << n;
    EXPECT_EQ(pd->GetNumberOfPoints(), 6 * n * n + 2) << "n = " << n;
    CheckOrientation(image, pd);
  }
}

TEST(DigitalSurface, BlockTouchingTheImageBorderIsClosed)
{
  // Everything beyond the extent is outside: a full image gives its border.
  auto image = dgtest::MakeImage(3, 4, 5, [](int, int, int) { return 1.0; });
  vtkNew<vtkDigitalSurfaceFilter> f;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(f);
  auto pd = Extract(image, f);
  EXPECT_EQ(obs->Warnings, 1) << "an all-inside image deserves a word";
  EXPECT_EQ(obs->Errors, 0);
  EXPECT_EQ(pd->GetNumberOfPolys(), 2 * (3 * 4 + 4 * 5 + 3 * 5));
  EXPECT_EQ(EulerCharacteristic(pd), 2);
  CheckOrientation(image, pd);
}

TEST(DigitalSurface, BallHasEulerCharacteristicTwoAndIsAManifold)
{
  for (double r : { 3.2, 7.5, 12.3 })
  {
    auto image = dgtest::Ball(2 * static_cast<int>(r) + 6, r);
    auto pd = Extract(image);
    EXPECT_EQ(EulerCharacteristic(pd), 2) << "r = " << r;
    for (const auto& e : EdgeIncidence(pd))
    {
      ASSERT_EQ(e.second.size(), 2u);
      ASSERT_EQ(e.second[0].second + e.second[1].second, 0) << "inconsistent winding";
    }
    auto s = NormalSum(pd);
    for (double x : s)
    {
      EXPECT_NEAR(x, 0.0, 1e-9);
    }
    CheckOrientation(image, pd);
    CheckPointsUnique(pd);
  }
}

TEST(DigitalSurface, TorusHasEulerCharacteristicZero)
{
  const int n = 48;
  const double c = 0.5 * (n - 1) + 0.17, R = 14.0, r = 5.5;
  auto image = dgtest::Digitize(n, [=](double x, double y, double z) {
    const double q = std::sqrt((x - c) * (x - c) + (y - c) * (y - c)) - R;
    return q * q + (z - c) * (z - c) <= r * r;
  });
  auto pd = Extract(image);
  EXPECT_EQ(EulerCharacteristic(pd), 0);
  auto s = NormalSum(pd);
  for (double x : s)
  {
    EXPECT_NEAR(x, 0.0, 1e-9);
  }
}

TEST(DigitalSurface, RandomVoxelSetsAreOrientedFromInsideToOutside)
{
  for (unsigned seed = 1; seed <= 12; ++seed)
  {
    auto image = dgtest::RandomVoxels(5 + seed % 4, 6 + seed % 3, 4 + seed % 5, 0.1 * (seed % 9) + 0.05, seed);
    auto pd = Extract(image);
    ASSERT_GT(pd->GetNumberOfPolys(), 0);
    CheckOrientation(image, pd);
    CheckPointsUnique(pd);
    auto s = NormalSum(pd);
    for (double x : s)
    {
      EXPECT_NEAR(x, 0.0, 1e-9);
    }
    // The number of quads equals the number of inside/outside face pairs.
    long expected = 0;
    int ext[6];
    image->GetExtent(ext);
    auto in = [&](int i, int j, int k) {
      return i >= 0 && j >= 0 && k >= 0 && i <= ext[1] && j <= ext[3] && k <= ext[5] &&
        image->GetScalarComponentAsDouble(i, j, k, 0) != 0;
    };
    for (int k = -1; k <= ext[5]; ++k)
      for (int j = -1; j <= ext[3]; ++j)
        for (int i = -1; i <= ext[1]; ++i)
        {
          expected += in(i, j, k) != in(i + 1, j, k);
          expected += in(i, j, k) != in(i, j + 1, k);
          expected += in(i, j, k) != in(i, j, k + 1);
        }
    EXPECT_EQ(pd->GetNumberOfPolys(), expected) << "seed " << seed;
  }
}

TEST(DigitalSurface, OriginSpacingAndExtentAreApplied)
{
  auto image = dgtest::MakeImage(4, 4, 4, [](int i, int j, int k) {
    return (i >= 1 && i <= 2 && j == 1 && k >= 1 && k <= 2) ? 1.0 : 0.0;
  });
  image->SetOrigin(10.0, -5.0, 2.0);
  image->SetSpacing(0.5, 2.0, 1.5);
  auto pd = Extract(image);
  double b[6];
  pd->GetBounds(b);
  // Voxels i in 1..2, j = 1, k in 1..2; corners half a voxel from the centres.
  EXPECT_NEAR(b[0], 10.0 + 0.5 * 0.5, 1e-12);
  EXPECT_NEAR(b[1], 10.0 + 0.5 * 2.5, 1e-12);
  EXPECT_NEAR(b[2], -5.0 + 2.0 * 0.5, 1e-12);
  EXPECT_NEAR(b[3], -5.0 + 2.0 * 1.5, 1e-12);
  EXPECT_NEAR(b[4], 2.0 + 1.5 * 0.5, 1e-12);
  EXPECT_NEAR(b[5], 2.0 + 1.5 * 2.5, 1e-12);
  CheckOrientation(image, pd);
  auto* fd = pd->GetFieldData();
  auto* spacing = fd->GetArray("ImageSpacing");
  auto* origin = fd->GetArray("ImageOrigin");
  auto* extent = fd->GetArray("ImageExtent");
  ASSERT_TRUE(spacing && origin && extent);
  EXPECT_DOUBLE_EQ(spacing->GetComponent(1, 0), 2.0);
  EXPECT_DOUBLE_EQ(origin->GetComponent(0, 0), 10.0);
  EXPECT_EQ(extent->GetComponent(5, 0), 3.0);

  // A shifted extent moves the voxels (and the reported InsideVoxel indices).
  image->SetExtent(5, 8, 0, 3, 0, 3);
  auto shifted = Extract(image);
  double b2[6];
  shifted->GetBounds(b2);
  EXPECT_NEAR(b2[0], b[0] + 5 * 0.5, 1e-12);
  CheckOrientation(image, shifted);
}

TEST(DigitalSurface, LabelMapGivesOneClosedSurfacePerLabel)
{
  // Three labelled blocks: 1 and 2 touch along a face, 3 is apart.
  auto image = dgtest::MakeImage(12, 8, 8, [](int i, int j, int k) {
    if (j < 1 || j > 5 || k < 1 || k > 5)
      return 0.0;
    if (i >= 1 && i <= 3)
      return 1.0;
    if (i >= 4 && i <= 6)
      return 2.0;
    if (i >= 8 && i <= 10)
      return 3.0;
    return 0.0;
  });
  vtkNew<vtkDigitalSurfaceFilter> f;
  f->SetSelectionModeToLabel();
  for (int label = 1; label <= 3; ++label)
  {
    f->SetLabel(label);
    auto pd = Extract(image, f);
    // Each block is 3 x 5 x 5 voxels.
    EXPECT_EQ(pd->GetNumberOfPolys(), 2 * (15 + 25 + 15)) << "label " << label;
    EXPECT_EQ(EulerCharacteristic(pd), 2);
    double b[6];
    pd->GetBounds(b);
    const int first[4] = { 0, 1, 4, 8 };
    EXPECT_NEAR(b[0], first[label] - 0.5, 1e-12);
  }
  // The range [1, 2] merges the two touching blocks into one box.
  f->SetSelectionModeToRange();
  f->SetLowerThreshold(1);
  f->SetUpperThreshold(2);
  auto merged = Extract(image, f);
  EXPECT_EQ(merged->GetNumberOfPolys(), 2 * (30 + 25 + 30));
  // Default: everything non-zero, two components.
  vtkNew<vtkDigitalSurfaceFilter> all;
  auto both = Extract(image, all);
  EXPECT_EQ(EulerCharacteristic(both), 4);
}

TEST(DigitalSurface, AnyNumericScalarTypeAndComponentSelection)
{
  const int types[] = { VTK_CHAR, VTK_UNSIGNED_CHAR, VTK_SHORT, VTK_UNSIGNED_SHORT, VTK_INT,
    VTK_LONG_LONG, VTK_FLOAT, VTK_DOUBLE };
  auto ref = Extract(dgtest::Ball(16, 5.3));
  for (int t : types)
  {
    auto ball = dgtest::Ball(16, 5.3);
    auto typed = dgtest::MakeImage(16, 16, 16,
      [&](int i, int j, int k) { return 3.0 * ball->GetScalarComponentAsDouble(i, j, k, 0); }, t);
    vtkNew<vtkDigitalSurfaceFilter> f;
    f->SetSelectionModeToRange();
    f->SetLowerThreshold(2.5);
    f->SetUpperThreshold(3.5);
    auto pd = Extract(typed, f);
    EXPECT_EQ(pd->GetNumberOfPolys(), ref->GetNumberOfPolys()) << "type " << t;
  }
  // Two components: the second selects, the first is noise.
  auto ball = dgtest::Ball(16, 5.3);
  vtkNew<vtkImageData> two;
  two->SetDimensions(16, 16, 16);
  two->AllocateScalars(VTK_FLOAT, 2);
  auto* s = two->GetPointData()->GetScalars();
  for (vtkIdType p = 0; p < s->GetNumberOfTuples(); ++p)
  {
    s->SetComponent(p, 0, static_cast<double>(p % 7));
    s->SetComponent(p, 1, ball->GetPointData()->GetScalars()->GetTuple1(p));
  }
  vtkNew<vtkDigitalSurfaceFilter> f;
  dgtest::ErrorObserver* obs = dgtest::ErrorObserver::New();
  obs->Observe(f);
  f->SetInputData(two);
  f->Update();
  EXPECT_EQ(obs->Errors, 1) << "multi-component scalars need a chosen component";
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 0);
  f->SetSelectedComponent(1);
  f->Update();
  EXPECT_EQ(f->GetOutput()->GetNumberOfPolys(), ref->GetNumberOfPolys());
  obs->Delete();
}

TEST(DigitalSurface, OutputDoesNotDependOnTheNumberOfThreads)
{
  auto image = dgtest::RandomVoxels(40, 37, 33, 0.4, 7);
  const std::string backend = vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "";
  vtkSMPTools::SetBackend("Sequential");
  auto seq = Extract(image);
  vtkSMPTools::SetBackend("STDThread");
  vtkSMPTools::Initialize(4);
  auto par = Extract(image);
  vtkSMPTools::SetBackend(backend.c_str());
  ASSERT_EQ(seq->GetNumberOfPoints(), par->GetNumberOfPoints());
  ASSERT_EQ(seq->GetNumberOfPolys(), par->GetNumberOfPolys());
  for (vtkIdType p = 0; p < seq->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    seq->GetPoint(p, a);
    par->GetPoint(p, b);
    ASSERT_TRUE(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]);
  }
  vtkNew<vtkIdList> x, y;
  for (vtkIdType c = 0; c < seq->GetNumberOfCells(); ++c)
  {
    seq->GetCellPoints(c, x);
    par->GetCellPoints(c, y);
    for (int a = 0; a < 4; ++a)
    {
      ASSERT_EQ(x->GetId(a), y->GetId(a));
    }
  }
}

namespace
{
void ExpectErrorAndEmpty(vtkImageData* image, vtkDigitalSurfaceFilter* f, const char* what)
{
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(f);
  obs->Observe(f->GetExecutive());
  f->SetInputData(image);
  f->Update();
  EXPECT_GE(obs->Errors, 1) << what;
  EXPECT_EQ(f->GetOutput()->GetNumberOfCells(), 0) << what;
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0) << what;
}
} // namespace

TEST(DigitalSurface, BadInputGivesAnErrorAndAnEmptyOutput)
{
  {
    vtkNew<vtkImageData> empty;
    vtkNew<vtkDigitalSurfaceFilter> f;
    ExpectErrorAndEmpty(empty, f, "empty image");
  }
  {
    vtkNew<vtkImageData> noScalars;
    noScalars->SetDimensions(4, 4, 4);
    vtkNew<vtkDigitalSurfaceFilter> f;
    ExpectErrorAndEmpty(noScalars, f, "no scalars");
  }
  {
    auto flat = dgtest::MakeImage(8, 8, 1, [](int, int, int) { return 1.0; });
    vtkNew<vtkDigitalSurfaceFilter> f;
    ExpectErrorAndEmpty(flat, f, "2D image");
  }
  {
    auto tiny = dgtest::MakeImage(1, 1, 1, [](int, int, int) { return 1.0; });
    vtkNew<vtkDigitalSurfaceFilter> f;
    ExpectErrorAndEmpty(tiny, f, "1x1x1 image");
  }
  {
    auto zero = dgtest::MakeImage(5, 5, 5, [](int, int, int) { return 0.0; });
    vtkNew<vtkDigitalSurfaceFilter> f;
    ExpectErrorAndEmpty(zero, f, "empty selection");
  }
  {
    auto labels = dgtest::MakeImage(5, 5, 5, [](int i, int, int) { return i; });
    vtkNew<vtkDigitalSurfaceFilter> f;
    f->SetSelectionModeToLabel();
    f->SetLabel(17);
    ExpectErrorAndEmpty(labels, f, "label that does not occur");
  }
  {
    auto nan = dgtest::MakeImage(
      5, 5, 5, [](int i, int, int) { return i == 2 ? std::nan("") : 1.0; }, VTK_FLOAT);
    vtkNew<vtkDigitalSurfaceFilter> f;
    ExpectErrorAndEmpty(nan, f, "NaN scalars");
  }
  {
    auto image = dgtest::MakeImage(5, 5, 5, [](int, int, int) { return 1.0; });
    vtkNew<vtkDigitalSurfaceFilter> f;
    f->SetSelectionModeToRange();
    f->SetLowerThreshold(3);
    f->SetUpperThreshold(2);
    ExpectErrorAndEmpty(image, f, "inverted range");
  }
  {
    auto image = dgtest::MakeImage(5, 5, 5, [](int, int, int) { return 1.0; });
    vtkNew<vtkDigitalSurfaceFilter> f;
    f->SetSelectedComponent(2);
    ExpectErrorAndEmpty(image, f, "component out of range");
  }
}
