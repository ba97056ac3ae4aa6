#include "dgATSolver.h"

#include <vtkSMPTools.h>

#include <Eigen/SparseCholesky>
#ifdef DG_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace dg
{
namespace
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

std::int64_t NumberOfBlocks(std::int64_t n)
{
  return (n + BlockSize - 1) / BlockSize;
}

// Sums `count` values per block, block by block in order.
void ReduceBlocks(const std::vector<double>& partial, std::int64_t nb, int count, double* out)
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
template<int NC>
inline void RowProduct(const ATSystemMatrix& m,
  std::int64_t i,
  const double* w,
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
    const double* wk = w + static_cast<std::int64_t>(inner[k]) * nc;
    for (int c = 0; c < nc; ++c)
    {
      t[c] += a * wk[c];
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
void ProductAndDot(const ATSystemMatrix& m,
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
void Interleave(const Eigen::MatrixXd& a, std::vector<double>& v)
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

bool AllFinite(const std::vector<double>& v)
{
  return std::all_of(v.begin(), v.end(), [](double a) { return std::isfinite(a); });
}

void Deinterleave(const std::vector<double>& v, Eigen::MatrixXd& a)
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
  const ATSystemMatrix& m,
  const Eigen::MatrixXd& b,
  Eigen::MatrixXd& x)
{
  switch (b.cols())
  {
    case 1:
      return system.template SolveN<1>(m, b, x, 1);
    case 3:
      return system.template SolveN<3>(m, b, x, 3);
    default:
      return system.template SolveN<0>(m, b, x, static_cast<int>(b.cols()));
  }
}

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
} // namespace

// One linear system whose pattern never changes: Analyze once, then
// Factorize + Solve at each step with new values.
class ATLinearSystem
{
public:
  virtual ~ATLinearSystem() = default;
  virtual bool Analyze(const ATSystemMatrix&) { return true; }
  virtual bool Factorize(const ATSystemMatrix&) = 0;
  /// x holds the previous solution on entry (a warm start for iterative
  /// solvers) and the new one on success.
  virtual bool Solve(const ATSystemMatrix& m, const Eigen::MatrixXd& b, Eigen::MatrixXd& x) = 0;
  bool Analyzed = false;
  std::int64_t Iterations = 0;
};

namespace
{
template<class Factor>
class DirectSystem : public ATLinearSystem
{
public:
  bool Analyze(const ATSystemMatrix& m) override
  {
    this->F.analyzePattern(m);
    return this->F.info() == Eigen::Success;
  }
  bool Factorize(const ATSystemMatrix& m) override
  {
    this->F.factorize(m);
    return this->F.info() == Eigen::Success;
  }
  bool Solve(const ATSystemMatrix&, const Eigen::MatrixXd& b, Eigen::MatrixXd& x) override
  {
    Eigen::MatrixXd y = this->F.solve(b);
    if (this->F.info() != Eigen::Success || !y.allFinite())
    {
      return false;
    }
    x = std::move(y);
    return true;
  }

private:
  Factor F;
};

// Jacobi-preconditioned conjugate gradients on all columns at once: one sweep
// over the matrix serves every right-hand side. The matrix is symmetric and
// stored full, so column i is row i.
class CGSystem : public ATLinearSystem
{
public:
  CGSystem(double tolerance, int maxIterations)
    : Tolerance(tolerance)
    , MaxIterations(maxIterations)
  {
  }
  bool Factorize(const ATSystemMatrix& m) override
  {
    const std::int64_t n = m.cols();
    this->InvDiag.resize(n);
    bool ok = true;
    const int* outer = m.outerIndexPtr();
    const int* inner = m.innerIndexPtr();
    const double* val = m.valuePtr();
    for (std::int64_t i = 0; i < n; ++i)
    {
      double d = 0;
      for (int k = outer[i]; k < outer[i + 1]; ++k)
      {
        d += inner[k] == i ? val[k] : 0.0;
      }
      ok = ok && d > 0;
      this->InvDiag[i] = d > 0 ? 1.0 / d : 1.0;
    }
    return ok;
  }

  bool Solve(const ATSystemMatrix& m, const Eigen::MatrixXd& b, Eigen::MatrixXd& x) override
  {
    return SolveColumns(*this, m, b, x);
  }

  // The vectors are stored interleaved (row i, column c at i * nc + c) so
  // that one read of a matrix row serves every column. NC > 0 fixes the
  // number of columns at compile time (1 for v, 3 for normals).
  //
  // The solve is memory-bound (BenchAT: ~20 GB/s of vector and matrix
  // traffic on octa-flower), so each iteration makes three sweeps and keeps
  // no more vectors than it must: q = A p (with p.q); r -= alpha q (with
  // r.D^-1 r and r.r: z = D^-1 r is never stored); then x += alpha p and
  // p = D^-1 r + beta p in one sweep. Same iterates as the textbook
  // algorithm, two vector passes fewer per iteration.
  template<int NC>
  bool SolveN(const ATSystemMatrix& m, const Eigen::MatrixXd& b, Eigen::MatrixXd& xOut, int ncRun)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t n = m.cols();
    if (xOut.rows() != n || xOut.cols() != nc)
    {
      xOut = Eigen::MatrixXd::Zero(n, nc);
    }
    const double* dinv = this->InvDiag.data();
    std::vector<double> x, r, p(n * nc), q(n * nc);
    Interleave(xOut, x);
    Interleave(b, r);
    const std::int64_t nb = NumberOfBlocks(n);
    std::vector<double> partial(nb * 3 * nc);
    std::vector<double> sums(3 * nc);
    std::vector<double> rz(nc), bb(nc), alpha(nc, 0.0), beta(nc, 0.0);
    std::vector<char> active(nc, 1);
    auto rowProduct = [&](std::int64_t i, const double* w, double* y)
    { RowProduct<NC>(m, i, w, y, nc); };

    // r = b - A x (r holds b on entry), p = D^-1 r; sums of r.z, b.b, r.r.
    ForBlocks(n,
      [&](std::int64_t blk, std::int64_t i0, std::int64_t i1)
      {
        double acc[3 * (NC > 0 ? NC : 16)] = {};
        std::vector<double> accDyn(NC > 0 ? 0 : 3 * nc, 0.0), y(nc);
        double* s = NC > 0 ? acc : accDyn.data();
        for (std::int64_t i = i0; i < i1; ++i)
        {
          rowProduct(i, x.data(), y.data());
          for (int c = 0; c < nc; ++c)
          {
            const std::int64_t ic = i * nc + c;
            const double bic = r[ic], ri = bic - y[c], zi = dinv[i] * ri;
            r[ic] = ri;
            p[ic] = zi;
            s[3 * c] += ri * zi;
            s[3 * c + 1] += bic * bic;
            s[3 * c + 2] += ri * ri;
          }
        }
        std::copy(s, s + 3 * nc, partial.data() + blk * 3 * nc);
      });
    ReduceBlocks(partial, nb, 3 * nc, sums.data());
    int nActive = 0;
    for (int c = 0; c < nc; ++c)
    {
      rz[c] = sums[3 * c];
      bb[c] = sums[3 * c + 1];
      active[c] = sums[3 * c + 2] > this->Tolerance * this->Tolerance * bb[c];
      nActive += active[c];
    }
    int it = 0;
    while (nActive > 0 && it < this->MaxIterations)
    {
      ++it;
      // q = A p and p.q (converged columns are computed but not used).
      ProductAndDot<NC>(m, p, q, nc, partial, sums.data());
      for (int c = 0; c < nc; ++c)
      {
        if (active[c] && !(sums[c] > 0))
        {
          return false; // not positive definite (or NaN)
        }
        alpha[c] = active[c] ? rz[c] / sums[c] : 0.0;
      }
      // r -= alpha q; sums of r.D^-1 r and r.r.
      ForBlocks(n,
        [&](std::int64_t blk, std::int64_t i0, std::int64_t i1)
        {
          double acc[2 * (NC > 0 ? NC : 16)] = {};
          std::vector<double> accDyn(NC > 0 ? 0 : 2 * nc, 0.0);
          double* s = NC > 0 ? acc : accDyn.data();
          for (std::int64_t i = i0; i < i1; ++i)
          {
            for (int c = 0; c < nc; ++c)
            {
              const std::int64_t ic = i * nc + c;
              const double ri = r[ic] - alpha[c] * q[ic];
              r[ic] = ri;
              s[2 * c] += ri * dinv[i] * ri;
              s[2 * c + 1] += ri * ri;
            }
          }
          std::copy(s, s + 2 * nc, partial.data() + blk * 2 * nc);
        });
      ReduceBlocks(partial, nb, 2 * nc, sums.data());
      nActive = 0;
      for (int c = 0; c < nc; ++c)
      {
        if (!active[c])
        {
          continue;
        }
        beta[c] = sums[2 * c] / rz[c];
        rz[c] = sums[2 * c];
        active[c] = sums[2 * c + 1] > this->Tolerance * this->Tolerance * bb[c];
        nActive += active[c];
      }
      // x += alpha p (alpha is 0 for columns converged before this
      // iteration), then p = D^-1 r + beta p for the columns still active.
      ForBlocks(n,
        [&](std::int64_t, std::int64_t i0, std::int64_t i1)
        {
          // p = g D^-1 r + h p with (g, h) = (1, beta), or (0, 1) to keep
          // p: no branch, and local copies the compiler need not reload.
          double a[NC > 0 ? NC : 16], g[NC > 0 ? NC : 16], h[NC > 0 ? NC : 16];
          const bool local = nc <= 16;
          for (int c = 0; local && c < nc; ++c)
          {
            a[c] = alpha[c];
            g[c] = active[c] ? 1.0 : 0.0;
            h[c] = active[c] ? beta[c] : 1.0;
          }
          for (std::int64_t i = i0; i < i1; ++i)
          {
            for (int c = 0; c < nc; ++c)
            {
              const std::int64_t ic = i * nc + c;
              const double ac = local ? a[c] : alpha[c];
              const double gc = local ? g[c] : (active[c] ? 1.0 : 0.0);
              const double hc = local ? h[c] : (active[c] ? beta[c] : 1.0);
              x[ic] += ac * p[ic];
              p[ic] = gc * dinv[i] * r[ic] + hc * p[ic];
            }
          }
        });
    }
    this->Iterations += it;
    if (nActive != 0 || !AllFinite(x))
    {
      return false; // xOut keeps the previous values
    }
    Deinterleave(x, xOut);
    return true;
  }

private:
  double Tolerance;
  int MaxIterations;
  Eigen::VectorXd InvDiag;
};

// Conjugate gradients preconditioned by a zero fill-in incomplete
// factorisation A ~ L D L^T (IC(0)) in the surface's own order, block
// Jacobi style: the rows are cut into fixed contiguous ranges (sizes below,
// a function of the matrix size only) and the
// couplings between ranges are left out of the factor, so that the ranges
// are factorised and swept in parallel and the result does not depend on
// the number of threads. The matrices are diagonally dominant with positive
// diagonals (H-matrices), for which IC(0) exists; should rounding still give
// a pivot <= 0, that solve falls back to the diagonal (Jacobi). The factor
// is refreshed at every step (numeric only: pattern and index maps once).
// The factor is stored in single precision: it only preconditions (the
// iterates, residuals and products stay in double, so the solution's
// accuracy is the same), and reading half the bytes saved 7 % of the solve
// time on octa-flower at the same iteration count.
//
// Block size: about 8 blocks (for the threads to share), each of 16 384 to
// 65 536 rows. Larger blocks drop fewer couplings: on octa-flower (671 270
// rows) CG needs 905 iterations with 16k-row blocks, 876 with 42k and 857
// with 65k, at the same cost per iteration.
constexpr std::int64_t ICMinBlockRows = 16384, ICMaxBlockRows = 65536, ICTargetBlocks = 8;

class ICSystem : public ATLinearSystem
{
public:
  ICSystem(double tolerance, int maxIterations)
    : Tolerance(tolerance)
    , MaxIterations(maxIterations)
  {
  }

  bool Analyze(const ATSystemMatrix& m) override
  {
    const std::int64_t n = m.cols();
    const int* outer = m.outerIndexPtr();
    const int* inner = m.innerIndexPtr();
    const std::int64_t rows = std::clamp(n / ICTargetBlocks, ICMinBlockRows, ICMaxBlockRows);
    const std::int64_t nBlocks = std::max<std::int64_t>(1, n / rows);
    this->Blocks.resize(nBlocks + 1);
    for (std::int64_t b = 0; b <= nBlocks; ++b)
    {
      this->Blocks[b] = b * n / nBlocks;
    }
    this->LPtr.assign(n + 1, 0);
    this->UPtr.assign(n + 1, 0);
    this->DPos.assign(n, -1);
    this->LCol.clear();
    this->LPos.clear();
    this->UCol.clear();
    for (std::int64_t i = 0, blk = 0; i < n; ++i)
    {
      blk += i == this->Blocks[blk + 1];
      const std::int64_t lo = this->Blocks[blk], hi = this->Blocks[blk + 1];
      for (int k = outer[i]; k < outer[i + 1]; ++k)
      {
        const int j = inner[k];
        if (j < lo || j >= hi)
        {
          continue; // coupling between blocks: not in the factor
        }
        if (j < i)
        {
          this->LCol.push_back(j);
          this->LPos.push_back(k);
        }
        else if (j == i)
        {
          this->DPos[i] = k;
        }
        else
        {
          this->UCol.push_back(j);
        }
      }
      this->LPtr[i + 1] = static_cast<int>(this->LCol.size());
      this->UPtr[i + 1] = static_cast<int>(this->UCol.size());
      if (this->DPos[i] < 0)
      {
        return false;
      }
    }
    // Upper entry (i, j) is L's (j, i): find it in row j (sorted columns).
    this->UFromL.resize(this->UCol.size());
    for (std::int64_t i = 0; i < n; ++i)
    {
      for (std::int64_t u = this->UPtr[i]; u < this->UPtr[i + 1]; ++u)
      {
        const int j = this->UCol[u];
        const auto b = this->LCol.begin() + this->LPtr[j],
                   e = this->LCol.begin() + this->LPtr[j + 1];
        const auto it = std::lower_bound(b, e, static_cast<int>(i));
        if (it == e || *it != i)
        {
          return false; // pattern not symmetric
        }
        this->UFromL[u] = it - this->LCol.begin();
      }
    }
    return true;
  }

  bool Factorize(const ATSystemMatrix& m) override
  {
    const std::int64_t n = m.cols();
    const double* val = m.valuePtr();
    this->LVal.resize(this->LCol.size());
    this->InvD.resize(n);
    std::vector<double> d(n);
    const std::int64_t nBlocks = static_cast<std::int64_t>(this->Blocks.size()) - 1;
    std::vector<char> blockOk(nBlocks, 1);
    vtkSMPTools::For(0,
      nBlocks,
      1,
      [&](std::int64_t b0, std::int64_t b1)
      {
        for (std::int64_t blk = b0; blk < b1; ++blk)
        {
          for (std::int64_t i = this->Blocks[blk]; i < this->Blocks[blk + 1]; ++i)
          {
            const std::int64_t l0 = this->LPtr[i], l1 = this->LPtr[i + 1];
            double di = val[this->DPos[i]];
            for (std::int64_t kk = l0; kk < l1; ++kk)
            {
              const int j = this->LCol[kk];
              // a_ij = sum_{m < j} l_im d_m l_jm + l_ij d_j over the common pattern.
              double t = val[this->LPos[kk]];
              std::int64_t a = l0, b = this->LPtr[j];
              const std::int64_t bEnd = this->LPtr[j + 1];
              while (a < kk && b < bEnd)
              {
                const int ca = this->LCol[a], cb = this->LCol[b];
                if (ca == cb)
                {
                  t -= this->LVal[a] * d[ca] * this->LVal[b];
                  ++a;
                  ++b;
                }
                else if (ca < cb)
                {
                  ++a;
                }
                else
                {
                  ++b;
                }
              }
              const double lij = t / d[j];
              this->LVal[kk] = lij;
              di -= lij * lij * d[j];
            }
            if (!(di > 0) || !std::isfinite(di))
            {
              blockOk[blk] = 0;
              break;
            }
            d[i] = di;
            this->InvD[i] = 1.0 / di;
          }
        }
      });
    if (std::find(blockOk.begin(), blockOk.end(), 0) != blockOk.end())
    {
      // Jacobi fallback: L = I, D = diag(A).
      std::fill(this->LVal.begin(), this->LVal.end(), 0.0);
      for (std::int64_t i = 0; i < n; ++i)
      {
        const double a = val[this->DPos[i]];
        if (!(a > 0))
        {
          return false;
        }
        this->InvD[i] = 1.0 / a;
      }
    }
    this->UVal.resize(this->UCol.size());
    for (std::size_t u = 0; u < this->UCol.size(); ++u)
    {
      this->UVal[u] = this->LVal[this->UFromL[u]];
    }
    return true;
  }

  bool Solve(const ATSystemMatrix& m, const Eigen::MatrixXd& b, Eigen::MatrixXd& x) override
  {
    return SolveColumns(*this, m, b, x);
  }

  // The CG below is arranged so that each iteration makes two passes over
  // memory instead of four (fewer loads and stores; profiling showed the
  // sweeps, not DRAM bandwidth, to be the cost, see the register sums below):
  //  1. per IC block: x += alpha p, r -= alpha q, then z = (L D L^T)^-1 r for
  //     that block (forward and backward sweeps while the block's rows are
  //     still in cache), with the sums r.r and r.z;
  //  2. per row: w = A z, p = z + beta p, q = w + beta q (q = A p by
  //     linearity, so A p is never formed from p), with the sums p.q.
  // r.z is summed in the forward sweep: with y = L^-1 r, r.z = y.D^-1 y.
  // Same iterates as the textbook algorithm up to rounding.
  template<int NC>
  void UpdateAndPrecondition(bool update,
    const double* alpha,
    std::vector<double>& x,
    const std::vector<double>& p,
    std::vector<double>& r,
    const std::vector<double>& q,
    std::vector<double>& z,
    int ncRun,
    double* rr,
    double* rz)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t nBlocks = static_cast<std::int64_t>(this->Blocks.size()) - 1;
    this->Partial.resize(nBlocks * 2 * nc); // every block writes its own sums
    double aFixed[NC > 0 ? NC : 1] = {};
    std::vector<double> aDyn(NC > 0 ? 0 : nc);
    double* a = NC > 0 ? aFixed : aDyn.data();
    for (int c = 0; c < nc; ++c)
    {
      a[c] = update ? alpha[c] : 0.0;
    }
    // Row i of the forward sweep: x, r update and y_i = r_i - sum_j l_ij y_j.
    // The row sums are kept in registers and stored once: z_i and z_j are
    // in the same array, so accumulating in z itself would chain every
    // product through a store and a reload.
    // t: nc doubles of scratch (registers when NC is fixed).
    auto forward = [&](std::int64_t i, double* s, double* t)
    {
      for (int c = 0; c < nc; ++c)
      {
        const std::int64_t ic = i * nc + c;
        double ri = r[ic];
        if (update)
        {
          x[ic] += a[c] * p[ic];
          ri -= a[c] * q[ic];
          r[ic] = ri;
        }
        s[c] += ri * ri;
        t[c] = ri;
      }
      for (std::int64_t kk = this->LPtr[i]; kk < this->LPtr[i + 1]; ++kk)
      {
        const double l = this->LVal[kk];
        const double* zj = z.data() + static_cast<std::int64_t>(this->LCol[kk]) * nc;
        for (int c = 0; c < nc; ++c)
        {
          t[c] -= l * zj[c];
        }
      }
      double* zi = z.data() + i * nc;
      for (int c = 0; c < nc; ++c)
      {
        zi[c] = t[c];
        s[nc + c] += t[c] * t[c] * this->InvD[i];
      }
    };
    auto backward = [&](std::int64_t i, double* t)
    {
      double* zi = z.data() + i * nc;
      const double di = this->InvD[i];
      for (int c = 0; c < nc; ++c)
      {
        t[c] = zi[c] * di;
      }
      for (std::int64_t u = this->UPtr[i]; u < this->UPtr[i + 1]; ++u)
      {
        const double l = this->UVal[u];
        const double* zj = z.data() + static_cast<std::int64_t>(this->UCol[u]) * nc;
        for (int c = 0; c < nc; ++c)
        {
          t[c] -= l * zj[c];
        }
      }
      for (int c = 0; c < nc; ++c)
      {
        zi[c] = t[c];
      }
    };
    vtkSMPTools::For(0,
      nBlocks,
      1,
      [&](std::int64_t b0, std::int64_t b1)
      {
        for (std::int64_t blk = b0; blk < b1; ++blk)
        {
          // Sums in a local array (z could alias Partial as far as the
          // compiler knows), copied out per block.
          double sFixed[2 * (NC > 0 ? NC : 1)] = {}, tFixed[NC > 0 ? NC : 1];
          std::vector<double> sDyn(NC > 0 ? 0 : 2 * nc, 0.0), tDyn(NC > 0 ? 0 : nc);
          double* s = NC > 0 ? sFixed : sDyn.data();
          double* t = NC > 0 ? tFixed : tDyn.data();
          const std::int64_t i0 = this->Blocks[blk], i1 = this->Blocks[blk + 1];
          for (std::int64_t i = i0; i < i1; ++i)
          {
            forward(i, s, t);
          }
          for (std::int64_t i = i1 - 1; i >= i0; --i)
          {
            backward(i, t);
          }
          std::copy(s, s + 2 * nc, this->Partial.begin() + blk * 2 * nc);
        }
      });
    std::vector<double> sums(2 * nc);
    ReduceBlocks(this->Partial, nBlocks, 2 * nc, sums.data());
    std::copy(sums.begin(), sums.begin() + nc, rr);
    std::copy(sums.begin() + nc, sums.end(), rz);
  }

  // p = g z + h p and q = g A z + h q per column, with the sums p.q; (g, h)
  // is (1, beta) for an active column, (0, 1) to keep a converged one, and
  // (1, 0) for the first direction.
  template<int NC>
  void NextDirection(const ATSystemMatrix& m,
    const std::vector<double>& z,
    std::vector<double>& p,
    std::vector<double>& q,
    const double* gIn,
    const double* hIn,
    int ncRun,
    std::vector<double>& partial,
    double* pq)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t n = m.cols();
    ForBlocks(n,
      [&](std::int64_t blk, std::int64_t i0, std::int64_t i1)
      {
        double sFixed[NC > 0 ? NC : 1] = {}, gFixed[NC > 0 ? NC : 1], hFixed[NC > 0 ? NC : 1],
                                    wFixed[NC > 0 ? NC : 1];
        std::vector<double> dyn(NC > 0 ? 0 : 4 * nc, 0.0);
        double* s = NC > 0 ? sFixed : dyn.data();
        double* g = NC > 0 ? gFixed : dyn.data() + nc;
        double* h = NC > 0 ? hFixed : dyn.data() + 2 * nc;
        double* w = NC > 0 ? wFixed : dyn.data() + 3 * nc;
        for (int c = 0; c < nc; ++c)
        {
          g[c] = gIn[c];
          h[c] = hIn[c];
        }
        for (std::int64_t i = i0; i < i1; ++i)
        {
          RowProduct<NC>(m, i, z.data(), w, nc);
          for (int c = 0; c < nc; ++c)
          {
            const std::int64_t ic = i * nc + c;
            const double pi = g[c] * z[ic] + h[c] * p[ic];
            const double qi = g[c] * w[c] + h[c] * q[ic];
            p[ic] = pi;
            q[ic] = qi;
            s[c] += pi * qi;
          }
        }
        std::copy(s, s + nc, partial.data() + blk * nc);
      });
    ReduceBlocks(partial, NumberOfBlocks(n), nc, pq);
  }

  template<int NC>
  bool SolveN(const ATSystemMatrix& m, const Eigen::MatrixXd& b, Eigen::MatrixXd& xOut, int ncRun)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t n = m.cols();
    if (xOut.rows() != n || xOut.cols() != nc)
    {
      xOut = Eigen::MatrixXd::Zero(n, nc);
    }
    // Work vectors kept from one solve to the next: fresh ones would cost
    // page faults and zeroing at every step.
    std::vector<double>&x = this->X, &r = this->R, &p = this->P, &q = this->Q, &z = this->Z;
    Interleave(xOut, x);
    Interleave(b, r);
    p.resize(n * nc);
    q.resize(n * nc);
    z.resize(n * nc);
    const std::int64_t nb = NumberOfBlocks(n);
    std::vector<double> partial(nb * 2 * nc);
    std::vector<double> sums(2 * nc);
    std::vector<double> rr(nc), rz(nc), rzNew(nc), pq(nc), bb(nc), alpha(nc, 0.0), g(nc), h(nc);
    std::vector<char> active(nc, 1);
    // r = b - A x (r holds b on entry); sums of b.b and r.r.
    ForBlocks(n,
      [&](std::int64_t blk, std::int64_t i0, std::int64_t i1)
      {
        double acc[2 * (NC > 0 ? NC : 16)] = {};
        std::vector<double> accDyn(NC > 0 ? 0 : 2 * nc, 0.0), y(nc);
        double* s = NC > 0 ? acc : accDyn.data();
        for (std::int64_t i = i0; i < i1; ++i)
        {
          RowProduct<NC>(m, i, x.data(), y.data(), nc);
          for (int c = 0; c < nc; ++c)
          {
            const std::int64_t ic = i * nc + c;
            const double bic = r[ic], ri = bic - y[c];
            r[ic] = ri;
            s[2 * c] += bic * bic;
            s[2 * c + 1] += ri * ri;
          }
        }
        std::copy(s, s + 2 * nc, partial.data() + blk * 2 * nc);
      });
    ReduceBlocks(partial, nb, 2 * nc, sums.data());
    const double tol2 = this->Tolerance * this->Tolerance;
    int nActive = 0;
    for (int c = 0; c < nc; ++c)
    {
      bb[c] = sums[2 * c];
      active[c] = sums[2 * c + 1] > tol2 * bb[c];
      nActive += active[c];
    }
    int it = 0;
    if (nActive > 0)
    {
      this->UpdateAndPrecondition<NC>(false, alpha.data(), x, p, r, q, z, nc, rr.data(), rz.data());
      std::fill(g.begin(), g.end(), 1.0);
      std::fill(h.begin(), h.end(), 0.0);
      this->NextDirection<NC>(m, z, p, q, g.data(), h.data(), nc, partial, pq.data());
    }
    while (nActive > 0 && it < this->MaxIterations)
    {
      ++it;
      for (int c = 0; c < nc; ++c)
      {
        if (active[c] && !(pq[c] > 0))
        {
          return false; // not positive definite (or NaN)
        }
        alpha[c] = active[c] ? rz[c] / pq[c] : 0.0;
      }
      this->UpdateAndPrecondition<NC>(
        true, alpha.data(), x, p, r, q, z, nc, rr.data(), rzNew.data());
      nActive = 0;
      for (int c = 0; c < nc; ++c)
      {
        active[c] = active[c] && rr[c] > tol2 * bb[c];
        nActive += active[c];
        g[c] = active[c] ? 1.0 : 0.0;
        h[c] = active[c] ? rzNew[c] / rz[c] : 1.0;
        rz[c] = active[c] ? rzNew[c] : rz[c];
      }
      if (nActive == 0)
      {
        break;
      }
      this->NextDirection<NC>(m, z, p, q, g.data(), h.data(), nc, partial, pq.data());
    }
    this->Iterations += it;
    if (nActive != 0 || !AllFinite(x))
    {
      return false; // xOut keeps the previous values
    }
    Deinterleave(x, xOut);
    return true;
  }

