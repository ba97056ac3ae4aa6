// vtkDigitalIslandFilter: small islands removed and small cavities filled,
// against a brute-force breadth-first search (6-connectivity) on random
// voxel sets; a ball with a speck and a cavity; the exterior is never
// filled; selection modes; geometry kept; bad input; sub-extents and pieces
// equal, voxel for voxel, to the whole run.
// Sub-extents and pieces: TestIslandPieces.cxx.
#include "dgIslands.h"
#include "dgPieces.h"
#include "dgIslandTestSupport.h"
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
using dgtest::BruteForce;
using dgtest::BruteForceComponents;
using dgtest::FromMask;
using dgtest::Mask;
using dgtest::Reference;
using dgtest::ValuesOf;

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
  const Case cases[] = { { { 13, 11, 9 }, 0.3 },
    { { 10, 12, 14 }, 0.5 },
    { { 9, 9, 12 }, 0.75 },
    { { 17, 5, 3 }, 0.6 },
    { { 14, 12, 1 }, 0.55 },
    { { 45, 9, 8 }, 0.97 },
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
          SCOPED_TRACE(testing::Message()
                       << c.Dims[0] << "x" << c.Dims[1] << "x" << c.Dims[2] << " p " << c.P
                       << " seed " << seed << " size " << minimumSize << " islands " << islands
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
  auto image = dgtest::MakeImage(12,
    12,
    12,
    [](int i, int j, int k)
    {
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
  auto notched = dgtest::MakeImage(10,
    10,
    10,
    [](int i, int j, int k)
    {
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

  auto borderSpeck = dgtest::MakeImage(10,
    10,
    10,
    [](int i, int j, int k)
    {
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
  auto image = dgtest::MakeImage(12,
    12,
    12,
    [](int i, int j, int k)
    {
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
  auto labels = dgtest::MakeImage(
    30,
    20,
    20,
    [](int i, int j, int k)
    {
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
    },
    VTK_SHORT);
  const Mask values = ValuesOf(labels);
  const int d[3] = { 30, 20, 20 };
  const auto selected = [&](auto in)
  {
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
  EXPECT_EQ(ValuesOf(f->GetOutput()),
    BruteForce(selected([](int v) { return v == 1; }), d, 8, true, true).Result);
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
  const auto run = [](vtkImageData* image, int minimumSize, int& errors, std::string& messages)
  {
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
  auto tiny = dgtest::MakeImage(6,
    6,
    6,
    [](int i, int j, int k) { return i >= 2 && i <= 3 && j >= 2 && j <= 3 && k == 2 ? 1.0 : 0.0; });
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
