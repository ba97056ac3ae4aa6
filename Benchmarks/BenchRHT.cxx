// Speed of vtkRHTNormalEstimator on octa-flower 512^3 (671 270 surfels; the
// paper's Fig. 5: r = 6, 648 trials). Prints the median wall time (and CPU
// time) of the filter for r = 6, 648 trials, then how it grows with r and
// with the number of trials.
// Usage: BenchRHT [runs] [file.vol] [radii] [trials]   (lists comma-separated)
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkRHTNormalEstimator.h"

#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace
{
double CpuSeconds()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec +
    1e-6 * u.ru_stime.tv_usec;
}

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::vector<double> List(const char* p)
{
  std::vector<double> out;
  while (*p)
  {
    char* end = nullptr;
    out.push_back(std::strtod(p, &end));
    p = *end ? end + 1 : end;
  }
  return out;
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
  surface->Update();
  const vtkIdType nSurfels = surface->GetOutput()->GetNumberOfCells();
  std::printf("%s: %lld surfels\n", file.c_str(), static_cast<long long>(nSurfels));

  vtkNew<vtkRHTNormalEstimator> rht;
  rht->SetInputConnection(surface->GetOutputPort());
  rht->SetSourceConnection(reader->GetOutputPort());
  std::vector<std::pair<double, int>> cases = { { 6, 648 } };
  // The growth table of docs/rht.md: r = 4, 6, 8 and 324, 648, 1296 trials.
  const std::vector<double> radii = argc > 3 ? List(argv[3]) : std::vector<double>{ 4, 8 };
  const std::vector<double> trials = argc > 4 ? List(argv[4]) : std::vector<double>{ 324, 1296 };
  for (double r : radii)
  {
    cases.emplace_back(r, 648);
  }
  for (double t : trials)
  {
    cases.emplace_back(6, static_cast<int>(t));
  }
  std::printf("\n%5s %7s %10s %10s %12s %10s\n", "r", "trials", "wall s", "cpu s", "us/surfel",
    "fallbacks");
  for (const auto& c : cases)
  {
    rht->SetRadius(c.first);
    rht->SetNumberOfTrials(c.second);
    std::vector<double> wall, cpu;
    for (int k = 0; k < runs; ++k)
    {
      rht->Modified();
      const double c0 = CpuSeconds();
      const auto t0 = std::chrono::steady_clock::now();
      rht->Update();
      wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      cpu.push_back(CpuSeconds() - c0);
    }
    std::printf("%5.1f %7d %10.2f %10.2f %12.2f %10lld\n", c.first, c.second, Median(wall),
      Median(cpu), 1e6 * Median(cpu) / std::max<vtkIdType>(1, nSurfels),
      static_cast<long long>(rht->GetNumberOfFallbacks()));
    std::fflush(stdout);
  }
  return 0;
}
