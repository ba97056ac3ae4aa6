// Preconditioners for the Ambrosio-Tortorelli systems, measured on the real
// pipeline's input (the issue asking to measure block IC(0), a Chebyshev
// polynomial preconditioner and hypre's BoomerAMG before adopting any).
//
// Per volume: .vol -> vtkDigitalSurfaceFilter -> vtkIINormalEstimator r = 3
// -> ATComplex::Build from the polygons -> ATSolver with the default
// ATParameters (as BenchATPipeline builds it). The AT schedule is then run
// step by step with the public ATSolver API (eps 2, 1, 0.5, 0.25, at most 5
// steps per level, a level stops when max |v - v_prev| < Tolerance, as
// ATSolver::Schedule does with the default CGToleranceEarlyFactor 1), and
// before each StepU / StepV the step's system is captured:
//   u: UMatrix() (assembled with the current v), b = alpha g, x0 = current u;
//   v: AssembleV(eps) then VMatrix(), b = lambda / (4 eps), x0 = current v.
// Each captured system is solved by every method from the same warm start to
// the module's tolerance (u: CGTolerance per column, v: CGTolerance x
// CGToleranceVFactor), and the true relative residual of the result is
// checked. The captured systems are what StepU / StepV solve: the IC row
// checks that its iteration count equals the solver's own (ATStatistics).
//
// Methods:
//   IC(0)      dg::MakeICSystem as the module runs it (float CG vectors,
//              block IC(0), all columns in one sweep; Analyze once per run
//              and system kind, Factorize + Solve per step).
//   Jacobi     CG with the diagonal preconditioner, double, written here.
//   Cheb k     CG preconditioned by k steps of the Chebyshev iteration on
//              D^-1 A from zero (k = 2, 4, 8), Gershgorin bounds on D^-1 A.
//   AMG ...    hypre's PCG with one BoomerAMG V-cycle per application (when
//              built with hypre, DG_HAVE_HYPRE), one rank; the 3 u columns
//              one after another sharing one setup.
//
// Usage: BenchPreconditioners [runs] [volumes...] [--no-amg] [--no-cheb]
//                             [--no-jacobi] [--max-steps N]
//   runs: repetitions of the whole schedule (medians), default 3; volumes:
//   names in the shared volgallery or paths, default fandisk-256.
//
// Files: this one (main: arguments, input pipeline, tables),
// BenchPreconditioners.h (what the parts share), BenchPreconditionersCG.cxx
// (Jacobi, Chebyshev, PCG), BenchPreconditionersAMG.cxx (hypre).
#include "BenchPreconditioners.h"
#include "dgBenchMachine.h"
#include "dgATLinearSystems.h"
#include "dgATOperators.h"
#include "dgATSolver.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#ifdef DG_HAVE_HYPRE
#include <mpi.h>

#include <HYPRE_utilities.h> // HYPRE_Init, HYPRE_Finalize, HYPRE_RELEASE_VERSION
#endif

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

using namespace dgbench;

namespace
{



struct Method
{
  std::string Name;
  std::function<void(int kind, System&, Tally&)> Run;
  std::function<void()> Reset; // per run
  std::string ProductsText;
};
} // namespace

