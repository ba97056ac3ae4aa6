// vtkDigitalIslandFilter: small islands removed and small cavities filled,
// against a brute-force breadth-first search (6-connectivity) on random
// voxel sets; a ball with a speck and a cavity; the exterior is never
// filled; selection modes; geometry kept; bad input; sub-extents and pieces
// equal, voxel for voxel, to the whole run.
#include "dgIslands.h"
#include "dgPieces.h"
#include "dgTestShapes.h"
#include "dgTestTemp.h"
#include "dgVolFormat.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalIslandFilter.h"
#include "vtkDigitalNoiseFilter.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkExtentTranslator.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <array>
#include <deque>
#include <random>

namespace
{
using Mask = std::vector<std::uint8_t>;

struct Reference
{
  Mask Result;
  std::int64_t Islands = 0, Cavities = 0, Changed = 0;
};

// Components of the voxels equal to value, by breadth-first search over the
// six face neighbours: a label per voxel (-1 for the others), then per label
// its size and whether it has a voxel on the image border.
int BruteForceComponents(const Mask& m, const int d[3], std::uint8_t value, std::vector<int>& label,
  std::vector<std::int64_t>& size, std::vector<bool>& border)
{
  label.assign(m.size(), -1);
  size.clear();
  border.clear();
  const auto id = [d](int i, int j, int k) { return (std::size_t(k) * d[1] + j) * d[0] + i; };
  int n = 0;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
      {
        if (m[id(i, j, k)] != value || label[id(i, j, k)] >= 0)
        {
          continue;
        }
        std::deque<std::array<int, 3>> queue{ { i, j, k } };
        label[id(i, j, k)] = n;
        size.push_back(0);
        border.push_back(false);
        while (!queue.empty())
        {
          const auto p = queue.front();
          queue.pop_front();
          ++size[n];
          for (int a = 0; a < 3; ++a)
          {
            if (p[a] == 0 || p[a] == d[a] - 1)
            {
              border[n] = true;
            }
          }
          static const int step[6][3] = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 },
            { 0, 0, -1 }, { 0, 0, 1 } };
          for (const auto& s : step)
          {
            const int q[3] = { p[0] + s[0], p[1] + s[1], p[2] + s[2] };
            if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= d[0] || q[1] >= d[1] || q[2] >= d[2])
            {
              continue;
            }
            const std::size_t v = id(q[0], q[1], q[2]);
            if (m[v] == value && label[v] < 0)
            {
              label[v] = n;
              queue.push_back({ q[0], q[1], q[2] });
            }
          }
        }
        ++n;
      }
  return n;
}

// The filter's definition, done the slow way: islands first, then the
// cavities of that result.
Reference BruteForce(const Mask& original, const int d[3], int minimumSize, bool islands,
  bool cavities)
{
  Reference r;
  r.Result = original;
  std::vector<int> label;
  std::vector<std::int64_t> size;
  std::vector<bool> border;
  if (islands)
  {
    BruteForceComponents(r.Result, d, 1, label, size, border);
    for (std::size_t c = 0; c < size.size(); ++c)
      r.Islands += size[c] < minimumSize;
    for (std::size_t v = 0; v < r.Result.size(); ++v)
      if (label[v] >= 0 && size[label[v]] < minimumSize)
        r.Result[v] = 0;
  }
  if (cavities)
  {
    BruteForceComponents(r.Result, d, 0, label, size, border);
    for (std::size_t c = 0; c < size.size(); ++c)
      r.Cavities += size[c] < minimumSize && !border[c];
    for (std::size_t v = 0; v < r.Result.size(); ++v)
      if (label[v] >= 0 && size[label[v]] < minimumSize && !border[label[v]])
        r.Result[v] = 1;
  }
  for (std::size_t v = 0; v < r.Result.size(); ++v)
    r.Changed += r.Result[v] != original[v];
  return r;
}

Mask ValuesOf(vtkImageData* image)
{
  vtkDataArray* s = image->GetPointData()->GetScalars();
  Mask m(s ? s->GetNumberOfTuples() : 0);
  for (std::size_t v = 0; v < m.size(); ++v)
    m[v] = static_cast<std::uint8_t>(s->GetTuple1(static_cast<vtkIdType>(v)));
  return m;
}

vtkSmartPointer<vtkImageData> FromMask(const Mask& m, const int d[3])
{
  return dgtest::MakeImage(
    d[0], d[1], d[2], [&](int i, int j, int k) { return m[(std::size_t(k) * d[1] + j) * d[0] + i]; });
}

int FieldValue(vtkImageData* image, const char* name)
{
  auto* a = vtkIntArray::SafeDownCast(image->GetFieldData()->GetArray(name));
  return a && a->GetNumberOfValues() == 1 ? a->GetValue(0) : -1;
}

// A ball of radius 9 in 32^3 (with a 2-voxel cavity at its centre when
// cavity) and, away from it, a 3-voxel speck along x (when speck).
Mask BallWithSpeckAndCavity(bool speck, bool cavity, int d[3])
{
  d[0] = d[1] = d[2] = 32;
  Mask m = ValuesOf(dgtest::Ball(32, 9));
  const auto id = [](int i, int j, int k) { return (std::size_t(k) * 32 + j) * 32 + i; };
  if (speck)
  {
    for (int i = 3; i < 6; ++i)
      m[id(i, 4, 5)] = 1;
  }
  if (cavity)
  {
    EXPECT_EQ(m[id(15, 16, 16)] + m[id(16, 16, 16)], 2);
    m[id(15, 16, 16)] = m[id(16, 16, 16)] = 0;
  }
  return m;
}
} // namespace

