// Speed of the Ambrosio-Tortorelli stage on the real pipeline's input (issue
// 16): a .vol volume -> vtkDigitalSurfaceFilter -> vtkIINormalEstimator
// (r = 3) -> the AT core (ATComplex + ATSolver, built from the II output
// exactly as vtkAmbrosioTortorelliFilter::RequestData does), default solver
// (ConjugateGradientIC), the paper's parameters (the ATParameters defaults)
// or, with --dgtal, DGtal's (at most 10 iterations per level, tolerance
// 1e-4). Prints per volume the phases' times, the CG iterations per solve,
// the bytes streamed per CG iteration (from the data structures), the floor
// set by a STREAM triad measured in the same process, and memory. BenchAT
// keeps the synthetic stand-in input and the solver comparison.
//
// Usage: BenchATPipeline [runs] [volumes...] [--dgtal] [--check] [--exact]
//                        [--tolerance T] [--vfactor F] [--early F] [--double] [--dv]
//                        [--dump PREFIX] [--no-triad]
//   --exact compares the first run with SimplicialLDLT on the same schedule
//   (the accuracy budget); --tolerance sets the CG tolerance (default: the
//   ATParameters default), --vfactor the v-system's multiple of it, --early
//   the multiple on every level but the last (CGToleranceEarlyFactor); --double keeps CG's r, p, q, z in double
//   (ATParameters::CGSinglePrecision off); --dv prints, for the first run,
//   every step's CG iterations and max |v - v_prev| (the stopping rule's test).
//   A volume is a name in the shared volgallery (fandisk-128) or a path,
//   with "x2" appended for the volume upsampled 2x (octa-flower17k-512x2:
//   1024^3); with 3 volumes or more, the growth exponent with the surface is
//   fitted;
//   default fandisk-128, fandisk-256, octa-flower17k-512. --check also runs
//   vtkAmbrosioTortorelliFilter on the same II output and compares its
//   NumberOfIterations, u and v with the core's. --dump writes the first
//   run's u and v (raw doubles, column major) to PREFIX-<volume>.u and .v, to
//   compare two builds bitwise (cmp); --no-triad skips the STREAM triad.
#include "dgATOperators.h"
#include "dgBenchMachine.h"
#include "dgATSolver.h"
#include "dgHugePages.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

using dgbench::CpuModel;
using dgbench::FirstLine;
using dgbench::MedianOf;

namespace
{
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
} // namespace

