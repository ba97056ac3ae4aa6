#include "dgNoise.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dg
{

double HashUniform(std::uint64_t seed, std::uint64_t index)
{
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + index + 0x632BE59BD9B4E019ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull; // a second round decorrelates nearby seeds
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

void BoundaryVoxels(const std::vector<std::uint8_t>& inside, const int dims[3],
  std::vector<std::uint8_t>& boundary, unsigned openFaces)
{
  BoundaryVoxels(inside.data(), dims, boundary, openFaces);
}

void BoundaryVoxels(const std::uint8_t* inside, const int dims[3],
  std::vector<std::uint8_t>& boundary, unsigned openFaces)
{
  const int nx = dims[0], ny = dims[1], nz = dims[2];
  boundary.assign(static_cast<std::size_t>(nx) * ny * nz, 0);
  auto at = [&](int i, int j, int k) -> int {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz)
    {
      return 0;
    }
    return inside[(static_cast<std::size_t>(k) * ny + j) * nx + i] != 0;
  };
  // The first and last index of each axis whose voxels are decided: an open
  // face's layer is not (its outer neighbours are unknown).
  const int lo[3] = { openFaces & 1u ? 1 : 0, openFaces & 4u ? 1 : 0, openFaces & 16u ? 1 : 0 };
  const int hi[3] = { nx - (openFaces & 2u ? 2 : 1), ny - (openFaces & 8u ? 2 : 1),
    nz - (openFaces & 32u ? 2 : 1) };
  vtkSMPTools::For(lo[2], std::max(lo[2], hi[2] + 1), [&](int kb, int ke) {
    for (int k = kb; k < ke; ++k)
    {
      for (int j = lo[1]; j <= hi[1]; ++j)
      {
        for (int i = lo[0]; i <= hi[0]; ++i)
        {
          const int s = at(i, j, k);
          const bool b = at(i - 1, j, k) != s || at(i + 1, j, k) != s || at(i, j - 1, k) != s ||
            at(i, j + 1, k) != s || at(i, j, k - 1) != s || at(i, j, k + 1) != s;
          boundary[(static_cast<std::size_t>(k) * ny + j) * nx + i] = b;
        }
      }
    }
  });
}

void SquaredDistanceTransform(
  const std::vector<std::uint8_t>& seeds, const int dims[3], std::vector<std::int64_t>& d2)
{
  const std::int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  const std::int64_t inf = std::numeric_limits<std::int64_t>::max() / 4;
  d2.assign(seeds.size(), inf);
  // Pass 1: 1D distance along x, exact.
  vtkSMPTools::For(0, ny * nz, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t r = b; r < e; ++r)
    {
      const std::int64_t base = r * nx;
      std::int64_t last = -1;
      for (std::int64_t i = 0; i < nx; ++i)
      {
        if (seeds[base + i])
        {
          last = i;
        }
        if (last >= 0)
        {
          d2[base + i] = (i - last) * (i - last);
        }
      }
      last = -1;
      for (std::int64_t i = nx - 1; i >= 0; --i)
      {
        if (seeds[base + i])
        {
          last = i;
        }
        if (last >= 0)
        {
          d2[base + i] = std::min(d2[base + i], (last - i) * (last - i));
        }
      }
    }
  });
  // Passes 2 and 3: lower envelope of parabolas along y, then z (Meijster).
  auto envelope = [&](std::int64_t n, std::int64_t stride, std::int64_t lines,
                    auto lineStart) {
    vtkSMPTools::For(0, lines, [&](std::int64_t b, std::int64_t e) {
      std::vector<std::int64_t> f(n), v(n), out(n);
      std::vector<double> z(n + 1);
      for (std::int64_t l = b; l < e; ++l)
      {
        const std::int64_t s0 = lineStart(l);
        for (std::int64_t q = 0; q < n; ++q)
        {
          f[q] = d2[s0 + q * stride];
        }
        std::int64_t kk = -1;
        for (std::int64_t q = 0; q < n; ++q)
        {
          if (f[q] >= inf)
          {
            continue;
          }
          double s = 0;
          while (kk >= 0)
          {
            const std::int64_t p = v[kk];
            s = ((f[q] + q * q) - (f[p] + p * p)) / (2.0 * (q - p));
            if (s <= z[kk])
            {
              --kk;
            }
            else
            {
              break;
            }
          }
          ++kk;
          v[kk] = q;
          z[kk] = kk == 0 ? -std::numeric_limits<double>::infinity() : s;
          z[kk + 1] = std::numeric_limits<double>::infinity();
        }
        if (kk < 0)
        {
          continue; // no seed on this line yet: stays infinite
        }
        std::int64_t j = 0;
        for (std::int64_t q = 0; q < n; ++q)
        {
          while (z[j + 1] < q)
          {
            ++j;
          }
          const std::int64_t p = v[j];
          out[q] = (q - p) * (q - p) + f[p];
        }
        for (std::int64_t q = 0; q < n; ++q)
        {
          d2[s0 + q * stride] = out[q];
        }
      }
    });
  };
  envelope(ny, nx, nx * nz, [&](std::int64_t l) { return (l / nx) * nx * ny + (l % nx); });
  envelope(nz, nx * ny, nx * ny, [&](std::int64_t l) { return l; });
}

