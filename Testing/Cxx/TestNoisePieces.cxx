// The noise on pieces (issue 38): a box grown by the reach gives the
// whole-volume noise on the box, bit for bit; every voxel that could differ
// is counted; through the pipeline each piece (2, 3, 4 pieces, with and
// without ghost levels) equals the whole run on its extent and reads its
// extent grown by the reach, not the whole volume.
#include "dgNoise.h"
#include "dgPieces.h"
#include "dgTestShapes.h"
#include "dgTestTemp.h"
#include "dgVolFormat.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalNoiseFilter.h"

#include <vtkExtentTranslator.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkTrivialProducer.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace
{
using Volume = std::vector<std::uint8_t>;

// A rotated cube and a ball along a long box, and 1 % specks and holes:
// boundary everywhere near the cuts, and voxels far from any boundary
// (inside the cube, in the air) whose distances a box does not see.
Volume Shapes(const int d[3])
{
  Volume v(static_cast<std::size_t>(d[0]) * d[1] * d[2]);
  std::mt19937 rng(17);
  const double c = std::cos(0.5), s = std::sin(0.5);
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
      {
        const double x = i - 0.5 * d[0] + 0.3, y = j - 0.5 * d[1] - 0.2;
        const double zc = k - 0.3 * d[2] + 0.1, zb = k - 0.72 * d[2];
        const double rx = c * x - s * y, ry = s * x + c * y;
        const bool cube = std::abs(rx) < 15 && std::abs(c * ry - s * zc) < 14 &&
          std::abs(s * ry + c * zc) < 16;
        const bool ball = x * x + y * y + zb * zb < 19.5 * 19.5;
        const bool speck = rng() % 100 == 0;
        v[(static_cast<std::size_t>(k) * d[1] + j) * d[0] + i] = (cube || ball) != speck;
      }
  return v;
}

// The voxels of `box` out of a volume over `extent`.
Volume Cut(const Volume& v, const int extent[6], const int box[6])
{
  Volume out(static_cast<std::size_t>(box[1] - box[0] + 1) * (box[3] - box[2] + 1) *
    (box[5] - box[4] + 1));
  dg::CopyExtent(v.data(), extent, box, 1, out.data());
  return out;
}

std::int64_t Voxels(const int e[6])
{
  return dg::ExtentEmpty(e)
    ? 0
    : std::int64_t(e[1] - e[0] + 1) * (e[3] - e[2] + 1) * (e[5] - e[4] + 1);
}
} // namespace

TEST(NoisePieces, ReachIsTheSmallestBelowTheBound)
{
  for (double k : { 0.1, 0.3, 0.5, 0.9 })
    for (double n : { 1e3, 1.0 * (1 << 24), 1e12 })
      for (double bound : { 1e-9, 1e-6, 1e-2 })
      {
        const int r = dg::NoiseReach(k, n, bound, 1 << 20);
        ASSERT_GE(r, 1);
        // n k^(1 + r) <= bound, and one layer less would not do (unless r
        // is the minimum of 1); 1e-9 relative slack for the logarithms.
        EXPECT_LE(n * std::pow(k, 1.0 + r), bound * (1 + 1e-9)) << k << " " << n << " " << bound;
        if (r > 1)
        {
          EXPECT_GT(n * std::pow(k, static_cast<double>(r)), bound * (1 - 1e-9))
            << k << " " << n << " " << bound;
        }
      }
  EXPECT_EQ(dg::NoiseReach(0.0, 1e6, 1e-6, 100), 0);  // no noise: nothing beyond the box
  EXPECT_EQ(dg::NoiseReach(1.0, 1e6, 1e-6, 100), 100); // k = 1: the whole volume
  EXPECT_EQ(dg::NoiseReach(0.3, 1e6, 0.0, 100), 100);  // bound 0: exact, the whole volume
  EXPECT_EQ(dg::NoiseReach(0.3, 1e6, std::nan(""), 100), 100);
  EXPECT_EQ(dg::NoiseReach(0.999, 1e6, 1e-6, 100), 100); // capped at the largest axis
}