TEST(IslandFilter, MatchesBruteForceOnRandomVoxels)
{
  struct Case
  {
    int Dims[3];
    double P;
  };
  // Dense, sparse and near-percolation sets; a one-voxel-thick image (no
  // cavity there: every voxel is on the border); nearly full and nearly
  // empty wide rows (long runs, skipped eight voxels at a time).
  const Case cases[] = { { { 13, 11, 9 }, 0.3 }, { { 10, 12, 14 }, 0.5 }, { { 9, 9, 12 }, 0.75 },
    { { 17, 5, 3 }, 0.6 }, { { 14, 12, 1 }, 0.55 }, { { 45, 9, 8 }, 0.97 },
    { { 43, 8, 7 }, 0.04 } };
  int tried = 0, changedSome = 0;
  for (const auto& c : cases)
  {
    for (unsigned seed = 1; seed <= 3; ++seed)
    {
      auto image = dgtest::RandomVoxels(c.Dims[0], c.Dims[1], c.Dims[2], c.P, seed);
      const Mask original = ValuesOf(image);
      for (int minimumSize : { 1, 2, 3, 5, 8, 20, 100 })
      {
        for (int flags = 0; flags < 4; ++flags)
        {
          const bool islands = flags & 1, cavities = flags & 2;
          SCOPED_TRACE(testing::Message() << c.Dims[0] << "x" << c.Dims[1] << "x" << c.Dims[2]
                                          << " p " << c.P << " seed " << seed << " size "
                                          << minimumSize << " islands " << islands
                                          << " cavities " << cavities);
          const Reference ref = BruteForce(original, c.Dims, minimumSize, islands, cavities);
          vtkNew<vtkDigitalIslandFilter> f;
          f->SetInputData(image);
          f->SetMinimumSize(minimumSize);
          f->SetRemoveIslands(islands);
          f->SetFillCavities(cavities);
          f->Update();
          ASSERT_EQ(ValuesOf(f->GetOutput()), ref.Result);
          EXPECT_EQ(f->GetNumberOfRemovedIslands(), ref.Islands);
          EXPECT_EQ(f->GetNumberOfFilledCavities(), ref.Cavities);
          EXPECT_EQ(f->GetNumberOfChangedVoxels(), ref.Changed);
          EXPECT_EQ(FieldValue(f->GetOutput(), "RemovedIslands"), ref.Islands);
          EXPECT_EQ(FieldValue(f->GetOutput(), "FilledCavities"), ref.Cavities);
          ++tried;
          changedSome += ref.Changed > 0;
        }
      }
    }
  }
  EXPECT_EQ(tried, 7 * 3 * 7 * 4);
  EXPECT_GT(changedSome, tried / 3); // the cases do exercise both passes
}

TEST(IslandFilter, ComponentSizesMatchBruteForce)
{
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    const int d[3] = { 12, 9, 11 };
    const Mask m = ValuesOf(dgtest::RandomVoxels(d[0], d[1], d[2], 0.3 + 0.1 * seed, seed));
    for (std::uint8_t value : { 0, 1 })
    {
      std::vector<int> label;
      std::vector<std::int64_t> refSizes, sizes;
      std::vector<bool> refBorder;
      std::vector<std::uint8_t> border;
      BruteForceComponents(m, d, value, label, refSizes, refBorder);
      dg::ComponentSizes(m, d, value, sizes, border);
      // Both number components in the order of their first voxel.
      ASSERT_EQ(sizes, refSizes) << "seed " << seed << " value " << int(value);
      ASSERT_EQ(border.size(), refBorder.size());
      for (std::size_t c = 0; c < border.size(); ++c)
        EXPECT_EQ(border[c] != 0, refBorder[c]) << c;
    }
  }
}

TEST(IslandFilter, SameResultWhateverTheThreads)
{
  auto image = dgtest::RandomVoxels(60, 50, 40, 0.6, 7);
  const std::string backend = vtkSMPTools::GetBackend();
  Mask results[2];
  vtkIdType changed[2];
  const char* backends[] = { "Sequential", "STDThread" };
  for (int b = 0; b < 2; ++b)
  {
    vtkSMPTools::SetBackend(backends[b]);
    vtkNew<vtkDigitalIslandFilter> f;
    f->SetInputData(image);
    f->SetMinimumSize(6);
    f->Update();
    results[b] = ValuesOf(f->GetOutput());
    changed[b] = f->GetNumberOfChangedVoxels();
  }
  vtkSMPTools::SetBackend(backend.c_str());
  EXPECT_EQ(results[0], results[1]);
  EXPECT_EQ(changed[0], changed[1]);
  EXPECT_GT(changed[0], 100);
}

