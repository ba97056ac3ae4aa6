// Speed of vtkDigitalSurfaceFilter: octa-flower 512^3 (when ../shared is
// present) and synthetic balls from 64^3 to 512^3. Prints surfels, median
// time over 5 runs and peak memory. Usage: BenchDigitalSurface [runs]
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
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

vtkSmartPointer<vtkImageData> Ball(int n)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, n);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars())->GetPointer(0);
  const double c = 0.5 * (n - 1) + 0.1, r = 0.4 * n;
  vtkSMPTools::For(0, n, [&](vtkIdType kb, vtkIdType ke) {
    for (vtkIdType k = kb; k < ke; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          v[(k * n + j) * n + i] = (i - c) * (i - c) + (j - c) * (j - c) + (k - c) * (k - c) <= r * r;
  });
  return image;
}

void Run(const std::string& name, vtkImageData* image, int runs)
{
  vtkNew<vtkDigitalSurfaceFilter> f;
  f->SetInputData(image);
  std::vector<double> times;
  for (int r = 0; r < runs; ++r)
  {
    f->Modified();
    const auto t0 = std::chrono::steady_clock::now();
    f->Update();
    times.push_back(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(times.begin(), times.end());
  int d[3];
  image->GetDimensions(d);
  const double voxels = double(d[0]) * d[1] * d[2];
  std::printf("%-24s %4dx%4dx%4d %10lld surfels %8.3f s median (min %.3f, max %.3f) %6.2f ns/voxel  peak %.0f MiB\n",
    name.c_str(), d[0], d[1], d[2], static_cast<long long>(f->GetOutput()->GetNumberOfPolys()),
    times[times.size() / 2], times.front(), times.back(), 1e9 * times[times.size() / 2] / voxels,
    PeakMemoryMiB());
}
} // namespace

int main(int argc, char* argv[])
{
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread");
  }
  std::printf("vtkSMPTools backend %s, %d threads, %d runs each\n", vtkSMPTools::GetBackend(),
    vtkSMPTools::GetEstimatedNumberOfThreads(), runs);
  const std::string flower = std::string(DG_SHARED_DATA_DIR) + "/octa-flower17k-512.vol";
  if (std::ifstream(flower).good())
  {
    vtkNew<vtkDGtalVolReader> reader;
    reader->SetFileName(flower.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    reader->Update();
    std::printf("read octa-flower17k-512.vol in %.3f s\n",
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    Run("octa-flower17k-512", reader->GetOutput(), runs);
  }
  else
  {
    std::printf("(octa-flower17k-512.vol absent: ../shared not found)\n");
  }
  for (int n : { 64, 128, 256, 512 })
  {
    auto image = Ball(n);
    Run("ball r=0.4n", image, runs);
  }
  return 0;
}