// Plain C++: boxes of every size against the whole volume. A voxel nearer
// than the reach to the whole volume's boundary must get its decision
// exactly; a voxel that differs must have been counted as uncertain; with
// the reach of the default bound nothing differs and nothing is uncertain.
TEST(NoisePieces, BoxesGiveTheWholeVolumeNoise)
{
  const int d[3] = { 48, 48, 48 };
  const Volume original = Shapes(d);
  dg::NoiseBox whole;
  for (int a = 0; a < 3; ++a)
  {
    whole.Whole[2 * a] = whole.Box[2 * a] = whole.Out[2 * a] = 0;
    whole.Whole[2 * a + 1] = whole.Box[2 * a + 1] = whole.Out[2 * a + 1] = d[a] - 1;
  }
  Volume boundary;
  dg::BoundaryVoxels(original, d, boundary);
  std::vector<std::int64_t> d2;
  dg::SquaredDistanceTransform(boundary, d, d2);
  std::mt19937 rng(3);
  for (double k : { 0.3, 0.5 })
  {
    Volume reference = original;
    dg::NoiseCounts all;
    ASSERT_TRUE(dg::ApplyNoise(reference.data(), whole, k, 11, reference.data(), all));
    EXPECT_EQ(all.Uncertain, 0);
    EXPECT_GT(all.Flipped, 1000);
    const int defaultReach = dg::NoiseReach(k, 48.0 * 48 * 48, 1e-6, 48);
    std::int64_t uncertain = 0, differing = 0;
    for (int reach : { 1, 2, 4, 8, defaultReach })
    {
      std::vector<std::array<int, 6>> outs;
      for (int n : { 2, 3, 4, 7 })
        for (int p = 0; p < n; ++p)
        {
          std::array<int, 6> e;
          dg::PieceExtent(whole.Whole, p, n, e.data());
          outs.push_back(e);
        }
      for (int t = 0; t < 6; ++t)
      {
        std::array<int, 6> e;
        for (int a = 0; a < 3; ++a)
        {
          const int u = rng() % d[a], v = rng() % d[a];
          e[2 * a] = std::min(u, v);
          e[2 * a + 1] = std::max(u, v);
        }
        outs.push_back(e);
      }
      for (const auto& e : outs)
      {
        dg::NoiseBox b = whole;
        std::copy(e.begin(), e.end(), b.Out);
        dg::GrowExtent(b.Out, reach, b.Whole, b.Box);
        const Volume in = Cut(original, b.Whole, b.Box);
        Volume result(Voxels(b.Out), 7);
        dg::NoiseCounts counts;
        ASSERT_TRUE(dg::ApplyNoise(in.data(), b, k, 11, result.data(), counts));
        const Volume expected = Cut(reference, b.Whole, b.Out);
        std::int64_t differ = 0, flips = 0;
        std::size_t o = 0;
        for (int z = b.Out[4]; z <= b.Out[5]; ++z)
          for (int y = b.Out[2]; y <= b.Out[3]; ++y)
            for (int x = b.Out[0]; x <= b.Out[1]; ++x, ++o)
            {
              const std::size_t g = (std::size_t(z) * d[1] + y) * d[0] + x;
              flips += result[o] != original[g];
              if (result[o] != expected[o])
              {
                ++differ;
                ASSERT_GE(d2[g], std::int64_t(reach) * reach)
                  << "a voxel nearer than the reach to the boundary differs: k " << k
                  << ", reach " << reach << ", voxel " << x << " " << y << " " << z;
              }
            }
        EXPECT_EQ(counts.Flipped, flips);
        EXPECT_LE(differ, counts.Uncertain) << "a voxel differs without being counted";
        uncertain += counts.Uncertain;
        differing += differ;
        if (reach == defaultReach)
        {
          EXPECT_EQ(differ, 0);
          EXPECT_EQ(counts.Uncertain, 0);
        }
      }
    }
    // The small reaches must have exercised the count (else it proves nothing).
    EXPECT_GT(differing, 0) << "k " << k;
    EXPECT_GT(uncertain, differing) << "k " << k;
  }
}

TEST(NoisePieces, CountedExtentAndLevelZero)
{
  const int d[3] = { 30, 20, 25 };
  const Volume original = Shapes(d);
  dg::NoiseBox b;
  for (int a = 0; a < 3; ++a)
  {
    b.Whole[2 * a] = b.Box[2 * a] = b.Out[2 * a] = 0;
    b.Whole[2 * a + 1] = b.Box[2 * a + 1] = b.Out[2 * a + 1] = d[a] - 1;
  }
  Volume v = original;
  dg::NoiseCounts all;
  ASSERT_TRUE(dg::ApplyNoise(v.data(), b, 0.4, 5, v.data(), all));
  std::int64_t sum = 0;
  for (int p = 0; p < 5; ++p)
  {
    dg::NoiseBox c = b;
    dg::PieceExtent(b.Whole, p, 5, c.Counted);
    Volume w = original;
    dg::NoiseCounts counts;
    ASSERT_TRUE(dg::ApplyNoise(w.data(), c, 0.4, 5, w.data(), counts));
    EXPECT_EQ(w, v); // counting changes nothing else
    sum += counts.Flipped;
  }
  EXPECT_EQ(sum, all.Flipped);

  // k = 0 copies the box's voxels of Out, flips nothing, reads nothing beyond.
  dg::NoiseBox z = b;
  const int out[6] = { 3, 9, 2, 2, 4, 20 };
  std::copy(out, out + 6, z.Out);
  Volume result(Voxels(out));
  dg::NoiseCounts counts;
  ASSERT_TRUE(dg::ApplyNoise(original.data(), z, 0.0, 5, result.data(), counts));
  EXPECT_EQ(result, Cut(original, b.Whole, out));
  EXPECT_EQ(counts.Flipped, 0);
  EXPECT_EQ(dg::NoiseReach(0.0, 1e4, 1e-6, 30), 0);
}