TEST(IslandFilter, BallWithSpeckAndCavity)
{
  int d[3];
  const Mask ball = BallWithSpeckAndCavity(false, false, d);
  const Mask noisy = BallWithSpeckAndCavity(true, true, d);
  auto image = FromMask(noisy, d);

  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(image);
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), ball) << "speck gone, cavity filled, ball unchanged";
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 1);
  EXPECT_EQ(f->GetNumberOfFilledCavities(), 1);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 5);
  EXPECT_EQ(FieldValue(f->GetOutput(), "RemovedIslands"), 1);
  EXPECT_EQ(FieldValue(f->GetOutput(), "FilledCavities"), 1);
  EXPECT_STREQ(f->GetOutput()->GetPointData()->GetScalars()->GetName(), "Inside");
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetScalars()->GetDataType(), VTK_UNSIGNED_CHAR);

  // The surface loses the speck's 14 surfels and the cavity's 10.
  vtkNew<vtkDigitalSurfaceFilter> before, after;
  before->SetInputData(image);
  after->SetInputConnection(f->GetOutputPort());
  before->Update();
  after->Update();
  EXPECT_EQ(before->GetOutput()->GetNumberOfCells() - after->GetOutput()->GetNumberOfCells(), 24);

  // MinimumSize 3: the 3-voxel speck stays, the 2-voxel cavity goes.
  f->SetMinimumSize(3);
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), BallWithSpeckAndCavity(true, false, d));
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 0);
  EXPECT_EQ(f->GetNumberOfFilledCavities(), 1);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 2);

  // Each pass on its own; MinimumSize 1 changes nothing.
  f->SetMinimumSize(8);
  f->FillCavitiesOff();
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), BallWithSpeckAndCavity(false, true, d));
  f->FillCavitiesOn();
  f->RemoveIslandsOff();
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), BallWithSpeckAndCavity(true, false, d));
  f->RemoveIslandsOn();
  f->SetMinimumSize(1);
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), noisy);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 0);
}

TEST(IslandFilter, SpeckInsideASmallCavityLeavesNoHole)
{
  // A block with a 3x3x3 hole holding one inside voxel at its centre: the
  // speck is removed, then the whole 27-voxel hole is filled (with
  // MinimumSize 30); the speck's voxel ends inside again and is not counted.
  const int d[3] = { 12, 12, 12 };
  auto image = dgtest::MakeImage(12, 12, 12, [](int i, int j, int k) {
    const bool block = i > 1 && j > 1 && k > 1 && i < 10 && j < 10 && k < 10;
    const bool hole = i >= 5 && j >= 5 && k >= 5 && i <= 7 && j <= 7 && k <= 7;
    const bool speck = i == 6 && j == 6 && k == 6;
    return (block && !hole) || speck ? 1.0 : 0.0;
  });
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(image);
  f->SetMinimumSize(30);
  f->Update();
  const Mask out = ValuesOf(f->GetOutput());
  for (int k = 0; k < 12; ++k)
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 12; ++i)
        ASSERT_EQ(out[(k * 12 + j) * 12 + i], i > 1 && j > 1 && k > 1 && i < 10 && j < 10 && k < 10)
          << i << " " << j << " " << k;
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 1);
  EXPECT_EQ(f->GetNumberOfFilledCavities(), 1);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 26);
  EXPECT_EQ(BruteForce(ValuesOf(image), d, 30, true, true).Result, out);
}

TEST(IslandFilter, TheExteriorIsNeverFilled)
{
  // A block filling the image but for a one-voxel notch in a corner and a
  // 2-voxel groove on one face: both are outside components smaller than
  // MinimumSize, but they touch the border, beyond which everything is
  // outside: they are the exterior and stay. A 2-voxel island on the border
  // of another image is removed.
  auto notched = dgtest::MakeImage(10, 10, 10, [](int i, int j, int k) {
    const bool notch = i == 0 && j == 0 && k == 0;
    const bool groove = k == 9 && j == 5 && (i == 4 || i == 5);
    return notch || groove ? 0.0 : 1.0;
  });
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(notched);
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), ValuesOf(notched));
  EXPECT_EQ(f->GetNumberOfFilledCavities(), 0);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 0);

  auto borderSpeck = dgtest::MakeImage(10, 10, 10, [](int i, int j, int k) {
    const bool ball = (i - 5) * (i - 5) + (j - 5) * (j - 5) + (k - 5) * (k - 5) <= 9;
    const bool speck = i == 9 && j == 0 && (k == 3 || k == 4);
    return ball || speck ? 1.0 : 0.0;
  });
  f->SetInputData(borderSpeck);
  f->Update();
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 1);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 2);
}

TEST(IslandFilter, EdgeContactIsNotConnection)
{
  // Two voxels sharing only an edge, and a speck touching a block at a
  // corner only: with 6-connectivity each is an island of its own.
  auto image = dgtest::MakeImage(12, 12, 12, [](int i, int j, int k) {
    const bool pair = (i == 1 && j == 1 && k == 1) || (i == 2 && j == 2 && k == 1);
    const bool block = i >= 5 && j >= 5 && k >= 5 && i <= 9 && j <= 9 && k <= 9;
    const bool corner = i == 4 && j == 4 && k == 4;
    return pair || block || corner ? 1.0 : 0.0;
  });
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(image);
  f->SetMinimumSize(2);
  f->Update();
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 3);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 3);
}

