// libFuzzer target: small voxel sets (boxes or noise) and random parameters through
// vtkDigitalSurfaceFilter -> vtkIINormalEstimator -> vtkAmbrosioTortorelliFilter,
// -> vtkSharpFeaturesFilter, and through vtkDigitalIslandFilter twice.
// Any crash or sanitizer report fails; so does a non-finite or non-unit
// normal in an output that was produced without an error, or a second island
// pass that changes a voxel.
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDigitalIslandFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"
#include "vtkSharpFeaturesFilter.h"

#include <vtkCellArray.h>

#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace
{
class Quiet : public vtkCommand
{
public:
  static Quiet* New() { return new Quiet; }
  void Execute(vtkObject*, unsigned long, void*) override { this->Errors++; }
  int Errors = 0;
};

struct Bytes
{
  const std::uint8_t* Data;
  std::size_t Size, Pos = 0;
  std::uint8_t Next() { return this->Pos < this->Size ? this->Data[this->Pos++] : 0; }
};

void CheckUnit(vtkDataArray* n)
{
  if (!n)
  {
    return;
  }
  for (vtkIdType c = 0; c < n->GetNumberOfTuples(); ++c)
  {
    double v[3];
    n->GetTuple(c, v);
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!std::isfinite(len) || std::fabs(len - 1.0) > 1e-6)
    {
      std::abort();
    }
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  // Sizes and schedules are bounded so that one input takes milliseconds
  // under ASan (thousands per minute), not the ~100 ms to 1.5 s of 10^3
  // random voxels with 6 AT levels: the sharp-features search from a band
  // face grows up to 64 face steps, so on noise (all band) it is quadratic in
  // the faces, and AT's cost is levels x iterations x CG solves.
  //
  // Byte 0 chooses the voxels: even, 1 to 3 boxes XOR-ed on a grid of up to
  // 10^3 (planar regions, edges and corners, holes: what sharp features
  // look for); odd, random bits on a grid of up to 5^3 (noise).
  Bytes in{ data, size };
  const bool noise = in.Next() & 1;
  const int span = noise ? 4 : 9;
  const int nx = 2 + in.Next() % span, ny = 2 + in.Next() % span, nz = 2 + in.Next() % span;
  const double radius = 0.25 * (in.Next() % 24) - 1.0; // -1 .. 4.75, some invalid
  const double alpha = 0.01 * (static_cast<int>(in.Next()) - 20);
  const double lambda = 0.001 * (static_cast<int>(in.Next()) - 20);
  const double eps1 = 0.05 * in.Next();
  double eps2 = 0.05 * in.Next();
  const double ratio = 1.0 + 0.05 * (static_cast<int>(in.Next()) - 20);
  // Valid schedules are capped at 3 levels: a ratio of 1.05 from 12.75 to
  // 0.05 means 114 levels, which costs seconds per input under ASan and
  // explores nothing new (the filter takes each level the same way).
  if (ratio > 1.0 && eps2 > 0.0 && eps1 >= eps2 && std::log(eps1 / eps2) > 3.0 * std::log(ratio))
  {
    eps2 = eps1 / std::pow(ratio, 3.0);
  }
  const int iterations = static_cast<int>(in.Next() % 5) - 1; // -1 (invalid) .. 3

  vtkNew<vtkImageData> image;
  image->SetDimensions(nx, ny, nz);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* s = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  if (noise)
  {
    std::uint8_t bits = 0;
    for (vtkIdType p = 0; p < s->GetNumberOfValues(); ++p)
    {
      if (p % 8 == 0)
      {
        bits = in.Next();
      }
      s->SetValue(p, (bits >> (p % 8)) & 1);
    }
  }
  else
  {
    s->FillValue(0);
    const int boxes = 1 + in.Next() % 3;
    const int n[3] = { nx, ny, nz };
    for (int b = 0; b < boxes; ++b)
    {
      int lo[3], hi[3];
      for (int a = 0; a < 3; ++a)
      {
        const int u = in.Next() % n[a], v = in.Next() % n[a];
        lo[a] = std::min(u, v);
        hi[a] = std::max(u, v);
      }
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x)
          {
            const vtkIdType p = x + static_cast<vtkIdType>(nx) * (y + static_cast<vtkIdType>(ny) * z);
            s->SetValue(p, s->GetValue(p) ^ 1);
          }
    }
  }

  vtkNew<Quiet> quiet;
  vtkNew<vtkDigitalSurfaceFilter> surface;
  vtkNew<vtkIINormalEstimator> ii;
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  for (vtkAlgorithm* a : { static_cast<vtkAlgorithm*>(surface.Get()),
         static_cast<vtkAlgorithm*>(ii.Get()), static_cast<vtkAlgorithm*>(at.Get()) })
  {
    a->AddObserver(vtkCommand::ErrorEvent, quiet);
    a->AddObserver(vtkCommand::WarningEvent, quiet);
    a->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, quiet);
  }
  surface->SetInputData(image);
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadius(radius);
  at->SetInputConnection(ii->GetOutputPort());
  at->SetAlpha(alpha);
  at->SetLambda(lambda);
  at->SetEpsilonStart(eps1);
  at->SetEpsilonEnd(eps2);
  at->SetEpsilonRatio(ratio);
  at->SetMaximumIterations(iterations);
  at->Update();
  if (quiet->Errors == 0)
  {
    CheckUnit(ii->GetOutput()->GetCellData()->GetArray("IINormals"));
    CheckUnit(at->GetOutput(0)->GetCellData()->GetArray("ATNormals"));
    // The sharp-features stage on AT's output (no byte of its own): unit
    // normals, and every feature line between two faces' points.
    vtkNew<vtkSharpFeaturesFilter> sharp;
    sharp->AddObserver(vtkCommand::ErrorEvent, quiet);
    sharp->AddObserver(vtkCommand::WarningEvent, quiet);
    sharp->SetInputConnection(at->GetOutputPort());
    sharp->SetMinimumRegionSize(1 + (nx + ny * nz) % 40);
    sharp->Update();
    if (quiet->Errors == 0)
    {
      CheckUnit(sharp->GetOutput(0)->GetCellData()->GetArray("SharpNormals"));
      const vtkIdType np = sharp->GetOutput(0)->GetNumberOfPoints();
      vtkCellArray* lines = sharp->GetOutput(1)->GetLines();
      vtkDataArray* conn = lines ? lines->GetConnectivityArray() : nullptr;
      for (vtkIdType i = 0; conn && i < conn->GetNumberOfValues(); ++i)
      {
        if (conn->GetTuple1(i) < 0 || conn->GetTuple1(i) >= np)
          std::abort();
      }
    }
  }

  // The island filter on the same voxels, with no byte of its own (the
  // corpus keeps its meaning): once cleaned, a second pass changes nothing.
  vtkNew<vtkDigitalIslandFilter> once, twice;
  for (vtkAlgorithm* a : { static_cast<vtkAlgorithm*>(once.Get()),
         static_cast<vtkAlgorithm*>(twice.Get()) })
  {
    a->AddObserver(vtkCommand::WarningEvent, quiet);
  }
  once->SetInputData(image);
  once->SetMinimumSize(1 + (nx * ny + nz) % 12);
  twice->SetInputConnection(once->GetOutputPort());
  twice->SetMinimumSize(once->GetMinimumSize());
  twice->Update();
  if (twice->GetNumberOfChangedVoxels() != 0 ||
    once->GetOutput()->GetNumberOfPoints() != image->GetNumberOfPoints())
  {
    std::abort();
  }
  return 0;
}