std::int64_t ApplyNoise(std::vector<std::uint8_t>& inside, const int dims[3], double k,
  std::uint64_t seed, const std::function<bool(double)>& progress)
{
  NoiseBox b;
  for (int a = 0; a < 3; ++a)
  {
    b.Whole[2 * a] = b.Box[2 * a] = b.Out[2 * a] = 0;
    b.Whole[2 * a + 1] = b.Box[2 * a + 1] = b.Out[2 * a + 1] = dims[a] - 1;
  }
  NoiseCounts counts;
  if (!ApplyNoise(inside.data(), b, k, seed, inside.data(), counts, progress))
  {
    return -1;
  }
  return counts.Flipped;
}

int NoiseReach(double k, double wholeVoxels, double bound, int cap)
{
  if (!(k > 0))
  {
    return 0;
  }
  if (!(k < 1) || !(bound > 0) || !(wholeVoxels > 0))
  {
    return cap;
  }
  // N k^(1 + R) <= bound  <=>  R >= ln(bound / N) / ln k - 1 (ln k < 0).
  const double r = std::ceil(std::log(bound / wholeVoxels) / std::log(k) - 1.0);
  if (!(r < cap)) // NaN, or the whole volume anyway
  {
    return cap;
  }
  return std::max(1, static_cast<int>(r));
}

