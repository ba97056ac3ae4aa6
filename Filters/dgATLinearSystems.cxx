#include "dgATLinearSystems.h"

#include "dgATBlocks.h"

#include <Eigen/SparseCholesky>
#ifdef DG_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include <algorithm>
#include <cmath>

namespace dg
{
namespace
{
template<class Factor>
class DirectSystem : public ATLinearSystem
{
public:
  bool Analyze(const ATSystemView& m) override
  {
    this->F.analyzePattern(ATSystemMatrix(m)); // a copy: these solvers are the slow references
    return this->F.info() == Eigen::Success;
  }
  bool Factorize(const ATSystemView& m) override
  {
    this->F.factorize(ATSystemMatrix(m));
    return this->F.info() == Eigen::Success;
  }
  bool Solve(const ATSystemView&, const ATRhs& b, ATColumns x) override
  {
    Eigen::MatrixXd y = this->F.solve(b.Dense());
    if (this->F.info() != Eigen::Success || !y.allFinite() || y.rows() != x.rows() ||
      y.cols() != x.cols())
    {
      return false;
    }
    x = y;
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
  void SetTolerance(double tolerance) override { this->Tolerance = tolerance; }
  bool Factorize(const ATSystemView& m) override
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

  bool Solve(const ATSystemView& m, const ATRhs& b, ATColumns x) override
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
  bool SolveN(const ATSystemView& m, const ATRhs& b, ATColumns xOut, int ncRun)
  {
    const int nc = NC > 0 ? NC : ncRun;
    const std::int64_t n = m.cols();
    if (xOut.rows() != n || xOut.cols() != nc)
    {
      return false;
    }
    const double* dinv = this->InvDiag.data();
    std::vector<double> x, r, p(n * nc), q(n * nc);
    Interleave(xOut, x);
    Interleave(b.Dense(), r);
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


} // namespace

std::unique_ptr<ATLinearSystem> MakeATLinearSystem(const ATParameters& p)
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
      return MakeICSystem(p.CGTolerance, p.CGMaximumIterations, nullptr, 0, p.CGSinglePrecision);
    case ATLinearSolver::ConjugateGradient:
    default:
      return std::unique_ptr<ATLinearSystem>(new CGSystem(p.CGTolerance, p.CGMaximumIterations));
  }
}

bool CholmodAvailable()
{
#ifdef DG_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

} // namespace dg
