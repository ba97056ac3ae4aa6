// The linear systems of the Ambrosio-Tortorelli steps (dgATSolver.h says
// which and why): one class per solver behind ATLinearSystem, private to the
// module.
#ifndef dgATLinearSystems_h
#define dgATLinearSystems_h

#include "dgATSolver.h"

#include <memory>

namespace dg
{

// One linear system whose pattern never changes: Analyze once, then
// Factorize + Solve at each step with new values.
class ATLinearSystem
{
public:
  virtual ~ATLinearSystem() = default;
  virtual bool Analyze(const ATSystemView&) { return true; }
  virtual bool Factorize(const ATSystemView&) = 0;
  /// Doubles that the next Factorize may use as work space (null: none),
  /// so that it allocates nothing; the caller's, free until Factorize returns.
  virtual void SetFactorScratch(double*, std::size_t) {}
  /// x (m.cols() x b.cols()) holds the previous solution on entry (a warm
  /// start for iterative solvers) and the new one on success. On failure it
  /// holds the previous values, except with ConjugateGradientIC: it solves in
  /// place (no copy of x: 24 bytes per face of the u-system), and leaves
  /// CG's last iterate, whose error in the A-norm is no larger than the warm
  /// start's; ATSolver handles a non-finite one.
  virtual bool Solve(const ATSystemView& m, const ATRhs& b, ATColumns x) = 0;
  /// The bytes this solver holds (factor, work vectors), by name.
  virtual void Memory(ATMemoryParts&, const std::string&) const {}
  /// Iterative solvers: the relative residual to stop at (direct ones ignore it).
  virtual void SetTolerance(double) {}
  /// Solves with `other`'s work vectors from now on (the two must never
  /// solve at the same time); false when the two solvers cannot share.
  virtual bool ShareWork(ATLinearSystem&) { return false; }
  bool Analyzed = false;
  std::int64_t Iterations = 0;
};

/// Conjugate gradients with block IC(0) (dgATICSystem.cxx).
/// With a distribution, CG runs over the process's owned rows of system
/// `kind` (0: u, 1: v), with halo updates and global sums. singlePrecision
/// stores CG's residual, search directions and preconditioned residual in float.
std::unique_ptr<ATLinearSystem> MakeICSystem(double tolerance, int maxIterations,
  const ATDistribution* distribution = nullptr, int kind = 0, bool singlePrecision = true);

/// The system for p.Solver (null for CHOLMOD in a build without it).
std::unique_ptr<ATLinearSystem> MakeATLinearSystem(const ATParameters& p);

} // namespace dg

#endif