TEST(IslandFilter, RunningItAgainChangesNothing)
{
  // The paper's noise on a ball: many specks and holes; once cleaned, a
  // second pass finds no island and no cavity below MinimumSize.
  vtkNew<vtkDigitalNoiseFilter> noise;
  noise->SetInputData(dgtest::Ball(48, 15));
  noise->SetNoiseLevel(0.5);
  noise->SetSeed(3);
  for (int minimumSize : { 2, 8, 40 })
  {
    vtkNew<vtkDigitalIslandFilter> once, twice;
    once->SetInputConnection(noise->GetOutputPort());
    once->SetMinimumSize(minimumSize);
    twice->SetInputConnection(once->GetOutputPort());
    twice->SetMinimumSize(minimumSize);
    twice->Update();
    EXPECT_GT(once->GetNumberOfRemovedIslands(), 0) << minimumSize;
    EXPECT_GT(once->GetNumberOfFilledCavities(), 0) << minimumSize;
    EXPECT_EQ(twice->GetNumberOfChangedVoxels(), 0) << minimumSize;
    EXPECT_EQ(ValuesOf(twice->GetOutput()), ValuesOf(once->GetOutput()));
  }
}

TEST(IslandFilter, SelectionModes)
{
  // Label 1: a ball with a 2-voxel speck of label 1; label 2: a block with a
  // 1-voxel speck of label 2 and a 1-voxel cavity (label 0) inside.
  auto labels = dgtest::MakeImage(30, 20, 20, [](int i, int j, int k) {
    if (i == 1 && j == 1 && (k == 1 || k == 2))
      return 1.0;
    if (i == 28 && j == 18 && k == 18)
      return 2.0;
    if (i == 21 && j == 10 && k == 10)
      return 0.0;
    if ((i - 8) * (i - 8) + (j - 10) * (j - 10) + (k - 10) * (k - 10) <= 25)
      return 1.0;
    if (i >= 17 && i <= 25 && j >= 6 && j <= 14 && k >= 6 && k <= 14)
      return 2.0;
    return 0.0;
  }, VTK_SHORT);
  const Mask values = ValuesOf(labels);
  const int d[3] = { 30, 20, 20 };
  const auto selected = [&](auto in) {
    Mask m(values.size());
    for (std::size_t v = 0; v < m.size(); ++v)
      m[v] = in(values[v]);
    return m;
  };
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(labels);

  // Label 2: its speck goes and its cavity is filled; label 1 is outside.
  f->SetSelectionModeToLabel();
  f->SetLabel(2);
  f->Update();
  const Mask two = selected([](int v) { return v == 2; });
  EXPECT_EQ(ValuesOf(f->GetOutput()), BruteForce(two, d, 8, true, true).Result);
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 1);
  EXPECT_EQ(f->GetNumberOfFilledCavities(), 1);
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 2);

  // Label 1: its speck goes; the block of label 2 is outside (and touches
  // no border, but is far larger than MinimumSize).
  f->SetLabel(1);
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), BruteForce(selected([](int v) { return v == 1; }), d, 8, true, true).Result);
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 1);
  EXPECT_EQ(f->GetNumberOfFilledCavities(), 0);

  // Non-zero (default) and the range [1, 2]: both labels; the label-0 voxel
  // inside the block is a cavity.
  f->SetSelectionModeToNonZero();
  f->Update();
  const Mask both = ValuesOf(f->GetOutput());
  EXPECT_EQ(both, BruteForce(selected([](int v) { return v != 0; }), d, 8, true, true).Result);
  EXPECT_EQ(f->GetNumberOfRemovedIslands(), 2);
  EXPECT_EQ(f->GetNumberOfFilledCavities(), 1);
  f->SetSelectionModeToRange();
  f->SetLowerThreshold(1);
  f->SetUpperThreshold(2);
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), both);
  // Range [2, 5]: label 2 only.
  f->SetLowerThreshold(2);
  f->SetUpperThreshold(5);
  f->Update();
  EXPECT_EQ(ValuesOf(f->GetOutput()), BruteForce(two, d, 8, true, true).Result);
}

TEST(IslandFilter, OutputHasTheInputGeometry)
{
  auto image = dgtest::Ball(20, 6);
  image->SetExtent(3, 22, -4, 15, 10, 29);
  image->SetOrigin(1.5, -2, 7);
  image->SetSpacing(0.5, 0.75, 2);
  const double dir[9] = { 0, -1, 0, 1, 0, 0, 0, 0, 1 };
  image->SetDirectionMatrix(dir);
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(image);
  f->Update();
  vtkImageData* out = f->GetOutput();
  int e[6];
  out->GetExtent(e);
  EXPECT_EQ(std::vector<int>(e, e + 6), std::vector<int>({ 3, 22, -4, 15, 10, 29 }));
  EXPECT_DOUBLE_EQ(out->GetOrigin()[0], 1.5);
  EXPECT_DOUBLE_EQ(out->GetOrigin()[1], -2);
  EXPECT_DOUBLE_EQ(out->GetOrigin()[2], 7);
  EXPECT_DOUBLE_EQ(out->GetSpacing()[0], 0.5);
  EXPECT_DOUBLE_EQ(out->GetSpacing()[1], 0.75);
  EXPECT_DOUBLE_EQ(out->GetSpacing()[2], 2);
  for (int a = 0; a < 9; ++a)
    EXPECT_EQ(out->GetDirectionMatrix()->GetData()[a], dir[a]) << a;
  EXPECT_EQ(ValuesOf(out), ValuesOf(image)); // a clean ball: nothing changes
}

