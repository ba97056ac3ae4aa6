// Fixed-block parallel loops, reductions and matrix products shared by the
// Ambrosio-Tortorelli solver's assembly and its linear systems (private to
// the module).
#ifndef dgATBlocks_h
#define dgATBlocks_h

#include "dgATOperators.h"
#include "dgATSolver.h" // ATColumns

#include <vtkSMPTools.h>

#include <Eigen/Dense>

#include <cstdint>
#include <vector>

namespace dg
{

// Fixed-size blocks: parallel loops and reductions are split the same way
// whatever the number of threads, and partial sums are added in block order,
// so every result is bitwise reproducible.
constexpr std::int64_t BlockSize = 2048;

template<class Body>
void ForBlocks(std::int64_t n, const Body& body)
{
  const std::int64_t nb = (n + BlockSize - 1) / BlockSize;
  // Tasks of at least ~32k rows: below that, waking threads costs more than
  // the work (CG makes three such loops per iteration).
  vtkSMPTools::For(0,
    nb,
    16,
    [&](std::int64_t b0, std::int64_t b1)
    {
      for (std::int64_t b = b0; b < b1; ++b)
      {
        body(b, b * BlockSize, std::min(n, (b + 1) * BlockSize));
      }
    });
}

inline std::int64_t NumberOfBlocks(std::int64_t n)
{
  return (n + BlockSize - 1) / BlockSize;
}

// Sums `count` values per block, block by block in order.
inline void ReduceBlocks(const std::vector<double>& partial, std::int64_t nb, int count, double* out)
{
  for (int c = 0; c < count; ++c)
  {
    out[c] = 0.0;
  }
  for (std::int64_t b = 0; b < nb; ++b)
  {
    for (int c = 0; c < count; ++c)
    {
      out[c] += partial[b * count + c];
    }
  }
}

// y_i = sum_k a_ik w_k for all nc columns of a column-interleaved w. With NC
// fixed the sums stay in registers (y may alias w as far as the compiler
// knows); a dynamic column count accumulates in y itself.
template<int NC, class T>
inline void RowProduct(const ATSystemView& m,
  std::int64_t i,
  const T* w,
  double* y,
  int ncRun)
{
  const int nc = NC > 0 ? NC : ncRun; // a constant lets the compiler unroll
  const int* outer = m.outerIndexPtr();
  const int* inner = m.innerIndexPtr();
  const double* val = m.valuePtr();
  double tFixed[NC > 0 ? NC : 1] = {};
  double* t = NC > 0 ? tFixed : y;
  for (int c = 0; NC == 0 && c < nc; ++c)
  {
    y[c] = 0.0;
  }
  for (int k = outer[i]; k < outer[i + 1]; ++k)
  {
    const double a = val[k];
    const T* wk = w + static_cast<std::int64_t>(inner[k]) * nc;
    for (int c = 0; c < nc; ++c)
    {
      t[c] += a * static_cast<double>(wk[c]);
    }
  }
  for (int c = 0; NC > 0 && c < nc; ++c)
  {
    y[c] = t[c];
  }
}

// q = A p for all columns and the per-column sums p.q (fixed blocks, summed
// in order); partial holds at least NumberOfBlocks(n) * nc values.
template<int NC>
inline void ProductAndDot(const ATSystemView& m,
  const std::vector<double>& p,
  std::vector<double>& q,
  int ncRun,
  std::vector<double>& partial,
  double* pq)
{
  const int nc = NC > 0 ? NC : ncRun;
  const std::int64_t n = m.cols();
  ForBlocks(n,
    [&](std::int64_t blk, std::int64_t i0, std::int64_t i1)
    {
      double acc[NC > 0 ? NC : 16] = {};
      std::vector<double> accDyn(NC > 0 ? 0 : nc, 0.0);
      double* s = NC > 0 ? acc : accDyn.data();
      for (std::int64_t i = i0; i < i1; ++i)
      {
        double* qi = q.data() + i * nc;
        RowProduct<NC>(m, i, p.data(), qi, nc);
        for (int c = 0; c < nc; ++c)
        {
          s[c] += p[i * nc + c] * qi[c];
        }
      }
      std::copy(s, s + nc, partial.data() + blk * nc);
    });
  ReduceBlocks(partial, NumberOfBlocks(n), nc, pq);
}

// Column-interleaved copies (row i, column c at i * nc + c): one read of a
// matrix row then serves every column.
inline void Interleave(ATConstColumns a, std::vector<double>& v)
{
  const std::int64_t n = a.rows(), nc = a.cols();
  v.resize(n * nc);
  for (std::int64_t c = 0; c < nc; ++c)
  {
    for (std::int64_t i = 0; i < n; ++i)
    {
      v[i * nc + c] = a(i, c);
    }
  }
}

inline bool AllFinite(const std::vector<double>& v)
{
  return std::all_of(v.begin(), v.end(), [](double a) { return std::isfinite(a); });
}

inline void Deinterleave(const std::vector<double>& v, ATColumns a)
{
  const std::int64_t n = a.rows(), nc = a.cols();
  for (std::int64_t c = 0; c < nc; ++c)
  {
    for (std::int64_t i = 0; i < n; ++i)
    {
      a(i, c) = v[i * nc + c];
    }
  }
}

// Calls system.SolveN<NC> with the column count fixed at compile time for
// the two common cases (1 for v, 3 for normals).
template<class System>
bool SolveColumns(System& system,
  const ATSystemView& m,
  const ATRhs& b,
  ATColumns x)
{
  switch (b.Columns)
  {
    case 1:
      return system.template SolveN<1>(m, b, x, 1);
    case 3:
      return system.template SolveN<3>(m, b, x, 3);
    default:
      return system.template SolveN<0>(m, b, x, static_cast<int>(b.Columns));
  }
}

} // namespace dg

#endif
