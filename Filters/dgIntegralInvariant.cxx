#include "dgIntegralInvariant.h"

#include <vtkSMPTools.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace dg
{
namespace
{
// Sum of x and of x^2 over the integers x in [a, e).
inline std::int64_t SumX(std::int64_t a, std::int64_t e)
{
  return (e * (e - 1) - a * (a - 1)) / 2;
}
inline std::int64_t SumXX0(std::int64_t n) // 0^2 + ... + (n-1)^2
{
  return (n - 1) * n * (2 * n - 1) / 6;
}
inline std::int64_t SumXX(std::int64_t a, std::int64_t e)
{
  return SumXX0(e) - SumXX0(a);
}

inline std::int64_t FloorDiv2(std::int64_t v)
{
  return v >= 0 ? v / 2 : -((-v + 1) / 2);
}
} // namespace

void IIMoments::Covariance(double cov[9], double barycentreOffset[3]) const
{
  if (this->Count == 0)
  {
    std::fill(cov, cov + 9, 0.0);
    std::fill(barycentreOffset, barycentreOffset + 3, 0.0);
    return;
  }
  // In doubled coordinates: 4 C = SS - S S^T / N. N * SS - S_i S_j is an exact
  // integer (128 bits: no overflow even for radii of several hundred voxels),
  // so C is the exact value rounded once.
  static const int index[3][3] = { { 0, 1, 2 }, { 1, 3, 4 }, { 2, 4, 5 } };
  const __int128 n = this->Count;
  for (int a = 0; a < 3; ++a)
  {
    for (int b = 0; b < 3; ++b)
    {
      const __int128 num = n * this->Sum2[index[a][b]] -
        static_cast<__int128>(this->Sum[a]) * static_cast<__int128>(this->Sum[b]);
      cov[3 * a + b] = static_cast<double>(num) / (4.0 * static_cast<double>(this->Count));
    }
    barycentreOffset[a] = this->Sum[a] / (2.0 * static_cast<double>(this->Count));
  }
}

//------------------------------------------------------------------------------
void RowRuns::Build(
  const std::uint8_t* mask, const int dims[3], std::int64_t rowStride, int rowOffset)
{
  std::copy(dims, dims + 3, this->Dims);
  const std::int64_t rows = static_cast<std::int64_t>(dims[1]) * dims[2];
  const int nx = dims[0];
  std::vector<std::int64_t> counts(rows + 1, 0);
  // Pass 1: runs per row. Pass 2 (after a prefix sum) writes each row's runs
  // at their final place, so the result does not depend on the thread count.
  vtkSMPTools::For(0, rows, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t r = b; r < e; ++r)
    {
      const std::uint8_t* row = mask + r * rowStride + rowOffset;
      std::int64_t c = 0;
      bool prev = false;
      for (int i = 0; i < nx; ++i)
      {
        const bool in = row[i] != 0;
        c += in && !prev;
        prev = in;
      }
      counts[r] = c;
    }
  });
  this->RowFirst.assign(rows + 1, 0);
  for (std::int64_t r = 0; r < rows; ++r)
  {
    this->RowFirst[r + 1] = this->RowFirst[r] + counts[r];
  }
  counts = std::vector<std::int64_t>();
  const std::int64_t nRuns = this->RowFirst[rows];
  this->Start.assign(nRuns, 0);
  this->End.assign(nRuns, 0);
  this->Before.assign(3 * nRuns, 0);
  vtkSMPTools::For(0, rows, [&](std::int64_t b, std::int64_t e) {
    for (std::int64_t r = b; r < e; ++r)
    {
      const std::uint8_t* row = mask + r * rowStride + rowOffset;
      std::int64_t q = this->RowFirst[r];
      std::int64_t n = 0, s1 = 0, s2 = 0;
      int i = 0;
      while (i < nx)
      {
        if (!row[i])
        {
          ++i;
          continue;
        }
        int j = i;
        while (j < nx && row[j])
        {
          ++j;
        }
        this->Start[q] = i;
        this->End[q] = j;
        this->Before[3 * q] = n;
        this->Before[3 * q + 1] = s1;
        this->Before[3 * q + 2] = s2;
        n += j - i;
        s1 += SumX(i, j);
        s2 += SumXX(i, j);
        ++q;
        i = j;
      }
    }
  });
}

