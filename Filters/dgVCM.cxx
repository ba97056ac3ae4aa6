#include "dgVCM.h"

#include <Eigen/Dense>
#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

namespace dg
{

std::int64_t DoubledRadiusBound(double radius)
{
  // |2 d|^2 <= 4 r^2; the tolerance keeps integer radii (and their squares)
  // from losing a shell to round-off.
  return static_cast<std::int64_t>(std::floor(4.0 * radius * radius * (1.0 + 1e-12) + 1e-9));
}

VCMSites ExtractSites(const std::uint8_t* mask, const int dims[3], const bool outsideBeyond[6])
{
  VCMSites sites;
  std::copy(dims, dims + 3, sites.Dims);
  const std::int64_t nx = dims[0], ny = dims[1], nz = dims[2];
  if (nx <= 0 || ny <= 0 || nz <= 0)
  {
    return sites;
  }
  // Count per slice in parallel, then fill each slice's range: grid order.
  std::vector<std::int64_t> first(nz + 1, 0);
  auto visit = [&](std::int64_t k, auto&& emit) {
    const std::int64_t step[3] = { 1, nx, nx * ny };
    for (std::int64_t j = 0; j < ny; ++j)
    {
      const std::uint8_t* row = mask + (k * ny + j) * nx;
      for (std::int64_t i = 0; i < nx; ++i)
      {
        if (!row[i])
        {
          continue;
        }
        const std::int64_t v[3] = { i, j, k };
        for (int d = 0; d < 6; ++d)
        {
          const int a = d / 2;
          const std::int64_t w = v[a] + ((d & 1) ? 1 : -1);
          const bool beyond = w < 0 || w >= dims[a];
          const bool surfel =
            beyond ? outsideBeyond[d] : !row[i + ((d & 1) ? step[a] : -step[a])];
          if (surfel)
          {
            emit(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k), d);
          }
        }
      }
    }
  };
  vtkSMPTools::For(0, nz, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t k = b; k < e; ++k)
    {
      std::int64_t n = 0;
      visit(k, [&](int, int, int, int) { ++n; });
      first[k + 1] = n;
    }
  });
  for (std::int64_t k = 0; k < nz; ++k)
  {
    first[k + 1] += first[k];
  }
  sites.Voxel.resize(3 * first[nz]);
  sites.Direction.resize(first[nz]);
  vtkSMPTools::For(0, nz, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t k = b; k < e; ++k)
    {
      std::int64_t s = first[k];
      visit(k, [&](int i, int j, int kk, int d) {
        sites.Voxel[3 * s] = i;
        sites.Voxel[3 * s + 1] = j;
        sites.Voxel[3 * s + 2] = kk;
        sites.Direction[s] = static_cast<std::uint8_t>(d);
        ++s;
      });
    }
  });
  return sites;
}

namespace
{
constexpr std::int32_t Inf = std::numeric_limits<std::int32_t>::max();

struct Parabola
{
  std::int64_t P; // position (doubled)
  std::int64_t F; // height (squared doubled distance so far)
  std::int32_t Id;
};

// Exact lower envelope of x -> (x - P)^2 + F over parabolas with strictly
// increasing P, evaluated at x = x0 + 2 t, t = 0 .. n - 1; emit(t, value,
// id) gets the smallest value and, among equal values, the smallest id.
// Breakpoints are rationals num / den (den > 0). A parabola is removed only
// when it is strictly above the envelope everywhere, so that every parabola
// reaching the minimum at a lattice point is still there to break the tie.
struct Envelope
{
  std::vector<int> V;
  std::vector<std::int64_t> ZNum, ZDen; // left breakpoint of V[k]; k = 0: -infinity