namespace
{
struct VolPipeline
{
  vtkNew<vtkDGtalVolReader> Reader;
  vtkNew<vtkDigitalNoiseFilter> Noise;
  explicit VolPipeline(const std::string& path, double k)
  {
    this->Reader->SetFileName(path.c_str());
    this->Noise->SetInputConnection(this->Reader->GetOutputPort());
    this->Noise->SetNoiseLevel(k);
    this->Noise->SetSeed(4);
  }
};

Volume Values(vtkImageData* image)
{
  auto* s = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  return s ? Volume(s->GetPointer(0), s->GetPointer(0) + s->GetNumberOfValues()) : Volume();
}
} // namespace

// Through VTK's pipeline, on a 48 x 48 x 144 volume read from a .vol: a
// long box, so that a piece grown by the reach (21 layers at k = 0.3, 38 at
// 0.5) is still less than the whole.
TEST(NoisePieces, PiecesEqualTheWholeRunAndReadTheirReach)
{
  const int d[3] = { 48, 48, 144 };
  const Volume original = Shapes(d);
  const std::string path = dgtest::TempPath("shapes.vol");
  std::string error;
  ASSERT_TRUE(dg::WriteVolFile(path, d, original.data(), 2, error)) << error;
  const int wholeExt[6] = { 0, d[0] - 1, 0, d[1] - 1, 0, d[2] - 1 };
  for (double k : { 0.3, 0.5 })
  {
    SCOPED_TRACE(k);
    VolPipeline one(path, k);
    one.Noise->Update();
    const Volume whole = Values(one.Noise->GetOutput());
    ASSERT_EQ(whole.size(), original.size());
    const vtkIdType wholeFlips = one.Noise->GetNumberOfFlippedVoxels();
    ASSERT_GT(wholeFlips, 1000);
    EXPECT_EQ(one.Noise->GetNumberOfUncertainVoxels(), 0);

    VolPipeline piece(path, k);
    vtkNew<dgtest::ErrorObserver> messages;
    messages->Observe(piece.Noise);
    messages->Observe(piece.Noise->GetExecutive());
    const int reach = piece.Noise->ComputeReach(double(Voxels(wholeExt)), d[2]);
    EXPECT_EQ(reach, dg::NoiseReach(k, double(Voxels(wholeExt)), 1e-6, d[2]));
    for (int n : { 2, 3, 4 })
    {
      vtkIdType ownFlips = 0;
      for (int p = 0; p < n; ++p)
        for (int ghosts : { 0, 1 })
        {
          SCOPED_TRACE(std::to_string(p) + " of " + std::to_string(n) + ", ghosts " +
            std::to_string(ghosts));
          int own[6];
          dg::PieceExtent(wholeExt, p, n, own);
          piece.Noise->SetCountedExtent(own);
          ASSERT_TRUE(piece.Noise->UpdatePiece(p, n, ghosts));
          vtkImageData* out = piece.Noise->GetOutput();
          // The executive's piece (by cells, ghosts included) ...
          int expected[6], ext[6];
          std::copy(wholeExt, wholeExt + 6, expected);
          vtkNew<vtkExtentTranslator> t;
          int all[6];
          std::copy(wholeExt, wholeExt + 6, all);
          t->PieceToExtentThreadSafe(p, n, ghosts, all, expected, vtkExtentTranslator::BLOCK_MODE, 0);
          out->GetExtent(ext);
          ASSERT_TRUE(std::equal(ext, ext + 6, expected));
          // ... is the whole run's there, bit for bit ...
          EXPECT_EQ(Values(out), Cut(whole, wholeExt, ext));
          EXPECT_EQ(piece.Noise->GetNumberOfUncertainVoxels(), 0);
          // ... from the piece grown by the reach, not the whole volume:
          // what it asks for, and what a fresh pipeline (a rank's) reads.
          // The kept pipeline's reader may hold more, from an earlier
          // piece (VTK does not re-execute a source whose output covers
          // the request): the filter takes any box that holds the reach.
          int grown[6], asked[6], read[6];
          dg::GrowExtent(ext, reach, wholeExt, grown);
          piece.Noise->GetInputInformation(0, 0)->Get(
            vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), asked);
          EXPECT_TRUE(std::equal(asked, asked + 6, grown));
          VolPipeline fresh(path, k);
          ASSERT_TRUE(fresh.Noise->UpdatePiece(p, n, ghosts));
          fresh.Reader->GetOutput()->GetExtent(read);
          EXPECT_TRUE(std::equal(read, read + 6, grown))
            << "read " << read[4] << ".." << read[5] << ", expected " << grown[4] << ".."
            << grown[5];
          EXPECT_LT(Voxels(read), Voxels(wholeExt));
          EXPECT_EQ(Values(fresh.Noise->GetOutput()), Values(out));
          EXPECT_EQ(piece.Noise->GetReach(), reach);
          if (ghosts == 0)
          {
            ownFlips += piece.Noise->GetNumberOfFlippedVoxels();
          }
        }
      // Each piece counts its own voxels: the counts add up.
      EXPECT_EQ(ownFlips, wholeFlips) << n << " pieces";
    }
    EXPECT_EQ(messages->Errors + messages->Warnings, 0) << messages->Messages;

    // UncertaintyBound 0: the whole volume is read, for the same piece.
    piece.Noise->SetUncertaintyBound(0);
    piece.Noise->SetCountedExtent(wholeExt);
    ASSERT_TRUE(piece.Noise->UpdatePiece(1, 3, 0));
    int read[6];
    piece.Reader->GetOutput()->GetExtent(read);
    EXPECT_TRUE(std::equal(read, read + 6, wholeExt));
    int ext[6];
    piece.Noise->GetOutput()->GetExtent(ext);
    EXPECT_EQ(Values(piece.Noise->GetOutput()), Cut(whole, wholeExt, ext));
  }
}