void RowRuns::RowSums(
  int j, int k, int x0, int x1, std::int64_t& n, std::int64_t& s1, std::int64_t& s2) const
{
  const std::int64_t row = static_cast<std::int64_t>(k) * this->Dims[1] + j;
  const std::int64_t b = this->RowFirst[row], e = this->RowFirst[row + 1];
  if (b == e)
  {
    n = s1 = s2 = 0;
    return;
  }
  if (e - b == 1)
  {
    // The common case near a smooth surface: one run, one intersection.
    const std::int64_t lo = std::max<std::int64_t>(this->Start[b], x0);
    const std::int64_t hi = std::min<std::int64_t>(this->End[b], x1 + 1);
    if (lo >= hi)
    {
      n = s1 = s2 = 0;
      return;
    }
    n = hi - lo;
    s1 = SumX(lo, hi);
    s2 = SumXX(lo, hi);
    return;
  }
  // Prefix sums over [0, X) from the run prefix of the last run starting
  // before X.
  const std::int32_t* starts = this->Start.data();
  auto prefix = [&](std::int64_t x, std::int64_t& pn, std::int64_t& p1, std::int64_t& p2) {
    const std::int64_t idx = std::lower_bound(starts + b, starts + e, x) - starts;
    if (idx == b)
    {
      pn = p1 = p2 = 0;
      return;
    }
    const std::int64_t q = idx - 1;
    const std::int64_t hi = std::min<std::int64_t>(this->End[q], x);
    pn = this->Before[3 * q] + (hi - this->Start[q]);
    p1 = this->Before[3 * q + 1] + SumX(this->Start[q], hi);
    p2 = this->Before[3 * q + 2] + SumXX(this->Start[q], hi);
  };
  std::int64_t an, a1, a2, bn, b1, b2;
  prefix(x1 + 1, bn, b1, b2);
  prefix(x0, an, a1, a2);
  n = bn - an;
  s1 = b1 - a1;
  s2 = b2 - a2;
}

bool RowRuns::Inside(int i, int j, int k) const
{
  if (i < 0 || j < 0 || k < 0 || i >= this->Dims[0] || j >= this->Dims[1] || k >= this->Dims[2])
  {
    return false;
  }
  std::int64_t n, s1, s2;
  this->RowSums(j, k, i, i, n, s1, s2);
  return n != 0;
}

std::size_t RowRuns::MemoryBytes() const
{
  return this->RowFirst.capacity() * sizeof(std::int64_t) +
    (this->Start.capacity() + this->End.capacity()) * sizeof(std::int32_t) +
    this->Before.capacity() * sizeof(std::int64_t);
}

//------------------------------------------------------------------------------
IIMoments HalfBallMoments(const BallRows& ball, const double n[3])
{
  const std::int64_t o = ball.Axis == 0;
  IIMoments m;
  std::int64_t N = 0, A = 0, B = 0;
  for (const BallRows::Row& row : ball.Rows)
  {
    // n_x u_x <= t on the row, u_x = 2 dx - o.
    const double t = -(n[1] * static_cast<double>(row.Uy) + n[2] * static_cast<double>(row.Uz));
    std::int64_t lo = row.X0, hi = row.X1;
    const double lim = 0.5 * (std::abs(n[0]) > 1e-12 ? t / n[0] + static_cast<double>(o) : 0.0);
    const double clamped = std::min(std::max(lim, row.X0 - 2.0), row.X1 + 2.0);
    if (n[0] > 1e-12)
    {
      hi = std::min(hi, static_cast<std::int64_t>(std::floor(clamped)));
    }
    else if (n[0] < -1e-12)
    {
      lo = std::max(lo, static_cast<std::int64_t>(std::ceil(clamped)));
    }
    else if (t < 0)
    {
      continue;
    }
    if (lo > hi)
    {
      continue;
    }
    const std::int64_t c = hi - lo + 1, s1 = SumX(lo, hi + 1), s2 = SumXX(lo, hi + 1);
    const std::int64_t sx = 2 * s1 - o * c;
    N += c;
    A += sx;
    B += 4 * s2 - 4 * o * s1 + o * o * c;
    m.Sum[1] += row.Uy * c;
    m.Sum[2] += row.Uz * c;
    m.Sum2[1] += row.Uy * sx;
    m.Sum2[2] += row.Uz * sx;
    m.Sum2[3] += row.Uy * row.Uy * c;
    m.Sum2[4] += row.Uy * row.Uz * c;
    m.Sum2[5] += row.Uz * row.Uz * c;
  }
  m.Count = N;
  m.Sum[0] = A;
  m.Sum2[0] = B;
  return m;
}