  template <typename Emit>
  void Run(const Parabola* p, int m, std::int64_t x0, std::int64_t n, Emit&& emit)
  {
    if (m <= 0 || n <= 0)
    {
      return;
    }
    V.resize(m);
    ZNum.resize(m);
    ZDen.resize(m);
    int k = 0;
    V[0] = 0;
    for (int q = 1; q < m; ++q)
    {
      std::int64_t num, den;
      for (;;)
      {
        const Parabola& a = p[V[k]];
        const Parabola& b = p[q];
        num = (b.F + b.P * b.P) - (a.F + a.P * a.P);
        den = 2 * (b.P - a.P);
        // s < z[k]: num / den < ZNum / ZDen
        if (k > 0 && num * ZDen[k] < ZNum[k] * den)
        {
          --k;
          continue;
        }
        break;
      }
      ++k;
      V[k] = q;
      ZNum[k] = num;
      ZDen[k] = den;
    }
    int j = 0;
    for (std::int64_t t = 0; t < n; ++t)
    {
      const std::int64_t x = x0 + 2 * t;
      // z[j + 1] < x: V[j] lies strictly left of x.
      while (j < k && ZNum[j + 1] < x * ZDen[j + 1])
      {
        ++j;
      }
      const Parabola& a = p[V[j]];
      std::int64_t best = (x - a.P) * (x - a.P) + a.F;
      std::int32_t id = a.Id;
      // Parabolas whose interval starts exactly at x tie with V[j] there.
      for (int u = j + 1; u <= k && ZNum[u] <= x * ZDen[u]; ++u)
      {
        const Parabola& b = p[V[u]];
        const std::int64_t val = (x - b.P) * (x - b.P) + b.F;
        if (val < best || (val == best && b.Id < id))
        {
          best = val;
          id = b.Id;
        }
      }
      emit(t, best, id);
    }
  }
};

struct PlaneScratch
{
  std::vector<Parabola> In;
  Envelope Env;
  std::vector<std::int32_t> Val, Id; // pass-1 results of the plane's non-empty lines
  std::vector<int> Lines;            // doubled Y of each non-empty line
  std::vector<int> XLo, XHi;         // finite range of each line
};

inline std::int64_t FloorDiv2(std::int64_t a)
{
  return a >= 0 ? a / 2 : -((-a + 1) / 2);
}
} // namespace