// A bound so loose that the reach is 1 layer: the pieces may differ from
// the whole run, and then say so (a warning and the count), never silently.
TEST(NoisePieces, ALooseBoundWarnsOfTheVoxelsThatMayDiffer)
{
  const int d[3] = { 48, 48, 48 };
  const Volume original = Shapes(d);
  const std::string path = dgtest::TempPath("shapes.vol");
  std::string error;
  ASSERT_TRUE(dg::WriteVolFile(path, d, original.data(), 2, error)) << error;
  const int wholeExt[6] = { 0, 47, 0, 47, 0, 47 };
  VolPipeline one(path, 0.5);
  one.Noise->Update();
  const Volume whole = Values(one.Noise->GetOutput());
  VolPipeline piece(path, 0.5);
  piece.Noise->SetUncertaintyBound(1e6);
  vtkNew<dgtest::ErrorObserver> messages;
  messages->Observe(piece.Noise);
  std::int64_t uncertain = 0, differing = 0;
  for (int p = 0; p < 4; ++p)
  {
    messages->Clear();
    ASSERT_TRUE(piece.Noise->UpdatePiece(p, 4, 0));
    EXPECT_EQ(piece.Noise->GetReach(), 1);
    int ext[6];
    piece.Noise->GetOutput()->GetExtent(ext);
    const Volume got = Values(piece.Noise->GetOutput()), want = Cut(whole, wholeExt, ext);
    ASSERT_EQ(got.size(), want.size());
    std::int64_t differ = 0;
    for (std::size_t i = 0; i < got.size(); ++i)
      differ += got[i] != want[i];
    const vtkIdType u = piece.Noise->GetNumberOfUncertainVoxels();
    EXPECT_LE(differ, u);
    EXPECT_EQ(messages->Warnings, u > 0 ? 1 : 0) << messages->Messages;
    EXPECT_EQ(messages->Errors, 0) << messages->Messages;
    if (u > 0)
    {
      EXPECT_NE(messages->Messages.find("may differ from the whole-volume noise"), std::string::npos)
        << messages->Messages;
    }
    uncertain += u;
    differing += differ;
  }
  EXPECT_GT(uncertain, 0);
}

TEST(NoisePieces, AnInputWithoutTheReachIsAnError)
{
  // An image smaller than the whole extent its producer announces, as a
  // source that ignores the request would give: the filter refuses it
  // rather than noise a box without its surroundings.
  auto image =
    dgtest::MakeImage(10, 10, 10, [](int i, int j, int k) { return (i + j + k) % 5 == 0; });
  vtkNew<vtkTrivialProducer> producer;
  producer->SetOutput(image);
  producer->SetWholeExtent(0, 9, 0, 9, 0, 29);
  vtkNew<vtkDigitalNoiseFilter> noise;
  vtkNew<dgtest::ErrorObserver> messages;
  messages->Observe(noise);
  messages->Observe(noise->GetExecutive());
  noise->SetInputConnection(producer->GetOutputPort());
  noise->SetNoiseLevel(0.3);
  const int box[6] = { 0, 9, 0, 9, 0, 4 };
  noise->UpdateExtent(box);
  EXPECT_GE(messages->Errors, 1);
  EXPECT_NE(messages->Messages.find("does not hold the requested extent"), std::string::npos)
    << messages->Messages;
  EXPECT_EQ(noise->GetOutput()->GetPointData()->GetScalars(), nullptr);
}