namespace
{
// 4 r^2 - (s_y u_y)^2 - (s_z u_z)^2: what is left of the ball's radius for
// the x part of a row, in doubled coordinates. With s = 1 this is the exact
// integer test u.u <= 4 r^2 (4 (r * r) is exact, and so are the squares).
inline double RowRemainder(double radius, const double s[3], std::int64_t uy, std::int64_t uz)
{
  const double ry = s[1] * static_cast<double>(uy), rz = s[2] * static_cast<double>(uz);
  return 4.0 * (radius * radius) - (ry * ry + rz * rz);
}
inline bool XInRow(const double s[3], std::int64_t ux, double rem)
{
  const double rx = s[0] * static_cast<double>(ux);
  return rx * rx <= rem;
}
const double UnitScale[3] = { 1, 1, 1 };
} // namespace

bool BallRows::Contains(
  double radius, const double scale[3], std::int64_t ux, std::int64_t uy, std::int64_t uz)
{
  const double* s = scale ? scale : UnitScale;
  const double rem = RowRemainder(radius, s, uy, uz);
  return rem >= 0 && XInRow(s, ux, rem);
}

void BallRows::Build(double radius, int axis, const double* scale)
{
  this->Axis = axis;
  this->Rows.clear();
  this->Voxels = 0;
  this->TangentMoment = 0.0;
  const double* s = scale ? scale : UnitScale;
  std::copy(s, s + 3, this->Scale);
  this->Scaled = s[0] != 1.0 || s[1] != 1.0 || s[2] != 1.0;
  std::fill(this->AxisMoment, this->AxisMoment + 3, 0.0);
  const int o[3] = { axis == 0, axis == 1, axis == 2 };
  int reach[3];
  for (int a = 0; a < 3; ++a)
  {
    reach[a] = static_cast<int>(std::ceil(radius / s[a])) + 1;
  }
  for (int dz = -reach[2]; dz <= reach[2]; ++dz)
  {
    const std::int64_t uz = 2 * dz - o[2];
    for (int dy = -reach[1]; dy <= reach[1]; ++dy)
    {
      const std::int64_t uy = 2 * dy - o[1];
      const double rem = RowRemainder(radius, s, uy, uz);
      if (rem < 0)
      {
        continue;
      }
      // Largest m with (s_x m)^2 <= rem, by the same test as Contains.
      std::int64_t m = static_cast<std::int64_t>(std::sqrt(rem) / s[0]);
      while (XInRow(s, m + 1, rem))
      {
        ++m;
      }
      while (m > 0 && !XInRow(s, m, rem))
      {
        --m;
      }
      // |2 dx - o[0]| <= m.
      const std::int64_t x0 = -FloorDiv2(m - o[0]); // ceil((o - m) / 2)
      const std::int64_t x1 = FloorDiv2(o[0] + m);
      if (x0 > x1)
      {
        continue;
      }
      if (this->Rows.empty())
      {
        this->MinDy = this->MaxDy = dy;
        this->MinDz = this->MaxDz = dz;
        this->MinX = static_cast<int>(x0);
        this->MaxX = static_cast<int>(x1);
      }
      this->MinDy = std::min(this->MinDy, dy);
      this->MaxDy = std::max(this->MaxDy, dy);
      this->MinDz = std::min(this->MinDz, dz);
      this->MaxDz = std::max(this->MaxDz, dz);
      this->MinX = std::min(this->MinX, static_cast<int>(x0));
      this->MaxX = std::max(this->MaxX, static_cast<int>(x1));
      this->Rows.push_back({ dy, dz, static_cast<int>(x0), static_cast<int>(x1), uy, uz });
      const std::int64_t c = x1 - x0 + 1;
      this->Voxels += c;
      // Sum of (2 x - o)^2 over the row, exactly.
      const std::int64_t sxx =
        4 * SumXX(x0, x1 + 1) - 4 * o[0] * SumX(x0, x1 + 1) + o[0] * o[0] * c;
      this->AxisMoment[0] += 0.25 * s[0] * s[0] * static_cast<double>(sxx);
      this->AxisMoment[1] += 0.25 * s[1] * s[1] * static_cast<double>(uy * uy * c);
      this->AxisMoment[2] += 0.25 * s[2] * s[2] * static_cast<double>(uz * uz * c);
      // Tangent axis (axis + 1) % 3: y for axis x, z for axis y, x for axis z.
      if (axis == 0)
      {
        this->TangentMoment += 0.25 * static_cast<double>(uy * uy * c);
      }
      else if (axis == 1)
      {
        this->TangentMoment += 0.25 * static_cast<double>(uz * uz * c);
      }
      else
      {
        for (std::int64_t x = x0; x <= x1; ++x)
        {
          this->TangentMoment += static_cast<double>(x * x);
        }
      }
    }
  }
}