TEST(IslandFilter, BadInputGivesAnErrorAndNoOutput)
{
  const auto run = [](vtkImageData* image, int minimumSize, int& errors, std::string& messages) {
    vtkNew<vtkDigitalIslandFilter> f;
    vtkNew<dgtest::ErrorObserver> obs;
    obs->Observe(f);
    obs->Observe(f->GetExecutive());
    f->SetInputData(image);
    f->SetMinimumSize(minimumSize);
    f->Update();
    errors = obs->Errors;
    messages = obs->Messages;
    return f->GetOutput()->GetPointData()->GetScalars() == nullptr;
  };
  int errors = 0;
  std::string messages;
  vtkNew<vtkImageData> noScalars;
  noScalars->SetDimensions(4, 4, 4);
  EXPECT_TRUE(run(noScalars, 8, errors, messages));
  EXPECT_GE(errors, 1);
  EXPECT_NE(messages.find("scalars"), std::string::npos) << messages;

  auto ball = dgtest::Ball(12, 4);
  for (int bad : { 0, -3 })
  {
    EXPECT_TRUE(run(ball, bad, errors, messages));
    EXPECT_GE(errors, 1);
    EXPECT_NE(messages.find("MinimumSize"), std::string::npos) << messages;
  }
  vtkNew<vtkImageData> empty;
  EXPECT_TRUE(run(empty, 8, errors, messages));
  EXPECT_GE(errors, 1);

  // A good run after a bad one: no error.
  EXPECT_FALSE(run(ball, 8, errors, messages));
  EXPECT_EQ(errors, 0) << messages;

  // A bad run after a good one on the same filter: the old result is gone.
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(ball);
  f->Update();
  ASSERT_NE(f->GetOutput()->GetPointData()->GetScalars(), nullptr);
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(f);
  obs->Observe(f->GetExecutive());
  f->SetMinimumSize(0);
  f->Update();
  EXPECT_GE(obs->Errors, 1);
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetScalars(), nullptr);
  EXPECT_EQ(f->GetOutput()->GetFieldData()->GetArray("RemovedIslands"), nullptr);
}

TEST(IslandFilter, WarnsWhenEverythingIsRemoved)
{
  auto tiny = dgtest::MakeImage(6, 6, 6, [](int i, int j, int k) {
    return i >= 2 && i <= 3 && j >= 2 && j <= 3 && k == 2 ? 1.0 : 0.0;
  });
  vtkNew<vtkDigitalIslandFilter> f;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(f);
  f->SetInputData(tiny);
  f->Update();
  EXPECT_EQ(obs->Errors, 0);
  EXPECT_EQ(obs->Warnings, 1);
  EXPECT_NE(obs->Messages.find("MinimumSize"), std::string::npos) << obs->Messages;
  EXPECT_EQ(f->GetNumberOfChangedVoxels(), 4);
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 6 * 6 * 6);
}

namespace
{
// 40^3: a ball and a slab joined by a bar (one big shape), then specks
// (inside) and holes (outside) of 1 to 12 voxels grown by random face
// steps, anywhere: in the air, in the shape, across the image border, on
// each other.
Mask NoisyVolume(unsigned seed, int d[3])
{
  d[0] = d[1] = d[2] = 40;
  Mask m(40 * 40 * 40, 0);
  const auto id = [](int i, int j, int k) { return (std::size_t(k) * 40 + j) * 40 + i; };
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i)
      {
        const int x = i - 14, y = j - 20, z = k - 20;
        const bool ball = x * x + y * y + z * z <= 100;
        const bool slab = i >= 26 && i <= 33 && j >= 4 && j <= 36 && k >= 6 && k <= 34;
        const bool bar = i >= 20 && i <= 27 && j >= 18 && j <= 21 && k >= 18 && k <= 21;
        m[id(i, j, k)] = ball || slab || bar;
      }
  std::mt19937 rng(seed);
  static const int step[6][3] = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 },
    { 0, 0, -1 }, { 0, 0, 1 } };
  for (int blob = 0; blob < 500; ++blob)
  {
    const std::uint8_t value = blob % 2 == 0 ? 1 : 0;
    const int size = 1 + static_cast<int>(rng() % 12);
    int p[3] = { static_cast<int>(rng() % 40), static_cast<int>(rng() % 40),
      static_cast<int>(rng() % 40) };
    for (int v = 0; v < size; ++v)
    {
      m[id(p[0], p[1], p[2])] = value;
      const int* s = step[rng() % 6];
      for (int a = 0; a < 3; ++a)
        p[a] = std::min(39, std::max(0, p[a] + s[a]));
    }
  }
  return m;
}

Mask BoxOf(const Mask& m, const int d[3], const int box[6])
{
  Mask out;
  for (int k = box[4]; k <= box[5]; ++k)
    for (int j = box[2]; j <= box[3]; ++j)
      for (int i = box[0]; i <= box[1]; ++i)
        out.push_back(m[(std::size_t(k) * d[1] + j) * d[0] + i]);
  return out;
}

std::vector<int> ExtentOf(vtkImageData* image)
{
  int e[6];
  image->GetExtent(e);
  return std::vector<int>(e, e + 6);
}