private:
  double Tolerance;
  int MaxIterations;
  std::vector<std::int64_t> Blocks, UFromL;
  // int like the matrix's own indices (the factor has fewer entries).
  std::vector<int> LPtr, UPtr;
  std::vector<int> LCol, LPos, UCol, DPos;
  std::vector<float> LVal, UVal, InvD;
  std::vector<double> Partial, X, R, P, Q, Z;
};

std::unique_ptr<ATLinearSystem> MakeSystem(const ATParameters& p)
{
  switch (p.Solver)
  {
    case ATLinearSolver::SimplicialLDLT:
      return std::unique_ptr<ATLinearSystem>(new DirectSystem<
        Eigen::SimplicialLDLT<ATSystemMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>>());
    case ATLinearSolver::Cholmod:
#ifdef DG_HAVE_CHOLMOD
      return std::unique_ptr<ATLinearSystem>(
        new DirectSystem<Eigen::CholmodSupernodalLLT<ATSystemMatrix, Eigen::Lower>>());
#else
      return nullptr;
#endif
    case ATLinearSolver::ConjugateGradientIC:
      return std::unique_ptr<ATLinearSystem>(new ICSystem(p.CGTolerance, p.CGMaximumIterations));
    case ATLinearSolver::ConjugateGradient:
    default:
      return std::unique_ptr<ATLinearSystem>(new CGSystem(p.CGTolerance, p.CGMaximumIterations));
  }
}
} // namespace

