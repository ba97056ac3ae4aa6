// The installed module from an external project: a digitised ball through
// digital surface -> integral-invariant normals -> Ambrosio-Tortorelli, and
// two properties that hold only when the pipeline really ran:
//   - the surface has exactly one quad per face between an inside and an
//     outside voxel (counted here from the volume itself);
//   - the regularised normals point along the ball's radius (mean and
//     worst angle).
// Prints one "ok"/"FAIL" line per check; exit status 0 when all hold.
#include <vtkAmbrosioTortorelliFilter.h>
#include <vtkDigitalSurfaceFilter.h>
#include <vtkIINormalEstimator.h>

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace
{
int failures = 0;
void Check(bool ok, const std::string& what)
{
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  failures += ok ? 0 : 1;
}
}

int main()
{
  const int n = 36;
  const double c[3] = { 17.3, 16.8, 17.1 }, r = 11.0;
  vtkNew<vtkImageData> image;
  image->SetDimensions(n, n, n);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* v = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  auto inside = [&](int i, int j, int k)
  {
    if (i < 0 || j < 0 || k < 0 || i >= n || j >= n || k >= n)
      return false;
    const double x = i - c[0], y = j - c[1], z = k - c[2];
    return x * x + y * y + z * z <= r * r;
  };
  long long faces = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const bool in = inside(i, j, k);
        v->SetValue((static_cast<vtkIdType>(k) * n + j) * n + i, in ? 1 : 0);
        if (in)
          faces += !inside(i - 1, j, k) + !inside(i + 1, j, k) + !inside(i, j - 1, k) +
            !inside(i, j + 1, k) + !inside(i, j, k - 1) + !inside(i, j, k + 1);
      }

  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadius(4);
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetInputConnection(ii->GetOutputPort());
  at->Update();

  vtkPolyData* out = at->GetOutput();
  Check(out->GetNumberOfPolys() == faces,
    "one quad per boundary face: " + std::to_string(out->GetNumberOfPolys()) + " quads, " +
      std::to_string(faces) + " faces");
  vtkDataArray* normals = out->GetCellData()->GetArray("ATNormals");
  Check(normals && normals->GetNumberOfTuples() == out->GetNumberOfCells(),
    "ATNormals, one per quad");
  if (!normals || out->GetNumberOfCells() == 0)
    return 1;
  double sum = 0, worst = 0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType q = 0; q < out->GetNumberOfCells(); ++q)
  {
    out->GetCellPoints(q, ids);
    double m[3] = { 0, 0, 0 };
    for (vtkIdType a = 0; a < ids->GetNumberOfIds(); ++a)
    {
      double p[3];
      out->GetPoint(ids->GetId(a), p);
      for (int d = 0; d < 3; ++d)
        m[d] += p[d] / ids->GetNumberOfIds();
    }
    double radial[3] = { m[0] - c[0], m[1] - c[1], m[2] - c[2] };
    const double len = std::sqrt(radial[0] * radial[0] + radial[1] * radial[1] + radial[2] * radial[2]);
    double nq[3];
    normals->GetTuple(q, nq);
    const double dot = (nq[0] * radial[0] + nq[1] * radial[1] + nq[2] * radial[2]) / len;
    const double angle = std::acos(std::max(-1.0, std::min(1.0, dot))) * 57.29577951308232;
    sum += angle;
    worst = std::max(worst, angle);
  }
  const double mean = sum / out->GetNumberOfCells();
  char line[160];
  std::snprintf(line, sizeof line, "AT normals along the radius: mean %.2f deg (< 4), worst %.2f deg (< 20)",
    mean, worst);
  Check(mean < 4 && worst < 20, line);
  Check(std::string(DG_FOUND_VERSION).size() > 0, std::string("package version ") + DG_FOUND_VERSION);
  return failures == 0 ? 0 : 1;
}
