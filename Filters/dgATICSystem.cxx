#include "dgATLinearSystems.h"

#include "dgATBlocks.h"

#include <algorithm>
#include <cmath>

namespace dg
{
namespace
{
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
// The factor is stored in single precision: it only preconditions, and
// reading half the bytes saved 7 % of the solve time on octa-flower at the
// same iteration count.
//
// So are, by default (ATParameters::CGSinglePrecision), the CG vectors r, p,
// q and z; x, the matrix and every sum (accumulated in double) are not.
// This cuts the CG vectors' memory from 160 to 96 bytes per surfel and the
// bytes per iteration from 396 to 276 per row of the u-system (3 columns)
// and from 204 to 164 for v; on a quiet machine it saved no time (the
// sweeps then run at 3.4x the bandwidth floor, docs/at-speed.md). On the real
// pipeline's input (BenchATPipeline) the CG iteration counts are the same
// (octa-flower 223 / 340, fandisk-256 216 / 252) and the accuracy budget's
// figures against LDL^T the same to three digits. Tight tolerances are
// kept by a check of the true residual (FloatCheckTolerance below).
//
// Block size: about 8 blocks (for the threads to share), each of 16 384 to
// 65 536 rows. Larger blocks drop fewer couplings: on octa-flower (671 270
// rows) CG needs 905 iterations with 16k-row blocks, 876 with 42k and 857
// with 65k, at the same cost per iteration.
constexpr std::int64_t ICMinBlockRows = 16384, ICMaxBlockRows = 65536, ICTargetBlocks = 8;

// Float vectors: the true residual is checked below this CG tolerance, and
// the solve restarted from it at most MaxRestarts times (see SolveN).
constexpr double FloatCheckTolerance = 1e-6;
constexpr int MaxRestarts = 3;

// S stores the CG vectors r, p, q and z (float or double); x and every sum
// stay in double. See MakeICSystem for why float.
template<class S>
class ICSystem : public ATLinearSystem
{
public:
  ICSystem(double tolerance, int maxIterations, const ATDistribution* distribution, int kind)
    : Tolerance(tolerance)
    , MaxIterations(maxIterations)
    , Dist(distribution)
    , Kind(kind)
  {
  }

  // The rows this process solves: all of them, or its owned ones (numbered
  // first; the rest are ghosts, read by the products but never updated).
  std::int64_t Rows(const ATSystemMatrix& m) const
  {
    return this->Dist ? this->Dist->Owned(this->Kind) : m.cols();
  }
  void Sum(double* v, int count) const
  {
    if (this->Dist)
    {
      this->Dist->SumAll(v, count);
    }
  }
  template<class T>
  void Ghosts(std::vector<T>& x, int nc) const
  {
    if (this->Dist)
    {
      this->Dist->UpdateGhosts(this->Kind, x.data(), nc);
    }
  }

  bool Analyze(const ATSystemMatrix& m) override
  {
    const std::int64_t n = this->Rows(m);
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
        this->UFromL[u] = static_cast<int>(it - this->LCol.begin());
      }
    }
    return true;
  }

