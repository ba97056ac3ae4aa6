// The paper's noise model (docs/method.md section 7): exact distance transform,
// flip rates k^(1 + d) by distance, k = 0 is the identity, seeds repeat.
#include "dgGroundTruth.h"
#include "dgNoise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

namespace
{
std::vector<std::uint8_t> BallVolume(int n, double r, int dims[3])
{
  dims[0] = dims[1] = dims[2] = n;
  std::vector<std::uint8_t> v(std::size_t(n) * n * n);
  const double c = 0.5 * (n - 1) + 0.21;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        v[(std::size_t(k) * n + j) * n + i] =
          (i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c) <= r * r;
  return v;
}
} // namespace

TEST(Noise, DistanceTransformMatchesBruteForce)
{
  std::mt19937 rng(5);
  for (int trial = 0; trial < 4; ++trial)
  {
    const int dims[3] = { 7 + trial, 9, 6 + 2 * trial };
    std::vector<std::uint8_t> seeds(std::size_t(dims[0]) * dims[1] * dims[2]);
    for (auto& s : seeds)
    {
      s = rng() % 23 == 0;
    }
    std::vector<std::int64_t> d2;
    dg::SquaredDistanceTransform(seeds, dims, d2);
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i)
        {
          std::int64_t best = -1;
          for (int z = 0; z < dims[2]; ++z)
            for (int y = 0; y < dims[1]; ++y)
              for (int x = 0; x < dims[0]; ++x)
                if (seeds[(std::size_t(z) * dims[1] + y) * dims[0] + x])
                {
                  const std::int64_t d = std::int64_t(x - i) * (x - i) +
                    std::int64_t(y - j) * (y - j) + std::int64_t(z - k) * (z - k);
                  best = best < 0 ? d : std::min(best, d);
                }
          const std::int64_t got = d2[(std::size_t(k) * dims[1] + j) * dims[0] + i];
          if (best < 0)
          {
            ASSERT_GT(got, std::int64_t(1) << 40);
          }
          else
          {
            ASSERT_EQ(got, best) << i << " " << j << " " << k;
          }
        }
  }
}

TEST(Noise, ZeroLevelLeavesTheVolumeUnchanged)
{
  int dims[3];
  auto v = BallVolume(24, 8, dims);
  auto copy = v;
  EXPECT_EQ(dg::ApplyNoise(v, dims, 0.0, 1), 0);
  EXPECT_EQ(v, copy);
}

TEST(Noise, FlipRateIsKToTheOnePlusDistance)
{
  int dims[3];
  const auto original = BallVolume(64, 22, dims);
  std::vector<std::uint8_t> boundary;
  dg::BoundaryVoxels(original, dims, boundary);
  std::vector<std::int64_t> d2;
  dg::SquaredDistanceTransform(boundary, dims, d2);
  for (double k : { 0.1, 0.3, 0.5 })
  {
    // Count flips by distance class over several seeds.
    std::map<std::int64_t, std::pair<double, double>> byD2; // d2 -> (flips, voxels)
    for (std::uint64_t seed = 1; seed <= 3; ++seed)
    {
      auto v = original;
      dg::ApplyNoise(v, dims, k, seed);
      for (std::size_t p = 0; p < v.size(); ++p)
      {
        if (d2[p] <= 9)
        {
          auto& e = byD2[d2[p]];
          e.first += v[p] != original[p];
          e.second += 1;
        }
      }
    }
    for (const auto& e : byD2)
    {
      const double n = e.second.second;
      const double expected = std::pow(k, 1.0 + std::sqrt(static_cast<double>(e.first)));
      const double observed = e.second.first / n;
      // Binomial standard deviation, 5 sigma plus a small floor.
      const double sigma = std::sqrt(expected * (1 - expected) / n);
      EXPECT_NEAR(observed, expected, 5 * sigma + 1e-4)
        << "k = " << k << ", d^2 = " << e.first << ", " << n << " voxels";
    }
    // Boundary voxels (d = 0) flip at rate k.
    EXPECT_GT(byD2[0].second, 10000);
  }
}

TEST(Noise, SameSeedSameVolumeOtherSeedOtherVolume)
{
  int dims[3];
  const auto original = BallVolume(32, 10, dims);
  auto a = original, b = original, c = original;
  const auto fa = dg::ApplyNoise(a, dims, 0.3, 42);
  const auto fb = dg::ApplyNoise(b, dims, 0.3, 42);
  dg::ApplyNoise(c, dims, 0.3, 43);
  EXPECT_EQ(fa, fb);
  EXPECT_GT(fa, 100);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

#include "dgTestShapes.h"
#include "vtkDigitalNoiseFilter.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

namespace
{
std::vector<std::uint8_t> NoisyValues(vtkImageData* image, double k, unsigned seed)
{
  vtkNew<vtkDigitalNoiseFilter> noise;
  noise->SetInputData(image);
  noise->SetNoiseLevel(k);
  noise->SetSeed(seed);
  noise->Update();
  auto* s = vtkUnsignedCharArray::SafeDownCast(noise->GetOutput()->GetPointData()->GetScalars());
  if (!s)
  {
    return {};
  }
  return std::vector<std::uint8_t>(s->GetPointer(0), s->GetPointer(0) + s->GetNumberOfValues());
}
} // namespace

TEST(NoiseFilter, LevelZeroIsTheSelectionAndSeedsRepeatAcrossThreadCounts)
{
  // Labels 0..3: the default selection (non-zero) keeps 1, 2 and 3.
  auto labels = dgtest::MakeImage(20, 18, 16, [](int i, int j, int k) {
    return (i > 3 && i < 15 && j > 3 && j < 14 && k > 2 && k < 13) ? 1.0 + (i + j) % 3 : 0.0;
  }, VTK_SHORT);
  auto clean = NoisyValues(labels, 0.0, 1);
  ASSERT_EQ(clean.size(), 20u * 18 * 16);
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 18; ++j)
      for (int i = 0; i < 20; ++i)
        ASSERT_EQ(clean[(k * 18 + j) * 20 + i], labels->GetScalarComponentAsDouble(i, j, k, 0) != 0);

  const std::string backend = vtkSMPTools::GetBackend();
  vtkSMPTools::SetBackend("Sequential");
  auto a = NoisyValues(labels, 0.4, 9);
  vtkSMPTools::SetBackend("STDThread");
  auto b = NoisyValues(labels, 0.4, 9);
  vtkSMPTools::SetBackend(backend.c_str());
  EXPECT_EQ(a, b);
  EXPECT_NE(a, clean);
  EXPECT_NE(a, NoisyValues(labels, 0.4, 10));
}

TEST(NoiseFilter, BadInputGivesAnError)
{
  vtkNew<vtkImageData> noScalars;
  noScalars->SetDimensions(4, 4, 4);
  vtkNew<vtkDigitalNoiseFilter> noise;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(noise);
  obs->Observe(noise->GetExecutive());
  noise->SetInputData(noScalars);
  noise->Update();
  EXPECT_GE(obs->Errors, 1);
  EXPECT_EQ(noise->GetOutput()->GetPointData()->GetScalars(), nullptr);
}
