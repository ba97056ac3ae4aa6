#include "dgNoise.h"

#include <vtkSMPTools.h>

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

void BoundaryVoxels(
  const std::vector<std::uint8_t>& inside, const int dims[3], std::vector<std::uint8_t>& boundary)
{
  const int nx = dims[0], ny = dims[1], nz = dims[2];
  boundary.assign(inside.size(), 0);
  auto at = [&](int i, int j, int k) -> int {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz)
    {
      return 0;
    }
    return inside[(static_cast<std::size_t>(k) * ny + j) * nx + i] != 0;
  };
  vtkSMPTools::For(0, nz, [&](int kb, int ke) {
    for (int k = kb; k < ke; ++k)
    {
      for (int j = 0; j < ny; ++j)
      {
        for (int i = 0; i < nx; ++i)
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
  if (!(k > 0))
  {
    return 0;
  }
  std::vector<std::uint8_t> boundary;
  BoundaryVoxels(inside, dims, boundary);
  if (progress && !progress(0.15))
  {
    return -1;
  }
  std::vector<std::int64_t> d2;
  SquaredDistanceTransform(boundary, dims, d2);
  if (progress && !progress(0.75))
  {
    return -1;
  }
  const std::int64_t n = static_cast<std::int64_t>(inside.size());
  const double logk = std::log(k);
  std::vector<std::int64_t> flips(static_cast<std::size_t>(dims[2]), 0);
  const std::int64_t slice = static_cast<std::int64_t>(dims[0]) * dims[1];
  vtkSMPTools::For(0, static_cast<std::int64_t>(dims[2]), [&](std::int64_t kb, std::int64_t ke) {
    for (std::int64_t kz = kb; kz < ke; ++kz)
    {
      std::int64_t count = 0;
      for (std::int64_t p = kz * slice; p < std::min(n, (kz + 1) * slice); ++p)
      {
        // k^(1 + d); k == 1 flips everything, as the formula says.
        const double prob = std::exp(logk * (1.0 + std::sqrt(static_cast<double>(d2[p]))));
        if (HashUniform(seed, static_cast<std::uint64_t>(p)) < prob)
        {
          inside[p] = inside[p] ? 0 : 1;
          ++count;
        }
      }
      flips[kz] = count;
    }
  });
  std::int64_t total = 0;
  for (auto c : flips)
  {
    total += c;
  }
  return total;
}

} // namespace dg