  bool Factorize(const ATSystemMatrix& m) override
  {
    const std::int64_t n = this->Rows(m);
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
    const std::vector<S>& p,
    std::vector<S>& r,
    const std::vector<S>& q,
    std::vector<S>& z,
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
          r[ic] = static_cast<S>(ri);
          ri = r[ic];
        }
        s[c] += ri * ri;
        t[c] = ri;
      }
      for (std::int64_t kk = this->LPtr[i]; kk < this->LPtr[i + 1]; ++kk)
      {
        const double l = this->LVal[kk];
        const S* zj = z.data() + static_cast<std::int64_t>(this->LCol[kk]) * nc;
        for (int c = 0; c < nc; ++c)
        {
          t[c] -= l * zj[c];
        }
      }
      S* zi = z.data() + i * nc;
      for (int c = 0; c < nc; ++c)
      {
        zi[c] = static_cast<S>(t[c]);
        s[nc + c] += t[c] * t[c] * this->InvD[i];
      }
    };
    auto backward = [&](std::int64_t i, double* t)
    {
      S* zi = z.data() + i * nc;
      const double di = this->InvD[i];
      for (int c = 0; c < nc; ++c)
      {
        t[c] = zi[c] * di;
      }
      for (std::int64_t u = this->UPtr[i]; u < this->UPtr[i + 1]; ++u)
      {
        const double l = this->UVal[u];
        const S* zj = z.data() + static_cast<std::int64_t>(this->UCol[u]) * nc;
        for (int c = 0; c < nc; ++c)
        {
          t[c] -= l * zj[c];
        }
      }
      for (int c = 0; c < nc; ++c)
      {
        zi[c] = static_cast<S>(t[c]);
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
    this->Sum(sums.data(), 2 * nc);
    std::copy(sums.begin(), sums.begin() + nc, rr);
    std::copy(sums.begin() + nc, sums.end(), rz);
  }

  // p = g z + h p and q = g A z + h q per column, with the sums p.q; (g, h)
  // is (1, beta) for an active column, (0, 1) to keep a converged one, and
  // (1, 0) for the first direction.
  template<int NC>
  void NextDirection(const ATSystemMatrix& m,
    const std::vector<S>& z,
    std::vector<S>& p,
    std::vector<S>& q,
    const double* gIn,
    const double* hIn,
    int ncRun,
    std::vector<double>& partial,
    double* pq)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t n = this->Rows(m);
    // A z reads z on the ghost rows: their owners' values.
    this->Ghosts(const_cast<std::vector<S>&>(z), nc);
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
            // alpha = r.z / p.q must see the p and q that are stored.
            const S pi = static_cast<S>(g[c] * z[ic] + h[c] * p[ic]);
            const S qi = static_cast<S>(g[c] * w[c] + h[c] * q[ic]);
            p[ic] = pi;
            q[ic] = qi;
            s[c] += static_cast<double>(pi) * static_cast<double>(qi);
          }
        }
        std::copy(s, s + nc, partial.data() + blk * nc);
      });
    ReduceBlocks(partial, NumberOfBlocks(n), nc, pq);
    this->Sum(pq, nc);
  }

  template<int NC>
  bool SolveN(const ATSystemMatrix& m, const Eigen::MatrixXd& b, Eigen::MatrixXd& xOut, int ncRun)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t n = this->Rows(m);
    if (xOut.rows() != m.cols() || xOut.cols() != nc)
    {
      xOut = Eigen::MatrixXd::Zero(m.cols(), nc);
    }
    // Work vectors kept from one solve to the next: fresh ones would cost
    // page faults and zeroing at every step.
    std::vector<double>& x = this->X;
    std::vector<S>&r = this->R, &p = this->P, &q = this->Q, &z = this->Z;
    Interleave(xOut, x);
    // Full length: the products read the ghost rows of z.
    p.resize(m.cols() * nc);
    q.resize(m.cols() * nc);
    z.resize(m.cols() * nc);
    const std::int64_t nb = NumberOfBlocks(n);
    std::vector<double> partial(nb * 2 * nc);
    std::vector<double> sums(2 * nc);
    std::vector<double> rr(nc), rz(nc), rzNew(nc), pq(nc), bb(nc), alpha(nc, 0.0), g(nc), h(nc);
    std::vector<char> active(nc, 1);
    // With p, q, z in float, the recurrence r -= alpha q drifts from the
    // true residual b - A x by about 1e-7 ||b|| (measured on the operator
    // tests), far below the default tolerance 1e-5 but not below 1e-8.
    // Below FloatCheckTolerance, a converged solve is checked against the
    // true residual and restarted from it when that is still too large.
    const bool check = sizeof(S) < sizeof(double) && this->Tolerance < FloatCheckTolerance;
    int it = 0, nActive = 0;
    for (int restart = 0; restart <= MaxRestarts; ++restart)
    {
      r.resize(m.cols() * nc);
      this->Ghosts(x, nc);
      // r = b - A x, from b in double; sums of b.b and r.r.
      const double* bData = b.data();
      const std::int64_t bRows = b.rows();
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
              const double bic = bData[c * bRows + i];
              r[ic] = static_cast<S>(bic - y[c]);
              const double ri = r[ic];
              s[2 * c] += bic * bic;
              s[2 * c + 1] += ri * ri;
            }
          }
          std::copy(s, s + 2 * nc, partial.data() + blk * 2 * nc);
        });
      ReduceBlocks(partial, nb, 2 * nc, sums.data());
      this->Sum(sums.data(), 2 * nc);
      const double tol2 = this->Tolerance * this->Tolerance;
      nActive = 0;
      for (int c = 0; c < nc; ++c)
      {
        bb[c] = sums[2 * c];
        active[c] = sums[2 * c + 1] > tol2 * bb[c];
        nActive += active[c];
      }
      if (nActive == 0 || (restart > 0 && it >= this->MaxIterations))
      {
        break;
      }
      if (nActive > 0)
      {
        this->template UpdateAndPrecondition<NC>(
          false, alpha.data(), x, p, r, q, z, nc, rr.data(), rz.data());
        std::fill(g.begin(), g.end(), 1.0);
        std::fill(h.begin(), h.end(), 0.0);
        this->template NextDirection<NC>(m, z, p, q, g.data(), h.data(), nc, partial, pq.data());
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
        this->template UpdateAndPrecondition<NC>(
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
        this->template NextDirection<NC>(m, z, p, q, g.data(), h.data(), nc, partial, pq.data());
      }
      if (!check || nActive > 0)
      {
        break;
      }
    }
    this->Iterations += it;
    bool ok = nActive == 0 && AllFinite(x);
    if (this->Dist)
    {
      ok = this->Dist->AllOk(ok);
    }
    if (!ok)
    {
      return false; // xOut keeps the previous values
    }
    this->Ghosts(x, nc);
    Deinterleave(x, xOut);
    return true;
  }

  void Memory(ATMemoryParts& parts, const std::string& name) const override
  {
    auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    parts.emplace_back(name + ": IC pattern (L, U columns, positions, row starts)",
      bytes(this->LPtr) + bytes(this->UPtr) + bytes(this->LCol) + bytes(this->LPos) +
        bytes(this->UCol) + bytes(this->DPos) + bytes(this->UFromL) + bytes(this->Blocks));
    parts.emplace_back(name + ": IC factor (L, U values, 1/D; float)",
      bytes(this->LVal) + bytes(this->UVal) + bytes(this->InvD));
    parts.emplace_back(name + (sizeof(S) == 4 ? ": CG vectors (x; r, p, q, z in float)"
                                              : ": CG vectors (x, r, p, q, z)"),
      bytes(this->X) + bytes(this->R) + bytes(this->P) + bytes(this->Q) + bytes(this->Z) +
        bytes(this->Partial));
  }

private:
  double Tolerance;
  int MaxIterations;
  const ATDistribution* Dist;
  int Kind;
  std::vector<std::int64_t> Blocks;
  std::vector<int> UFromL; // index into LCol/LVal (fewer than the matrix's int-indexed non-zeros)
  // int like the matrix's own indices (the factor has fewer entries).
  std::vector<int> LPtr, UPtr;
  std::vector<int> LCol, LPos, UCol, DPos;
  std::vector<float> LVal, UVal, InvD;
  std::vector<double> Partial, X;
  std::vector<S> R, P, Q, Z;
};
} // namespace

std::unique_ptr<ATLinearSystem> MakeICSystem(double tolerance,
  int maxIterations,
  const ATDistribution* distribution,
  int kind,
  bool singlePrecision)
{
  if (singlePrecision)
  {
    return std::unique_ptr<ATLinearSystem>(
      new ICSystem<float>(tolerance, maxIterations, distribution, kind));
  }
  return std::unique_ptr<ATLinearSystem>(
    new ICSystem<double>(tolerance, maxIterations, distribution, kind));
}

} // namespace dg
