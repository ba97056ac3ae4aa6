#include "dgDicomGeometry.h"
#include "dgImageHeader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace dg
{
namespace
{
double Dot(const DicomVec& a, const DicomVec& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

DicomVec Cross(const DicomVec& a, const DicomVec& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

DicomVec Scaled(const DicomVec& a, double s)
{
  return { a[0] * s, a[1] * s, a[2] * s };
}

bool Finite(const std::vector<double>& v)
{
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}
} // namespace

std::string DicomFileName(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string DicomNumber(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

bool OrderDicomSlices(const std::vector<DicomSliceTags>& slices, DicomStack& stack, std::string& error)
{
  stack = DicomStack();
  if (slices.empty())
  {
    error = "no slice";
    return false;
  }
  std::vector<DicomVec> positions;
  for (std::size_t s = 0; s < slices.size(); ++s)
  {
    const std::string name = "'" + DicomFileName(slices[s].File) + "'";
    const auto ipp = ParseNumbers(slices[s].Position);
    const auto iop = ParseNumbers(slices[s].Orientation);
    const auto ps = ParseNumbers(slices[s].PixelSpacing);
    if (iop.size() != 6 || !Finite(iop))
      return error = name + " has no valid ImageOrientationPatient (0020,0037)", false;
    if (ipp.size() != 3 || !Finite(ipp))
      return error = name + " has no valid ImagePositionPatient (0020,0032)", false;
    if (ps.size() != 2 || !(ps[0] > 0) || !(ps[1] > 0) || !Finite(ps))
      return error = name + " has no valid PixelSpacing (0028,0030)", false;
    const DicomVec r{ iop[0], iop[1], iop[2] }, c{ iop[3], iop[4], iop[5] };
    if (s == 0)
    {
      const double lr = std::sqrt(Dot(r, r)), lc = std::sqrt(Dot(c, c));
      if (!(std::abs(lr - 1) <= 1e-3) || !(std::abs(lc - 1) <= 1e-3))
        return error = "ImageOrientationPatient (0020,0037) of " + name + " is not made of unit vectors", false;
      stack.Row = Scaled(r, 1 / lr);
      stack.Column = Scaled(c, 1 / lc);
      const double cosAngle = Dot(stack.Row, stack.Column);
      if (std::abs(cosAngle) > 1e-3)
        return error = "ImageOrientationPatient (0020,0037) of " + name + " has rows and columns at " +
                 DicomNumber(std::acos(std::max(-1.0, std::min(1.0, cosAngle))) * 180 / M_PI) +
                 " degrees (sheared)",
               false;
      const DicomVec n = Cross(stack.Row, stack.Column);
      stack.Normal = Scaled(n, 1 / std::sqrt(Dot(n, n)));
      stack.PixelSpacing[0] = ps[0];
      stack.PixelSpacing[1] = ps[1];
    }
    else
    {
      for (int a = 0; a < 3; ++a)
        if (!(std::abs(r[a] - stack.Row[a]) <= 1e-4) || !(std::abs(c[a] - stack.Column[a]) <= 1e-4))
          return error = name + " has another ImageOrientationPatient than '" +
                   DicomFileName(slices[0].File) + "' (one volume needs one orientation)",
                 false;
      if (std::abs(ps[0] - stack.PixelSpacing[0]) > 1e-6 * stack.PixelSpacing[0] ||
        std::abs(ps[1] - stack.PixelSpacing[1]) > 1e-6 * stack.PixelSpacing[1])
        return error = name + " has another PixelSpacing than '" + DicomFileName(slices[0].File) + "'", false;
    }
    positions.push_back({ ipp[0], ipp[1], ipp[2] });
  }
  std::vector<std::size_t> order(slices.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<double> along(slices.size());
  for (std::size_t s = 0; s < slices.size(); ++s)
    along[s] = Dot(positions[s], stack.Normal);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return along[a] < along[b]; });
  for (std::size_t s : order)
  {
    stack.Files.push_back(slices[s].File);
    stack.Positions.push_back(positions[s]);
    stack.Along.push_back(along[s]);
  }
  return true;
}

bool UniformDicomStep(const DicomStack& stack, double& step, std::string& error)
{
  const std::size_t n = stack.Along.size();
  if (n < 2 || stack.Positions.size() != n || stack.Files.size() != n)
  {
    error = "fewer than two slices";
    return false;
  }
  for (std::size_t s = 1; s < n; ++s)
    if (stack.Along[s] - stack.Along[s - 1] <= 1e-6 * std::max(1.0, std::abs(stack.Along[s])))
      return error = "'" + DicomFileName(stack.Files[s - 1]) + "' and '" + DicomFileName(stack.Files[s]) +
               "' are at the same position along the slice normal (several acquisitions or echoes in one series?)",
             false;
  step = (stack.Along.back() - stack.Along.front()) / static_cast<double>(n - 1);
  // Every slice within 1% of a slice spacing of the uniform grid, and on the
  // normal through the first slice's corner (no gantry tilt).
  double worst = 0, worstShift = 0;
  const DicomVec& origin = stack.Positions[0];
  const DicomVec& normal = stack.Normal;
  for (std::size_t s = 0; s < n; ++s)
  {
    worst = std::max(worst, std::abs(stack.Along[s] - stack.Along[0] - step * static_cast<double>(s)));
    const DicomVec off{ stack.Positions[s][0] - origin[0], stack.Positions[s][1] - origin[1],
      stack.Positions[s][2] - origin[2] };
    const double a = Dot(off, normal);
    const DicomVec across{ off[0] - a * normal[0], off[1] - a * normal[1], off[2] - a * normal[2] };
    worstShift = std::max(worstShift, std::sqrt(Dot(across, across)));
  }
  if (!(worst <= 0.01 * step))
  {
    std::vector<double> distinct;
    for (std::size_t s = 1; s < n; ++s)
    {
      const double gap = stack.Along[s] - stack.Along[s - 1];
      if (std::none_of(distinct.begin(), distinct.end(), [&](double g) { return std::abs(g - gap) <= 0.01 * step; }))
        distinct.push_back(gap);
      if (distinct.size() > 8)
        break;
    }
    std::string gaps;
    for (std::size_t i = 0; i < distinct.size() && i < 8; ++i)
      gaps += (i ? ", " : "") + DicomNumber(distinct[i]);
    if (distinct.size() > 8)
      gaps += ", ...";
    error = "non-uniform slice spacing (" + gaps + " mm between consecutive slices of " + std::to_string(n) +
      "; missing slices?): refused rather than resampled";
    return false;
  }
  if (!(worstShift <= 0.01 * std::min({ stack.PixelSpacing[0], stack.PixelSpacing[1], step })))
  {
    error = "the slices are not stacked along their normal (shifted by up to " + DicomNumber(worstShift) +
      " mm across it: gantry tilt?), which origin, spacing and direction cannot express";
    return false;
  }
  return true;
}
} // namespace dg
