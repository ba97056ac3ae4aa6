// Speed of vtkIINormalEstimator on octa-flower 512^3 (671 270 surfels; the
// paper: 443 s for r = 8). Prints, for r = 3, 4, 8 (and 12, 16 to show how
// the cost grows), the median time over several runs of the filter (normals
// only, then with curvatures), the time of the bare ball sums, the cost per
// surfel, the rows per ball and the peak memory.
// Usage: BenchII [runs] [file.vol] [radii, comma-separated]
#include "dgIntegralInvariant.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace
{
double PeakMemoryMiB()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

double CpuSeconds()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec +
    1e-6 * u.ru_stime.tv_usec;
}

double Seconds(const std::function<void()>& f)
{
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
} // namespace

int main(int argc, char* argv[])
{
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const std::string file =
    argc > 2 && *argv[2] ? argv[2] : std::string(DG_SHARED_DATA_DIR) + "/octa-flower17k-512.vol";
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread");
  }
  std::printf("vtkSMPTools backend %s, %d threads, median of %d runs\n", vtkSMPTools::GetBackend(),
    vtkSMPTools::GetEstimatedNumberOfThreads(), runs);
  if (!std::ifstream(file).good())
  {
    std::printf("(%s absent: ../shared not found)\n", file.c_str());
    return 0;
  }
  vtkNew<vtkDGtalVolReader> reader;
  reader->SetFileName(file.c_str());
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputConnection(reader->GetOutputPort());
  const double tSurface = Seconds([&] { surface->Update(); });
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  const vtkIdType nSurfels = surface->GetOutput()->GetNumberOfCells();
  std::printf("%s: %d x %d x %d, %lld surfels (read + surface %.2f s), peak %.0f MiB\n",
    file.c_str(), dims[0], dims[1], dims[2], static_cast<long long>(nSurfels), tSurface,
    PeakMemoryMiB());

  // The bare kernel: runs of the volume, then the ball sums alone.
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  {
    vtkDataArray* s = image->GetPointData()->GetScalars();
    vtkSMPTools::For(0, static_cast<vtkIdType>(mask.size()), [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType v = b; v < e; ++v)
      {
        mask[v] = s->GetComponent(v, 0) != 0; // GetTuple1 is not thread-safe
      }
    });
  }
  dg::IntegralInvariantKernel kernel;
  const double tRuns = Seconds([&] { kernel.SetVolume(mask.data(), dims, dims[0], 0); });
  mask = std::vector<std::uint8_t>();
  std::printf("runs along x: %lld runs, %.1f MiB, built in %.3f s (the 1-byte mask, %.0f MiB, "
              "exists only meanwhile)\n",
    static_cast<long long>(kernel.GetRuns().NumberOfRuns()),
    kernel.GetRuns().MemoryBytes() / 1048576.0, tRuns,
    double(dims[0]) * dims[1] * dims[2] / 1048576.0);
  vtkDataArray* vox = surface->GetOutput()->GetCellData()->GetArray("InsideVoxel");
  vtkDataArray* dir = surface->GetOutput()->GetCellData()->GetArray("SurfelDirection");
  std::vector<int> sv(3 * nSurfels), sd(nSurfels);
  for (vtkIdType s = 0; s < nSurfels; ++s)
  {
    for (int a = 0; a < 3; ++a)
    {
      sv[3 * s + a] = static_cast<int>(vox->GetComponent(s, a));
    }
    sd[s] = static_cast<int>(dir->GetTuple1(s));
  }

  // Wall times are medians; "cpu" is the median CPU time (all threads) of a
  // normals run, which a loaded machine inflates less than the wall time.
  std::printf("\n%4s %6s %10s %9s %12s %10s %12s %9s %12s %10s\n", "r", "rows", "ball sums",
    "cpu", "ns/surfel", "normals", "ns/surfel", "cpu", "+curvatures", "peak MiB");
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceConnection(reader->GetOutputPort());
  std::vector<double> radii = { 3.0, 4.0, 8.0, 12.0, 16.0 };
  if (argc > 3)
  {
    radii.clear();
    for (const char* p = argv[3]; *p;)
    {
      char* end = nullptr;
      radii.push_back(std::strtod(p, &end));
      p = *end ? end + 1 : end;
    }
  }
  for (double r : radii)
  {
    kernel.SetRadius(r);
    std::vector<double> tk, tn, tc, cn, ck;
    std::atomic<std::int64_t> sink(0);
    for (int k = 0; k < runs; ++k)
    {
      const double c0 = CpuSeconds();
      tk.push_back(Seconds([&] {
        vtkSMPTools::For(0, nSurfels, [&](vtkIdType b, vtkIdType e) {
          std::int64_t local = 0;
          for (vtkIdType s = b; s < e; ++s)
          {
            local += kernel.Moments(sv[3 * s], sv[3 * s + 1], sv[3 * s + 2], sd[s]).Count;
          }
          sink += local;
        });
      }));
      ck.push_back(CpuSeconds() - c0);
    }
    ii->SetRadius(r);
    ii->ComputeCurvaturesOff();
    for (int k = 0; k < runs; ++k)
    {
      ii->Modified();
      const double c0 = CpuSeconds();
      tn.push_back(Seconds([&] { ii->Update(); }));
      cn.push_back(CpuSeconds() - c0);
    }
    ii->ComputeCurvaturesOn();
    for (int k = 0; k < runs; ++k)
    {
      ii->Modified();
      tc.push_back(Seconds([&] { ii->Update(); }));
    }
    const double k = Median(tk), n = Median(tn), c = Median(tc);
    std::printf("%4.0f %6zu %9.3fs %8.3fs %12.1f %9.3fs %12.1f %8.3fs %11.3fs %10.0f\n", r,
      kernel.GetBall(0).Rows.size(), k, Median(ck), 1e9 * k / nSurfels, n, 1e9 * n / nSurfels, Median(cn), c,
      PeakMemoryMiB());
    if (sink.load() == 42)
    {
      std::printf(" ");
    }
  }
  return 0;
}