std::string BoxName(const int b[6])
{
  std::ostringstream s;
  s << b[0] << ".." << b[1] << " " << b[2] << ".." << b[3] << " " << b[4] << ".." << b[5];
  return s.str();
}

struct WholeRun
{
  Mask Result;
  vtkIdType Islands = 0, Cavities = 0, Changed = 0;
};

void Configure(vtkDigitalIslandFilter* f, int minimumSize, bool islands, bool cavities)
{
  f->SetMinimumSize(minimumSize);
  f->SetRemoveIslands(islands);
  f->SetFillCavities(cavities);
}

WholeRun RunWhole(vtkImageData* image, int minimumSize, bool islands, bool cavities)
{
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputData(image);
  Configure(f, minimumSize, islands, cavities);
  f->Update();
  return { ValuesOf(f->GetOutput()), f->GetNumberOfRemovedIslands(),
    f->GetNumberOfFilledCavities(), f->GetNumberOfChangedVoxels() };
}
} // namespace

TEST(IslandFilter, SubExtentsEqualTheWholeRun)
{
  // A reader upstream gives exactly the extent asked for, so each run sees
  // only the requested box grown by the filter's reach; the output must be
  // the whole run's voxels on the box, whatever the box.
  const int whole[6] = { 0, 39, 0, 39, 0, 39 };
  int tried = 0, changedSomewhere = 0;
  for (unsigned seed : { 1u, 2u })
  {
    int d[3];
    const Mask noisy = NoisyVolume(seed, d);
    const std::string path = dgtest::TempPath("noisy" + std::to_string(seed) + ".vol");
    std::string error;
    ASSERT_TRUE(dg::WriteVolFile(path, d, noisy.data(), 2, error)) << error;
    auto image = FromMask(noisy, d);
    for (int minimumSize : { 2, 5, 8, 13 })
      for (int flags = 1; flags < 4; ++flags)
      {
        const bool islands = flags & 1, cavities = flags & 2;
        const WholeRun ref = RunWhole(image, minimumSize, islands, cavities);
        ASSERT_EQ(ref.Result, BruteForce(noisy, d, minimumSize, islands, cavities).Result);
        changedSomewhere += ref.Changed > 0;
        const int reach = dg::ComponentReach(minimumSize, islands, cavities);
        // Boxes: inside, on the border, one voxel thick, a single voxel,
        // the whole; then the pieces of 2, 3 and 4 (dg::PieceExtent),
        // whose counts must add up to the whole run's.
        std::vector<std::array<int, 6>> boxes = { { 10, 25, 12, 30, 5, 22 },
          { 0, 39, 0, 39, 0, 9 }, { 30, 39, 0, 12, 27, 39 }, { 17, 17, 0, 39, 0, 39 },
          { 0, 39, 22, 22, 3, 36 }, { 5, 30, 8, 31, 39, 39 }, { 21, 21, 19, 19, 20, 20 },
          { 0, 0, 0, 0, 0, 0 }, { 0, 39, 0, 39, 0, 39 } };
        for (int n : { 2, 3, 4 })
          for (int p = 0; p < n; ++p)
          {
            std::array<int, 6> b;
            ASSERT_TRUE(dg::PieceExtent(whole, p, n, b.data()));
            boxes.push_back(b);
          }
        vtkIdType sums[3][3] = {};
        for (std::size_t c = 0; c < boxes.size(); ++c)
        {
          const int* box = boxes[c].data();
          SCOPED_TRACE(testing::Message() << "seed " << seed << " size " << minimumSize
                                          << " islands " << islands << " cavities " << cavities
                                          << " box " << BoxName(box));
          vtkNew<vtkDGtalVolReader> reader;
          reader->SetFileName(path.c_str());
          vtkNew<vtkDigitalIslandFilter> f;
          f->SetInputConnection(reader->GetOutputPort());
          Configure(f, minimumSize, islands, cavities);
          ASSERT_TRUE(f->UpdateExtent(box));
          EXPECT_EQ(ExtentOf(f->GetOutput()), std::vector<int>(box, box + 6));
          int grown[6];
          dg::GrowExtent(box, reach, whole, grown);
          EXPECT_EQ(ExtentOf(reader->GetOutput()), std::vector<int>(grown, grown + 6))
            << "the reader is asked for the box grown by " << reach;
          ASSERT_EQ(ValuesOf(f->GetOutput()), BoxOf(ref.Result, d, box));
          if (c + 1 == 9)
          {
            // The whole extent: the whole run's counts.
            EXPECT_EQ(f->GetNumberOfRemovedIslands(), ref.Islands);
            EXPECT_EQ(f->GetNumberOfFilledCavities(), ref.Cavities);
            EXPECT_EQ(f->GetNumberOfChangedVoxels(), ref.Changed);
          }
          if (c >= 9)
          {
            const int n = c < 11 ? 0 : c < 14 ? 1 : 2;
            sums[n][0] += f->GetNumberOfRemovedIslands();
            sums[n][1] += f->GetNumberOfFilledCavities();
            sums[n][2] += f->GetNumberOfChangedVoxels();
          }
          ++tried;
        }
        for (const auto& sum : sums)
        {
          EXPECT_EQ(sum[0], ref.Islands) << "pieces' islands add up";
          EXPECT_EQ(sum[1], ref.Cavities) << "pieces' cavities add up";
          EXPECT_EQ(sum[2], ref.Changed) << "pieces' changed voxels add up";
        }
      }
  }
  EXPECT_EQ(tried, 2 * 4 * 3 * 18);
  EXPECT_EQ(changedSomewhere, 2 * 4 * 3);
}