//------------------------------------------------------------------------------
void IntegralInvariantKernel::SetVolume(
  const std::uint8_t* mask, const int dims[3], std::int64_t rowStride, int rowOffset)
{
  this->Runs.Build(mask, dims, rowStride, rowOffset);
}

void IntegralInvariantKernel::SetRadius(double radius, const double* scale)
{
  this->Radius = radius;
  for (int a = 0; a < 3; ++a)
  {
    this->Balls[a].Build(radius, a, scale);
  }
}

namespace
{
// The ball sum proper. Clip is false when the ball's bounding box lies in the
// grid (most surfels), which drops the bounds tests from the row loop.
// Per row: n, sum x, sum x^2 of its inside voxels (absolute x); the y
// moments are weighted per row, the z moments once per z-slice of the ball
// (rows are sorted by Dz), and x is shifted to the centre at the end: all
// exact integers.
template <bool Clip>
IIMoments SumBall(const RowRuns& runs, const BallRows& ball, const int lower[3])
{
  const int nx = runs.Dims[0], ny = runs.Dims[1], nz = runs.Dims[2];
  const std::int64_t* first = runs.RowFirst.data();
  const std::int32_t* start = runs.Start.data();
  const std::int32_t* end = runs.End.data();
  std::int64_t N = 0, A = 0, B = 0, Sy = 0, Syy = 0, Sz = 0, Szz = 0, Syz = 0, Ay = 0, Az = 0;
  // Current z-slice partial sums.
  std::int64_t zN = 0, zA = 0, zSy = 0;
  std::int64_t uz = ball.Rows.empty() ? 0 : ball.Rows.front().Uz;
  for (const BallRows::Row& row : ball.Rows)
  {
    if (row.Uz != uz)
    {
      Sz += uz * zN;
      Szz += uz * uz * zN;
      Syz += uz * zSy;
      Az += uz * zA;
      zN = zA = zSy = 0;
      uz = row.Uz;
    }
    const int z = lower[2] + row.Dz;
    const int y = lower[1] + row.Dy;
    int x0 = lower[0] + row.X0;
    int x1 = lower[0] + row.X1;
    if (Clip)
    {
      if (z < 0 || z >= nz || y < 0 || y >= ny)
      {
        continue;
      }
      x0 = std::max(x0, 0);
      x1 = std::min(x1, nx - 1);
      if (x0 > x1)
      {
        continue;
      }
    }
    const std::int64_t r = static_cast<std::int64_t>(z) * ny + y;
    const std::int64_t b = first[r], e = first[r + 1];
    if (b == e)
    {
      continue;
    }
    std::int64_t n, s1, s2;
    if (e - b == 1)
    {
      const std::int64_t lo = std::max(start[b], x0);
      const std::int64_t hi = std::min(end[b], x1 + 1);
      if (lo >= hi)
      {
        continue;
      }
      n = hi - lo;
      s1 = SumX(lo, hi);
      s2 = SumXX(lo, hi);
    }
    else
    {
      runs.RowSums(y, z, x0, x1, n, s1, s2);
      if (n == 0)
      {
        continue;
      }
    }
    const std::int64_t yn = row.Uy * n;
    N += n;
    A += s1;
    B += s2;
    Sy += yn;
    Syy += row.Uy * yn;
    Ay += row.Uy * s1;
    zN += n;
    zA += s1;
    zSy += yn;
  }
  Sz += uz * zN;
  Szz += uz * uz * zN;
  Syz += uz * zSy;
  Az += uz * zA;
  const std::int64_t cx = 2 * static_cast<std::int64_t>(lower[0]) + (ball.Axis == 0);
  IIMoments m;
  m.Count = N;
  m.Sum[0] = 2 * A - cx * N;
  m.Sum[1] = Sy;
  m.Sum[2] = Sz;
  m.Sum2[0] = 4 * B - 4 * cx * A + cx * cx * N;
  m.Sum2[1] = 2 * Ay - cx * Sy;
  m.Sum2[2] = 2 * Az - cx * Sz;
  m.Sum2[3] = Syy;
  m.Sum2[4] = Syz;
  m.Sum2[5] = Szz;
  return m;
}
} // namespace

