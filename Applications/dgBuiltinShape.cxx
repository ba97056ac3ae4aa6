#include "dgBuiltinShape.h"

#include <vtkPointData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>

namespace dg
{
vtkSmartPointer<vtkImageData> MakeBuiltinShape(int n)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, n);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* values = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  values->SetName("Inside");
  unsigned char* v = values->GetPointer(0);
  // Rotation by 20, 30 and 10 degrees about x, y, z: the cube's faces are not
  // aligned with the grid, so its edges are genuine digital sharp features.
  const double ax = 20 * M_PI / 180, ay = 30 * M_PI / 180, az = 10 * M_PI / 180;
  const double cx = std::cos(ax), sx = std::sin(ax), cy = std::cos(ay), sy = std::sin(ay),
               cz = std::cos(az), sz = std::sin(az);
  // R = Rz * Ry * Rx; a point p is tested in the cube frame as R^T p.
  const double R[3][3] = { { cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx },
    { sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx }, { -sy, cy * sx, cy * cx } };
  const double c = 0.5 * (n - 1);
  const double h = 0.26 * n;        // cube half side
  const double rs = 0.22 * n;       // sphere radius, centred near a cube corner
  const double rc = 0.12 * n;       // cylinder radius (a hole through the cube)
  vtkSMPTools::For(0, n, [&](vtkIdType kb, vtkIdType ke) {
    for (vtkIdType k = kb; k < ke; ++k)
    {
      for (int j = 0; j < n; ++j)
      {
        for (int i = 0; i < n; ++i)
        {
          const double p[3] = { i - c, j - c, k - c };
          double q[3];
          for (int a = 0; a < 3; ++a)
          {
            q[a] = R[0][a] * p[0] + R[1][a] * p[1] + R[2][a] * p[2];
          }
          const bool cube = std::fabs(q[0]) <= h && std::fabs(q[1]) <= h && std::fabs(q[2]) <= h;
          const double s[3] = { q[0] - 0.55 * h, q[1] - 0.55 * h, q[2] - 0.55 * h };
          const bool sphere = s[0] * s[0] + s[1] * s[1] + s[2] * s[2] <= rs * rs;
          const bool hole = q[0] * q[0] + q[1] * q[1] <= rc * rc;
          v[(k * n + j) * n + i] = ((cube || sphere) && !hole) ? 1 : 0;
        }
      }
    }
  });
  return image;
}
} // namespace dg
