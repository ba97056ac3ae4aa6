// BenchPreconditioners' hypre side: PCG with one BoomerAMG V-cycle per
// application (HypreSolve); compiles to nothing without DG_HAVE_HYPRE.
#ifdef DG_HAVE_HYPRE
#include "BenchPreconditioners.h"

#include <mpi.h>

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
#include <_hypre_parcsr_ls.h> // the hierarchy's levels, for the operator complexity

#include <algorithm>
#include <vector>

namespace dgbench
{
void HypreSolve(const AmgConfig& cfg, System& s, Tally& t)
{
  const auto& A = s.A;
  const HYPRE_Int n = static_cast<HYPRE_Int>(A.cols());
  const int nc = static_cast<int>(s.B.cols());
  auto t0 = Clock::now();
  HYPRE_IJMatrix ij;
  HYPRE_IJMatrixCreate(MPI_COMM_WORLD, 0, n - 1, 0, n - 1, &ij);
  HYPRE_IJMatrixSetObjectType(ij, HYPRE_PARCSR);
  std::vector<HYPRE_Int> sizes(n), rows(n);
  for (HYPRE_Int i = 0; i < n; ++i)
  {
    sizes[i] = A.outerIndexPtr()[i + 1] - A.outerIndexPtr()[i];
    rows[i] = i;
  }
  HYPRE_IJMatrixSetRowSizes(ij, sizes.data());
  HYPRE_IJMatrixInitialize(ij);
  // Column i of the symmetric matrix is its row i.
  std::vector<HYPRE_BigInt> cols(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  std::vector<HYPRE_BigInt> bigRows(rows.begin(), rows.end());
  HYPRE_IJMatrixSetValues(ij, n, sizes.data(), bigRows.data(), cols.data(), A.valuePtr());
  HYPRE_IJMatrixAssemble(ij);
  HYPRE_ParCSRMatrix parA;
  HYPRE_IJMatrixGetObject(ij, reinterpret_cast<void**>(&parA));
  auto makeVector = [&](const double* values, HYPRE_IJVector* v, HYPRE_ParVector* pv) {
    HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, n - 1, v);
    HYPRE_IJVectorSetObjectType(*v, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(*v);
    HYPRE_IJVectorSetValues(*v, n, bigRows.data(), values);
    HYPRE_IJVectorAssemble(*v);
    HYPRE_IJVectorGetObject(*v, reinterpret_cast<void**>(pv));
  };
  std::vector<HYPRE_IJVector> bs(nc), xs(nc);
  std::vector<HYPRE_ParVector> pbs(nc), pxs(nc);
  Eigen::MatrixXd x = s.X0;
  for (int c = 0; c < nc; ++c)
  {
    makeVector(s.B.col(c).data(), &bs[c], &pbs[c]);
    makeVector(x.col(c).data(), &xs[c], &pxs[c]);
  }
  t.Copy += Seconds(t0);

  HYPRE_Solver amg, pcg;
  HYPRE_BoomerAMGCreate(&amg);
  HYPRE_BoomerAMGSetPrintLevel(amg, 0);
  HYPRE_BoomerAMGSetMaxIter(amg, 1); // one V-cycle per application
  HYPRE_BoomerAMGSetTol(amg, 0.0);
  if (cfg.Coarsen >= 0)
    HYPRE_BoomerAMGSetCoarsenType(amg, cfg.Coarsen);
  if (cfg.Interp >= 0)
    HYPRE_BoomerAMGSetInterpType(amg, cfg.Interp);
  if (cfg.Strong >= 0)
    HYPRE_BoomerAMGSetStrongThreshold(amg, cfg.Strong);
  if (cfg.AggLevels >= 0)
    HYPRE_BoomerAMGSetAggNumLevels(amg, cfg.AggLevels);
  if (cfg.PMax >= 0)
    HYPRE_BoomerAMGSetPMaxElmts(amg, cfg.PMax);
  HYPRE_ParCSRPCGCreate(MPI_COMM_WORLD, &pcg);
  HYPRE_PCGSetTol(pcg, s.Tolerance);
  HYPRE_PCGSetAbsoluteTol(pcg, 0.0);
  HYPRE_PCGSetTwoNorm(pcg, 1);
  HYPRE_PCGSetMaxIter(pcg, 5000);
  HYPRE_PCGSetPrintLevel(pcg, 0);
  HYPRE_PCGSetPrecond(pcg, reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSolve),
    reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSetup), amg);
  t0 = Clock::now();
  HYPRE_ParCSRPCGSetup(pcg, parA, pbs[0], pxs[0]); // the AMG hierarchy
  t.Setup += Seconds(t0);
  {
    // Operator complexity: sum of the levels' non-zeros / the matrix's.
    auto* data = reinterpret_cast<hypre_ParAMGData*>(amg);
    const int levels = hypre_ParAMGDataNumLevels(data);
    hypre_ParCSRMatrix** As = hypre_ParAMGDataAArray(data);
    double nnz = 0, rowsAll = 0, nnz0 = 0, rows0 = 0;
    for (int l = 0; l < levels; ++l)
    {
      hypre_ParCSRMatrix* Al = As[l];
      const double z = hypre_CSRMatrixNumNonzeros(hypre_ParCSRMatrixDiag(Al)) +
        hypre_CSRMatrixNumNonzeros(hypre_ParCSRMatrixOffd(Al));
      const double r = hypre_ParCSRMatrixGlobalNumRows(Al);
      nnz += z;
      rowsAll += r;
      if (l == 0)
      {
        nnz0 = z;
        rows0 = r;
      }
    }
    t.OperatorComplexity = std::max(t.OperatorComplexity, nnz0 > 0 ? nnz / nnz0 : 0.0);
    t.GridComplexity = std::max(t.GridComplexity, rows0 > 0 ? rowsAll / rows0 : 0.0);
    t.Levels = std::max(t.Levels, levels);
  }
  t0 = Clock::now();
  int maxCol = 0;
  bool ok = true;
  for (int c = 0; c < nc; ++c)
  {
    const HYPRE_Int err = HYPRE_ParCSRPCGSolve(pcg, parA, pbs[c], pxs[c]);
    HYPRE_Int its = 0;
    HYPRE_PCGGetNumIterations(pcg, &its);
    double rel = 0;
    HYPRE_PCGGetFinalRelativeResidualNorm(pcg, &rel);
    ok = ok && (err == 0 || rel <= s.Tolerance);
    HYPRE_ClearAllErrors();
    t.Iterations += its;
    maxCol = std::max(maxCol, static_cast<int>(its));
  }
  t.Solve += Seconds(t0);
  t.IterationsMaxColumn += maxCol;
  for (int c = 0; c < nc; ++c)
  {
    HYPRE_IJVectorGetValues(xs[c], n, bigRows.data(), x.col(c).data());
  }
  const double res = TrueResidual(A, s.B, x);
  t.WorstResidual = std::max(t.WorstResidual, res / s.Tolerance);
  t.Failures += !ok;
  ++t.Solves;
  const double rowBytes = 12.0 * A.nonZeros() / n + 4.0; // CSR: values + columns + row starts
  t.BytesPerRow = std::max(t.BytesPerRow, t.OperatorComplexity * rowBytes);
  HYPRE_ParCSRPCGDestroy(pcg);
  HYPRE_BoomerAMGDestroy(amg);
  for (int c = 0; c < nc; ++c)
  {
    HYPRE_IJVectorDestroy(bs[c]);
    HYPRE_IJVectorDestroy(xs[c]);
  }
  HYPRE_IJMatrixDestroy(ij);
}
} // namespace dgbench
#endif