IIMoments IntegralInvariantKernel::Moments(int i, int j, int k, int direction) const
{
  const int axis = direction / 2;
  int lower[3] = { i, j, k };
  if (!(direction & 1))
  {
    --lower[axis];
  }
  const BallRows& ball = this->Balls[axis];
  const int* dims = this->Runs.Dims;
  const bool inside = lower[0] + ball.MinX >= 0 && lower[0] + ball.MaxX < dims[0] &&
    lower[1] + ball.MinDy >= 0 && lower[1] + ball.MaxDy < dims[1] &&
    lower[2] + ball.MinDz >= 0 && lower[2] + ball.MaxDz < dims[2];
  return inside ? SumBall<false>(this->Runs, ball, lower) : SumBall<true>(this->Runs, ball, lower);
}

//------------------------------------------------------------------------------
namespace
{
template <typename Visit>
void VisitBall(const std::uint8_t* mask, const int dims[3], double radius, int i, int j, int k,
  int direction, const double* scale, Visit&& visit)
{
  const int axis = direction / 2;
  double c[3] = { double(i), double(j), double(k) };
  c[axis] += (direction & 1) ? 0.5 : -0.5;
  const int v[3] = { i, j, k };
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a)
  {
    const int reach = static_cast<int>(std::ceil(radius / (scale ? scale[a] : 1.0))) + 1;
    lo[a] = std::max(v[a] - reach, 0);
    hi[a] = std::min(v[a] + reach, dims[a] - 1);
  }
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x)
      {
        const double d[3] = { x - c[0], y - c[1], z - c[2] };
        if (!BallRows::Contains(radius, scale, std::llround(2 * d[0]), std::llround(2 * d[1]),
              std::llround(2 * d[2])))
        {
          continue;
        }
        if (mask[(static_cast<std::int64_t>(z) * dims[1] + y) * dims[0] + x])
        {
          visit(d);
        }
      }
}
} // namespace

