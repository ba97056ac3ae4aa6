#include "dgRHT.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dg
{
namespace
{
constexpr double Pi = 3.14159265358979323846;

// The doubled offset of a surfel centre from its inside voxel's doubled
// centre, along the surfel's axis.
inline int Offset(int d) { return (d & 1) ? 1 : -1; }

inline std::uint64_t Mix(std::uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// splitmix64 (Steele, Lea, Flood 2014): one 64-bit state, handed out as two
// 32-bit halves for the bounded draws.
class Generator
{
public:
  explicit Generator(std::uint64_t seed)
    : State(seed)
  {
  }
  std::uint64_t Next64()
  {
    this->State += 0x9E3779B97F4A7C15ull;
    return Mix(this->State);
  }
  std::uint32_t Next32()
  {
    if (this->Have)
    {
      this->Have = false;
      return static_cast<std::uint32_t>(this->Buffer >> 32);
    }
    this->Buffer = this->Next64();
    this->Have = true;
    return static_cast<std::uint32_t>(this->Buffer);
  }
  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(this->Next64() >> 11) * 0x1.0p-53; }
  /// Uniform in [0, n), exactly (Lemire 2019).
  std::uint32_t Below(std::uint32_t n)
  {
    std::uint64_t m = static_cast<std::uint64_t>(this->Next32()) * n;
    std::uint32_t low = static_cast<std::uint32_t>(m);
    if (low < n)
    {
      const std::uint32_t threshold = (0u - n) % n;
      while (low < threshold)
      {
        m = static_cast<std::uint64_t>(this->Next32()) * n;
        low = static_cast<std::uint32_t>(m);
      }
    }
    return static_cast<std::uint32_t>(m >> 32);
  }

private:
  std::uint64_t State;
  std::uint64_t Buffer = 0;
  bool Have = false;
};

// A uniformly random rotation (Shoemake 1992), row-major.
void RandomRotation(Generator& g, double R[9])
{
  const double u1 = g.Uniform(), u2 = g.Uniform(), u3 = g.Uniform();
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  const double x = a * std::sin(2 * Pi * u2), y = a * std::cos(2 * Pi * u2);
  const double z = b * std::sin(2 * Pi * u3), w = b * std::cos(2 * Pi * u3);
  R[0] = 1 - 2 * (y * y + z * z);
  R[1] = 2 * (x * y - z * w);
  R[2] = 2 * (x * z + y * w);
  R[3] = 2 * (x * y + z * w);
  R[4] = 1 - 2 * (x * x + z * z);
  R[5] = 2 * (y * z - x * w);
  R[6] = 2 * (x * z - y * w);
  R[7] = 2 * (y * z + x * w);
  R[8] = 1 - 2 * (x * x + y * y);
}

void Fallback(const double reference[3], int points, RHTEstimate& out)
{
  std::copy(reference, reference + 3, out.Normal);
  out.Fallback = true;
  out.Points = points;
  out.Trials = 0;
}
} // namespace

// ---------------------------------------------------------------------------
void SurfelRows::Build(
  const std::uint8_t* mask, const int dims[3], std::int64_t rowStride, int rowOffset)
{
  std::copy(dims, dims + 3, this->Dims);
  const int nx = dims[0], ny = dims[1], nz = dims[2];
  const std::int64_t rows = static_cast<std::int64_t>(ny) * nz;
  // Calls f(i, d) for every surfel of row r, in (i, d) order.
  auto scan = [&](std::int64_t r, auto&& f) {
    const int j = static_cast<int>(r % ny), k = static_cast<int>(r / ny);
    const std::uint8_t* row = mask + r * rowStride + rowOffset;
    const std::uint8_t* ym = j > 0 ? row - rowStride : nullptr;
    const std::uint8_t* yp = j + 1 < ny ? row + rowStride : nullptr;
    const std::uint8_t* zm = k > 0 ? row - rowStride * ny : nullptr;
    const std::uint8_t* zp = k + 1 < nz ? row + rowStride * ny : nullptr;
    for (int i = 0; i < nx; ++i)
    {
      if (!row[i])
      {
        continue;
      }
      if (i == 0 || !row[i - 1])
        f(i, 0);
      if (i + 1 == nx || !row[i + 1])
        f(i, 1);
      if (!ym || !ym[i])
        f(i, 2);
      if (!yp || !yp[i])
        f(i, 3);
      if (!zm || !zm[i])
        f(i, 4);
      if (!zp || !zp[i])
        f(i, 5);
    }
  };
  std::vector<std::int64_t> counts(rows, 0);
  vtkSMPTools::For(0, rows, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t r = b; r < e; ++r)
    {
      std::int64_t c = 0;
      scan(r, [&](int, int) { ++c; });
      counts[r] = c;
    }
  });
  this->RowFirst.assign(rows + 1, 0);
  for (std::int64_t r = 0; r < rows; ++r)
  {
    this->RowFirst[r + 1] = this->RowFirst[r] + counts[r];
  }
  counts = std::vector<std::int64_t>();
  this->X.assign(this->RowFirst[rows], 0);
  this->Dir.assign(this->RowFirst[rows], 0);
  vtkSMPTools::For(0, rows, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t r = b; r < e; ++r)
    {
      std::int64_t q = this->RowFirst[r];
      scan(r, [&](int i, int d) {
        this->X[q] = i;
        this->Dir[q] = static_cast<std::uint8_t>(d);
        ++q;
      });
    }
  });
}