bool VoronoiCovarianceMeasure::Compute(
  const VCMSites& sites, double offsetRadius, const std::function<bool(double)>& progress)
{
  this->Sites = &sites;
  const std::int64_t ns = sites.Size();
  this->Measures.assign(6 * ns, 0);
  this->OffsetPoints = 0;
  this->Bytes = 0;
  // Rows of sites for the convolution.
  this->NJ = sites.Dims[1];
  this->NK = sites.Dims[2];
  this->RowFirst.assign(static_cast<std::size_t>(this->NJ) * this->NK + 1, 0);
  for (std::int64_t s = 0; s < ns; ++s)
  {
    ++this->RowFirst[static_cast<std::size_t>(sites.Voxel[3 * s + 2]) * this->NJ +
      sites.Voxel[3 * s + 1] + 1];
  }
  for (std::size_t r = 1; r < this->RowFirst.size(); ++r)
  {
    this->RowFirst[r] += this->RowFirst[r - 1];
  }
  if (ns == 0)
  {
    return true;
  }

  const std::int64_t cap = DoubledRadiusBound(offsetRadius);
  const std::int64_t reach = static_cast<std::int64_t>(std::floor(std::sqrt(static_cast<double>(cap))));
  // Doubled site centres; the lattice domain covers every point within R.
  std::vector<std::int32_t> P(3 * ns);
  std::int64_t pmin[3], pmax[3];
  for (int a = 0; a < 3; ++a)
  {
    pmin[a] = std::numeric_limits<std::int64_t>::max();
    pmax[a] = std::numeric_limits<std::int64_t>::min();
  }
  for (std::int64_t s = 0; s < ns; ++s)
  {
    std::int64_t c[3];
    DoubledCentre(&sites.Voxel[3 * s], sites.Direction[s], c);
    for (int a = 0; a < 3; ++a)
    {
      pmin[a] = std::min(pmin[a], c[a]);
      pmax[a] = std::max(pmax[a], c[a]);
    }
  }
  std::int64_t lo[3], n[3];
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = FloorDiv2(pmin[a] - reach);          // lattice origin of the domain
    n[a] = FloorDiv2(pmax[a] + reach + 1) - lo[a] + 1;
  }
  for (std::int64_t s = 0; s < ns; ++s)
  {
    std::int64_t c[3];
    DoubledCentre(&sites.Voxel[3 * s], sites.Direction[s], c);
    for (int a = 0; a < 3; ++a)
    {
      P[3 * s + a] = static_cast<std::int32_t>(c[a] - 2 * lo[a]);
    }
  }
  const std::int64_t nx = n[0], ny = n[1], nz = n[2];
  const std::int64_t n2y = 2 * ny - 1, n2z = 2 * nz - 1;

  // Sites per doubled line (Z, Y), sorted by X.
  std::vector<std::int64_t> lineFirst(n2z * n2y + 1, 0);
  for (std::int64_t s = 0; s < ns; ++s)
  {
    ++lineFirst[P[3 * s + 2] * n2y + P[3 * s + 1] + 1];
  }
  for (std::size_t l = 1; l < lineFirst.size(); ++l)
  {
    lineFirst[l] += lineFirst[l - 1];
  }
  std::vector<std::int32_t> lineSites(ns);
  {
    std::vector<std::int64_t> fill(lineFirst.begin(), lineFirst.end() - 1);
    for (std::int64_t s = 0; s < ns; ++s)
    {
      lineSites[fill[P[3 * s + 2] * n2y + P[3 * s + 1]]++] = static_cast<std::int32_t>(s);
    }
  }
  vtkSMPTools::For(0, n2z * n2y, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t l = b; l < e; ++l)
    {
      std::sort(lineSites.begin() + lineFirst[l], lineSites.begin() + lineFirst[l + 1],
        [&](std::int32_t u, std::int32_t v) { return P[3 * u] < P[3 * v]; });
    }
  });
  // Planes of doubled Z holding any site, to skip empty ones fast.
  std::vector<char> planeHasSites(n2z, 0);
  for (std::int64_t s = 0; s < ns; ++s)
  {
    planeHasSites[P[3 * s + 2]] = 1;
  }

  // Ring buffer of doubled planes (X, Y pass results), [x][y] per plane.
  const std::int64_t T = std::min<std::int64_t>(this->SlabPlanes, nz);
  const std::int64_t Q = std::min<std::int64_t>(n2z, 2 * (T - 1) + 2 * reach + 2);
  const std::size_t planeSize = static_cast<std::size_t>(nx * ny);
  std::unique_ptr<std::int32_t[]> val(new std::int32_t[planeSize * Q]);
  std::unique_ptr<std::int32_t[]> ids(new std::int32_t[planeSize * Q]);
  std::vector<std::int32_t> yLo(nx * Q), yHi(nx * Q);
  this->Bytes = planeSize * Q * 8 + nx * Q * 8 + lineFirst.size() * 8 + ns * 16;

  vtkSMPThreadLocal<PlaneScratch> scratch;
  auto computePlane = [&](std::int64_t Z) {
    PlaneScratch& w = scratch.Local();
    const std::int64_t slot = Z % Q;
    std::int32_t* pv = val.get() + slot * planeSize;
    std::int32_t* pi = ids.get() + slot * planeSize;
    std::int32_t* lo2 = &yLo[slot * nx];
    std::int32_t* hi2 = &yHi[slot * nx];
    std::fill(lo2, lo2 + nx, 1);
    std::fill(hi2, hi2 + nx, 0);
    if (!planeHasSites[Z])
    {
      return;
    }
    // Pass 1 (X) on the plane's lines with sites.
    w.Lines.clear();
    for (std::int64_t Y = 0; Y < n2y; ++Y)
    {
      if (lineFirst[Z * n2y + Y + 1] > lineFirst[Z * n2y + Y])
      {
        w.Lines.push_back(static_cast<int>(Y));
      }
    }
    const std::size_t nl = w.Lines.size();
    w.Val.resize(nl * nx);
    w.Id.resize(nl * nx);
    w.XLo.resize(nl);
    w.XHi.resize(nl);
    for (std::size_t l = 0; l < nl; ++l)
    {
      const std::int64_t line = Z * n2y + w.Lines[l];
      const std::int64_t b = lineFirst[line], e = lineFirst[line + 1];
      w.In.clear();
      for (std::int64_t t = b; t < e; ++t)
      {
        const std::int32_t s = lineSites[t];
        w.In.push_back({ P[3 * s], 0, s });
      }
      const std::int64_t x0 = std::max<std::int64_t>(0, FloorDiv2(w.In.front().P - reach + 1));
      const std::int64_t x1 = std::min<std::int64_t>(nx - 1, FloorDiv2(w.In.back().P + reach));
      w.XLo[l] = static_cast<int>(x0);
      w.XHi[l] = static_cast<int>(x1);
      std::int32_t* lv = &w.Val[l * nx];
      std::int32_t* li = &w.Id[l * nx];
      w.Env.Run(w.In.data(), static_cast<int>(w.In.size()), 2 * x0, x1 - x0 + 1,
        [&](std::int64_t t, std::int64_t v, std::int32_t id) {
          lv[x0 + t] = v <= cap ? static_cast<std::int32_t>(v) : Inf;
          li[x0 + t] = id;
        });
    }
    // Pass 2 (Y) per lattice x.
    for (std::int64_t x = 0; x < nx; ++x)
    {
      w.In.clear();
      for (std::size_t l = 0; l < nl; ++l)
      {
        if (x >= w.XLo[l] && x <= w.XHi[l] && w.Val[l * nx + x] != Inf)
        {
          w.In.push_back({ w.Lines[l], w.Val[l * nx + x], w.Id[l * nx + x] });
        }
      }
      if (w.In.empty())
      {
        continue;
      }
      const std::int64_t y0 = std::max<std::int64_t>(0, FloorDiv2(w.In.front().P - reach + 1));
      const std::int64_t y1 = std::min<std::int64_t>(ny - 1, FloorDiv2(w.In.back().P + reach));
      std::int32_t* cv = pv + x * ny;
      std::int32_t* ci = pi + x * ny;
      std::int64_t first = -1, last = -2;
      w.Env.Run(w.In.data(), static_cast<int>(w.In.size()), 2 * y0, y1 - y0 + 1,
        [&](std::int64_t t, std::int64_t v, std::int32_t id) {
          const std::int64_t y = y0 + t;
          if (v <= cap)
          {
            cv[y] = static_cast<std::int32_t>(v);
            ci[y] = id;
            if (first < 0)
            {
              first = y;
            }
            last = y;
          }
          else
          {
            cv[y] = Inf;
          }
        });
      lo2[x] = static_cast<std::int32_t>(first < 0 ? 1 : first);
      hi2[x] = static_cast<std::int32_t>(first < 0 ? 0 : last);
    }
  };

  std::unique_ptr<std::atomic<std::int64_t>[]> acc(new std::atomic<std::int64_t>[6 * ns]);
  for (std::int64_t t = 0; t < 6 * ns; ++t)
  {
    acc[t].store(0, std::memory_order_relaxed);
  }
  std::atomic<std::int64_t> offsetPoints(0);
  std::int64_t computed = -1; // highest doubled plane in the ring
  const std::int64_t slabs = (nz + T - 1) / T;
  for (std::int64_t sl = 0; sl < slabs; ++sl)
  {
    const std::int64_t z0 = sl * T, z1 = std::min(nz, z0 + T);
    const std::int64_t A = std::max<std::int64_t>(0, 2 * z0 - reach);
    const std::int64_t B = std::min<std::int64_t>(n2z - 1, 2 * (z1 - 1) + reach);
    const std::int64_t from = std::max(A, computed + 1);
    vtkSMPTools::For(from, B + 1, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t Z = b; Z < e; ++Z)
      {
        computePlane(Z);
      }
    });
    computed = B;
    // Pass 3 (Z) per column, accumulating into the sites.
    std::vector<std::int64_t> slotOf(B - A + 1);
    for (std::int64_t Z = A; Z <= B; ++Z)
    {
      slotOf[Z - A] = Z % Q;
    }
    vtkSMPTools::For(0, nx, [&](std::int64_t b, std::int64_t e) {
      std::vector<Parabola> in(B - A + 1);
      std::vector<std::int64_t> planes; // slots with finite values at this x, by Z
      std::vector<std::int32_t> pz, plo, phi;
      Envelope env;
      std::int64_t localPoints = 0;
      for (std::int64_t x = b; x < e; ++x)
      {
        planes.clear();
        pz.clear();
        plo.clear();
        phi.clear();
        std::int32_t ylo = std::numeric_limits<std::int32_t>::max(), yhi = -1;
        for (std::int64_t Z = A; Z <= B; ++Z)
        {
          const std::int64_t slot = slotOf[Z - A];
          const std::int32_t l = yLo[slot * nx + x], h = yHi[slot * nx + x];
          if (l <= h)
          {
            planes.push_back(slot * planeSize + x * ny);
            pz.push_back(static_cast<std::int32_t>(Z));
            plo.push_back(l);
            phi.push_back(h);
            ylo = std::min(ylo, l);
            yhi = std::max(yhi, h);
          }
        }
        const std::size_t np = planes.size();
        for (std::int64_t y = ylo; y <= yhi; ++y)
        {
          int m = 0;
          for (std::size_t q = 0; q < np; ++q)
          {
            if (y < plo[q] || y > phi[q])
            {
              continue;
            }
            const std::size_t at = planes[q] + y;
            if (val[at] != Inf)
            {
              in[m++] = { pz[q], val[at], ids[at] };
            }
          }
          if (m == 0)
          {
            continue;
          }
          const std::int64_t za = std::max(z0, FloorDiv2(in[0].P - reach + 1));
          const std::int64_t zb = std::min(z1 - 1, FloorDiv2(in[m - 1].P + reach));
          if (za > zb)
          {
            continue;
          }
          std::int32_t runId = -1;
          std::int64_t run[6] = { 0, 0, 0, 0, 0, 0 };
          auto flush = [&]() {
            if (runId >= 0)
            {
              for (int c = 0; c < 6; ++c)
              {
                acc[6 * runId + c].fetch_add(run[c], std::memory_order_relaxed);
                run[c] = 0;
              }
            }
          };
          env.Run(in.data(), m, 2 * za, zb - za + 1,
            [&](std::int64_t t, std::int64_t v, std::int32_t id) {
              if (v > cap)
              {
                return;
              }
              if (id != runId)
              {
                flush();
                runId = id;
              }
              const std::int64_t d0 = 2 * x - P[3 * id], d1 = 2 * y - P[3 * id + 1],
                                 d2 = 2 * (za + t) - P[3 * id + 2];
              run[0] += d0 * d0;
              run[1] += d0 * d1;
              run[2] += d0 * d2;
              run[3] += d1 * d1;
              run[4] += d1 * d2;
              run[5] += d2 * d2;
              ++localPoints;
            });
          flush();
        }
      }
      offsetPoints += localPoints;
    });
    if (progress && !progress(static_cast<double>(sl + 1) / slabs))
    {
      return false;
    }
  }
  for (std::int64_t t = 0; t < 6 * ns; ++t)
  {
    this->Measures[t] = acc[t].load(std::memory_order_relaxed);
  }
  this->OffsetPoints = offsetPoints;
  return true;
}