IIMoments BruteForceMoments(const std::uint8_t* mask, const int dims[3], double radius, int i,
  int j, int k, int direction, const double* scale)
{
  IIMoments m;
  VisitBall(mask, dims, radius, i, j, k, direction, scale, [&](const double d[3]) {
    const std::int64_t u[3] = { std::llround(2 * d[0]), std::llround(2 * d[1]),
      std::llround(2 * d[2]) };
    ++m.Count;
    for (int a = 0; a < 3; ++a)
    {
      m.Sum[a] += u[a];
    }
    m.Sum2[0] += u[0] * u[0];
    m.Sum2[1] += u[0] * u[1];
    m.Sum2[2] += u[0] * u[2];
    m.Sum2[3] += u[1] * u[1];
    m.Sum2[4] += u[1] * u[2];
    m.Sum2[5] += u[2] * u[2];
  });
  return m;
}

void BruteForceCovariance(const std::uint8_t* mask, const int dims[3], double radius, int i, int j,
  int k, int direction, double cov[9], std::int64_t& count, const double* scale)
{
  double b[3] = { 0, 0, 0 };
  count = 0;
  VisitBall(mask, dims, radius, i, j, k, direction, scale, [&](const double d[3]) {
    ++count;
    for (int a = 0; a < 3; ++a)
    {
      b[a] += d[a];
    }
  });
  std::fill(cov, cov + 9, 0.0);
  if (count == 0)
  {
    return;
  }
  for (double& x : b)
  {
    x /= static_cast<double>(count);
  }
  VisitBall(mask, dims, radius, i, j, k, direction, scale, [&](const double d[3]) {
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
      {
        cov[3 * a + c] += (d[a] - b[a]) * (d[c] - b[c]);
      }
  });
}

