// What the integral-invariant tests share: 0/1 images, the surface + II
// run, and small statistics.
#ifndef dgIITestSupport_h
#define dgIITestSupport_h

#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace dgtest
{
inline std::vector<std::uint8_t> MaskOf(vtkImageData* image)
{
  auto* s = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  return std::vector<std::uint8_t>(s->GetPointer(0), s->GetPointer(0) + s->GetNumberOfValues());
}

inline vtkSmartPointer<vtkImageData> ImageOf(const std::vector<std::uint8_t>& m, const int dims[3])
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(dims[0], dims[1], dims[2]);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* s = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  std::copy(m.begin(), m.end(), s->GetPointer(0));
  return image;
}

// Surface + II estimator on an image; returns the estimator's output.
inline vtkSmartPointer<vtkPolyData> Estimate(vtkImageData* image,
  double r,
  bool curvatures = false,
  int reference = 2)
{
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadius(r);
  ii->SetComputeCurvatures(curvatures);
  ii->SetCurvatureReference(reference);
  ii->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(ii->GetOutput());
  return out;
}

inline Eigen::Vector3d Tuple(vtkDataArray* a, vtkIdType i)
{
  double t[3];
  a->GetTuple(i, t);
  return Eigen::Vector3d(t[0], t[1], t[2]);
}

inline double Percentile(std::vector<double> v, double q)
{
  if (v.empty())
  {
    return NAN;
  }
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

inline double Mean(const std::vector<double>& v)
{
  double s = 0;
  for (double x : v)
  {
    s += x;
  }
  return v.empty() ? NAN : s / v.size();
}
} // namespace dgtest

#endif