std::size_t SurfelRows::MemoryBytes() const
{
  return this->RowFirst.size() * sizeof(std::int64_t) + this->X.size() * sizeof(std::int32_t) +
    this->Dir.size();
}

void SurfelRows::Neighbours(
  int i, int j, int k, int d, double radius, std::vector<std::int32_t>& out) const
{
  out.clear();
  const int nx = this->Dims[0], ny = this->Dims[1], nz = this->Dims[2];
  const double r4 = 4.0 * (radius * radius);
  // A neighbour's inside and outside voxels lie within floor(r) + 1 of (i, j, k)
  // along every axis.
  const int reach = static_cast<int>(std::floor(radius)) + 1;
  const int o[3] = { d / 2 == 0 ? Offset(d) : 0, d / 2 == 1 ? Offset(d) : 0,
    d / 2 == 2 ? Offset(d) : 0 };
  auto minAbs = [](int v) { return std::max(0, std::abs(v) - 1); };
  const int x0 = std::max(0, i - reach), x1 = std::min(nx - 1, i + reach);
  for (int dz = -reach; dz <= reach; ++dz)
  {
    const int kk = k + dz;
    if (kk < 0 || kk >= nz)
    {
      continue;
    }
    const std::int64_t mz = minAbs(2 * dz - o[2]);
    for (int dy = -reach; dy <= reach; ++dy)
    {
      const int jj = j + dy;
      if (jj < 0 || jj >= ny)
      {
        continue;
      }
      const std::int64_t my = minAbs(2 * dy - o[1]);
      if (static_cast<double>(my * my + mz * mz) > r4)
      {
        continue;
      }
      const std::int64_t row = static_cast<std::int64_t>(kk) * ny + jj;
      const std::int32_t* first = this->X.data() + this->RowFirst[row];
      const std::int32_t* last = this->X.data() + this->RowFirst[row + 1];
      if (first == last)
      {
        continue;
      }
      const std::int32_t* p = first;
      if (*p < x0)
      {
        p = std::lower_bound(first, last, x0);
      }
      for (; p != last && *p <= x1; ++p)
      {
        const int dt = this->Dir[p - this->X.data()];
        const int a = dt / 2, ot = Offset(dt);
        const std::int32_t u[3] = { 2 * (*p - i) + (a == 0 ? ot : 0) - o[0],
          2 * dy + (a == 1 ? ot : 0) - o[1], 2 * dz + (a == 2 ? ot : 0) - o[2] };
        const std::int64_t n2 = static_cast<std::int64_t>(u[0]) * u[0] +
          static_cast<std::int64_t>(u[1]) * u[1] + static_cast<std::int64_t>(u[2]) * u[2];
        if (static_cast<double>(n2) <= r4)
        {
          out.insert(out.end(), u, u + 3);
        }
      }
    }
  }
}