void VoronoiCovarianceMeasure::Convolve(
  const std::int32_t voxel[3], int direction, double r, std::int64_t out[6]) const
{
  std::fill(out, out + 6, 0);
  const VCMSites& sites = *this->Sites;
  const std::int64_t bound = DoubledRadiusBound(r);
  std::int64_t c[3];
  DoubledCentre(voxel, direction, c);
  // A site within r of c has its inside voxel within r + 1 of the
  // surfel's: rows (j, k) of that disc, i within the chord.
  const double w2 = (r + 1) * (r + 1);
  const int w = static_cast<int>(std::floor(r + 1));
  for (int k = std::max(0, voxel[2] - w); k <= std::min(this->NK - 1, voxel[2] + w); ++k)
  {
    const int dk = k - voxel[2];
    const int wj = static_cast<int>(std::floor(std::sqrt(std::max(0.0, w2 - dk * dk))));
    for (int j = std::max(0, voxel[1] - wj); j <= std::min(this->NJ - 1, voxel[1] + wj); ++j)
    {
      const int dj = j - voxel[1];
      const int wi =
        static_cast<int>(std::floor(std::sqrt(std::max(0.0, w2 - dk * dk - dj * dj))));
      const std::size_t row = static_cast<std::size_t>(k) * this->NJ + j;
      std::int64_t s = this->RowFirst[row];
      const std::int64_t e = this->RowFirst[row + 1];
      if (s == e)
      {
        continue;
      }
      // Sites of a row are sorted by i: skip to voxel[0] - wi.
      const int ilo = voxel[0] - wi, ihi = voxel[0] + wi;
      std::int64_t count = e - s;
      while (count > 0)
      {
        const std::int64_t half = count / 2;
        if (sites.Voxel[3 * (s + half)] < ilo)
        {
          s += half + 1;
          count -= half + 1;
        }
        else
        {
          count = half;
        }
      }
      for (; s < e && sites.Voxel[3 * s] <= ihi; ++s)
      {
        std::int64_t p[3];
        DoubledCentre(&sites.Voxel[3 * s], sites.Direction[s], p);
        const std::int64_t d0 = p[0] - c[0], d1 = p[1] - c[1], d2 = p[2] - c[2];
        if (d0 * d0 + d1 * d1 + d2 * d2 <= bound)
        {
          const std::int64_t* m = &this->Measures[6 * s];
          for (int t = 0; t < 6; ++t)
          {
            out[t] += m[t];
          }
        }
      }
    }
  }
}