//------------------------------------------------------------------------------
void EstimateFromMoments(const IIMoments& m, int direction, double radius, bool curvatures,
  IIEstimate& out, IICurvatureReference reference, const BallRows* ball)
{
  const int axis = direction / 2;
  const double sign = (direction & 1) ? 1.0 : -1.0;
  double cov[9], offset[3];
  m.Covariance(cov, offset);
  // On a scaled grid everything below runs in the scaled frame q = S p
  // (S = diag(scale)), where the ball is Euclidean: covariance S C S, first
  // moments S Sum, each voxel a cell of volume det S.
  const bool scaled = ball && ball->Scaled;
  const Eigen::Vector3d S = scaled ? Eigen::Vector3d(ball->Scale[0], ball->Scale[1], ball->Scale[2])
                                   : Eigen::Vector3d::Ones();
  const double cell = scaled ? S.prod() : 1.0;
  Eigen::Matrix3d C = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(cov);
  if (scaled)
  {
    C = cell * (S.asDiagonal() * C * S.asDiagonal()).eval();
  }
  // Closed-form 3x3 solver: about 5x faster than the iterative one; the
  // normal's eigenvalue is well separated from the others (0.059 r^2 vs
  // 0.2 r^2 per voxel for a plane), where it is accurate.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(C);
  const Eigen::Vector3d mu = eig.eigenvalues(); // increasing
  const Eigen::Matrix3d& V = eig.eigenvectors();
  Eigen::Vector3d n = V.col(0);
  out.TrivialFallback = false;
  // A line of voxels (or one voxel) has no normal direction.
  if (m.Count < 3 || !(mu[1] > 1e-12 * std::max(mu[2], 1e-300)))
  {
    n.setZero();
    n[axis] = sign;
    out.TrivialFallback = true;
  }
  else
  {
    // Outward: from the barycentre b to the centre c, i.e. along -(b - c).
    // Sum is the exact integer 2 N (b - c): zero or perpendicular to n means
    // the ball gives no side, and only then the surfel's axis decides.
    Eigen::Vector3d s(
      static_cast<double>(m.Sum[0]), static_cast<double>(m.Sum[1]), static_cast<double>(m.Sum[2]));
    if (scaled)
    {
      s = S.cwiseProduct(s);
    }
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
  // A covector of the scaled frame is S times the grid's (n . dq = n . S dp).
  const Eigen::Vector3d ng = scaled ? S.cwiseProduct(n).normalized() : n;
  for (int a = 0; a < 3; ++a)
  {
    out.Normal[a] = ng[a];
  }
  if (!curvatures)
  {
    return;
  }
  // docs/method.md section 6 with its constants written as the reference half
  // ball's volume V and tangent moments J1, J2 (along the eigenvectors of mu1
  // and mu2): 8/(3r) = 4 V / (pi r^4) and 8/(5r) = 6 (2 J) / (pi r^6) for the
  // Euclidean half ball, where J1 = J2 = J = 2 pi r^5 / 15.
  const double r = radius;
  const double pi = 3.14159265358979323846;
  const double r4 = r * r * r * r, r6 = r4 * r * r;
  double vol, J1, J2;
  if (reference == IICurvatureReference::Continuous || !ball)
  {
    vol = 2.0 * pi * r * r * r / 3.0;
    J1 = J2 = 2.0 * pi * r4 * r / 15.0;
  }
  else if (reference == IICurvatureReference::DigitalBall)
  {
    vol = 0.5 * static_cast<double>(ball->Voxels) * cell;
    if (scaled)
    {
      // The half ball cut across the surfel's axis: half of the ball's
      // (diagonal) second moments, read along each eigenvector.
      const Eigen::Vector3d Q(ball->AxisMoment[0], ball->AxisMoment[1], ball->AxisMoment[2]);
      J1 = 0.5 * cell * V.col(1).cwiseAbs2().dot(Q);
      J2 = 0.5 * cell * V.col(2).cwiseAbs2().dot(Q);
    }
    else
    {
      J1 = J2 = 0.5 * ball->TangentMoment;
    }
  }
  else
  {
    // HalfBallMoments takes the half-space in grid coordinates: the grid
    // covector ng gives the same plane as n in the scaled frame.
    const IIMoments half = HalfBallMoments(*ball, out.Normal);
    double hc[9], ho[3];
    half.Covariance(hc, ho);
    Eigen::Matrix3d ref = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(hc);
    if (scaled)
    {
      ref = cell * (S.asDiagonal() * ref * S.asDiagonal()).eval();
    }
    vol = static_cast<double>(half.Count) * cell;
    J1 = V.col(1).dot(ref * V.col(1));
    J2 = V.col(2).dot(ref * V.col(2));
  }
  out.Mean = 4.0 / (pi * r4) * (vol - static_cast<double>(m.Count) * cell);
  const double a1 = mu[1] - J1, a2 = mu[2] - J2;
  out.K1 = 6.0 / (pi * r6) * (a2 - 3.0 * a1);
  out.K2 = 6.0 / (pi * r6) * (a1 - 3.0 * a2);
  out.Gaussian = out.K1 * out.K2;
  // K1 comes from a2 - 3 a1: it is the curvature along mu1's eigenvector,
  // the smaller tangent eigenvalue (a surface that curves away more along a
  // direction leaves less of the ball's inside near the rim there). The
  // project's first method notes paired k1 with mu2's eigenvector (so did DGtal's combined
  // curvature-and-direction functor until its pull request 1657); the
  // tilted-cylinder and torus tests settle it. With a
  // per-direction reference the order can flip (k1 >= k2 always).
  const int e1 = out.K1 >= out.K2 ? 1 : 2;
  if (out.K1 < out.K2)
  {
    std::swap(out.K1, out.K2);
  }
  // A vector of the scaled frame is S^-1 times the grid's.
  const Eigen::Vector3d d1 = scaled ? V.col(e1).cwiseQuotient(S).normalized() : V.col(e1).eval();
  const Eigen::Vector3d d2 =
    scaled ? V.col(3 - e1).cwiseQuotient(S).normalized() : V.col(3 - e1).eval();
  for (int a = 0; a < 3; ++a)
  {
    out.Direction1[a] = d1[a];
    out.Direction2[a] = d2[a];
  }
}

} // namespace dg