namespace
{


// A "Key:   123 kB" line of /proc/self/status, in MiB (-1 when absent).
double StatusMiB(const char* key)
{
  std::ifstream f("/proc/self/status");
  const std::string k = std::string(key) + ":";
  for (std::string line; std::getline(f, line);)
  {
    if (line.compare(0, k.size(), k) == 0)
    {
      return std::atof(line.c_str() + k.size()) / 1024.0;
    }
  }
  return -1;
}

// Resets VmHWM (the peak RSS) to the current RSS (Linux >= 4.0), so that the
// peak of one phase can be read; getrusage's ru_maxrss cannot be reset.
bool ResetPeakRss()
{
  std::ofstream f("/proc/self/clear_refs");
  f << "5" << std::flush;
  return f.good();
}


// STREAM triad a[i] = b[i] + s c[i] on 3 arrays of n doubles, with
// vtkSMPTools over the same backend and thread count as the core (and the
// core's task size, 16 blocks of 2048 rows); bytes counted as STREAM does
// (24 per element: 2 reads, 1 write; no write-allocate). Best of reps, GB/s.
double TriadGBs(std::int64_t n, int reps, double* median)
{
  std::unique_ptr<double[]> a(new double[n]), b(new double[n]), c(new double[n]);
  constexpr std::int64_t grain = 16 * 2048;
  vtkSMPTools::For(0, n, grain, [&](std::int64_t i0, std::int64_t i1) {
    for (std::int64_t i = i0; i < i1; ++i)
    {
      a[i] = 0.0;
      b[i] = 1.0 + 1e-9 * i;
      c[i] = 2.0;
    }
  });
  const double s = 3.0;
  std::vector<double> t;
  for (int r = 0; r < reps; ++r)
  {
    const auto t0 = Clock::now();
    vtkSMPTools::For(0, n, grain, [&](std::int64_t i0, std::int64_t i1) {
      double* __restrict pa = a.get();
      const double* __restrict pb = b.get();
      const double* __restrict pc = c.get();
      for (std::int64_t i = i0; i < i1; ++i)
      {
        pa[i] = pb[i] + s * pc[i];
      }
    });
    t.push_back(Seconds(t0));
  }
  volatile double sink = a[n / 2];
  (void)sink;
  const double bytes = 24.0 * static_cast<double>(n);
  *median = bytes / MedianOf(t) / 1e9;
  return bytes / *std::min_element(t.begin(), t.end()) / 1e9;
}

// Strictly lower entries of ICSystem's IC(0) factor: the matrix's lower
// triangle inside the fixed row blocks of ICSystem::Analyze. The block rule
// (constants ICMinBlockRows 16384, ICMaxBlockRows 65536, ICTargetBlocks 8)
// is copied from dgATSolver.cxx: keep the two in step.
std::int64_t ICLowerEntries(const dg::ATSystemMatrix& m, std::int64_t* blocks)
{
  const std::int64_t n = m.cols();
  const std::int64_t rows = std::clamp<std::int64_t>(n / 8, 16384, 65536);
  const std::int64_t nBlocks = std::max<std::int64_t>(1, n / rows);
  *blocks = nBlocks;
  const int* outer = m.outerIndexPtr();
  const int* inner = m.innerIndexPtr();
  std::int64_t count = 0;
  for (std::int64_t i = 0, blk = 0; i < n; ++i)
  {
    blk += i == (blk + 1) * n / nBlocks;
    const std::int64_t lo = blk * n / nBlocks;
    for (int k = outer[i]; k < outer[i + 1]; ++k)
    {
      count += inner[k] >= lo && inner[k] < i;
    }
  }
  return count;
}

// Bytes streamed by one CG iteration of ICSystem (dgATSolver.cxx) on a
// system of n rows, nnz stored non-zeros (both triangles), nL factor entries
// below the diagonal and nc right-hand sides. One iteration is two passes
// over memory: UpdateAndPrecondition (x += a p, r -= a q, then per IC block
// the forward and backward sweeps z = (C C^T)^-1 r) and NextDirection
// (w = A z, p = z + b p, q = w + b q). Every array is counted once per pass
// it is read in and once per pass it is written in (a floor: the backward
// sweep's re-read of z and the gathers of neighbours' z are taken as cache
// hits; writes are counted without write-allocate, as STREAM counts them):
//   vectors  nc n (8 (1 + 1) + s (3 + 2 + 5)), s the bytes of r, p, q, z
//            (4 in float, the default; 8 with --double), x in double:
//            pass 1 reads x r p q, writes x r z; pass 2 reads z p q,
//            writes p q;
//   matrix   12 nnz + 4 (n + 1): double values, int row indices, int column
//            starts (stored full, column major = row major by symmetry);
//   factor   8 nL + 4 (n + 1) + 4 n: float values and int columns of C's
//            lower triangle (read by both sweeps, the backward one by
//            columns), int row starts, float 1 / C_ii.
// B = (16 + 10 s) nc n + 12 nnz + 4 (n + 1) + 8 nL + 4 (n + 1) + 4 n
//   (56 nc n for the vectors in float, 96 nc n in double).
// Per solve, outside B: r = b - A x (matrix, x read, r read and written),
// the first preconditioning (r read, z written, the factor), Interleave and
// Deinterleave of x (4 nc n doubles); the first NextDirection takes
// the place of the one the last iteration skips:
// S = 12 nnz + 4 (n + 1) + 8 nL + 4 (n + 1) + 4 n + nc n (8 (2 + 4) + 3 s)
//   (x and b read, r written; r read, z written; x interleaved and back).
struct SystemBytes
{
  std::int64_t N = 0, Nnz = 0, NL = 0, Blocks = 0;
  int NC = 0;
  double PerIteration = 0, PerSolveSetup = 0;
  void Set(const dg::ATSystemMatrix& m, int nc, int s)
  {
    this->N = m.cols();
    this->Nnz = m.nonZeros();
    this->NL = ICLowerEntries(m, &this->Blocks);
    this->NC = nc;
    const double n = static_cast<double>(this->N), nnz = static_cast<double>(this->Nnz),
                 nl = static_cast<double>(this->NL);
    const double matrix = 12 * nnz + 4 * (n + 1);
    const double factor = 8 * nl + 4 * (n + 1) + 4 * n;
    this->PerIteration = (16.0 + 10.0 * s) * nc * n + matrix + factor;
    this->PerSolveSetup = matrix + factor + (48.0 + 3.0 * s) * nc * n;
  }
};

vtkSmartPointer<vtkImageData> Upsampled(vtkImageData* in, int f)
{
  int d[3];
  in->GetDimensions(d);
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->SetDimensions(d[0] * f, d[1] * f, d[2] * f);
  out->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  const auto* src = static_cast<const unsigned char*>(in->GetScalarPointer());
  auto* dst = static_cast<unsigned char*>(out->GetScalarPointer());
  const std::int64_t nx = d[0] * f, ny = d[1] * f, nz = d[2] * f;
  vtkSMPTools::For(0, nz, [&](std::int64_t k0, std::int64_t k1) {
    for (std::int64_t k = k0; k < k1; ++k)
      for (std::int64_t j = 0; j < ny; ++j)
        for (std::int64_t i = 0; i < nx; ++i)
        {
          dst[(k * ny + j) * nx + i] =
            src[((k / f) * d[1] + j / f) * static_cast<std::int64_t>(d[0]) + i / f];
        }
  });
  return out;
}

// Least-squares slope of log(y) against log(x): the growth exponent.
double Exponent(const std::vector<double>& x, const std::vector<double>& y)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
  {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

double CpuSeconds()
{
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

struct RealRun
{
  double Surface = 0, II = 0, Prep = 0, Complex = 0, Run = 0, AT = 0;
  double ATCpu = 0; // user + system seconds of all threads during AT
  dg::ATStatistics Stats;
  std::vector<std::int64_t> ItU, ItV; // CG iterations of each u and v solve
  double RssBefore = 0, PeakDuring = 0; // MiB
};

struct VolumeResult
{
  std::string Name;
  std::int64_t Faces = 0, Edges = 0, Vertices = 0;
  std::vector<RealRun> Runs;
  SystemBytes U, V;
  double ProcessPeak = 0;
  bool Deterministic = true;
  dg::ATMemoryParts Memory; // what the core holds at the end of the first run
  std::size_t InputCopy = 0; // g, the field as the filter hands it over (0: taken by the solver)
};

void MinMax(const std::vector<std::int64_t>& v, std::int64_t& total, std::int64_t& lo,
  std::int64_t& hi)
{
  total = 0;
  lo = v.empty() ? 0 : v[0];
  hi = lo;
  for (auto x : v)
  {
    total += x;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
}

std::string CGText(const std::vector<std::int64_t>& v)
{
  std::int64_t t, lo, hi;
  MinMax(v, t, lo, hi);
  char buf[96];
  std::snprintf(buf, sizeof buf, "%5lld/%-3zu=%6.1f [%lld..%lld]", static_cast<long long>(t),
    v.size(), v.empty() ? 0.0 : static_cast<double>(t) / v.size(), static_cast<long long>(lo),
    static_cast<long long>(hi));
  return buf;
}
} // namespace

int main(int argc, char* argv[])
{
  int runs = 3;
  bool dgtal = false, check = false, exact = false, doublePrecision = false, printDv = false;
  bool triadWanted = true;
  double cgTolerance = 0, vFactor = 0, earlyFactor = 0;
  std::string dumpPrefix;
  std::vector<std::string> volumes;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--dgtal")
      dgtal = true;
    else if (a == "--check")
      check = true;
    else if (a == "--exact")
      exact = true;
    else if (a == "--tolerance" && i + 1 < argc)
      cgTolerance = std::atof(argv[++i]);
    else if (a == "--double")
      doublePrecision = true;
    else if (a == "--dv")
      printDv = true;
    else if (a == "--no-triad")
      triadWanted = false;
    else if (a == "--dump" && i + 1 < argc)
      dumpPrefix = argv[++i];
    else if (a == "--vfactor" && i + 1 < argc)
      vFactor = std::atof(argv[++i]);
    else if (a == "--early" && i + 1 < argc)
      earlyFactor = std::atof(argv[++i]);
    else if (i == 1 && !a.empty() && std::isdigit(static_cast<unsigned char>(a[0])))
      runs = std::max(1, std::atoi(a.c_str()));
    else
      volumes.push_back(a);
  }
  if (volumes.empty())
  {
    volumes = { "fandisk-128", "fandisk-256", "octa-flower17k-512" };
  }
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread");
  }
  dg::ATParameters params; // the paper's: alpha 0.1, lambda 0.01, eps 2 -> 0.25 by 2, <= 5
  if (dgtal)
  {
    params.MaximumIterations = 10; // DGtal's at-u2-v0 settings
    params.Tolerance = 1e-4;
  }
  if (cgTolerance > 0)
  {
    params.CGTolerance = cgTolerance;
  }
  params.CGSinglePrecision = !doublePrecision;
  if (earlyFactor > 0)
  {
    params.CGToleranceEarlyFactor = earlyFactor;
  }
  if (vFactor > 0)
  {
    params.CGToleranceVFactor = vFactor;
  }
  // As vtkAmbrosioTortorelliFilter::RequestData: it normalises the outputs,
  // not the core's u.
  params.Normalize = false;

  char host[256] = "?";
  gethostname(host, sizeof host - 1);
  const char* env = std::getenv("VTK_SMP_BACKEND_IN_USE");
  std::printf("BenchATPipeline: %d runs each (medians), %s parameters: alpha %g, lambda %g, "
              "eps %g -> %g by %g, <= %d iterations per level, tolerance %g, solver %s, "
              "CG tolerance %g (v: x %g; levels before the last: x %g), %s precision\n",
    runs, dgtal ? "DGtal's" : "the paper's", params.Alpha, params.Lambda, params.EpsilonStart,
    params.EpsilonEnd, params.EpsilonRatio, params.MaximumIterations, params.Tolerance,
    dg::ATLinearSolverName(params.Solver), params.CGTolerance, params.CGToleranceVFactor,
    params.CGToleranceEarlyFactor, params.CGSinglePrecision ? "single" : "double");
  std::printf("machine: %s, nproc %ld, CPU %s\n", host, sysconf(_SC_NPROCESSORS_ONLN),
    CpuModel().c_str());
  std::printf("VTK_SMP_BACKEND_IN_USE=%s, vtkSMPTools backend %s, %d threads\n",
    env ? env : "(unset)", vtkSMPTools::GetBackend(), vtkSMPTools::GetEstimatedNumberOfThreads());
  {
    // The program runs with glibc's huge-page malloc (dgProgramSupport.h);
    // a library host runs with what it was started with.
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    std::printf("malloc: %s (GLIBC_TUNABLES=%s)\n",
      tunables && std::strstr(tunables, "glibc.malloc.hugetlb=1")
        ? "glibc huge pages, as the program runs"
        : "default 4 KiB pages (large AT arrays advised for huge pages), as a library host runs",
      tunables ? tunables : "(unset)");
  }
  {
    const std::time_t now = std::time(nullptr);
    char when[64];
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S %Z", std::localtime(&now));
    std::printf("start %s, loadavg %s\n", when, FirstLine("/proc/loadavg").c_str());
  }
  std::printf("pipeline per run: vtkDigitalSurfaceFilter, vtkIINormalEstimator r = 3 (voxels), "
              "then the AT core as vtkAmbrosioTortorelliFilter::RequestData builds it\n"
              "(prep = field and polygon buffers, complex = ATComplex::Build, then "
              "ATSolver::Run: assem/analys/factor/solve from ATStatistics).\n");
  std::fflush(stdout);

  std::vector<VolumeResult> results;
  for (const std::string& volume : volumes)
  {
    // "NAMEx2": the volume upsampled 2x in each direction (each voxel becomes
    // 2 x 2 x 2), for surfaces larger than the gallery's (octa-flower 1024^3).
    int upsample = 1;
    std::string base = volume;
    if (base.size() > 2 && base.compare(base.size() - 2, 2, "x2") == 0)
    {
      upsample = 2;
      base = base.substr(0, base.size() - 2);
    }
    const std::string path = base.find('/') != std::string::npos ||
        (base.size() > 4 && base.compare(base.size() - 4, 4, ".vol") == 0)
      ? base
      : std::string(DG_SHARED_DATA_DIR) + "/" + base + ".vol";
    if (!std::ifstream(path).good())
    {
      std::printf("\n%s: %s not found, skipped\n", volume.c_str(), path.c_str());
      continue;
    }
    VolumeResult vr;
    vr.Name = volume;
    vtkNew<vtkDGtalVolReader> reader;
    reader->SetFileName(path.c_str());
    auto t0 = Clock::now();
    reader->Update();
    const double tRead = Seconds(t0);
    vtkSmartPointer<vtkImageData> image = reader->GetOutput();
    if (upsample > 1)
    {
      image = Upsampled(reader->GetOutput(), upsample);
    }
    int dims[3];
    image->GetDimensions(dims);
    vtkSmartPointer<vtkPolyData> lastII;
    Eigen::MatrixXd firstU;
    Eigen::VectorXd firstV;
    bool hwm = true;
    std::printf("\n== %s (%dx%dx%d, read %.2f s)\n", volume.c_str(), dims[0], dims[1], dims[2],
      tRead);
    std::printf("  %3s %7s %7s | %6s %7s %6s %6s %6s %7s %7s | %5s %-34s %-34s | %8s %8s %7s\n",
      "run", "surface", "II", "prep", "complex", "assem", "analys", "factor", "solve", "AT",
      "iters", "CG u: total/solves=mean [min..max]", "CG v: same", "RSS MiB", "AT+ MiB", "B/surfel");
    for (int r = 0; r < runs; ++r)
    {
      RealRun run;
      vtkNew<vtkDigitalSurfaceFilter> surface;
      surface->SetInputData(image);
      t0 = Clock::now();
      surface->Update();
      run.Surface = Seconds(t0);
      vtkNew<vtkIINormalEstimator> ii;
      ii->SetInputConnection(surface->GetOutputPort());
      ii->SetSourceData(image);
      ii->SetRadius(3);
      t0 = Clock::now();
      ii->Update();
      run.II = Seconds(t0);
      vtkPolyData* input = ii->GetOutput();

      // The AT core, as vtkAmbrosioTortorelliFilter::RequestData and
      // Internals::Solve build it (the field: the active cell normals,
      // "IINormals", unit, so no scaling; the filter's diagnostics of the
      // complex - interior/boundary/coincident edges - are left out).
      // Free heap pages go back to the system first: else the RSS before AT
      // would include what the previous run freed, and AT reuse it unseen.
      malloc_trim(0);
      run.RssBefore = StatusMiB("VmRSS");
      hwm = hwm && ResetPeakRss();
      const double cpu0 = CpuSeconds();
      t0 = Clock::now();
      vtkCellArray* polys = input->GetPolys();
      const vtkIdType nFaces = polys->GetNumberOfCells();
      const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
      vtkDataArray* field = input->GetCellData()->GetNormals();
      const int nc = field->GetNumberOfComponents();
      Eigen::MatrixXd g(nFaces, nc);
      dg::AdviseHugePages(g.data(), static_cast<std::size_t>(g.size()) * sizeof(double)); // before first touch
      {
        const auto tuples = vtk::DataArrayTupleRange(field);
        vtkSMPTools::For(0, nFaces, [&](vtkIdType b, vtkIdType e) {
          for (vtkIdType f = b; f < e; ++f)
          {
            const auto t = tuples[polyOffset + f];
            for (int c = 0; c < nc; ++c)
            {
              g(f, c) = static_cast<double>(t[c]);
            }
          }
        });
      }
      std::vector<std::int64_t> offsets, connectivity;
      dg::AssignHuge(offsets, static_cast<std::size_t>(nFaces + 1), std::int64_t(0));
      dg::AssignHuge(connectivity, static_cast<std::size_t>(polys->GetNumberOfConnectivityIds()), std::int64_t(0));
      {
        const auto off = vtk::DataArrayValueRange<1>(polys->GetOffsetsArray());
        const auto conn = vtk::DataArrayValueRange<1>(polys->GetConnectivityArray());
        vtkSMPTools::For(0, nFaces + 1, [&](vtkIdType b, vtkIdType e) {
          for (vtkIdType i = b; i < e; ++i)
          {
            offsets[i] = static_cast<std::int64_t>(off[i]);
          }
        });
        vtkSMPTools::For(0, static_cast<vtkIdType>(connectivity.size()),
          [&](vtkIdType b, vtkIdType e) {
            for (vtkIdType i = b; i < e; ++i)
            {
              connectivity[i] = static_cast<std::int64_t>(conn[i]);
            }
          });
      }
      run.Prep = Seconds(t0);
      t0 = Clock::now();
      dg::ATComplex complex;
      std::string error;
      if (!complex.Build(input->GetNumberOfPoints(), offsets, connectivity, &error))
      {
        std::printf("cannot build the complex: %s\n", error.c_str());
        return 1;
      }
      offsets = std::vector<std::int64_t>();
      connectivity = std::vector<std::int64_t>();
      run.Complex = Seconds(t0);
      // As the filter does, unless the exact run needs the patterns later.
      std::unique_ptr<dg::ATSolver> solverPtr(exact ? new dg::ATSolver(complex, params)
                                                    : new dg::ATSolver(complex, params, dg::ATSolver::TakePatterns));
      dg::ATSolver& solver = *solverPtr;
      // Run calls the progress callback after every u-step + v-step pair:
      // the counters' differences are the CG iterations of that u solve and
      // of that v solve (the core is not changed for this).
      std::int64_t seenU = 0, seenV = 0;
      Eigen::VectorXd vSeen = Eigen::VectorXd::Ones(complex.NumberOfVertices());
      t0 = Clock::now();
      // As the filter, the solver takes g, unless the exact run needs it.
      const auto progress = [&](double) {
        const dg::ATStatistics& st = solver.Statistics();
        const std::int64_t u = st.CGIterationsU, v = st.CGIterations - st.CGIterationsU;
        if (printDv && r == 0)
        {
          // What the per-level stopping rule (ATParameters::Tolerance) sees.
          std::printf("  step %zu: CG u %lld, v %lld, max |v - v_prev| %.3e\n", run.ItU.size() + 1,
            static_cast<long long>(u - seenU), static_cast<long long>(v - seenV),
            (solver.V() - vSeen).lpNorm<Eigen::Infinity>());
          vSeen = solver.V();
        }
        run.ItU.push_back(u - seenU);
        run.ItV.push_back(v - seenV);
        seenU = u;
        seenV = v;
        return true;
      };
      // As the filter: the right-hand sides read g in the II output array.
      if (vtkDoubleArray* doubles = vtkDoubleArray::FastDownCast(field))
      {
        solver.SetFieldSource(doubles->GetPointer(polyOffset * nc), nc, 1);
      }
      const bool ok = exact ? solver.Run(g, progress) : solver.Run(std::move(g), progress);
      run.Run = Seconds(t0);
      run.AT = run.Prep + run.Complex + run.Run;
      run.ATCpu = CpuSeconds() - cpu0;
      {
        rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        run.PeakDuring = hwm ? StatusMiB("VmHWM") : ru.ru_maxrss / 1024.0;
      }
      if (!ok)
      {
        std::printf("ATSolver::Run failed: %s\n", solver.Error().c_str());
        return 1;
      }
      run.Stats = solver.Statistics();
      if (r == 0)
      {
        vr.Faces = complex.NumberOfFaces();
        vr.Edges = complex.NumberOfEdges();
        vr.Vertices = complex.NumberOfVertices();
        const int s = params.CGSinglePrecision ? 4 : 8;
        vr.U.Set(solver.UMatrix(), nc, s);
        vr.V.Set(solver.VMatrix(), 1, s);
        complex.Memory(vr.Memory);
        solver.Memory(vr.Memory);
        vr.InputCopy = static_cast<std::size_t>(g.size()) * sizeof(double);
        firstU = solver.U();
        firstV = solver.V();
        if (!dumpPrefix.empty())
        {
          const std::string base = dumpPrefix + "-" + volume;
          std::ofstream(base + ".u", std::ios::binary)
            .write(reinterpret_cast<const char*>(firstU.data()),
              static_cast<std::streamsize>(firstU.size() * sizeof(double)));
          std::ofstream(base + ".v", std::ios::binary)
            .write(reinterpret_cast<const char*>(firstV.data()),
              static_cast<std::streamsize>(firstV.size() * sizeof(double)));
        }
        if (exact)
        {
          // The accuracy budget against the exact solver, same schedule.
          dg::ATParameters ep = params;
          ep.Solver = dg::ATLinearSolver::SimplicialLDLT;
          dg::ATSolver ex(complex, ep);
          const auto te = Clock::now();
          ex.Run(g);
          const double exactSeconds = Seconds(te);
          std::vector<double> angles(firstU.rows());
          for (Eigen::Index f = 0; f < firstU.rows(); ++f)
          {
            const Eigen::VectorXd a = firstU.row(f).normalized(), b = ex.U().row(f).normalized();
            angles[f] = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180.0 / M_PI;
          }
          std::sort(angles.begin(), angles.end());
          const double dv = (firstV - ex.V()).lpNorm<Eigen::Infinity>();
          std::int64_t edgesExact = 0, edgesDiffer = 0;
          for (std::int64_t e = 0; e < complex.NumberOfEdges(); ++e)
          {
            const int a = complex.EdgeVertices[2 * e], b = complex.EdgeVertices[2 * e + 1];
            const bool fe = firstV[a] < 0.5 && firstV[b] < 0.5;
            const bool ee = ex.V()[a] < 0.5 && ex.V()[b] < 0.5;
            edgesExact += ee;
            edgesDiffer += fe != ee;
          }
          std::printf("  against SimplicialLDLT (%.1f s): normals p99.9 %.3g deg (max %.3g), max "
                      "|dv| %.3g, feature edges %lld exact, %lld differ (%.3f %%); budget 0.05 "
                      "deg, 1e-3, 0.5 %%: %s\n",
            exactSeconds, angles[static_cast<std::size_t>(0.999 * (angles.size() - 1))],
            angles.back(), dv, static_cast<long long>(edgesExact),
            static_cast<long long>(edgesDiffer), 100.0 * edgesDiffer / std::max<std::int64_t>(1, edgesExact),
            angles[static_cast<std::size_t>(0.999 * (angles.size() - 1))] < 0.05 && dv < 1e-3 &&
                edgesDiffer <= 0.005 * edgesExact
              ? "within"
              : "OUTSIDE");
        }
      }
      else
      {
        vr.Deterministic = vr.Deterministic && solver.U() == firstU && solver.V() == firstV &&
          run.ItU == vr.Runs[0].ItU && run.ItV == vr.Runs[0].ItV;
      }
      lastII = input;
      const auto& st = run.Stats;
      const double extra = run.PeakDuring - run.RssBefore;
      std::printf("  %3d %7.3f %7.3f | %6.3f %7.3f %6.3f %6.3f %6.3f %7.3f %7.3f | %5d %-34s "
                  "%-34s | %8.0f %8.1f %7.0f%s\n",
        r + 1, run.Surface, run.II, run.Prep, run.Complex, st.Assembly, st.Analysis,
        st.Factorization, st.Solve, run.AT, st.Iterations, CGText(run.ItU).c_str(),
        CGText(run.ItV).c_str(), run.RssBefore, extra,
        extra * 1048576.0 / static_cast<double>(vr.Faces), st.FailedSolves ? " FAILED SOLVES" : "");
      std::fflush(stdout);
      vr.Runs.push_back(std::move(run));
    }
    auto med = [&](double RealRun::*m) {
      std::vector<double> v;
      for (const auto& x : vr.Runs)
        v.push_back(x.*m);
      return MedianOf(v);
    };
    auto medS = [&](double dg::ATStatistics::*m) {
      std::vector<double> v;
      for (const auto& x : vr.Runs)
        v.push_back(x.Stats.*m);
      return MedianOf(v);
    };
    const double medExtra = [&] {
      std::vector<double> v;
      for (const auto& x : vr.Runs)
        v.push_back(x.PeakDuring - x.RssBefore);
      return MedianOf(v);
    }();
    const RealRun& r0 = vr.Runs[0];
    std::printf("  %3s %7.3f %7.3f | %6.3f %7.3f %6.3f %6.3f %6.3f %7.3f %7.3f | %5d %-34s "
                "%-34s | %8.0f %8.1f %7.0f\n",
      "med", med(&RealRun::Surface), med(&RealRun::II), med(&RealRun::Prep),
      med(&RealRun::Complex), medS(&dg::ATStatistics::Assembly),
      medS(&dg::ATStatistics::Analysis), medS(&dg::ATStatistics::Factorization),
      medS(&dg::ATStatistics::Solve), med(&RealRun::AT), r0.Stats.Iterations,
      CGText(r0.ItU).c_str(), CGText(r0.ItV).c_str(), med(&RealRun::RssBefore), medExtra,
      medExtra * 1048576.0 / static_cast<double>(vr.Faces));
    rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    vr.ProcessPeak = ru.ru_maxrss / 1024.0;
    std::printf("  %lld surfels (faces), %lld edges, %lld vertices; %d levels; runs bitwise "
                "identical (u, v, CG counts): %s; AT CPU time (user + sys) %.3f s\n",
      static_cast<long long>(vr.Faces), static_cast<long long>(vr.Edges),
      static_cast<long long>(vr.Vertices), r0.Stats.Levels, vr.Deterministic ? "yes" : "NO",
      med(&RealRun::ATCpu));
    std::printf("  peak memory (getrusage ru_maxrss, whole process so far) %.0f MiB; AT+ = AT's "
                "peak (%s) - RSS before AT, per surfel in B/surfel\n",
      vr.ProcessPeak, hwm ? "VmHWM reset before AT" : "ru_maxrss: VmHWM reset unavailable");
    for (const SystemBytes* sb : { &vr.U, &vr.V })
    {
      std::printf("  %s-system: n %lld, nnz %lld (%.2f/row), IC factor %lld lower entries in %lld "
                  "blocks, nc %d: %.2f MB per CG iteration (%.0f B/row), %.2f MB setup per solve\n",
        sb == &vr.U ? "u" : "v", static_cast<long long>(sb->N), static_cast<long long>(sb->Nnz),
        static_cast<double>(sb->Nnz) / sb->N, static_cast<long long>(sb->NL),
        static_cast<long long>(sb->Blocks), sb->NC, sb->PerIteration / 1e6,
        sb->PerIteration / sb->N, sb->PerSolveSetup / 1e6);
    }
    // Where AT's bytes go: every structure the complex and the solver hold
    // at the end of the run (allocated capacity), per surfel.
    {
      dg::ATMemoryParts parts = vr.Memory;
      parts.emplace_back("input field g (the caller's copy; 0: taken by the solver)", vr.InputCopy);
      std::size_t total = 0;
      for (const auto& p : parts)
      {
        total += p.second;
      }
      std::printf("  memory by structure (B/surfel; MiB):\n");
      for (const auto& p : parts)
      {
        std::printf("    %-62s %7.1f  %8.1f\n", p.first.c_str(),
          static_cast<double>(p.second) / static_cast<double>(vr.Faces), p.second / 1048576.0);
      }
      std::printf("    %-62s %7.1f  %8.1f (measured AT+ peak: %.0f B/surfel)\n", "total",
        static_cast<double>(total) / static_cast<double>(vr.Faces), total / 1048576.0,
        medExtra * 1048576.0 / static_cast<double>(vr.Faces));
    }
    std::fflush(stdout);

    if (check)
    {
      // The filter on the same II output: same iterations, same u and v.
      vtkNew<vtkAmbrosioTortorelliFilter> at;
      at->SetInputData(lastII);
      at->NormalizeVectorFieldOff(); // its "ATNormals" are then u itself
      at->SetMaximumIterations(params.MaximumIterations);
      at->SetTolerance(params.Tolerance);
      at->Update();
      vtkDataArray* au = at->GetOutput()->GetCellData()->GetArray("ATNormals");
      vtkDataArray* av = at->GetOutput()->GetPointData()->GetArray("ATFeatureIndicator");
      double du = 0, dv = 0;
      std::int64_t differ = 0;
      const std::int64_t off = lastII->GetNumberOfVerts() + lastII->GetNumberOfLines();
      for (std::int64_t f = 0; au && f < firstU.rows(); ++f)
        for (int c = 0; c < firstU.cols(); ++c)
        {
          const double a = au->GetComponent(off + f, c);
          du = std::max(du, std::abs(a - firstU(f, c)));
          differ += a != firstU(f, c);
        }
      for (std::int64_t i = 0; av && i < firstV.size(); ++i)
      {
        const double a = av->GetComponent(i, 0);
        dv = std::max(dv, std::abs(a - firstV[i]));
        differ += a != firstV[i];
      }
      std::printf("  check against vtkAmbrosioTortorelliFilter: NumberOfIterations %d (core %d), "
                  "max|du| %.3g, max|dv| %.3g, %lld values not bitwise equal: %s\n",
        at->GetNumberOfIterations(), r0.Stats.Iterations, du, dv, static_cast<long long>(differ),
        au && av && at->GetNumberOfIterations() == r0.Stats.Iterations && du <= 1e-12 &&
            dv <= 1e-12
          ? "OK"
          : "MISMATCH");
      std::fflush(stdout);
    }
    results.push_back(std::move(vr));
  }

  // The triad last: its 768 MB would otherwise be the process's peak RSS.
  const std::int64_t triadN = std::int64_t(1) << 25; // 3 x 256 MiB, 24x a 32 MiB L3
  double triadMedian = 0;
  if (!triadWanted)
  {
    return 0;
  }
  const double triad = TriadGBs(triadN, 10, &triadMedian);
  std::printf("\nSTREAM triad a = b + s c, 3 x %.0f MiB, %d threads, best of 10: %.2f GB/s "
              "(median %.2f GB/s)\n",
    triadN * 8.0 / 1048576.0, vtkSMPTools::GetEstimatedNumberOfThreads(), triad, triadMedian);
  std::printf("floor = CG iterations x bytes per iteration / triad (best); bytes per iteration "
              "B = (16 + 10 s) nc n + 12 nnz + 4 (n+1) + 8 nL + 4 (n+1) + 4 n\n"
              "  (CG vectors: x in double, 2 transfers; r, p, q, z of s bytes (4: float), 10 transfers; matrix values, "
              "row indices, column starts; IC factor C's lower triangle in float + int,\n"
              "  row starts, float 1/C_ii); 'floor+setup' adds per solve S = 12 nnz + 4 (n+1) + "
              "8 nL + 4 (n+1) + 4 n + (48 + 3 s) nc n (residual, first preconditioning, (de)interleaving).\n");
  std::printf("  %-20s %8s %8s %8s %9s %9s %8s %7s %9s %7s %8s %8s\n", "volume", "solve s",
    "CGits u", "CGits v", "MB/it u", "MB/it v", "floor s", "ratio", "floor+set", "ratio",
    "factor s", "GB/s eff");
  for (const VolumeResult& vr : results)
  {
    const RealRun& r0 = vr.Runs[0];
    std::int64_t tu, tv, lo, hi;
    MinMax(r0.ItU, tu, lo, hi);
    MinMax(r0.ItV, tv, lo, hi);
    std::vector<double> solve, factor;
    for (const auto& x : vr.Runs)
    {
      solve.push_back(x.Stats.Solve);
      factor.push_back(x.Stats.Factorization);
    }
    const double s = MedianOf(solve);
    const double bytes = tu * vr.U.PerIteration + tv * vr.V.PerIteration;
    const double bytesSetup = bytes + r0.ItU.size() * vr.U.PerSolveSetup +
      r0.ItV.size() * vr.V.PerSolveSetup;
    const double floor = bytes / (triad * 1e9), floorSetup = bytesSetup / (triad * 1e9);
    std::printf("  %-20s %8.3f %8lld %8lld %9.2f %9.2f %8.3f %7.2f %9.3f %7.2f %8.3f %8.2f\n",
      vr.Name.c_str(), s, static_cast<long long>(tu), static_cast<long long>(tv),
      vr.U.PerIteration / 1e6, vr.V.PerIteration / 1e6, floor, s / floor, floorSetup,
      s / floorSetup, MedianOf(factor), bytesSetup / s / 1e9);
    std::printf("  %-20s u share of the floor %.0f %%, v %.0f %%\n", "",
      100 * tu * vr.U.PerIteration / bytes, 100 * tv * vr.V.PerIteration / bytes);
    // Each system against its own floor (its CG iterations x its bytes per
    // iteration / triad): where the solve time goes between the two.
    std::vector<double> solveU, solveV;
    for (const auto& x : vr.Runs)
    {
      solveU.push_back(x.Stats.SolveU);
      solveV.push_back(x.Stats.Solve - x.Stats.SolveU);
    }
    const double su = MedianOf(solveU), sv = MedianOf(solveV);
    const double fu = tu * vr.U.PerIteration / (triad * 1e9);
    const double fv = tv * vr.V.PerIteration / (triad * 1e9);
    std::printf("  %-20s u-system: solves %.3f s, floor %.3f s, ratio %.2f, %.2f ms per CG "
                "iteration; v-system: %.3f s, %.3f s, %.2f, %.2f ms\n",
      "", su, fu, su / fu, 1e3 * su / std::max<std::int64_t>(tu, 1), sv, fv, sv / fv,
      1e3 * sv / std::max<std::int64_t>(tv, 1));
  }
  if (results.size() >= 3)
  {
    // Growth with the surface: AT time (and solve time) against surfels.
    std::vector<double> faces, at, solve, cg;
    for (const VolumeResult& vr : results)
    {
      std::vector<double> a, sv;
      for (const auto& x : vr.Runs)
      {
        a.push_back(x.AT);
        sv.push_back(x.Stats.Solve);
      }
      faces.push_back(static_cast<double>(vr.Faces));
      at.push_back(MedianOf(a));
      solve.push_back(MedianOf(sv));
      cg.push_back(static_cast<double>(vr.Runs[0].Stats.CGIterations));
      std::printf("  series %-22s %9lld surfels  AT %8.3f s  solves %8.3f s  %7.2f us/surfel  CG "
                  "iterations %lld\n",
        vr.Name.c_str(), static_cast<long long>(vr.Faces), at.back(), solve.back(),
        1e6 * at.back() / faces.back(), static_cast<long long>(vr.Runs[0].Stats.CGIterations));
    }
    std::printf("  fitted exponent (log-log least squares) of AT time vs surfels: %.3f; solves: "
                "%.3f; CG iterations: %.3f\n",
      Exponent(faces, at), Exponent(faces, solve), Exponent(faces, cg));
  }
  {
    rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    const std::time_t now = std::time(nullptr);
    char when[64];
    std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S %Z", std::localtime(&now));
    std::printf("end %s, loadavg %s, peak memory with the triad %.0f MiB\n", when,
      FirstLine("/proc/loadavg").c_str(), ru.ru_maxrss / 1024.0);
  }
  return 0;
}