std::vector<std::int64_t> BruteForceSiteMeasures(const VCMSites& sites, double offsetRadius)
{
  const std::int64_t ns = sites.Size();
  std::vector<std::int64_t> m(6 * ns, 0);
  if (ns == 0)
  {
    return m;
  }
  const std::int64_t cap = DoubledRadiusBound(offsetRadius);
  std::vector<std::int64_t> P(3 * ns);
  std::int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a)
  {
    lo[a] = std::numeric_limits<std::int64_t>::max();
    hi[a] = std::numeric_limits<std::int64_t>::min();
  }
  for (std::int64_t s = 0; s < ns; ++s)
  {
    DoubledCentre(&sites.Voxel[3 * s], sites.Direction[s], &P[3 * s]);
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = std::min(lo[a], P[3 * s + a]);
      hi[a] = std::max(hi[a], P[3 * s + a]);
    }
  }
  const std::int64_t reach = static_cast<std::int64_t>(std::ceil(2.0 * offsetRadius)) + 2;
  for (std::int64_t X = FloorDiv2(lo[0] - reach); 2 * X <= hi[0] + reach; ++X)
    for (std::int64_t Y = FloorDiv2(lo[1] - reach); 2 * Y <= hi[1] + reach; ++Y)
      for (std::int64_t Z = FloorDiv2(lo[2] - reach); 2 * Z <= hi[2] + reach; ++Z)
      {
        std::int64_t best = std::numeric_limits<std::int64_t>::max(), arg = -1;
        for (std::int64_t s = 0; s < ns; ++s)
        {
          const std::int64_t d0 = 2 * X - P[3 * s], d1 = 2 * Y - P[3 * s + 1],
                             d2 = 2 * Z - P[3 * s + 2];
          const std::int64_t d = d0 * d0 + d1 * d1 + d2 * d2;
          if (d < best)
          {
            best = d;
            arg = s;
          }
        }
        if (best > cap)
        {
          continue;
        }
        const std::int64_t d0 = 2 * X - P[3 * arg], d1 = 2 * Y - P[3 * arg + 1],
                           d2 = 2 * Z - P[3 * arg + 2];
        std::int64_t* o = &m[6 * arg];
        o[0] += d0 * d0;
        o[1] += d0 * d1;
        o[2] += d0 * d2;
        o[3] += d1 * d1;
        o[4] += d1 * d2;
        o[5] += d2 * d2;
      }
  return m;
}