TEST(IslandFilter, PieceRequestsWithGhostLayers)
{
  // UpdatePiece(p, n, g), as ParaView asks on each rank: the executive's
  // piece extent (by cells), g ghost layers marked in vtkGhostType; the
  // voxels are the whole run's. The input is read as one box (piece 0 of
  // 1), so the reader does not split it again.
  int d[3];
  const Mask noisy = NoisyVolume(3, d);
  const std::string path = dgtest::TempPath("noisy3.vol");
  std::string error;
  ASSERT_TRUE(dg::WriteVolFile(path, d, noisy.data(), 2, error)) << error;
  const WholeRun ref = RunWhole(FromMask(noisy, d), 8, true, true);
  int whole[6] = { 0, 39, 0, 39, 0, 39 };
  for (int n : { 2, 3, 4 })
    for (int ghosts : { 0, 1, 3 })
      for (int p = 0; p < n; ++p)
      {
        SCOPED_TRACE(testing::Message() << "piece " << p << " of " << n << " ghosts " << ghosts);
        int expected[6], own[6];
        vtkNew<vtkExtentTranslator> t;
        t->PieceToExtentThreadSafe(p, n, ghosts, whole, expected, vtkExtentTranslator::BLOCK_MODE, 0);
        t->PieceToExtentThreadSafe(p, n, 0, whole, own, vtkExtentTranslator::BLOCK_MODE, 0);
        vtkNew<vtkDGtalVolReader> reader;
        reader->SetFileName(path.c_str());
        vtkNew<vtkDigitalIslandFilter> f;
        f->SetInputConnection(reader->GetOutputPort());
        ASSERT_TRUE(f->UpdatePiece(p, n, ghosts));
        vtkImageData* out = f->GetOutput();
        ASSERT_EQ(ExtentOf(out), std::vector<int>(expected, expected + 6));
        int grown[6];
        dg::GrowExtent(expected, dg::ComponentReach(8, true, true), whole, grown);
        EXPECT_EQ(ExtentOf(reader->GetOutput()), std::vector<int>(grown, grown + 6));
        EXPECT_EQ(
          reader->GetOutput()->GetPointData()->GetArray(vtkDataSetAttributes::GhostArrayName()),
          nullptr);
        ASSERT_EQ(ValuesOf(out), BoxOf(ref.Result, d, expected));
        vtkDataArray* ghost = out->GetPointData()->GetArray(vtkDataSetAttributes::GhostArrayName());
        if (ghosts == 0)
        {
          EXPECT_EQ(ghost, nullptr);
          continue;
        }
        ASSERT_NE(ghost, nullptr);
        vtkIdType marked = 0, outside = 0;
        for (vtkIdType v = 0; v < ghost->GetNumberOfTuples(); ++v)
          marked += ghost->GetTuple1(v) != 0;
        for (int k = expected[4]; k <= expected[5]; ++k)
          for (int j = expected[2]; j <= expected[3]; ++j)
            for (int i = expected[0]; i <= expected[1]; ++i)
              outside += !(i >= own[0] && i <= own[1] && j >= own[2] && j <= own[3] &&
                k >= own[4] && k <= own[5]);
        EXPECT_EQ(marked, outside);
        EXPECT_GT(marked, 0);
      }
}

TEST(IslandFilter, SubExtentOfALargerInput)
{
  // An input that gives more than asked (SetInputData: the whole image):
  // the output is still the requested box, the whole run's voxels.
  int d[3];
  const Mask noisy = NoisyVolume(4, d);
  auto image = FromMask(noisy, d);
  const WholeRun ref = RunWhole(image, 8, true, true);
  for (const auto& box : std::vector<std::array<int, 6>>{
         { 3, 20, 0, 39, 11, 12 }, { 39, 39, 0, 39, 0, 39 }, { 8, 31, 8, 31, 8, 31 } })
  {
    vtkNew<vtkDigitalIslandFilter> f;
    f->SetInputData(image);
    ASSERT_TRUE(f->UpdateExtent(box.data()));
    EXPECT_EQ(ExtentOf(f->GetOutput()), std::vector<int>(box.begin(), box.end()));
    EXPECT_EQ(ValuesOf(f->GetOutput()), BoxOf(ref.Result, d, box.data())) << BoxName(box.data());
  }
}

