// vtkDigitalIslandFilter on sub-extents and pieces: each box of a noisy
// volume, with the filter's ghost layers, equal voxel for voxel to the whole
// run (islands and cavities that reach across piece borders included).
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
using dgtest::FromMask;
using dgtest::Mask;
using dgtest::Reference;
using dgtest::ValuesOf;
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
  static const int step[6][3] = {
    { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 }
  };
  for (int blob = 0; blob < 500; ++blob)
  {
    const std::uint8_t value = blob % 2 == 0 ? 1 : 0;
    const int size = 1 + static_cast<int>(rng() % 12);
    int p[3] = {
      static_cast<int>(rng() % 40), static_cast<int>(rng() % 40), static_cast<int>(rng() % 40)
    };
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
  return { ValuesOf(f->GetOutput()),
    f->GetNumberOfRemovedIslands(),
    f->GetNumberOfFilledCavities(),
    f->GetNumberOfChangedVoxels() };
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
          { 0, 39, 0, 39, 0, 9 },
          { 30, 39, 0, 12, 27, 39 },
          { 17, 17, 0, 39, 0, 39 },
          { 0, 39, 22, 22, 3, 36 },
          { 5, 30, 8, 31, 39, 39 },
          { 21, 21, 19, 19, 20, 20 },
          { 0, 0, 0, 0, 0, 0 },
          { 0, 39, 0, 39, 0, 39 } };
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
          SCOPED_TRACE(testing::Message()
                       << "seed " << seed << " size " << minimumSize << " islands " << islands
                       << " cavities " << cavities << " box " << BoxName(box));
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
    {
      // The pieces overlap (by cells, and their ghost layers): counted on
      // each piece's own voxels (CountedExtent, dg::PieceExtent) they add
      // up to the whole run's.
      vtkIdType sums[3] = {};
      for (int p = 0; p < n; ++p)
      {
        SCOPED_TRACE(testing::Message() << "piece " << p << " of " << n << " ghosts " << ghosts);
        int expected[6], own[6];
        vtkNew<vtkExtentTranslator> t;
        t->PieceToExtentThreadSafe(
          p, n, ghosts, whole, expected, vtkExtentTranslator::BLOCK_MODE, 0);
        t->PieceToExtentThreadSafe(p, n, 0, whole, own, vtkExtentTranslator::BLOCK_MODE, 0);
        vtkNew<vtkDGtalVolReader> reader;
        reader->SetFileName(path.c_str());
        vtkNew<vtkDigitalIslandFilter> f;
        f->SetInputConnection(reader->GetOutputPort());
        int counted[6];
        dg::PieceExtent(whole, p, n, counted);
        f->SetCountedExtent(counted);
        ASSERT_TRUE(f->UpdatePiece(p, n, ghosts));
        sums[0] += f->GetNumberOfRemovedIslands();
        sums[1] += f->GetNumberOfFilledCavities();
        sums[2] += f->GetNumberOfChangedVoxels();
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
      EXPECT_EQ(sums[0], ref.Islands) << n << " pieces, " << ghosts << " ghost levels";
      EXPECT_EQ(sums[1], ref.Cavities) << n << " pieces, " << ghosts << " ghost levels";
      EXPECT_EQ(sums[2], ref.Changed) << n << " pieces, " << ghosts << " ghost levels";
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
  auto image = dgtest::MakeImage(30,
    9,
    9,
    [](int i, int j, int k)
    {
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