bool CholmodAvailable()
{
#ifdef DG_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

const char* ATLinearSolverName(ATLinearSolver s)
{
  switch (s)
  {
    case ATLinearSolver::SimplicialLDLT:
      return "SimplicialLDLT";
    case ATLinearSolver::Cholmod:
      return "Cholmod";
    case ATLinearSolver::ConjugateGradientIC:
      return "ConjugateGradientIC";
    case ATLinearSolver::ConjugateGradient:
    default:
      return "ConjugateGradient";
  }
}

std::string ATParameters::Check() const
{
  std::ostringstream s;
  // Written as !(x > 0) so that NaN is rejected too.
  if (!(this->Alpha > 0))
  {
    s << "Alpha must be > 0 (got " << this->Alpha << "). ";
  }
  if (!(this->Lambda > 0))
  {
    s << "Lambda must be > 0 (got " << this->Lambda << "). ";
  }
  if (!(this->EpsilonEnd > 0))
  {
    s << "EpsilonEnd must be > 0 (got " << this->EpsilonEnd << "). ";
  }
  if (!(this->EpsilonStart >= this->EpsilonEnd) || !std::isfinite(this->EpsilonStart))
  {
    s << "EpsilonStart (" << this->EpsilonStart << ") must be finite and >= EpsilonEnd ("
      << this->EpsilonEnd << "). ";
  }
  if (!(this->EpsilonRatio > 1))
  {
    s << "EpsilonRatio must be > 1 (got " << this->EpsilonRatio << "). ";
  }
  if (this->MaximumIterations < 1)
  {
    s << "MaximumIterations must be >= 1 (got " << this->MaximumIterations << "). ";
  }
  if (!(this->Tolerance >= 0))
  {
    s << "Tolerance must be >= 0 (got " << this->Tolerance << "). ";
  }
  if (!(this->CGTolerance > 0) || this->CGMaximumIterations < 1)
  {
    s << "CGTolerance must be > 0 and CGMaximumIterations >= 1. ";
  }
  std::string r = s.str();
  if (!r.empty())
  {
    r.pop_back();
  }
  return r;
}

ATSolver::ATSolver(const ATComplex& complex, const ATParameters& parameters)
  : Complex(complex)
  , Params(parameters)
  , UM(complex.UPattern)
  , VM(complex.VPattern)
{
}

ATSolver::~ATSolver() = default;

void ATSolver::Initialize(const Eigen::MatrixXd& field)
{
  this->g = field;
  this->u = field;
  this->URhs = this->Params.Alpha * field;
  this->v = Eigen::VectorXd::Ones(this->Complex.NumberOfVertices());
}

void ATSolver::AssembleU()
{
  const ATComplex& K = this->Complex;
  const std::int64_t ne = K.NumberOfEdges(), nf = K.NumberOfFaces();
  // w(e) = ((M v)_e)^2, the weight of edge e in B^T diag(Mv)^2 B.
  std::vector<double>& w = this->EdgeWork;
  w.resize(ne);
  ForBlocks(ne,
    [&](std::int64_t, std::int64_t e0, std::int64_t e1)
    {
      for (std::int64_t e = e0; e < e1; ++e)
      {
        const double m =
          0.5 * (this->v[K.EdgeVertices[2 * e]] + this->v[K.EdgeVertices[2 * e + 1]]);
        w[e] = m * m;
      }
    });
  const int* outer = this->UM.outerIndexPtr();
  double* val = this->UM.valuePtr();
  const double alpha = this->Params.Alpha;
  ForBlocks(nf,
    [&](std::int64_t, std::int64_t f0, std::int64_t f1)
    {
      for (std::int64_t f = f0; f < f1; ++f)
      {
        for (int k = outer[f]; k < outer[f + 1]; ++k)
        {
          double s = 0;
          for (std::int64_t j = K.UContribPtr[k]; j < K.UContribPtr[k + 1]; ++j)
          {
            s += K.UContribCoef[j] * w[K.UContribEdge[j]];
          }
          val[k] = s;
        }
        val[K.UDiagonal[f]] += alpha;
      }
    });
}

void ATSolver::AssembleV(double epsilon)
{
  const ATComplex& K = this->Complex;
  const std::int64_t ne = K.NumberOfEdges(), nv = K.NumberOfVertices();
  const int nc = static_cast<int>(this->u.cols());
  // q(e) = sum_i ((B u_i)_e)^2: the squared jump of u across edge e.
  std::vector<double>& q = this->EdgeWork;
  q.resize(ne);
  ForBlocks(ne,
    [&](std::int64_t, std::int64_t e0, std::int64_t e1)
    {
      for (std::int64_t e = e0; e < e1; ++e)
      {
        double s = 0;
        // Boundary edges carry no jump (dgATOperators.h).
        for (int c = 0; c < nc && K.EdgeFacePtr[e + 1] - K.EdgeFacePtr[e] > 1; ++c)
        {
          double d = 0;
          for (std::int64_t i = K.EdgeFacePtr[e]; i < K.EdgeFacePtr[e + 1]; ++i)
          {
            d += K.EdgeFaceSigns[i] * this->u(K.EdgeFaces[i], c);
          }
          s += d * d;
        }
        q[e] = s;
      }
    });
  const double lambda = this->Params.Lambda;
  const double diagConst = lambda / (4 * epsilon), lapl = lambda * epsilon;
  const int* outer = this->VM.outerIndexPtr();
  double* val = this->VM.valuePtr();
  ForBlocks(nv,
    [&](std::int64_t, std::int64_t a0, std::int64_t a1)
    {
      for (std::int64_t a = a0; a < a1; ++a)
      {
        for (int k = outer[a]; k < outer[a + 1]; ++k)
        {
          const int e = K.VEdge[k];
          if (e >= 0)
          {
            val[k] = -lapl + 0.25 * q[e];
          }
          else
          {
            double s = 0;
            for (std::int64_t j = K.VertexEdgePtr[a]; j < K.VertexEdgePtr[a + 1]; ++j)
            {
              s += q[K.VertexEdges[j]];
            }
            val[k] = diagConst + lapl * (K.VertexEdgePtr[a + 1] - K.VertexEdgePtr[a]) + 0.25 * s;
          }
        }
      }
    });
}

bool ATSolver::SolveSystem(ATLinearSystem& system,
  const ATSystemMatrix& m,
  const Eigen::MatrixXd& b,
  Eigen::MatrixXd& x,
  const char* name)
{
  auto t0 = Clock::now();
  if (!system.Analyzed)
  {
    system.Analyzed = system.Analyze(m);
    this->Stats.Analysis += Seconds(t0);
    if (!system.Analyzed)
    {
      this->WarningList.push_back(std::string("symbolic analysis of the ") + name + " failed");
      ++this->Stats.FailedSolves;
      return false;
    }
    t0 = Clock::now();
  }
  const bool factored = system.Factorize(m);
  this->Stats.Factorization += Seconds(t0);
  t0 = Clock::now();
  const std::int64_t it0 = system.Iterations;
  // Solve leaves x as it was when it fails.
  const bool solved = factored && system.Solve(m, b, x);
  this->Stats.Solve += Seconds(t0);
  this->Stats.CGIterations += system.Iterations - it0;
  if (!solved)
  {
    std::ostringstream s;
    s << "the " << name << " linear solve failed ("
      << (factored ? "no convergence or non-finite result" : "factorisation failed")
      << "); the previous values are kept";
    this->WarningList.push_back(s.str());
    ++this->Stats.FailedSolves;
    return false;
  }
  return true;
}

bool ATSolver::StepU()
{
  if (!this->USystem)
  {
    this->USystem = MakeSystem(this->Params);
  }
  auto t0 = Clock::now();
  this->AssembleU();
  this->Stats.Assembly += Seconds(t0);
  const std::int64_t it0 = this->Stats.CGIterations;
  const bool ok = this->SolveSystem(*this->USystem, this->UM, this->URhs, this->u, "u-step");
  this->Stats.CGIterationsU += this->Stats.CGIterations - it0;
  return ok;
}

bool ATSolver::StepV(double epsilon)
{
  if (!this->VSystem)
  {
    this->VSystem = MakeSystem(this->Params);
  }
  auto t0 = Clock::now();
  this->AssembleV(epsilon);
  this->Stats.Assembly += Seconds(t0);
  const double rhs = this->Params.Lambda / (4 * epsilon);
  if (this->VRhs.rows() != this->v.size() || this->VRhs.size() == 0 || this->VRhs(0, 0) != rhs)
  {
    this->VRhs.setConstant(this->v.size(), 1, rhs);
  }
  this->VX = this->v;
  const bool ok = this->SolveSystem(*this->VSystem, this->VM, this->VRhs, this->VX, "v-step");
  if (ok)
  {
    this->v = this->VX.col(0);
  }
  return ok;
}

double ATSolver::Energy(double epsilon) const
{
  const ATComplex& K = this->Complex;
  const std::int64_t nf = K.NumberOfFaces(), ne = K.NumberOfEdges(), nv = K.NumberOfVertices();
  const int nc = static_cast<int>(this->u.cols());
  const double lambda = this->Params.Lambda;
  double total = 0;
  {
    const std::int64_t nb = NumberOfBlocks(nf);
    std::vector<double> part(nb);
    ForBlocks(nf,
      [&](std::int64_t b, std::int64_t f0, std::int64_t f1)
      {
        double s = 0;
        for (std::int64_t f = f0; f < f1; ++f)
        {
          s += (this->u.row(f) - this->g.row(f)).squaredNorm();
        }
        part[b] = s;
      });
    double s;
    ReduceBlocks(part, nb, 1, &s);
    total += this->Params.Alpha * s;
  }
  {
    const std::int64_t nb = NumberOfBlocks(ne);
    std::vector<double> part(nb);
    ForBlocks(ne,
      [&](std::int64_t b, std::int64_t e0, std::int64_t e1)
      {
        double s = 0;
        for (std::int64_t e = e0; e < e1; ++e)
        {
          const double va = this->v[K.EdgeVertices[2 * e]], vb = this->v[K.EdgeVertices[2 * e + 1]];
          const double m = 0.5 * (va + vb);
          for (int c = 0; c < nc && K.EdgeFacePtr[e + 1] - K.EdgeFacePtr[e] > 1; ++c)
          {
            double d = 0;
            for (std::int64_t i = K.EdgeFacePtr[e]; i < K.EdgeFacePtr[e + 1]; ++i)
            {
              d += K.EdgeFaceSigns[i] * this->u(K.EdgeFaces[i], c);
            }
            s += m * m * d * d;
          }
          s += lambda * epsilon * (vb - va) * (vb - va);
        }
        part[b] = s;
      });
    double s;
    ReduceBlocks(part, nb, 1, &s);
    total += s;
  }
  {
    const std::int64_t nb = NumberOfBlocks(nv);
    std::vector<double> part(nb);
    ForBlocks(nv,
      [&](std::int64_t b, std::int64_t a0, std::int64_t a1)
      {
        double s = 0;
        for (std::int64_t a = a0; a < a1; ++a)
        {
          s += (1 - this->v[a]) * (1 - this->v[a]);
        }
        part[b] = s;
      });
    double s;
    ReduceBlocks(part, nb, 1, &s);
    total += lambda / (4 * epsilon) * s;
  }
  return total;
}

void ATSolver::NormalizeU()
{
  ForBlocks(this->u.rows(),
    [&](std::int64_t, std::int64_t f0, std::int64_t f1)
    {
      for (std::int64_t f = f0; f < f1; ++f)
      {
        const double n = this->u.row(f).norm();
        if (n > 0)
        {
          this->u.row(f) /= n;
        }
      }
    });
}

bool ATSolver::Run(const Eigen::MatrixXd& field, const ATProgressCallback& progress)
{
  this->Stats = ATStatistics();
  this->WarningList.clear();
  this->ErrorText = this->Params.Check();
  if (!this->ErrorText.empty())
  {
    return false;
  }
  if (field.rows() != this->Complex.NumberOfFaces() || field.cols() < 1)
  {
    this->ErrorText = "the field has " + std::to_string(field.rows()) + " rows for " +
                      std::to_string(this->Complex.NumberOfFaces()) + " faces";
    return false;
  }
  if (this->Params.Solver == ATLinearSolver::Cholmod && !CholmodAvailable())
  {
    this->WarningList.push_back("CHOLMOD is not available in this build: using SimplicialLDLT");
    this->Params.Solver = ATLinearSolver::SimplicialLDLT;
  }
  this->USystem.reset();
  this->VSystem.reset();
  this->Initialize(field);

  // The schedule eps_1, eps_1 / r, ... down to eps_2 (a relative slack so
  // that 2 -> 0.25 by 2 or 1 -> 0.1 by 10 include their last level).
  std::vector<double> levels;
  for (double eps = this->Params.EpsilonStart;
       eps >= this->Params.EpsilonEnd * (1 - 1e-9) && levels.size() < 1000;
       eps /= this->Params.EpsilonRatio)
  {
    levels.push_back(eps);
  }
  const double steps = static_cast<double>(levels.size()) * this->Params.MaximumIterations;
  for (std::size_t l = 0; l < levels.size(); ++l)
  {
    ++this->Stats.Levels;
    for (int it = 0; it < this->Params.MaximumIterations; ++it)
    {
      const Eigen::VectorXd vPrev = this->v;
      this->StepU();
      this->StepV(levels[l]);
      ++this->Stats.Iterations;
      const double change = (this->v - vPrev).lpNorm<Eigen::Infinity>();
      if (progress &&
          !progress((static_cast<double>(l) * this->Params.MaximumIterations + it + 1) / steps))
      {
        return false;
      }
      if (change < this->Params.Tolerance)
      {
        break;
      }
    }
  }
  if (this->Params.Normalize)
  {
    this->NormalizeU();
  }
  return true;
}

} // namespace dg