void BruteForceNeighbours(const std::uint8_t* mask, const int dims[3], double radius, int i, int j,
  int k, int d, std::vector<std::int32_t>& out)
{
  out.clear();
  auto inside = [&](int x, int y, int z) {
    return x >= 0 && y >= 0 && z >= 0 && x < dims[0] && y < dims[1] && z < dims[2] &&
      mask[(static_cast<std::int64_t>(z) * dims[1] + y) * dims[0] + x] != 0;
  };
  const int c[3] = { 2 * i + (d / 2 == 0 ? Offset(d) : 0), 2 * j + (d / 2 == 1 ? Offset(d) : 0),
    2 * k + (d / 2 == 2 ? Offset(d) : 0) };
  for (int z = 0; z < dims[2]; ++z)
    for (int y = 0; y < dims[1]; ++y)
      for (int x = 0; x < dims[0]; ++x)
      {
        if (!inside(x, y, z))
        {
          continue;
        }
        for (int dt = 0; dt < 6; ++dt)
        {
          int v[3] = { x, y, z };
          v[dt / 2] += Offset(dt);
          if (inside(v[0], v[1], v[2]))
          {
            continue;
          }
          std::int32_t u[3] = { 2 * x - c[0], 2 * y - c[1], 2 * z - c[2] };
          u[dt / 2] += Offset(dt);
          const double n2 = double(u[0]) * u[0] + double(u[1]) * u[1] + double(u[2]) * u[2];
          if (n2 <= 4.0 * (radius * radius))
          {
            out.insert(out.end(), u, u + 3);
          }
        }
      }
}

// ---------------------------------------------------------------------------
void HoughAccumulator::Build(int resolution)
{
  this->K = std::max(1, resolution);
  const int K = this->K;
  const double w = 0.5 * Pi / K;
  this->BandTop.resize(K + 1);
  this->BandFirst.resize(K);
  this->BandBins.resize(K);
  for (int b = 0; b <= K; ++b)
  {
    this->BandTop[b] = std::cos(b * w);
  }
  this->BandTop[0] = 1.0;
  this->BandTop[K] = 0.0;
  this->Bins = 0;
  for (int b = 0; b < K; ++b)
  {
    const int n = std::max(1, static_cast<int>(std::lround(Pi * K * std::sin((b + 0.5) * w))));
    this->BandFirst[b] = this->Bins;
    this->BandBins[b] = n;
    this->Bins += n;
  }
  // A band guess per z cell; Bin() corrects it in both directions.
  const int cells = 8 * K;
  this->Guess.resize(cells);
  for (int q = 0; q < cells; ++q)
  {
    const double z = (q + 0.5) / cells;
    int b = 0;
    while (b + 1 < K && z <= this->BandTop[b + 1])
    {
      ++b;
    }
    this->Guess[q] = b;
  }
}

// ---------------------------------------------------------------------------
void HoughTables::Build(int resolution, int accumulators, std::uint64_t seed)
{
  this->Accumulator.Build(resolution);
  this->A = std::max(1, accumulators);
  this->P = std::max(MinimumPool, this->A);
  const int A = this->P, G = CellsPerSide;
  // The rotations from the seed alone (a stream apart from the surfels').
  Generator g(Mix(seed ^ 0x5851F42D4C957F2Dull));
  this->Rotations.resize(9 * static_cast<std::size_t>(A));
  for (int a = 0; a < A; ++a)
  {
    RandomRotation(g, this->Rotations.data() + 9 * a);
  }
  const std::size_t cells = 3 * static_cast<std::size_t>(G) * G;
  this->Tables.resize(cells * A);
  for (int a = 0; a < A; ++a)
  {
    const double* R = this->Rotation(a);
    std::uint16_t* table = this->Tables.data() + cells * a;
    for (int face = 0; face < 3; ++face)
      for (int iv = 0; iv < G; ++iv)
        for (int iu = 0; iu < G; ++iu)
        {
          // The cell's centre on the face m = 1 (u, v in -1..1).
          const double u = (iu + 0.5) * 2.0 / G - 1, v = (iv + 0.5) * 2.0 / G - 1;
          double p[3];
          p[face] = 1;
          p[(face + 1) % 3] = u;
          p[(face + 2) % 3] = v;
          const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
          double x = (R[0] * p[0] + R[1] * p[1] + R[2] * p[2]) / l;
          double y = (R[3] * p[0] + R[4] * p[1] + R[5] * p[2]) / l;
          double z = (R[6] * p[0] + R[7] * p[1] + R[8] * p[2]) / l;
          const bool folded = z < 0;
          if (folded)
          {
            x = -x;
            y = -y;
            z = -z;
          }
          const int bin = this->Accumulator.Bin(x, y, z);
          table[(face * G + iv) * G + iu] = static_cast<std::uint16_t>(2 * bin + (folded ? 1 : 0));
        }
  }
}

