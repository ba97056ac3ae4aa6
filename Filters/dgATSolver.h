// The Ambrosio-Tortorelli alternating minimisation (docs/method.md sections 3-5) on
// an ATComplex: u (C values per face) and v (one value per vertex), the two
// SPD linear systems, the epsilon schedule and the energy.
//
// Both system matrices keep the sparsity pattern built once by ATComplex;
// each iteration only recomputes their values (row by row from the complex's
// incidences, parallel and deterministic), so a direct solver analyses (orders) once and
// refactorises numerically, and the iterative solver just reads the values.
//
// Linear solvers (ATLinearSolver):
// - ConjugateGradientIC (default): CG preconditioned by a zero fill-in
//   incomplete factorisation L D L^T, block-Jacobi style over fixed row
//   ranges (parallel, thread-count independent), warm-started from the
//   previous u and v, all C right-hand sides of the u-system in one sweep
//   over the matrix, stopped when ||r||_2 <= CGTolerance ||b||_2 for every
//   column.
// - ConjugateGradient: the same with the diagonal (Jacobi) preconditioner.
// - SimplicialLDLT: Eigen's sparse LDL^T (AMD ordering once, numeric
//   factorisation per step). The exact reference.
// - Cholmod: CHOLMOD's supernodal Cholesky through Eigen's CholmodSupport,
//   when the module was built with it (CholmodAvailable()).
// Products and reductions run over fixed blocks with vtkSMPTools, so every
// iterative result is bitwise identical whatever the number of threads.
//
// Why (BenchAT, 2 cores, paper's parameters, 20 steps, medians of 3): the
// CGs are 5-10x faster than SimplicialLDLT already at 50k faces (IC 0.70 s,
// Jacobi 1.27 s, LDL^T 5.5 s; CHOLMOD with Debian's reference BLAS is slower
// still), and the direct solvers' refactorisation (fill-in on a closed
// surface) grows faster than the surface. IC(0) needs 2.3x fewer iterations
// than Jacobi and, arranged to make two passes over memory per iteration
// (ICSystem::UpdateAndPrecondition), costs little more per iteration: on
// octa-flower 512^3 with BenchAT's stand-in input the whole run took 8.6 s
// against 12.2 s (857 against 1951 iterations, at CGTolerance 1e-8).
//
// CGTolerance 1e-5 (was 1e-8): each solve is warm-started and followed by
// another alternating step, so solving it to 1e-8 buys accuracy the outer
// iteration throws away. Against the exact LDL^T run with the same schedule
// (TestATAccuracyBudget, BenchATPipeline --exact; noisy rotated cube and
// cube-sphere 64^3 at k = 0.3, fandisk-128 and fandisk-256 on II r = 3):
// normals within 0.0015 degrees at the 99.9th percentile, v within 4e-4,
// the same feature edges; the budget is 0.05 degrees, 1e-3 and 0.5 % of the
// edges. 1e-4 breaks the v budget (4.7e-3 on the cube). CG iterations on
// octa-flower 1 148 -> 563, AT 15.0 -> 8.5 s (BenchATPipeline, 2 cores,
// medians of 3 in one sitting, 2026-12-01).
#ifndef dgATSolver_h
#define dgATSolver_h

#include "dgATMetric.h"
#include "dgATOperators.h"