int main(int argc, char* argv[])
{
#ifdef DG_HAVE_HYPRE
  MPI_Init(&argc, &argv);
  HYPRE_Init();
#endif
  int runs = 3, maxSteps = 1 << 30;
  bool amg = true, cheb = true, jacobi = true;
  std::vector<std::string> volumes;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--no-amg")
      amg = false;
    else if (a == "--no-cheb")
      cheb = false;
    else if (a == "--no-jacobi")
      jacobi = false;
    else if (a == "--max-steps" && i + 1 < argc)
      maxSteps = std::atoi(argv[++i]);
    else if (i == 1 && !a.empty() && a[0] >= '0' && a[0] <= '9')
      runs = std::max(1, std::atoi(a.c_str()));
    else
      volumes.push_back(a);
  }
  if (volumes.empty())
  {
    volumes = { "fandisk-256" };
  }
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread");
  }
  dg::ATParameters params; // the paper's: alpha 0.1, lambda 0.01, eps 2 -> 0.25 by 2, <= 5
  params.Normalize = false;
  const double tolU = params.CGTolerance, tolV = params.CGTolerance * params.CGToleranceVFactor;

  char host[256] = "?";
  gethostname(host, sizeof host - 1);
  const char* env = std::getenv("VTK_SMP_BACKEND_IN_USE");
  const char* maxThreads = std::getenv("VTK_SMP_MAX_THREADS");
  std::printf("BenchPreconditioners: %d runs each (medians), tolerance u %g, v %g, maximum "
              "5000 iterations\n",
    runs, tolU, tolV);
  std::printf("machine: %s, nproc %ld, CPU %s\n", host, sysconf(_SC_NPROCESSORS_ONLN),
    CpuModel().c_str());
  std::printf("VTK_SMP_BACKEND_IN_USE=%s, VTK_SMP_MAX_THREADS=%s, vtkSMPTools backend %s, %d "
              "threads (IC, Jacobi, Chebyshev)\n",
    env ? env : "(unset)", maxThreads ? maxThreads : "(unset)", vtkSMPTools::GetBackend(),
    vtkSMPTools::GetEstimatedNumberOfThreads());
#ifdef DG_HAVE_HYPRE
  {
    int ranks = 0;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    std::printf("hypre %s: %d MPI rank(s), built without OpenMP (HYPRE_USING_OPENMP %s): 1 "
                "thread\n",
      HYPRE_RELEASE_VERSION, ranks,
#ifdef HYPRE_USING_OPENMP
      "defined"
#else
      "undefined"
#endif
    );
  }
#else
  std::printf("hypre: not built in (DG_HAVE_HYPRE undefined), AMG skipped\n");
  (void)amg;
