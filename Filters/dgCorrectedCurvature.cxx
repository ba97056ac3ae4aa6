#include "dgCorrectedCurvature.h"

#include <vtkSMPTools.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace dg
{
namespace
{
using V3 = Eigen::Vector3d;

V3 At(const double* p, std::int64_t i)
{
  return V3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
}

void AddTriangle(const V3& a, const V3& b, const V3& c, const V3& ua, const V3& ub,
  const V3& uc, CorrectedMeasures& m)
{
  const V3 um = (ua + ub + uc) / 3.0;
  m.Mu0 += 0.5 * um.dot((b - a).cross(c - a));
  m.Mu1 += 0.5 * (um.dot((uc - ub).cross(a)) + um.dot((ua - uc).cross(b)) + um.dot((ub - ua).cross(c)));
  m.Mu2 += 0.5 * ua.dot(ub.cross(uc));
  // det(um, <Y, uc - ua> X, b - a) = <Y, uc - ua> <X, (b - a) x um>.
  const V3 w1 = (b - a).cross(um), w2 = (c - a).cross(um);
  const V3 d1 = uc - ua, d2 = ub - ua;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      m.MuXY[3 * i + j] += 0.5 * (w1[i] * d1[j] - w2[i] * d2[j]);
}

// Cell key of a uniform grid of cell size h (21 bits per axis).
std::int64_t Key(const V3& c, double h, int dx = 0, int dy = 0, int dz = 0)
{
  const auto k = [&](double v, int d) {
    return (static_cast<std::int64_t>(std::floor(v / h)) + d + (1 << 20)) & ((1 << 21) - 1);
  };
  return (k(c.x(), dx) << 42) | (k(c.y(), dy) << 21) | k(c.z(), dz);
}
} // namespace

CorrectedMeasures PolygonMeasures(int corners, const double* x, const double* u)
{
  CorrectedMeasures m;
  if (corners < 3)
    return m;
  if (corners == 3)
  {
    AddTriangle(At(x, 0), At(x, 1), At(x, 2), At(u, 0), At(u, 1), At(u, 2), m);
    return m;
  }
  V3 b = V3::Zero(), ub = V3::Zero();
  for (int i = 0; i < corners; ++i)
  {
    b += At(x, i);
    ub += At(u, i).normalized();
  }
  b /= corners;
  ub = ub.norm() > 0 ? ub.normalized() : ub;
  for (int i = 0; i < corners; ++i)
  {
    const int j = (i + 1) % corners;
    AddTriangle(b, At(x, i), At(x, j), ub, At(u, i), At(u, j), m);
  }
  return m;
}

bool ComputeCorrectedCurvatures(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* normals, const int* region, const CurvatureParameters& par,
  CurvatureResult& result, std::string* error)
{
  auto fail = [&](const std::string& message) {
    if (error)
      *error = message;
    return false;
  };
  if (offsets.empty() || offsets.front() != 0 ||
    offsets.back() != static_cast<std::int64_t>(connectivity.size()))
    return fail("inconsistent polygon offsets");
  if (!(par.Radius > 0) || !std::isfinite(par.Radius))
    return fail("the ball radius must be a positive number");
  const std::int64_t F = static_cast<std::int64_t>(offsets.size()) - 1;
  for (std::int64_t id : connectivity)
    if (id < 0 || id >= numberOfPoints)
      return fail("a polygon refers to a point that does not exist");
  for (std::int64_t f = 0; f < F; ++f)
  {
    const double n = At(normals, f).norm();
    if (!(std::abs(n - 1) < 1e-3))
      return fail("the normal field is not made of unit vectors (face " + std::to_string(f) + ")");
  }

  // Faces around each point (CSR).
  std::vector<std::int64_t> start(numberOfPoints + 1, 0), around(connectivity.size());
  for (std::int64_t id : connectivity)
    ++start[id + 1];
  for (std::int64_t p = 0; p < numberOfPoints; ++p)
    start[p + 1] += start[p];
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::int64_t f = 0; f < F; ++f)
      for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
        around[fill[connectivity[k]]++] = f;
  }
  const auto sameSide = [&](std::int64_t f, std::int64_t g) {
    return !region || region[f] == region[g];
  };

  // Each face's measures, with corner normals from its own side's faces.
  std::vector<CorrectedMeasures> measures(F);
  std::vector<V3> centre(F);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    std::vector<double> x, u;
    for (std::int64_t f = begin; f < end; ++f)
    {
      const int m = static_cast<int>(offsets[f + 1] - offsets[f]);
      x.assign(3 * m, 0.0);
      u.assign(3 * m, 0.0);
      V3 c = V3::Zero();
      for (int i = 0; i < m; ++i)
      {
        const std::int64_t p = connectivity[offsets[f] + i];
        const V3 xp = At(points, p);
        c += xp;
        V3 up = V3::Zero();
        for (std::int64_t k = start[p]; k < start[p + 1]; ++k)
          if (sameSide(f, around[k]))
            up += At(normals, around[k]);
        up = up.norm() > 0 ? up.normalized() : At(normals, f);
        for (int d = 0; d < 3; ++d)
        {
          x[3 * i + d] = xp[d];
          u[3 * i + d] = up[d];
        }
      }
      centre[f] = m > 0 ? V3(c / m) : c;
      measures[f] = PolygonMeasures(m, x.data(), u.data());
    }
  });

  result.Area = result.TotalMean = result.TotalGaussian = 0;
  double edgeSum = 0;
  std::int64_t edgeCount = 0;
  for (std::int64_t f = 0; f < F; ++f)
  {
    result.Area += measures[f].Mu0;
    result.TotalMean += 0.5 * measures[f].Mu1;
    result.TotalGaussian += measures[f].Mu2;
    const std::int64_t m = offsets[f + 1] - offsets[f];
    for (std::int64_t i = 0; i < m; ++i)
    {
      edgeSum += (At(points, connectivity[offsets[f] + i]) -
        At(points, connectivity[offsets[f] + (i + 1) % m]))
                   .norm();
      ++edgeCount;
    }
  }
  // A face cut by the ball's sphere counts for the share of it inside,
  // estimated from its centre's distance d: 1/2 + (R - d) / l, clamped to
  // [0, 1], l the mean edge length (exact for a square face of side l moving
  // across a plane, and the sphere is locally a plane for R >> l).
  const double l = edgeCount ? edgeSum / edgeCount : 1.0;
  const double R = par.Radius, reach = R + 0.5 * l;
  std::unordered_map<std::int64_t, std::vector<std::int64_t>> grid;
  for (std::int64_t f = 0; f < F; ++f)
    grid[Key(centre[f], reach)].push_back(f);

  result.Mean.assign(F, 0.0);
  result.Gaussian.assign(F, 0.0);
  result.K1.assign(F, 0.0);
  result.K2.assign(F, 0.0);
  result.D1.assign(3 * F, 0.0);
  result.D2.assign(3 * F, 0.0);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      double mu0 = 0, mu1 = 0, mu2 = 0;
      Eigen::Matrix3d muXY = Eigen::Matrix3d::Zero();
      V3 n = V3::Zero();
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz)
          {
            const auto it = grid.find(Key(centre[f], reach, dx, dy, dz));
            if (it == grid.end())
              continue;
            for (std::int64_t g : it->second)
            {
              if (!sameSide(f, g))
                continue;
              const double d = (centre[g] - centre[f]).norm();
              const double w = std::min(1.0, std::max(0.0, 0.5 + (R - d) / l));
              if (w <= 0)
                continue;
              const CorrectedMeasures& m = measures[g];
              mu0 += w * m.Mu0;
              mu1 += w * m.Mu1;
              mu2 += w * m.Mu2;
              muXY += w * Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.MuXY);
              n += w * At(normals, g);
            }
          }
      if (!(mu0 > 0) || n.norm() == 0)
        continue;
      n.normalize();
      result.Mean[f] = mu1 / (2 * mu0);
      result.Gaussian[f] = mu2 / mu0;
      // Principal curvatures: the symmetrised anisotropic measure in the
      // tangent plane of the ball's mean normal.
      const Eigen::Matrix3d T = 0.5 * (muXY + muXY.transpose()) / mu0;
      V3 t1 = n.unitOrthogonal();
      V3 t2 = n.cross(t1);
      Eigen::Matrix2d A;
      A << t1.dot(T * t1), t1.dot(T * t2), t2.dot(T * t1), t2.dot(T * t2);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
      // The measure's tangential eigenvalues are the principal curvatures
      // with the opposite sign (muXY pairs the normal's change along Y with
      // X x u, a quarter turn away), so the smallest is k1.
      const double k1 = -eig.eigenvalues()[0], k2 = -eig.eigenvalues()[1];
      const Eigen::Vector2d e1 = eig.eigenvectors().col(0), e2 = eig.eigenvectors().col(1);
      const V3 d1 = (e1[0] * t1 + e1[1] * t2).normalized();
      const V3 d2 = (e2[0] * t1 + e2[1] * t2).normalized();
      result.K1[f] = k1;
      result.K2[f] = k2;
      for (int d = 0; d < 3; ++d)
      {
        result.D1[3 * f + d] = d1[d];
        result.D2[3 * f + d] = d2[d];
      }
    }
  });
  return true;
}

} // namespace dg