#include <Eigen/Dense>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dg
{

enum class ATLinearSolver
{
  ConjugateGradient = 0,
  SimplicialLDLT = 1,
  Cholmod = 2,
  ConjugateGradientIC = 3
};

/// True when CHOLMOD was found at build time.
bool CholmodAvailable();
const char* ATLinearSolverName(ATLinearSolver s);

/// Parameters in grid units (identity metric: a voxel side is 1).
struct ATParameters
{
  double Alpha = 0.1;   // data fidelity weight
  double Lambda = 0.01; // length weight of the discontinuity set
  double EpsilonStart = 2.0;
  double EpsilonEnd = 0.25;
  double EpsilonRatio = 2.0;
  int MaximumIterations = 5; // u-step + v-step pairs per epsilon level
  double Tolerance = 1e-4;   // on ||v - v_prev||_inf
  bool Normalize = true;     // unit-length u at the end (skip zero vectors)
  ATLinearSolver Solver = ATLinearSolver::ConjugateGradientIC;
  double CGTolerance = 1e-5; // relative residual per right-hand side (see above)
  // The v-system is solved to CGToleranceVFactor * CGTolerance: v's error
  // against LDL^T comes mostly from the u-solve. At 3, octa-flower's
  // v-solves take 291 CG iterations instead of 340 and the budget holds
  // with a margin of 1.9x or more (fandisk-256's max |dv| 5.2e-4; 10 leaves
  // 1.3x); docs/at-speed.md.
  double CGToleranceVFactor = 3.0;
  // With CGToleranceEarlyFactor F > 1, the levels before the last solve
  // both systems to a looser tolerance: sqrt(F) times looser per level away
  // from the last, at most F, while v still moves by more than 10 x
  // Tolerance (ATSolver::Schedule). What an early level gets wrong, the next
  // levels' warm-started steps mostly solve again: at F = 6, CG iterations
  // fall by 17 % (octa-flower 514 -> 428) and the budget against LDL^T holds
  // on fandisk-128/256 (max |dv| 5.2e-4 at most, both schedules). But two
  // CG runs drift further apart: 3 MPI ranks against one process on the
  // noisy rotated cube differ in v by 8.5e-4 at F = 1, 1.3e-3 at F = 3 and
  // 1.8e-3 at F = 6, past the 1e-3 that mpi.pvbatch.rotated-cube-noisy
  // asserts, and the 3-rank run alone is 1.3e-3 from the exact solve
  // (a one-process run at CGTolerance 1e-8), out of the v-budget. So it is
  // an option, off by default (docs/at-speed.md).
  double CGToleranceEarlyFactor = 1.0;
  int CGMaximumIterations = 5000;
  // ConjugateGradientIC stores r, p, q and z in float (x, the matrix and
  // every sum in double): fewer bytes per iteration (see dgATICSystem.cxx).
  bool CGSinglePrecision = true;

  /// Empty when valid, else what is wrong.
  std::string Check() const;
};

/// Wall-clock seconds per phase and counters of the last Run().
struct ATStatistics
{
  double Assembly = 0;      // system values (both systems, every step)
  double Analysis = 0;      // symbolic analysis / ordering (once per system)
  double Factorization = 0; // numeric factorisation or preconditioner
  double Solve = 0;         // triangular solves or CG iterations
  double SolveU = 0;        // of which the u-system's
  int Levels = 0;
  int Iterations = 0;             // u-step + v-step pairs, all levels
  std::int64_t CGIterations = 0;  // both systems (one u sweep serves all columns)
  std::int64_t CGIterationsU = 0; // u-system only
  int FailedSolves = 0;
};

/// Reports progress in [0, 1]; returns false to abort.
using ATProgressCallback = std::function<bool(double)>;

class ATLinearSystem;
/// Dense columns passed to the linear solvers without copies (an
/// Eigen::MatrixXd, or an Eigen::VectorXd as one column).
using ATColumns = Eigen::Ref<Eigen::MatrixXd>;
using ATConstColumns = Eigen::Ref<const Eigen::MatrixXd>;

/// A right-hand side read where it lies, without a dense copy: entry (i, c)
/// is (Scale * Data[i * RowStride + c * ColumnStride]) * RowScale[i], a null
/// Data reading 1 and a null RowScale 1. The products are taken in the order
/// the dense right-hand sides it replaced were made in (alpha g, then the
/// face areas; lambda / (4 eps), then the vertex areas), so the same bits.
struct ATRhs
{
  const double* Data = nullptr;
  std::int64_t Rows = 0, Columns = 0, RowStride = 0, ColumnStride = 0;
  double Scale = 1;
  const double* RowScale = nullptr;
  double operator()(std::int64_t i, std::int64_t c) const
  {
    const double d =
      this->Data ? this->Scale * this->Data[i * this->RowStride + c * this->ColumnStride] : this->Scale;
    return this->RowScale ? d * this->RowScale[i] : d;
  }
  /// A dense matrix's columns (b must outlive the result).
  static ATRhs Of(const Eigen::MatrixXd& b)
  {
    ATRhs r;
    r.Data = b.data();
    r.Rows = b.rows();
    r.Columns = b.cols();
    r.RowStride = 1;
    r.ColumnStride = b.rows();
    return r;
  }
  /// The same as a dense matrix (for the reference solvers).
  Eigen::MatrixXd Dense() const
  {
    Eigen::MatrixXd b(this->Rows, this->Columns);
    for (std::int64_t c = 0; c < this->Columns; ++c)
    {
      for (std::int64_t i = 0; i < this->Rows; ++i)
      {
        b(i, c) = (*this)(i, c);
      }
    }
    return b;
  }
};

/// The communication of a distributed solve (one process per piece, see
/// docs/distributed.md): each process holds its rows of both systems (its
/// owned faces and vertices, numbered first) and a halo of ghost rows whose
/// values belong to other processes. The solver calls these at fixed points
/// of its schedule and of every CG iteration; every process must make the
/// same calls in the same order.
class ATDistribution
{
public:
  virtual ~ATDistribution() = default;
  /// Sums values[0..count) over all processes, in place: every process gets
  /// the same bits (summed in process order).
  virtual void SumAll(double* values, int count) const = 0;
  virtual double MaxAll(double value) const = 0;
  /// True on every process when `ok` is true on every process.
  virtual bool AllOk(bool ok) const = 0;
  /// Overwrites the ghost rows (from Owned(kind) on) of x, `nc` interleaved
  /// values per row, with their owners' values. kind 0: faces (u), 1: vertices (v).
  virtual void UpdateGhosts(int kind, double* x, int nc) const = 0;
  virtual void UpdateGhosts(int kind, float* x, int nc) const = 0;
  virtual std::int64_t Owned(int kind) const = 0;
};

class ATSolver
{
public:
  explicit ATSolver(const ATComplex& complex, const ATParameters& parameters = ATParameters());
  /// The same, taking the complex's system patterns instead of copying them
  /// (48 bytes per face of a closed quad surface that would otherwise be
  /// held twice). The complex keeps everything else; no other solver can
  /// then be built on it (its Run() fails with a message).
  struct TakePatternsTag
  {
  };
  static constexpr TakePatternsTag TakePatterns{};
  ATSolver(ATComplex& complex, const ATParameters& parameters, TakePatternsTag);
  ~ATSolver();
  ATSolver(const ATSolver&) = delete;
  ATSolver& operator=(const ATSolver&) = delete;

  /// Makes the solve distributed (null: one process, the default). The
  /// complex is then the process's local one, owned faces and vertices
  /// first; only ConjugateGradientIC is supported. Must outlive Run().
  void SetDistribution(const ATDistribution* d) { this->Distribution = d; }

  /// Weighs the energy's terms by a metric (dgATMetric.h; null: the
  /// identity, the paper's, the default). Its arrays must match the complex
  /// and outlive Run(). Set before Run() or Initialize().
  void SetMetric(const ATMetric* m) { this->Metric = m; }

  /// Reads g, for the u right-hand sides alpha g, from the caller's array
  /// instead of a copy of its own (24 bytes per face with normals): entry
  /// (f, c) at g[f * rowStride + c * columnStride], which must hold the
  /// field given to Run or Initialize and outlive the steps
  /// (vtkAmbrosioTortorelliFilter passes its input array). A source that
  /// differs from that field is not used (the solver copies the field).
  /// Null: the solver's own copy, the default.
  void SetFieldSource(const double* g, std::int64_t rowStride, std::int64_t columnStride)
  {
    this->FieldSource = g;
    this->FieldRowStride = rowStride;
    this->FieldColumnStride = columnStride;
  }
  /// True when the last Initialize or Run reads g from the caller's array.
  bool UsesFieldSource() const { return this->G.size() == 0 && this->FieldSource; }

  /// The whole schedule: u <- g, v <- 1, then levels of alternating steps.
  /// g is F x C (one row per face). Returns false when aborted or when the
  /// parameters are invalid (see Error()). Solver failures do not stop the
  /// run: the step keeps what the linear solver left (IC CG's last iterate,
  /// no farther from the solution than the previous values; the previous
  /// values for the other solvers, or when the iterate is not finite) and
  /// Warnings() says so.
  bool Run(const Eigen::MatrixXd& g, const ATProgressCallback& progress = ATProgressCallback());
  /// The same, taking g instead of copying it (F x C doubles that the caller
  /// would otherwise hold beside the solver's copy; g is left empty or with
  /// unspecified contents).
  bool Run(Eigen::MatrixXd&& g, const ATProgressCallback& progress = ATProgressCallback());

  /// Single steps, for tests: Initialize sets u = g, v = 1.
  void Initialize(const Eigen::MatrixXd& g);
  void Initialize(Eigen::MatrixXd&& g);
  bool StepU();
  bool StepV(double epsilon);
  /// AT_epsilon(u, v) of docs/method.md section 3 for the current u, v (g is
  /// recovered from the u right-hand sides alpha g, so to rounding).
  double Energy(double epsilon) const;
  /// Normalises every row of u to unit length (zero rows are left as they are).
  void NormalizeU();

  const Eigen::MatrixXd& U() const { return this->u; }
  const Eigen::VectorXd& V() const { return this->v; }
  Eigen::MatrixXd& U() { return this->u; }
  Eigen::VectorXd& V() { return this->v; }
  /// Copies of the system matrices for the current u and v (VMatrix: for
  /// the epsilon of the last AssembleV). The two systems share one values
  /// buffer, so each assembles again when the buffer holds the other's.
  ATSystemMatrix UMatrix();
  ATSystemMatrix VMatrix();
  void AssembleU();
  void AssembleV(double epsilon);

  const ATParameters& Parameters() const { return this->Params; }
  /// The bytes the solver holds, by structure (its complex not included:
  /// ATComplex::Memory).
  void Memory(ATMemoryParts& parts) const;
  const ATStatistics& Statistics() const { return this->Stats; }
  const std::vector<std::string>& Warnings() const { return this->WarningList; }
  const std::string& Error() const { return this->ErrorText; }

private:
  bool Prepare(const Eigen::MatrixXd& field);
  bool Schedule(const ATProgressCallback& progress);
  void InitializeFromU();
  void MakeSystems();
  bool SolveSystem(ATLinearSystem& system,
    const ATSystemView& m,
    const ATRhs& b,
    ATColumns x,
    const char* name,
    const std::function<void()>& restore,
    std::pair<double*, std::size_t> factorScratch);
  /// The u right-hand sides alpha g (times the face areas with a metric).
  ATRhs URhs() const;
  double GValue(std::int64_t f, std::int64_t c) const;
  double* EdgeScratch();
  void RecoverG(Eigen::MatrixXd& out) const;
  const ATComplex& Complex;
  const ATDistribution* Distribution = nullptr;
  const ATMetric* Metric = nullptr;
  double LastVChange = 0; // max |v - v_prev| of the last StepV (owned rows)
  double ToleranceFactor = 1.0; // CGToleranceEarlyFactor on the levels before the last
  ATParameters Params;
  ATStatistics Stats;
  Eigen::MatrixXd u;
  Eigen::VectorXd v;
  // g, for the u right-hand sides: the solver's copy G, or the caller's
  // array (SetFieldSource), in which case G is empty.
  Eigen::MatrixXd G;
  const double* FieldSource = nullptr;
  std::int64_t FieldRowStride = 0, FieldColumnStride = 0;
  // Per-edge weights or jumps of the assembly; during a v-step, the previous
  // v instead, so that it needs no array of its own (8 bytes per vertex).
  std::vector<double> EdgeWork;
  // The systems' patterns and one values buffer for both: a step assembles
  // its system, factorises and solves it, and the next step's system then
  // overwrites the values (40 bytes per surfel less on a quad surface).
  ATPattern UP, VP;
  std::vector<double> Values;
  int ValuesHold = -1;        // 0: the u-system's values, 1: the v-system's, -1: none
  double VAssemblyEpsilon = 0; // the epsilon of the last AssembleV
  double* SystemValues();
  std::unique_ptr<ATLinearSystem> USystem, VSystem;
  std::vector<std::string> WarningList;
  std::string ErrorText;
};

} // namespace dg

#endif
