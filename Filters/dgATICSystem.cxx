#include "dgATLinearSystems.h"

#include "dgATBlocks.h"
#include "dgHugePages.h"

#include <algorithm>
#include <cmath>
#include <memory>

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
// is refreshed at every step (numeric only: the pattern once), and kept as
// C = L D^(1/2), A ~ C C^T: its lower triangle in row order serves both
// triangular sweeps (the backward one by columns), so that no transposed
// copy and no index maps are stored (with the exactly sized pattern, 107
// bytes per surfel less for the two systems on octa-flower, 20 fewer bytes
// per row and iteration; docs/at-speed.md).
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

// CG's work vectors, kept from one solve to the next (fresh ones would cost
// page faults and zeroing at every step) and shared by the u- and v-systems,
// which never solve at the same time: the v-system's own set would hold 24
// more bytes per surfel for nothing (docs/at-speed.md). Nothing in them
// carries over from one solve to the next. x is not among them: CG updates
// the caller's u or v in place (column major), which saves an interleaved
// copy of u (24 bytes per face) and v's unknown; the iterates are bitwise
// those of the copy.
// The factor's values too: each step factorises its system just before
// solving it, so the u- and v-factors are never needed at the same time
// (12 bytes per surfel less on a quad surface); the patterns are kept per
// system.
template<class S>
struct ICWork
{
  std::vector<double> Partial;
  std::vector<S> R, P, Q, Z;
  std::vector<float> LVal, InvC; // C's entries below the diagonal, 1 / C_ii
};

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
    , Work(std::make_shared<ICWork<S>>())
  {
  }
  void SetTolerance(double tolerance) override { this->Tolerance = tolerance; }
  void SetFactorScratch(double* scratch, std::size_t size) override
  {
    this->Scratch = scratch;
    this->ScratchSize = scratch ? size : 0;
  }
  bool ShareWork(ATLinearSystem& other) override
  {
    auto* o = dynamic_cast<ICSystem<S>*>(&other);
    if (!o || o == this)
    {
      return false;
    }
    this->Work = o->Work;
    this->WorkOwner = false;
    return true;
  }

  // The rows this process solves: all of them, or its owned ones (numbered
  // first; the rest are ghosts, read by the products but never updated).
  std::int64_t Rows(const ATSystemView& m) const
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
  // The same for x, column c at x + c * ld.
  void GhostColumns(double* x, std::int64_t ld, int nc) const
  {
    for (int c = 0; this->Dist && c < nc; ++c)
    {
      this->Dist->UpdateGhosts(this->Kind, x + c * ld, 1);
    }
  }

  bool Analyze(const ATSystemView& m) override
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
    // Two passes: count, then fill arrays of the exact size (push_back's
    // doubling left about 13 bytes per row unused).
    AssignHuge(this->LPtr, static_cast<std::size_t>(n + 1), 0);
    for (int pass = 0; pass < 2; ++pass)
    {
      if (pass == 1)
      {
        std::vector<int>().swap(this->LCol);
        AssignHuge(this->LCol, static_cast<std::size_t>(this->LPtr[n]), 0);
      }
      for (std::int64_t i = 0, blk = 0; i < n; ++i)
      {
        blk += i == this->Blocks[blk + 1];
        const std::int64_t lo = this->Blocks[blk];
        int count = 0;
        bool diagonal = false;
        for (int k = outer[i]; k < outer[i + 1]; ++k)
        {
          const int j = inner[k];
          diagonal = diagonal || j == i;
          if (j >= lo && j < i) // couplings between blocks are not in the factor
          {
            if (pass == 1)
            {
              this->LCol[this->LPtr[i] + count] = j;
            }
            ++count;
          }
        }
        if (!diagonal)
        {
          return false;
        }
        if (pass == 0)
        {
          this->LPtr[i + 1] = this->LPtr[i] + count;
        }
      }
    }
    return true;
  }

  // The factor is kept as A ~ C C^T with C = L D^(1/2) (lower, non-unit
  // diagonal): L's values in row order serve both sweeps (the backward one
  // column by column, below), so no transposed copy of the factor and no
  // index maps are stored. Row i of the matrix lists its lower in-block
  // entries in the order of LCol (columns ascending), which is how
  // Factorize finds their values without stored positions.
  bool Factorize(const ATSystemView& m) override
  {
    const std::int64_t n = this->Rows(m);
    const int* outer = m.outerIndexPtr();
    const int* inner = m.innerIndexPtr();
    const double* val = m.valuePtr();
    auto diagonal = [&](std::int64_t i)
    {
      for (int k = outer[i]; k < outer[i + 1]; ++k)
      {
        if (inner[k] == i)
        {
          return val[k];
        }
      }
      return 0.0;
    };
    // Shared with the other system (ICWork), grown only, and then
    // reallocated at the exact size (nothing in them is kept): growing in
    // place would double the capacity.
    std::vector<float>& lij = this->Work->LVal;
    std::vector<float>& invC = this->Work->InvC;
    if (lij.size() < static_cast<std::size_t>(this->LPtr[n]))
    {
      std::vector<float>().swap(lij);
      ResizeHuge(lij, static_cast<std::size_t>(this->LPtr[n]));
    }
    if (invC.size() < static_cast<std::size_t>(n))
    {
      std::vector<float>().swap(invC);
      ResizeHuge(invC, static_cast<std::size_t>(n));
    }
    // The pivots: in the caller's scratch when it is large enough (every
    // entry is written before it is read), else an array of their own.
    std::vector<double> own;
    double* d = this->Scratch;
    if (!d || this->ScratchSize < static_cast<std::size_t>(n))
    {
      AssignHuge(own, static_cast<std::size_t>(n), 0.0);
      d = own.data();
    }
    // LVal first holds L D L^T's unit-diagonal L (in float, as the
    // recurrences read it), then C's values.
    const std::int64_t nBlocks = static_cast<std::int64_t>(this->Blocks.size()) - 1;
    std::vector<char> blockOk(nBlocks, 1);
    vtkSMPTools::For(0,
      nBlocks,
      1,
      [&](std::int64_t b0, std::int64_t b1)
      {
        for (std::int64_t blk = b0; blk < b1; ++blk)
        {
          const std::int64_t lo = this->Blocks[blk];
          for (std::int64_t i = lo; i < this->Blocks[blk + 1]; ++i)
          {
            const std::int64_t l0 = this->LPtr[i], l1 = this->LPtr[i + 1];
            double di = diagonal(i);
            std::int64_t kk = l0;
            for (int k = outer[i]; k < outer[i + 1] && kk < l1; ++k)
            {
              const int j = inner[k];
              if (j < lo || j >= i)
              {
                continue;
              }
              // a_ij = sum_{m < j} l_im d_m l_jm + l_ij d_j over the common pattern.
              double t = val[k];
              std::int64_t a = l0, b = this->LPtr[j];
              const std::int64_t bEnd = this->LPtr[j + 1];
              while (a < kk && b < bEnd)
              {
                const int ca = this->LCol[a], cb = this->LCol[b];
                if (ca == cb)
                {
                  t -= lij[a] * d[ca] * lij[b];
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
              lij[kk] = t / d[j];
              di -= lij[kk] * lij[kk] * d[j];
              ++kk;
            }
            if (!(di > 0) || !std::isfinite(di))
            {
              blockOk[blk] = 0;
              break;
            }
            d[i] = di;
          }
          // C = L D^(1/2) for this block's rows, while they are in cache.
          for (std::int64_t i = lo; blockOk[blk] && i < this->Blocks[blk + 1]; ++i)
          {
            d[i] = std::sqrt(d[i]);
            invC[i] = static_cast<float>(1.0 / d[i]);
            for (std::int64_t kk = this->LPtr[i]; kk < this->LPtr[i + 1]; ++kk)
            {
              lij[kk] = static_cast<float>(lij[kk] * d[this->LCol[kk]]);
            }
          }
        }
      });
    if (std::find(blockOk.begin(), blockOk.end(), 0) != blockOk.end())
    {
      // Jacobi fallback: L = I, D = diag(A).
      std::fill(lij.begin(), lij.begin() + this->LPtr[n], 0.0f);
      for (std::int64_t i = 0; i < n; ++i)
      {
        const double a = diagonal(i);
        if (!(a > 0))
        {
          return false;
        }
        invC[i] = static_cast<float>(1.0 / std::sqrt(a));
      }
    }
    return true;
  }

  bool Solve(const ATSystemView& m, const ATRhs& b, ATColumns x) override
  {
    return SolveColumns(*this, m, b, x);
  }

  // The CG below is arranged so that each iteration makes two passes over
  // memory instead of four (fewer loads and stores; profiling showed the
  // sweeps, not DRAM bandwidth, to be the cost, see the register sums below):
  //  1. per IC block: x += alpha p, r -= alpha q, then z = (C C^T)^-1 r for
  //     that block (forward and backward sweeps while the block's rows are
  //     still in cache), with the sums r.r and r.z;
  //  2. per row: w = A z, p = z + beta p, q = w + beta q (q = A p by
  //     linearity, so A p is never formed from p), with the sums p.q.
  // r.z is summed in the forward sweep: with y = C^-1 r, r.z = y.y.
  // Same iterates as the textbook algorithm up to rounding.
  // x is column major (row i, column c at x[c * ld + i]); r, p, q, z are
  // interleaved.
  template<int NC>
  void UpdateAndPrecondition(bool update,
    const double* alpha,
    double* x,
    std::int64_t ld,
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
    const float* lVal = this->Work->LVal.data();
    const float* invC = this->Work->InvC.data();
    std::vector<double>& partialSums = this->Work->Partial;
    partialSums.resize(nBlocks * 2 * nc); // every block writes its own sums
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
          x[c * ld + i] += a[c] * p[ic];
          ri -= a[c] * q[ic];
          r[ic] = static_cast<S>(ri);
          ri = r[ic];
        }
        s[c] += ri * ri;
        t[c] = ri;
      }
      for (std::int64_t kk = this->LPtr[i]; kk < this->LPtr[i + 1]; ++kk)
      {
        const double l = lVal[kk];
        const S* zj = z.data() + static_cast<std::int64_t>(this->LCol[kk]) * nc;
        for (int c = 0; c < nc; ++c)
        {
          t[c] -= l * zj[c];
        }
      }
      S* zi = z.data() + i * nc;
      const double ci = invC[i];
      for (int c = 0; c < nc; ++c)
      {
        const double y = t[c] * ci;
        zi[c] = static_cast<S>(y);
        s[nc + c] += y * y;
      }
    };
    // Row i of the backward sweep, column by column: z_i has received every
    // later row's contribution, so it is final once scaled; it then passes
    // its own to the rows it couples to.
    auto backward = [&](std::int64_t i, double* t)
    {
      S* zi = z.data() + i * nc;
      const double ci = invC[i];
      for (int c = 0; c < nc; ++c)
      {
        t[c] = zi[c] * ci;
        zi[c] = static_cast<S>(t[c]);
        t[c] = zi[c]; // pass on the value stored, as CG will read it
      }
      for (std::int64_t kk = this->LPtr[i]; kk < this->LPtr[i + 1]; ++kk)
      {
        const double l = lVal[kk];
        S* zj = z.data() + static_cast<std::int64_t>(this->LCol[kk]) * nc;
        for (int c = 0; c < nc; ++c)
        {
          zj[c] = static_cast<S>(zj[c] - l * t[c]);
        }
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
          std::copy(s, s + 2 * nc, partialSums.begin() + blk * 2 * nc);
        }
      });
    std::vector<double> sums(2 * nc);
    ReduceBlocks(partialSums, nBlocks, 2 * nc, sums.data());
    this->Sum(sums.data(), 2 * nc);
    std::copy(sums.begin(), sums.begin() + nc, rr);
    std::copy(sums.begin() + nc, sums.end(), rz);
  }

  // p = g z + h p and q = g A z + h q per column, with the sums p.q; (g, h)
  // is (1, beta) for an active column, (0, 1) to keep a converged one, and
  // (1, 0) for the first direction.
  template<int NC>
  void NextDirection(const ATSystemView& m,
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
  bool SolveN(const ATSystemView& m, const ATRhs& b, ATColumns xOut, int ncRun)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t n = this->Rows(m);
    if (xOut.rows() != m.cols() || xOut.cols() != nc || b.Rows < n || b.Columns != nc)
    {
      return false;
    }
    ICWork<S>& work = *this->Work;
    double* x = xOut.data();
    const std::int64_t ld = xOut.outerStride();
    std::vector<S>&r = work.R, &p = work.P, &q = work.Q, &z = work.Z;
    // Full length (the products read the ghost rows of z), and only ever
    // grown: the vectors alternate between the u- and v-systems' sizes, and
    // shrinking then growing again would zero the difference at every step.
    const std::size_t len = static_cast<std::size_t>(m.cols()) * nc;
    for (std::vector<S>* w : { &r, &p, &q, &z })
    {
      if (w->size() < len)
      {
        std::vector<S>().swap(*w); // nothing to keep; growing in place could double it
        ResizeHuge(*w, len);
      }
    }
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
    const int* outer = m.outerIndexPtr();
    const int* inner = m.innerIndexPtr();
    const double* val = m.valuePtr();
    int it = 0, nActive = 0;
    bool breakdown = false;
    for (int restart = 0; restart <= MaxRestarts && !breakdown; ++restart)
    {
      this->GhostColumns(x, ld, nc);
      // r = b - A x, from b in double; sums of b.b and r.r. (A x row by
      // row in the order of RowProduct, columns of x read in place.)
      ForBlocks(n,
        [&](std::int64_t blk, std::int64_t i0, std::int64_t i1)
        {
          double acc[2 * (NC > 0 ? NC : 16)] = {}, yFixed[NC > 0 ? NC : 1];
          std::vector<double> accDyn(NC > 0 ? 0 : 2 * nc, 0.0), yDyn(NC > 0 ? 0 : nc);
          double* s = NC > 0 ? acc : accDyn.data();
          double* y = NC > 0 ? yFixed : yDyn.data();
          for (std::int64_t i = i0; i < i1; ++i)
          {
            std::fill(y, y + nc, 0.0);
            for (int k = outer[i]; k < outer[i + 1]; ++k)
            {
              const double a = val[k];
              const double* xk = x + inner[k];
              for (int c = 0; c < nc; ++c)
              {
                y[c] += a * xk[c * ld];
              }
            }
            for (int c = 0; c < nc; ++c)
            {
              const std::int64_t ic = i * nc + c;
              const double bic = b(i, c);
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
          false, alpha.data(), x, ld, p, r, q, z, nc, rr.data(), rz.data());
        std::fill(g.begin(), g.end(), 1.0);
        std::fill(h.begin(), h.end(), 0.0);
        this->template NextDirection<NC>(m, z, p, q, g.data(), h.data(), nc, partial, pq.data());
      }
      while (nActive > 0 && it < this->MaxIterations)
      {
        ++it;
        for (int c = 0; c < nc; ++c)
        {
          // Not positive definite (or NaN): stop before x takes the step.
          breakdown = breakdown || (active[c] && !(pq[c] > 0));
          alpha[c] = active[c] && !breakdown ? rz[c] / pq[c] : 0.0;
        }
        if (breakdown)
        {
          break;
        }
        this->template UpdateAndPrecondition<NC>(
          true, alpha.data(), x, ld, p, r, q, z, nc, rr.data(), rzNew.data());
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
    bool ok = nActive == 0 && !breakdown;
    for (int c = 0; ok && c < nc; ++c)
    {
      ok = std::all_of(x + c * ld, x + c * ld + m.cols(), [](double a) { return std::isfinite(a); });
    }
    if (this->Dist)
    {
      ok = this->Dist->AllOk(ok);
    }
    // The ghost rows take their owners' values, success or not, so that
    // the step goes on from one consistent u or v (the caller deals with
    // a failure).
    this->GhostColumns(x, ld, nc);
    return ok;
  }

  void Memory(ATMemoryParts& parts, const std::string& name) const override
  {
    auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
    parts.emplace_back(name + ": IC pattern (L columns, row starts)",
      bytes(this->LPtr) + bytes(this->LCol) + bytes(this->Blocks));
    parts.emplace_back(name +
        (this->WorkOwner ? ": IC factor (C values, 1/C_ii; float; u and v in turn)"
                         : ": IC factor (shared with the u solver)"),
      this->WorkOwner ? bytes(this->Work->LVal) + bytes(this->Work->InvC) : 0);
    const ICWork<S>& w = *this->Work;
    parts.emplace_back(name +
        (!this->WorkOwner        ? ": CG vectors (shared with the u solver)"
            : sizeof(S) == 4 ? ": CG vectors (r, p, q, z in float; x is u or v)"
                             : ": CG vectors (r, p, q, z; x is u or v)"),
      !this->WorkOwner ? 0
                       : bytes(w.R) + bytes(w.P) + bytes(w.Q) + bytes(w.Z) + bytes(w.Partial));
  }

private:
  double Tolerance;
  int MaxIterations;
  const ATDistribution* Dist;
  int Kind;
  std::vector<std::int64_t> Blocks;
  // int like the matrix's own indices (the factor has fewer entries).
  std::vector<int> LPtr;
  std::vector<int> LCol;
  double* Scratch = nullptr;
  std::size_t ScratchSize = 0;
  std::shared_ptr<ICWork<S>> Work;
  bool WorkOwner = true;
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