void BruteForceConvolve(const VCMSites& sites, const std::vector<std::int64_t>& measures,
  const std::int32_t voxel[3], int direction, double r, std::int64_t out[6])
{
  std::fill(out, out + 6, 0);
  const std::int64_t bound = DoubledRadiusBound(r);
  std::int64_t c[3];
  DoubledCentre(voxel, direction, c);
  for (std::int64_t s = 0; s < sites.Size(); ++s)
  {
    std::int64_t p[3];
    DoubledCentre(&sites.Voxel[3 * s], sites.Direction[s], p);
    const std::int64_t d0 = p[0] - c[0], d1 = p[1] - c[1], d2 = p[2] - c[2];
    if (d0 * d0 + d1 * d1 + d2 * d2 <= bound)
    {
      for (int t = 0; t < 6; ++t)
      {
        out[t] += measures[6 * s + t];
      }
    }
  }
}

void EstimateFromMeasure(const std::int64_t v[6], const std::int64_t barycentreSum[3],
  int direction, VCMEstimate& out)
{
  const int axis = direction / 2;
  const double sign = (direction & 1) ? 1.0 : -1.0;
  Eigen::Matrix3d C;
  // Doubled units: divide by 4 for voxel^2.
  C << v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5];
  C *= 0.25;
  // The iterative solver: the feature score needs the two smaller
  // eigenvalues accurately too, and it runs once per output surfel only.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
  const Eigen::Vector3d mu = eig.eigenvalues(); // increasing
  Eigen::Vector3d n = eig.eigenvectors().col(2);
  out.TrivialFallback = false;
  out.Eigenvalues[0] = mu[2];
  out.Eigenvalues[1] = mu[1];
  out.Eigenvalues[2] = mu[0];
  const double sum = mu[0] + mu[1] + mu[2];
  out.FeatureScore = sum > 0 ? mu[1] / sum : 0.0;
  if (!(mu[2] > 0))
  {
    n.setZero();
    n[axis] = sign;
    out.TrivialFallback = true;
  }
  else
  {
    const Eigen::Vector3d s(static_cast<double>(barycentreSum[0]),
      static_cast<double>(barycentreSum[1]), static_cast<double>(barycentreSum[2]));
    const double side = -n.dot(s);
    if (std::abs(side) > 1e-9 * s.norm())
    {
      if (side < 0)
      {
        n = -n;
      }
    }
    else
    {
      out.TrivialFallback = true;
      if (n[axis] * sign < 0)
      {
        n = -n;
      }
    }
  }
  for (int a = 0; a < 3; ++a)
  {
    out.Normal[a] = n[a];
  }
}

} // namespace dg