#endif
  {
    const std::time_t now = std::time(nullptr);
    char when[64];
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S %Z", std::localtime(&now));
    std::printf("start %s, loadavg %s\n", when, FirstLine("/proc/loadavg").c_str());
  }
  std::fflush(stdout);

  for (const std::string& volume : volumes)
  {
    const std::string path = volume.find('/') != std::string::npos ||
        (volume.size() > 4 && volume.compare(volume.size() - 4, 4, ".vol") == 0)
      ? volume
      : std::string(DG_SHARED_DATA_DIR) + "/" + volume + ".vol";
    if (!std::ifstream(path).good())
    {
      std::printf("\n%s: %s not found, skipped\n", volume.c_str(), path.c_str());
      continue;
    }
    // The input, as BenchATPipeline builds it (once: the systems do not
    // depend on the run).
    vtkNew<vtkDGtalVolReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkImageData* image = reader->GetOutput();
    vtkNew<vtkDigitalSurfaceFilter> surface;
    surface->SetInputData(image);
    vtkNew<vtkIINormalEstimator> ii;
    ii->SetInputConnection(surface->GetOutputPort());
    ii->SetSourceData(image);
    ii->SetRadius(3);
    ii->Update();
    vtkPolyData* input = ii->GetOutput();
    vtkCellArray* polys = input->GetPolys();
    const vtkIdType nFaces = polys->GetNumberOfCells();
    const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
    vtkDataArray* field = input->GetCellData()->GetNormals();
    const int nc = field->GetNumberOfComponents();
    Eigen::MatrixXd g(nFaces, nc);
    {
      const auto tuples = vtk::DataArrayTupleRange(field);
      for (vtkIdType f = 0; f < nFaces; ++f)
      {
        const auto t = tuples[polyOffset + f];
        for (int c = 0; c < nc; ++c)
        {
          g(f, c) = static_cast<double>(t[c]);
        }
      }
    }
    std::vector<std::int64_t> offsets(nFaces + 1), connectivity(polys->GetNumberOfConnectivityIds());
    {
      const auto off = vtk::DataArrayValueRange<1>(polys->GetOffsetsArray());
      const auto conn = vtk::DataArrayValueRange<1>(polys->GetConnectivityArray());
      for (vtkIdType i = 0; i <= nFaces; ++i)
        offsets[i] = static_cast<std::int64_t>(off[i]);
      for (std::size_t i = 0; i < connectivity.size(); ++i)
        connectivity[i] = static_cast<std::int64_t>(conn[i]);
    }
    dg::ATComplex complex;
    std::string error;
    if (!complex.Build(input->GetNumberOfPoints(), offsets, connectivity, &error))
    {
      std::printf("cannot build the complex: %s\n", error.c_str());
      return 1;
    }
    const std::int64_t nVertices = complex.NumberOfVertices();
    std::printf("\n== %s: %lld faces (u rows, %d columns), %lld vertices (v rows)\n",
      volume.c_str(), static_cast<long long>(nFaces), nc, static_cast<long long>(nVertices));
    std::fflush(stdout);

    // The methods.
    std::vector<Method> methods;
    std::unique_ptr<dg::ATLinearSystem> icSys[2];
    methods.push_back({ "IC(0) (module)",
      [&](int kind, System& s, Tally& t) {
        dg::ATLinearSystem& sys = *icSys[kind];
        dg::ATSystemView view(s.A.rows(), s.A.cols(), s.A.nonZeros(), s.A.outerIndexPtr(),
          s.A.innerIndexPtr(), s.A.valuePtr());
        auto t0 = Clock::now();
        if (!sys.Analyzed)
        {
          sys.Analyzed = sys.Analyze(view);
        }
        const bool fok = sys.Factorize(view);
        t.Setup += Seconds(t0);
        Eigen::MatrixXd x = s.X0;
        const std::int64_t it0 = sys.Iterations;
        t0 = Clock::now();
        const bool ok = fok && sys.Solve(view, dg::ATRhs::Of(s.B), x);
        t.Solve += Seconds(t0);
        const std::int64_t its = sys.Iterations - it0;
        t.Iterations += its;
        t.Failures += !ok;
        t.Mismatch += s.ModuleIterations >= 0 && its != s.ModuleIterations;
        t.WorstResidual = std::max(t.WorstResidual, TrueResidual(s.A, s.B, x) / s.Tolerance);
        ++t.Solves;
        t.Products += static_cast<double>(its);
        dg::ATMemoryParts parts;
        sys.Memory(parts, "ic");
        double bytes = 0;
        for (const auto& p : parts)
        {
          if (p.first.find("CG vectors") == std::string::npos)
          {
            bytes += static_cast<double>(p.second);
          }
        }
        t.BytesPerRow = std::max(t.BytesPerRow, bytes / s.A.cols());
      },
      [&]() {
        icSys[0] = dg::MakeICSystem(tolU, 5000);
        icSys[1] = dg::MakeICSystem(tolV, 5000);
        icSys[1]->ShareWork(*icSys[0]);
      },
      "1 + 2 sweeps" });
    auto cgMethod = [&](const std::string& name, std::function<Preconditioner*()> make,
                      const std::string& products) {
      auto prec = std::make_shared<std::unique_ptr<Preconditioner>>();
      auto work = std::make_shared<CGWork>();
      methods.push_back({ name,
        [prec, work, make](int, System& s, Tally& t) {
          if (!*prec)
          {
            prec->reset(make());
          }
          Preconditioner& M = **prec;
          auto t0 = Clock::now();
          M.Setup(s.A, s.Shift);
          t.Setup += Seconds(t0);
          Eigen::MatrixXd x = s.X0;
          t0 = Clock::now();
          const int its = PCG(s.A, s.B, x, s.Tolerance, 5000, M, *work);
          t.Solve += Seconds(t0);
          t.Failures += its < 0;
          t.Iterations += std::max(its, 0);
          t.Products += std::max(its, 0) * (1.0 + M.ProductsPerApply()) +
            (its >= 0 ? 1 + M.ProductsPerApply() : 0); // + r = b - A x0 and the first M^-1 r
          t.WorstResidual = std::max(t.WorstResidual, TrueResidual(s.A, s.B, x) / s.Tolerance);
          ++t.Solves;
          t.BytesPerRow = M.BytesPerRow(static_cast<int>(s.B.cols()));
          if (auto* ch = dynamic_cast<ChebyshevPreconditioner*>(&M))
          {
            // Widest interval seen: largest Gershgorin radius, smallest lower end.
            t.OperatorComplexity = std::max(t.OperatorComplexity, ch->Gershgorin);
            t.GridComplexity = t.Solves == 1 ? ch->Lo : std::min(t.GridComplexity, ch->Lo);
          }
        },
        [prec, work]() {
          prec->reset();
          *work = CGWork();
        },
        products });
    };
    if (jacobi)
    {
      cgMethod("Jacobi-CG", [] { return new JacobiPreconditioner; }, "1");
    }
    if (cheb)
    {
      for (int k : { 2, 4, 8 })
      {
        cgMethod("Chebyshev k=" + std::to_string(k),
          [k] { return new ChebyshevPreconditioner(k); }, std::to_string(k));
      }
    }
#ifdef DG_HAVE_HYPRE
    if (amg)
    {
      const AmgConfig configs[] = {
        { "AMG default (HMIS,ext+i,0.25,P4)" },
        { "AMG HMIS+aggr.1 lvl,0.25", 10, 6, 1, 4, 0.25 },
        { "AMG Falgout,classical,0.25", 6, 0, -1, 0, 0.25 },
      };
      for (const AmgConfig& cfg : configs)
      {
        methods.push_back({ cfg.Name,
          [cfg](int, System& s, Tally& t) { HypreSolve(cfg, s, t); }, [] {},
          "1 + V-cycle" });
      }
    }
#endif

    // runs x methods x kind.
    std::vector<std::vector<std::array<Tally, 2>>> tallies(
      runs, std::vector<std::array<Tally, 2>>(methods.size()));
    std::vector<std::array<double, 2>> moduleSolve(runs), moduleIts(runs);
    int steps = 0;
    for (int r = 0; r < runs; ++r)
    {
      for (auto& m : methods)
      {
        m.Reset();
      }
      dg::ATSolver solver(complex, params);
      solver.Initialize(g);
      System su, sv;
      su.Tolerance = tolU;
      sv.Tolerance = tolV;
      su.B = params.Alpha * g; // alpha g: URhs with the identity metric
      su.Shift = params.Alpha;
      steps = 0;
      const double levels[] = { 2.0, 1.0, 0.5, 0.25 };
      for (double eps : levels)
      {
        for (int it = 0; it < params.MaximumIterations && steps < maxSteps; ++it, ++steps)
        {
          // u-step.
          su.A = solver.UMatrix();
          su.X0 = solver.U();
          std::int64_t c0 = solver.Statistics().CGIterationsU;
          double s0 = solver.Statistics().Solve;
          solver.StepU();
          su.ModuleIterations = solver.Statistics().CGIterationsU - c0;
          moduleSolve[r][0] += solver.Statistics().Solve - s0;
          moduleIts[r][0] += static_cast<double>(su.ModuleIterations);
          for (std::size_t m = 0; m < methods.size(); ++m)
          {
            methods[m].Run(0, su, tallies[r][m][0]);
          }
          // v-step.
          solver.AssembleV(eps);
          sv.A = solver.VMatrix();
          sv.X0 = solver.V();
          sv.B = Eigen::MatrixXd::Constant(nVertices, 1, params.Lambda / (4 * eps));
          sv.Shift = params.Lambda / (4 * eps);
          const Eigen::VectorXd vPrev = solver.V();
          c0 = solver.Statistics().CGIterations - solver.Statistics().CGIterationsU;
          s0 = solver.Statistics().Solve;
          solver.StepV(eps);
          sv.ModuleIterations =
            solver.Statistics().CGIterations - solver.Statistics().CGIterationsU - c0;
          moduleSolve[r][1] += solver.Statistics().Solve - s0;
          moduleIts[r][1] += static_cast<double>(sv.ModuleIterations);
          for (std::size_t m = 0; m < methods.size(); ++m)
          {
            methods[m].Run(1, sv, tallies[r][m][1]);
          }
          const double change = (solver.V() - vPrev).lpNorm<Eigen::Infinity>();
          if (change < params.Tolerance)
          {
            ++steps;
            break;
          }
        }
      }
      std::printf("  run %d: %d steps, module's own CG iterations u %g, v %g (its solve %.3f + "
                  "%.3f s), loadavg %s\n",
        r + 1, steps, moduleIts[r][0], moduleIts[r][1], moduleSolve[r][0], moduleSolve[r][1],
        FirstLine("/proc/loadavg").c_str());
      std::fflush(stdout);
    }

    for (int kind = 0; kind < 2; ++kind)
    {
      const std::int64_t rows = kind == 0 ? nFaces : nVertices;
      std::printf("\n  %s-system: %lld rows, %d rhs, tolerance %g, %d solves; medians of %d runs\n",
        kind == 0 ? "u" : "v", static_cast<long long>(rows), kind == 0 ? nc : 1,
        kind == 0 ? tolU : tolV, steps, runs);
      std::printf("  %-33s %7s %7s %8s %8s %8s %8s %9s %9s %8s %7s %9s %s\n", "method", "iters",
        "/solve", "setup s", "solve s", "copy s", "total s", "ms/iter", "matvec/it", "mv/solve",
        "B/row", "max res", "notes");
      const Tally* icRef = nullptr;
      for (std::size_t m = 0; m < methods.size(); ++m)
      {
        std::vector<double> it, setup, solve, copy, total;
        for (int r = 0; r < runs; ++r)
        {
          const Tally& t = tallies[r][m][kind];
          it.push_back(static_cast<double>(t.Iterations));
          setup.push_back(t.Setup);
          solve.push_back(t.Solve);
          copy.push_back(t.Copy);
          total.push_back(t.Setup + t.Solve + t.Copy);
        }
        const Tally& t0 = tallies[0][m][kind];
        if (m == 0)
        {
          icRef = &t0;
        }
        const double iters = MedianOf(it);
        char notes[256] = "";
        if (m == 0)
        {
          std::snprintf(notes, sizeof notes, "steps with an iteration count != the solver's: %d",
            t0.Mismatch);
        }
        else if (methods[m].Name.compare(0, 9, "Chebyshev") == 0)
        {
          std::snprintf(notes, sizeof notes,
            "Gershgorin g max %.4f; widest bounds used [%.4g, %.4f] (lower: max(1 - g, c / max a_ii))",
            t0.OperatorComplexity, t0.GridComplexity, 1 + t0.OperatorComplexity);
        }
        else if (methods[m].Name.compare(0, 3, "AMG") == 0)
        {
          std::snprintf(notes, sizeof notes,
            "op. complexity %.3f, grid %.3f, %d levels%s; iters = sum over columns (max-column "
            "sum %lld)",
            t0.OperatorComplexity, t0.GridComplexity, t0.Levels, "",
            static_cast<long long>(t0.IterationsMaxColumn));
        }
        if (t0.Failures)
        {
          std::snprintf(notes + std::strlen(notes), sizeof notes - std::strlen(notes),
            " FAILED solves: %d", t0.Failures);
        }
        const double mvPerIt = methods[m].Name.compare(0, 9, "Chebyshev") == 0
          ? std::atof(methods[m].ProductsText.c_str())
          : 1.0;
        std::printf("  %-33s %7.0f %7.1f %8.3f %8.3f %8.3f %8.3f %9.3f %9s %8.1f %7.1f %9.3f %s\n",
          methods[m].Name.c_str(), iters, iters / std::max(1, t0.Solves), MedianOf(setup),
          MedianOf(solve), MedianOf(copy), MedianOf(total), iters > 0 ? 1e3 * MedianOf(solve) / iters : 0.0,
          methods[m].ProductsText.c_str(),
          methods[m].Name.compare(0, 3, "AMG") == 0 ? iters / std::max(1, t0.Solves)
                                                    : mvPerIt * iters / std::max(1, t0.Solves),
          t0.BytesPerRow, t0.WorstResidual, notes);
      }
      (void)icRef;
      std::printf("  (max res: worst true ||b - A x|| / ||b|| over the solves, in units of the "
                  "tolerance; B/row: bytes per row the preconditioner holds beyond the matrix "
                  "and the CG vectors)\n");
    }
    std::fflush(stdout);
  }
  {
    const std::time_t now = std::time(nullptr);
    char when[64];
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S %Z", std::localtime(&now));
    std::printf("\nend %s, loadavg %s\n", when, FirstLine("/proc/loadavg").c_str());
  }
#ifdef DG_HAVE_HYPRE
  HYPRE_Finalize();
  MPI_Finalize();
#endif
  return 0;
}
