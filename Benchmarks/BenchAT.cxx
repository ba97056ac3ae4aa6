// Speed of the Ambrosio-Tortorelli core (dgATOperators + dgATSolver) with the
// paper's parameters (alpha 0.1, lambda 0.01, eps 2 -> 0.25 by 2, at most 5
// iterations per level): octa-flower 512^3 (when ../shared is present) and
// synthetic shapes (ball, rotated cube) from 64^3 to 256^3.
//
// Input field: the trivial normals smoothed by 10 passes of face-neighbour
// averaging (a cheap stand-in for the II normals, smooth but with blurred
// edges, as the II field is). Prints, per linear solver, the time of each
// phase (complex/patterns, assembly, analysis, factorisation, solves),
// iterations, CG iterations, peak memory (getrusage), the median over runs,
// and the largest difference in u and v to the SimplicialLDLT reference.
//
// Usage: BenchAT [runs] [max size: 64..256 synthetic, 512 adds octa-flower,
//                "flower" for octa-flower only]
//                [solvers: ldlt,cg,ic,cholmod]; env DG_CG_TOLERANCE overrides 1e-8.
#include "dgATOperators.h"
#include "dgATSolver.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double PeakMemoryMiB()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

vtkSmartPointer<vtkImageData> Shape(int n, bool cube)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, n);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars())->GetPointer(0);
  const double c = 0.5 * (n - 1) + 0.1, r = 0.4 * n, h = 0.3 * n;
  // Rotation by 20, 30, 10 degrees about x, y, z (R = Rz Ry Rx); a point is
  // in the cube when |R^T (p - c)|_inf <= h.
  const double ax = 20 * M_PI / 180, ay = 30 * M_PI / 180, az = 10 * M_PI / 180;
  const double cx = std::cos(ax), sx = std::sin(ax), cy = std::cos(ay), sy = std::sin(ay),
               cz = std::cos(az), sz = std::sin(az);
  const double R[3][3] = { { cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx },
    { sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx }, { -sy, cy * sx, cy * cx } };
  vtkSMPTools::For(0, n, [&](vtkIdType kb, vtkIdType ke) {
    for (vtkIdType k = kb; k < ke; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
        {
          const double p[3] = { i - c, j - c, k - c };
          bool in;
          if (cube)
          {
            in = true;
            for (int a = 0; a < 3; ++a)
            {
              const double q = R[0][a] * p[0] + R[1][a] * p[1] + R[2][a] * p[2];
              in = in && std::abs(q) <= h;
            }
          }
          else
          {
            in = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= r * r;
          }
          v[(k * n + j) * n + i] = in;
        }
  });
  return image;
}

struct Result
{
  dg::ATStatistics Stats;
  double Complex = 0, Total = 0;
  Eigen::MatrixXd U;
  Eigen::VectorXd V;
};