// ---------------------------------------------------------------------------
std::uint64_t SurfelSeed(std::uint64_t seed, std::int64_t i, std::int64_t j, std::int64_t k, int d)
{
  std::uint64_t h = Mix(seed + 0x9E3779B97F4A7C15ull);
  h = Mix(h ^ static_cast<std::uint64_t>(i));
  h = Mix(h ^ static_cast<std::uint64_t>(j));
  h = Mix(h ^ static_cast<std::uint64_t>(k));
  return Mix(h ^ static_cast<std::uint64_t>(d));
}

namespace
{
// T valid triplets of the n points (at most 10 T draws), gathered per
// cube-map cell: count and sum of unit normals (largest component positive);
// touched lists the cells in the order of their first trial. I: the
// integer type of the cross products. Returns the number of valid trials.
template <typename I>
int GatherTrials(const std::int32_t* points, int n, int T, Generator& g, RHTCellSum* slots,
  std::int32_t* touched, int& distinct)
{
  int valid = 0;
  const std::int64_t maxDraws = 10 * static_cast<std::int64_t>(T);
  const std::uint32_t un = static_cast<std::uint32_t>(n);
  for (std::int64_t draw = 0; draw < maxDraws && valid < T; ++draw)
  {
    const std::uint32_t a = g.Below(un), b = g.Below(un), c = g.Below(un);
    if (a == b || b == c || a == c)
    {
      continue;
    }
    const std::int32_t* pa = points + 3 * a;
    const std::int32_t* pb = points + 3 * b;
    const std::int32_t* pc = points + 3 * c;
    const I e1[3] = { pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2] };
    const I e2[3] = { pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2] };
    const I cr[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
      e1[0] * e2[1] - e1[1] * e2[0] };
    if (cr[0] == 0 && cr[1] == 0 && cr[2] == 0)
    {
      continue; // collinear: the only degenerate triangles of surfel centres
    }
    I major;
    const int cell = HoughTables::Cell(cr, major);
    const double v[3] = { static_cast<double>(cr[0]), static_cast<double>(cr[1]),
      static_cast<double>(cr[2]) };
    const double inv = std::copysign(
      1.0 / std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), static_cast<double>(major));
    RHTCellSum& slot = slots[cell];
    // A cell's first trial lists it, without a branch.
    touched[distinct] = cell;
    distinct += slot.Count == 0;
    ++slot.Count;
    slot.Sum[0] += v[0] * inv;
    slot.Sum[1] += v[1] * inv;
    slot.Sum[2] += v[2] * inv;
    ++valid;
  }
  return valid;
}
} // namespace

