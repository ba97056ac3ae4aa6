// BenchPreconditioners' shared declarations: the captured System, the per
// method Tally, the timing helper, the CG preconditioners and PCG (defined in
// BenchPreconditionersCG.cxx) and, with hypre, HypreSolve
// (BenchPreconditionersAMG.cxx). See BenchPreconditioners.cxx for the method.
#ifndef BenchPreconditioners_h
#define BenchPreconditioners_h

#include "dgATOperators.h"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dgbench
{
using Clock = std::chrono::steady_clock;
inline double Seconds(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A captured system: the matrix (symmetric, stored full, column major, so
// column i is row i), the right-hand sides and the warm start (n x nc).
struct System
{
  dg::ATSystemMatrix A;
  Eigen::MatrixXd B, X0;
  double Tolerance = 0;
  double Shift = 0; // c > 0 with A - c I positive semi-definite
  std::int64_t ModuleIterations = -1; // what the solver's own step took
};

// Per method and system kind: sums over the steps of one run.
struct Tally
{
  std::int64_t Iterations = 0; // sweeps (u: all columns at once), AMG: sum over columns
  std::int64_t IterationsMaxColumn = 0; // AMG u: sum over solves of the max over columns
  int Solves = 0, Failures = 0;
  double Setup = 0, Solve = 0, Copy = 0;
  double WorstResidual = 0; // max true ||b - A x|| / ||b|| / tol
  int Mismatch = 0; // IC: steps whose count differs from the solver's own
  double BytesPerRow = 0; // extra memory held, per row (largest seen)
  double OperatorComplexity = 0, GridComplexity = 0; // AMG (largest seen)
  int Levels = 0;
  double Products = 0; // matrix-vector products per solve (sum over solves)
};

// max over columns of ||b - A x|| / ||b|| (x n x nc, column major), in double.
double TrueResidual(
  const dg::ATSystemMatrix& A, const Eigen::MatrixXd& b, const Eigen::MatrixXd& x);

// ---------------------------------------------------------------------------
// Preconditioners for the CG below: Setup(A) per step, Apply(r, z) computes
// z = M^-1 r for all nc interleaved columns and returns r.z per column.
struct Preconditioner
{
  virtual ~Preconditioner() = default;
  /// shift: a c > 0 with A - c I positive semi-definite (the AT systems:
  /// alpha for u, lambda / (4 eps) for v), for a lower eigenvalue bound.
  virtual void Setup(const dg::ATSystemMatrix& A, double shift) = 0;
  virtual void Apply(const dg::ATSystemMatrix& A, const std::vector<double>& r,
    std::vector<double>& z, int nc, double* rz) = 0;
  virtual int ProductsPerApply() const = 0;
  /// Bytes per row it needs for a system of nc columns (work vectors, diagonal).
  virtual double BytesPerRow(int nc) const = 0;
  std::vector<double> InvDiag;
  void SetInvDiag(const dg::ATSystemMatrix& A);
};

struct JacobiPreconditioner : Preconditioner
{
  void Setup(const dg::ATSystemMatrix& A, double) override { this->SetInvDiag(A); }
  void Apply(const dg::ATSystemMatrix& A, const std::vector<double>& r, std::vector<double>& z,
    int nc, double* rz) override;
  int ProductsPerApply() const override { return 0; }
  double BytesPerRow(int) const override { return sizeof(double); }
};

// Chebyshev polynomial preconditioner: k steps of the Chebyshev iteration
// for A z = r on the Jacobi-scaled system (D = diag A), from z = 0, on the
// fixed interval [Lo, Hi] bounding the spectrum of D^-1 A (the formulation,
// why PCG applies and why the bounds are valid: BenchPreconditionersCG.cxx).
struct ChebyshevPreconditioner : Preconditioner
{
  explicit ChebyshevPreconditioner(int k)
    : K(k)
  {
  }
  int K;
  double Lo = 0, Hi = 0, Gershgorin = 0, ShiftBound = 0;
  std::vector<double> S, D0, D1; // residual, increments (ping-pong)
  void Setup(const dg::ATSystemMatrix& A, double shift) override;
  void Apply(const dg::ATSystemMatrix& A, const std::vector<double>& r, std::vector<double>& z,
    int nc, double* rz) override;
  int ProductsPerApply() const override { return this->K - 1; }
  double BytesPerRow(int nc) const override
  {
    return sizeof(double) * (1.0 + 3.0 * nc); // 1 / a_ii; s, d_old, d_new
  }
};

// Preconditioned CG on all nc columns at once (one sweep over the matrix per
// iteration serves every column; a converged column is frozen), double
// precision, stopped when the recurrence residual ||r|| <= tol ||b|| for
// every column. Returns the iterations (sweeps), -1 on failure; x (n x nc)
// holds the warm start on entry and the solution on exit.
struct CGWork
{
  std::vector<double> X, R, Z, P, Q;
  std::size_t Bytes() const
  {
    return (X.capacity() + R.capacity() + Z.capacity() + P.capacity() + Q.capacity()) *
      sizeof(double);
  }
};

int PCG(const dg::ATSystemMatrix& A, const Eigen::MatrixXd& b, Eigen::MatrixXd& xOut, double tol,
  int maxIt, Preconditioner& M, CGWork& w);

#ifdef DG_HAVE_HYPRE
// A BoomerAMG configuration: -1 leaves hypre's default.
struct AmgConfig
{
  std::string Name;
  int Coarsen = -1, Interp = -1, AggLevels = -1, PMax = -1;
  double Strong = -1;
};

// hypre's PCG + BoomerAMG on one system, the columns one after another
// sharing one setup; adds to t (a failed solve counts in t.Failures).
void HypreSolve(const AmgConfig& cfg, System& s, Tally& t);
#endif
} // namespace dgbench

#endif