void Bench(const std::string& name, vtkImageData* image, int runs,
  const std::vector<dg::ATLinearSolver>& solvers)
{
  vtkNew<vtkDigitalSurfaceFilter> surf;
  surf->SetInputData(image);
  surf->Update();
  vtkPolyData* pd = surf->GetOutput();
  const vtkIdType nf = pd->GetNumberOfPolys();
  std::vector<std::int64_t> offsets(nf + 1), conn(pd->GetPolys()->GetNumberOfConnectivityIds());
  {
    const auto o = vtk::DataArrayValueRange<1>(pd->GetPolys()->GetOffsetsArray());
    const auto c = vtk::DataArrayValueRange<1>(pd->GetPolys()->GetConnectivityArray());
    std::copy(o.begin(), o.end(), offsets.begin());
    std::copy(c.begin(), c.end(), conn.begin());
  }
  // Complex once to smooth the field.
  dg::ATComplex k0;
  k0.Build(pd->GetNumberOfPoints(), offsets, conn);
  Eigen::MatrixXd g(nf, 3);
  vtkDataArray* n = pd->GetCellData()->GetNormals();
  for (vtkIdType f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c)
      g(f, c) = n->GetComponent(f, c);
  for (int pass = 0; pass < 10; ++pass)
  {
    Eigen::MatrixXd s = g;
    for (std::int64_t e = 0; e < k0.NumberOfEdges(); ++e)
    {
      for (auto i = k0.EdgeFacePtr[e]; i < k0.EdgeFacePtr[e + 1]; ++i)
        for (auto j = k0.EdgeFacePtr[e]; j < k0.EdgeFacePtr[e + 1]; ++j)
          if (i != j)
          {
            s.row(k0.EdgeFaces[i]) += g.row(k0.EdgeFaces[j]);
          }
    }
    g = s.rowwise().normalized();
  }
  std::printf("\n%s: %lld faces, %lld edges, %lld vertices\n", name.c_str(),
    static_cast<long long>(nf), static_cast<long long>(k0.NumberOfEdges()),
    static_cast<long long>(k0.NumberOfVertices()));
  std::printf("  %-18s %7s %7s %7s %7s %7s %7s %5s %11s %9s %9s %7s\n", "solver", "total",
    "complex", "assem", "analys", "factor", "solve", "iters", "CGits(u)", "s/iter", "max|du|",
    "max|dv|");
  Result reference;
  bool haveReference = false;
  for (auto solver : solvers)
  {
    if (solver == dg::ATLinearSolver::Cholmod && !dg::CholmodAvailable())
    {
      continue;
    }
    std::vector<Result> results;
    for (int r = 0; r < runs; ++r)
    {
      Result res;
      auto t0 = Clock::now();
      dg::ATComplex k;
      k.Build(pd->GetNumberOfPoints(), offsets, conn);
      res.Complex = Seconds(t0);
      dg::ATParameters p;
      p.Solver = solver;
      if (const char* tol = std::getenv("DG_CG_TOLERANCE"))
      {
        p.CGTolerance = std::atof(tol);
      }
      dg::ATSolver s(k, p);
      s.Run(g);
      res.Total = Seconds(t0);
      res.Stats = s.Statistics();
      if (r == 0)
      {
        res.U = s.U();
        res.V = s.V();
      }
      results.push_back(std::move(res));
    }
    std::vector<std::size_t> order(results.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      order[i] = i;
    std::sort(order.begin(), order.end(),
      [&](std::size_t a, std::size_t b) { return results[a].Total < results[b].Total; });
    const Result& med = results[order[order.size() / 2]];
    const Result& first = results[0];
    double du = 0, dv = 0;
    if (solver == dg::ATLinearSolver::SimplicialLDLT)
    {
      reference = first;
      haveReference = true;
    }
    else if (haveReference)
    {
      du = (first.U - reference.U).cwiseAbs().maxCoeff();
      dv = (first.V - reference.V).cwiseAbs().maxCoeff();
    }
    const auto& st = med.Stats;
    std::printf("  %-18s %7.3f %7.3f %7.3f %7.3f %7.3f %7.3f %5d %5lld(%4lld) %9.4f %9.2e %7.2e\n",
      dg::ATLinearSolverName(solver), med.Total, med.Complex, st.Assembly, st.Analysis,
      st.Factorization, st.Solve, st.Iterations, static_cast<long long>(st.CGIterations),
      static_cast<long long>(st.CGIterationsU),
      (med.Total - med.Complex) / std::max(1, st.Iterations), du, dv);
    std::fflush(stdout);
  }
  std::printf("  peak memory so far %.0f MiB\n", PeakMemoryMiB());
}
} // namespace

int main(int argc, char* argv[])
{
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  // "flower" runs octa-flower only.
  const bool flowerOnly = argc > 2 && std::string(argv[2]) == "flower";
  const int maxSize = flowerOnly ? 512 : (argc > 2 ? std::atoi(argv[2]) : 256);
  std::vector<dg::ATLinearSolver> solvers;
  const std::string which = argc > 3 ? argv[3] : "ldlt,cg,cholmod";
  for (std::size_t b = 0; b <= which.size();)
  {
    std::size_t e = which.find(',', b);
    e = e == std::string::npos ? which.size() : e;
    const std::string w = which.substr(b, e - b);
    b = e + 1;
    if (w == "ldlt")
      solvers.push_back(dg::ATLinearSolver::SimplicialLDLT);
    else if (w == "cg")
      solvers.push_back(dg::ATLinearSolver::ConjugateGradient);
    else if (w == "ic")
      solvers.push_back(dg::ATLinearSolver::ConjugateGradientIC);
    else if (w == "cholmod")
      solvers.push_back(dg::ATLinearSolver::Cholmod);
    else if (!w.empty())
    {
      std::fprintf(stderr, "unknown solver '%s' (ldlt, cg, ic, cholmod)\n", w.c_str());
      return 2;
    }
  }
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread");
  }
  std::printf("vtkSMPTools backend %s, %d threads, %d runs each (median), CHOLMOD %s\n",
    vtkSMPTools::GetBackend(), vtkSMPTools::GetEstimatedNumberOfThreads(), runs,
    dg::CholmodAvailable() ? "available" : "absent");
  std::printf("max|du|, max|dv|: largest difference to the SimplicialLDLT run (when run)\n");
  for (int n = 64; !flowerOnly && n <= std::min(maxSize, 256); n *= 2)
  {
    Bench("ball r=0.4n " + std::to_string(n) + "^3", Shape(n, false), runs, solvers);
    Bench("rotated cube " + std::to_string(n) + "^3", Shape(n, true), runs, solvers);
  }
  const std::string flower = std::string(DG_SHARED_DATA_DIR) + "/octa-flower17k-512.vol";
  if (maxSize < 512)
  {
    std::printf("(octa-flower skipped: give a max size of 512 to run it)\n");
  }
  else if (std::ifstream(flower).good())
  {
    vtkNew<vtkDGtalVolReader> reader;
    reader->SetFileName(flower.c_str());
    reader->Update();
    Bench("octa-flower17k-512", reader->GetOutput(), runs, solvers);
  }
  else
  {
    std::printf("(octa-flower17k-512.vol absent: ../shared not found)\n");
  }
  return 0;
}