void EstimateRHT(const std::int32_t* points, int numberOfPoints, const double reference[3],
  const RHTParameters& parameters, std::uint64_t surfelSeed, const HoughTables& tables,
  RHTWorkspace& work, RHTEstimate& out)
{
  const int n = numberOfPoints;
  const int T = std::max(1, parameters.Trials);
  const int A = tables.NumberOfAccumulators();
  if (n < 3)
  {
    Fallback(reference, n, out);
    return;
  }
  Generator g(surfelSeed);
  // The accumulators' rotations: A distinct ones of the pool (a partial
  // Fisher-Yates shuffle), then the triplets.
  const int P = tables.PoolSize();
  work.Pool.resize(static_cast<std::size_t>(P));
  int* pool = work.Pool.data();
  for (int q = 0; q < P; ++q)
  {
    pool[q] = q;
  }
  for (int a = 0; a < A; ++a)
  {
    std::swap(pool[a], pool[a + static_cast<int>(g.Below(static_cast<std::uint32_t>(P - a)))]);
  }

  // 1. T valid triplets (at most 10 T draws). Every accumulator bins a
  // normal by its cube-map cell alone, so the trials are gathered per cell
  // first (count, and sum of the unit normals turned so that their largest
  // component is positive): the votes and the winners' means then run over
  // the distinct cells (tens to a few hundred) instead of A x T trials.
  // The slots are all zero between surfels.
  work.Slots.resize(HoughTables::NumberOfCells());
  work.Touched.resize(HoughTables::NumberOfCells() + 1);
  RHTCellSum* slots = work.Slots.data();
  std::int32_t* touched = work.Touched.data();
  int distinct = 0;
  // Cross products of doubled offsets up to M in absolute value stay below
  // 8 M^2: 32-bit arithmetic up to M = 16383 (r up to about 8000 voxels).
  std::int32_t reach = 0;
  for (int q = 0; q < 3 * n; ++q)
  {
    reach = std::max(reach, points[q] < 0 ? -points[q] : points[q]);
  }
  const int valid = reach <= 16383
    ? GatherTrials<std::int32_t>(points, n, T, g, slots, touched, distinct)
    : GatherTrials<std::int64_t>(points, n, T, g, slots, touched, distinct);
  if (valid == 0)
  {
    Fallback(reference, n, out);
    return;
  }

  // 2. Per accumulator, the votes of the distinct cells: its table gives a
  // cell's bin and whether the cell's direction folds (then its normals
  // enter the bin's mean negated: n and -n are one plane). The winner has
  // most votes (ties: the lowest bin).
  const int bins = tables.NumberOfBins();
  work.Counts.resize(static_cast<std::size_t>(bins));
  work.Entries.resize(static_cast<std::size_t>(distinct));
  std::int32_t* counts = work.Counts.data();
  std::uint16_t* entries = work.Entries.data();
  double total[3] = { 0, 0, 0 };
  for (int a = 0; a < A; ++a)
  {
    const std::uint16_t* table = tables.Table(pool[a]);
    // The winner as the counts grow: counts only grow, so the bins that
    // reach the largest final count are all seen reaching it. One key per
    // (count, bin), larger for more votes and then for a lower bin: a max
    // without a branch (which bin wins is a coin toss for the predictor).
    std::int64_t bestKey = -1;
    for (int d = 0; d < distinct; ++d)
    {
      const std::uint16_t e = table[touched[d]];
      entries[d] = e;
      const int b = e >> 1;
      const std::int64_t c = (counts[b] += slots[touched[d]].Count);
      bestKey = std::max(bestKey, (c << 16) | (0xFFFF - b));
    }
    const int best = 0xFFFF - static_cast<int>(bestKey & 0xFFFF);
    double sum[3] = { 0, 0, 0 };
    for (int d = 0; d < distinct; ++d)
    {
      const unsigned e = entries[d];
      counts[e >> 1] = 0;
      if ((e >> 1) == static_cast<unsigned>(best))
      {
        const double w = (e & 1u) ? -1.0 : 1.0;
        const double* s = slots[touched[d]].Sum;
        sum[0] += w * s[0];
        sum[1] += w * s[1];
        sum[2] += w * s[2];
      }
    }
    const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    if (!(len > 0))
    {
      continue;
    }
    const double s =
      (sum[0] * reference[0] + sum[1] * reference[1] + sum[2] * reference[2] < 0 ? -1.0 : 1.0) /
      len;
    total[0] += s * sum[0];
    total[1] += s * sum[1];
    total[2] += s * sum[2];
  }
  for (int d = 0; d < distinct; ++d)
  {
    slots[touched[d]] = RHTCellSum();
  }
  const double len = std::sqrt(total[0] * total[0] + total[1] * total[1] + total[2] * total[2]);
  if (!(len > 0))
  {
    Fallback(reference, n, out);
    return;
  }
  for (int c = 0; c < 3; ++c)
  {
    out.Normal[c] = total[c] / len;
  }
  out.Fallback = false;
  out.Points = n;
  out.Trials = valid;
}

} // namespace dg
