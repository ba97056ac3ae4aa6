// Speed of vtkVCMNormalEstimator on octa-flower 512^3 (671 270 surfels; the
// paper: 97 s for VCM). Prints, for (R, r) = (10, 4) (the paper's) and
// around it (R = 5, 15, 20 at r = 4; r = 2, 8 at R = 10), the median time
// over several runs of the filter (normals, then with the feature score),
// the time of the core's per-site measures alone (the distance transform
// and the accumulation), the offset's lattice points, the buffers and the
// peak memory.
// Usage: BenchVCM [runs] [file.vol] [R:r pairs, comma-separated, e.g. 10:4,5:4]
#include "dgVCM.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkVCMNormalEstimator.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace
{
double PeakMemoryMiB()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
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

std::string CpuName()
{
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind("model name", 0) == 0)
    {
      return line.substr(line.find(':') + 2);
    }
  }
  return "unknown CPU";
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
  std::printf("%s, %ld cores; vtkSMPTools backend %s, %d threads, median of %d runs\n",
    CpuName().c_str(), sysconf(_SC_NPROCESSORS_ONLN), vtkSMPTools::GetBackend(),
    vtkSMPTools::GetEstimatedNumberOfThreads(), runs);
  if (!std::ifstream(file).good())
  {
    std::printf("(%s absent: ../shared not found)\n", file.c_str());
    return 0;
  }
  std::vector<std::pair<double, double>> radii = { { 10, 4 }, { 5, 4 }, { 15, 4 }, { 20, 4 },
    { 10, 2 }, { 10, 8 } };
  if (argc > 3)
  {
    radii.clear();
    for (const char* p = argv[3]; *p;)
    {
      char* end = nullptr;
      const double R = std::strtod(p, &end);
      const double r = std::strtod(end + 1, &end);
      radii.emplace_back(R, r);
      p = *end ? end + 1 : end;
    }
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

  // The core alone: sites of the mask, then the per-site measures.
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  {
    vtkDataArray* s = image->GetPointData()->GetScalars();
    vtkSMPTools::For(0, static_cast<vtkIdType>(mask.size()), [&](vtkIdType b, vtkIdType e) {
      for (vtkIdType v = b; v < e; ++v)
      {
        mask[v] = s->GetComponent(v, 0) != 0;
      }
    });
  }
  const bool beyond[6] = { true, true, true, true, true, true };
  dg::VCMSites sites;
  const double tSites = Seconds([&] { sites = dg::ExtractSites(mask.data(), dims, beyond); });
  mask = std::vector<std::uint8_t>();
  std::printf("sites: %lld surfels of the image in %.3f s\n",
    static_cast<long long>(sites.Size()), tSites);

  std::printf("\n%5s %5s %12s %10s %10s %12s %11s %11s %10s\n", "R", "r", "offset pts",
    "measures", "ns/point", "normals", "+score", "buffers MiB", "peak MiB");
  vtkNew<vtkVCMNormalEstimator> vcm;
  vcm->SetInputConnection(surface->GetOutputPort());
  vcm->SetSourceConnection(reader->GetOutputPort());
  for (const auto& rr : radii)
  {
    std::vector<double> tm, tn, ts;
    dg::VoronoiCovarianceMeasure core;
    for (int k = 0; k < runs; ++k)
    {
      tm.push_back(Seconds([&] { core.Compute(sites, rr.first); }));
    }
    vcm->SetOffsetRadius(rr.first);
    vcm->SetConvolutionRadius(rr.second);
    vcm->ComputeFeatureScoreOff();
    for (int k = 0; k < runs; ++k)
    {
      vcm->Modified();
      tn.push_back(Seconds([&] { vcm->Update(); }));
    }
    vcm->ComputeFeatureScoreOn();
    for (int k = 0; k < runs; ++k)
    {
      vcm->Modified();
      ts.push_back(Seconds([&] { vcm->Update(); }));
    }
    const double m = Median(tm);
    std::printf("%5.1f %5.1f %12lld %9.3fs %10.1f %11.3fs %10.3fs %11.0f %10.0f\n", rr.first,
      rr.second, static_cast<long long>(core.NumberOfOffsetPoints()), m,
      1e9 * m / std::max<std::int64_t>(1, core.NumberOfOffsetPoints()), Median(tn), Median(ts),
      core.BufferBytes() / 1048576.0, PeakMemoryMiB());
  }
  return 0;
}