TEST(IslandFilter, MinimumSizeOnePassesPiecesThrough)
{
  // MinimumSize 1 changes nothing (0 is an error, as on the whole image):
  // the reach is 0, the reader is asked for the box itself.
  int d[3];
  const Mask noisy = NoisyVolume(5, d);
  const std::string path = dgtest::TempPath("noisy5.vol");
  std::string error;
  ASSERT_TRUE(dg::WriteVolFile(path, d, noisy.data(), 2, error)) << error;
  const int whole[6] = { 0, 39, 0, 39, 0, 39 };
  for (int p = 0; p < 3; ++p)
  {
    int box[6];
    ASSERT_TRUE(dg::PieceExtent(whole, p, 3, box));
    vtkNew<vtkDGtalVolReader> reader;
    reader->SetFileName(path.c_str());
    vtkNew<vtkDigitalIslandFilter> f;
    f->SetInputConnection(reader->GetOutputPort());
    f->SetMinimumSize(1);
    ASSERT_TRUE(f->UpdateExtent(box));
    EXPECT_EQ(ExtentOf(reader->GetOutput()), std::vector<int>(box, box + 6));
    EXPECT_EQ(ValuesOf(f->GetOutput()), BoxOf(noisy, d, box));
    EXPECT_EQ(f->GetNumberOfChangedVoxels(), 0);
  }
  vtkNew<vtkDGtalVolReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkDigitalIslandFilter> f;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(f);
  obs->Observe(f->GetExecutive());
  f->SetInputConnection(reader->GetOutputPort());
  f->SetMinimumSize(0);
  int box[6];
  ASSERT_TRUE(dg::PieceExtent(whole, 1, 3, box));
  f->UpdateExtent(box);
  EXPECT_GE(obs->Errors, 1);
  EXPECT_NE(obs->Messages.find("MinimumSize"), std::string::npos) << obs->Messages;
  EXPECT_EQ(f->GetOutput()->GetPointData()->GetScalars(), nullptr);
}

TEST(IslandFilter, EmptyPieceIsNoError)
{
  // More pieces than voxel slabs: some pieces hold no voxel.
  auto image = dgtest::Ball(6, 2);
  vtkNew<vtkDigitalIslandFilter> f;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(f);
  obs->Observe(f->GetExecutive());
  f->SetInputData(image);
  const int empty[6] = { 0, -1, 0, -1, 0, -1 };
  ASSERT_TRUE(f->UpdateExtent(empty));
  EXPECT_EQ(obs->Errors, 0) << obs->Messages;
  EXPECT_EQ(f->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(IslandFilter, CavitiesDependOnIslandsTwiceTheReachAway)
{
  // Why both passes need 2 (MinimumSize - 1) layers, not MinimumSize: a
  // dead-end tunnel of 7 outside voxels (x = 9..15) starts in the box
  // (x <= 9) and ends on a 2-voxel island (x = 16, 17) sitting in a small
  // chamber. The whole run removes the island, which joins tunnel and
  // chamber into one outside component of 18 voxels: not a cavity to fill.
  // With only MinimumSize = 8 layers, the window would end at x = 17, keep
  // the island (it touches the open face) and fill the tunnel, box voxel
  // x = 9 included.
  const int d[3] = { 30, 9, 9 };
  auto image = dgtest::MakeImage(30, 9, 9, [](int i, int j, int k) {
    const bool solid = i >= 1 && i <= 28 && j >= 1 && j <= 7 && k >= 1 && k <= 7;
    const bool tunnel = j == 4 && k == 4 && i >= 9 && i <= 15;
    const bool island = j == 4 && k == 4 && (i == 16 || i == 17);
    const bool chamber = (i == 16 || i == 17) && (std::abs(j - 4) + std::abs(k - 4) == 1);
    const bool end = i == 18 && j == 4 && k == 4;
    if (island)
      return 1.0;
    return solid && !tunnel && !chamber && !end ? 1.0 : 0.0;
  });
  const Mask in = ValuesOf(image);
  const WholeRun ref = RunWhole(image, 8, true, true);
  ASSERT_EQ(ref.Result, BruteForce(in, d, 8, true, true).Result);
  EXPECT_EQ(ref.Islands, 1);
  EXPECT_EQ(ref.Cavities, 0);
  EXPECT_EQ(ref.Result[(std::size_t(4) * 9 + 4) * 30 + 9], 0) << "the tunnel stays open";
  EXPECT_EQ(dg::ComponentReach(8, true, true), 14);
  const std::string path = dgtest::TempPath("tunnel.vol");
  Mask bytes = in;
  std::string error;
  ASSERT_TRUE(dg::WriteVolFile(path, d, bytes.data(), 2, error)) << error;
  const int box[6] = { 0, 9, 0, 8, 0, 8 };
  vtkNew<vtkDGtalVolReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkDigitalIslandFilter> f;
  f->SetInputConnection(reader->GetOutputPort());
  ASSERT_TRUE(f->UpdateExtent(box));
  EXPECT_EQ(ValuesOf(f->GetOutput()), BoxOf(ref.Result, d, box));
  // The same box labelled in a window of only MinimumSize layers does fill
  // the tunnel: the reach is not a mere safety margin.
  Mask window = BoxOf(in, d, std::array<int, 6>{ 0, 17, 0, 8, 0, 8 }.data());
  const int wd[3] = { 18, 9, 9 };
  dg::ComponentWindow w;
  w.OpenFaces = 2; // x high
  w.Counted[1] = 9;
  w.Counted[3] = 8;
  w.Counted[5] = 8;
  dg::IslandCounts counts;
  ASSERT_TRUE(dg::RemoveSmallComponents(window.data(), wd, 8, true, true, counts, {}, &w));
  EXPECT_EQ(window[(std::size_t(4) * 9 + 4) * 18 + 9], 1);
}