bool ApplyNoise(const std::uint8_t* inside, const NoiseBox& b, double k, std::uint64_t seed,
  std::uint8_t* result, NoiseCounts& counts, const std::function<bool(double)>& progress)
{
  counts = NoiseCounts();
  int dims[3], out[3], off[3];
  std::int64_t whole[3];
  unsigned openFaces = 0;
  for (int a = 0; a < 3; ++a)
  {
    dims[a] = b.Box[2 * a + 1] - b.Box[2 * a] + 1;
    out[a] = b.Out[2 * a + 1] - b.Out[2 * a] + 1;
    off[a] = b.Out[2 * a] - b.Box[2 * a];
    whole[a] = static_cast<std::int64_t>(b.Whole[2 * a + 1]) - b.Whole[2 * a] + 1;
    // (GCC 12 at -O2 with the sanitizers dropped these bits when written as
    // (c ? 1u : 0u) << n: every box then looked closed, TestNoisePieces.)
    if (b.Box[2 * a] > b.Whole[2 * a])
      openFaces |= 1u << (2 * a);
    if (b.Box[2 * a + 1] < b.Whole[2 * a + 1])
      openFaces |= 2u << (2 * a);
  }
  if (out[0] <= 0 || out[1] <= 0 || out[2] <= 0)
  {
    return true;
  }
  const std::int64_t outRow = out[0];
  const auto boxIndex = [&](std::int64_t i, std::int64_t j, std::int64_t kz) {
    return ((kz + off[2]) * dims[1] + (j + off[1])) * dims[0] + (i + off[0]);
  };
  if (!(k > 0))
  {
    if (result != inside)
    {
      for (std::int64_t kz = 0; kz < out[2]; ++kz)
      {
        for (std::int64_t j = 0; j < out[1]; ++j)
        {
          std::copy_n(inside + boxIndex(0, j, kz), outRow, result + (kz * out[1] + j) * outRow);
        }
      }
    }
    return true;
  }
  std::vector<std::uint8_t> boundary;
  BoundaryVoxels(inside, dims, boundary, openFaces);
  if (progress && !progress(0.15))
  {
    return false;
  }
  std::vector<std::int64_t> d2;
  SquaredDistanceTransform(boundary, dims, d2);
  std::vector<std::uint8_t>().swap(boundary);
  if (progress && !progress(0.75))
  {
    return false;
  }
  const double logk = std::log(k);
  // k^(1 + d) from d^2, the one formula for every decision and bound.
  const auto probability = [logk](std::int64_t squared) {
    return std::exp(logk * (1.0 + std::sqrt(static_cast<double>(squared))));
  };
  // Beyond an open face (its own layer included) boundary voxels may lie
  // unseen: a voxel whose distance within the box is larger than its
  // distance to such a face may be nearer to the boundary than the box
  // shows. No open face: every distance is the whole volume's.
  const auto unseen = [&](std::int64_t i, std::int64_t j, std::int64_t kz) {
    std::int64_t m = std::numeric_limits<std::int64_t>::max();
    const std::int64_t p[3] = { i + off[0], j + off[1], kz + off[2] };
    for (int a = 0; a < 3; ++a)
    {
      if (openFaces & (1u << (2 * a)))
      {
        m = std::min(m, p[a]);
      }
      if (openFaces & (2u << (2 * a)))
      {
        m = std::min(m, static_cast<std::int64_t>(dims[a] - 1) - p[a]);
      }
    }
    return m;
  };
  std::vector<std::int64_t> flips(static_cast<std::size_t>(out[2]), 0);
  std::vector<std::int64_t> uncertain(static_cast<std::size_t>(out[2]), 0);
  vtkSMPTools::For(0, static_cast<std::int64_t>(out[2]), [&](std::int64_t kb, std::int64_t ke) {
    for (std::int64_t kz = kb; kz < ke; ++kz)
    {
      std::int64_t count = 0, unsure = 0;
      for (std::int64_t j = 0; j < out[1]; ++j)
      {
        // The draws are indexed in the whole volume, as one process's are.
        const std::int64_t gRow =
          ((b.Out[4] - b.Whole[4] + kz) * whole[1] + (b.Out[2] - b.Whole[2] + j)) * whole[0] +
          (b.Out[0] - b.Whole[0]);
        const std::int64_t src = boxIndex(0, j, kz);
        const std::int64_t dst = (kz * out[1] + j) * outRow;
        // The row's counted voxels: [c0, c1) (empty when the row is not).
        const std::int64_t y = b.Out[2] + j, z = b.Out[4] + kz;
        const bool rowCounted = y >= b.Counted[2] && y <= b.Counted[3] && z >= b.Counted[4] &&
          z <= b.Counted[5];
        const std::int64_t c0 = rowCounted
          ? std::max<std::int64_t>(0, static_cast<std::int64_t>(b.Counted[0]) - b.Out[0])
          : 0;
        const std::int64_t c1 = rowCounted
          ? std::min<std::int64_t>(outRow, static_cast<std::int64_t>(b.Counted[1]) - b.Out[0] + 1)
          : 0;
        for (std::int64_t i = 0; i < outRow; ++i)
        {
          const std::int64_t d = d2[src + i];
          // k^(1 + d); k == 1 flips everything, as the formula says.
          const double prob = probability(d);
          const double u = HashUniform(seed, static_cast<std::uint64_t>(gRow + i));
          const std::uint8_t v = inside[src + i];
          if (u < prob)
          {
            result[dst + i] = v ? 0 : 1;
            count += i >= c0 && i < c1;
          }
          else
          {
            result[dst + i] = v;
            if (openFaces)
            {
              const std::int64_t m = unseen(i, j, kz);
              if (d > m * m && u < probability(m * m))
              {
                ++unsure;
              }
            }
          }
        }
      }
      flips[kz] = count;
      uncertain[kz] = unsure;
    }
  });
  for (std::size_t z = 0; z < flips.size(); ++z)
  {
    counts.Flipped += flips[z];
    counts.Uncertain += uncertain[z];
  }
  return true;
}

} // namespace dg
