#include "dgSharpFeaturesRegionFits.h"

#include <vtkSMPTools.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace dg
{
namespace sharp
{

Eigen::Matrix3d RegionSample::Covariance() const
{
  const double n = this->Count;
  const Vec3 c = this->CentroidSum * (1.0 / n);
  Eigen::Matrix3d cov;
  cov(0, 0) = this->Moment[0] / n - c.x * c.x;
  cov(0, 1) = cov(1, 0) = this->Moment[1] / n - c.x * c.y;
  cov(0, 2) = cov(2, 0) = this->Moment[2] / n - c.x * c.z;
  cov(1, 1) = this->Moment[3] / n - c.y * c.y;
  cov(1, 2) = cov(2, 1) = this->Moment[4] / n - c.y * c.z;
  cov(2, 2) = this->Moment[5] / n - c.z * c.z;
  return cov;
}

// The linear fit u(x) = mean + S (x - c) of the normals to the positions
// (cov: the positions' covariance): S, and the normals' cross-covariance
// with the positions, cux. A small ridge: the samples barely spread along
// the normal.
Eigen::Matrix3d RegionSample::NormalSlope(const Eigen::Matrix3d& cov, Eigen::Matrix3d& cux) const
{
  const double n = this->Count;
  const Eigen::Vector3d c(
    this->CentroidSum.x / n, this->CentroidSum.y / n, this->CentroidSum.z / n);
  const Eigen::Vector3d ubar(
    this->NormalSum.x / n, this->NormalSum.y / n, this->NormalSum.z / n);
  cux = this->NormalMoment / n - ubar * c.transpose();
  const Eigen::Matrix3d reg = cov + 1e-3 * cov.trace() * Eigen::Matrix3d::Identity();
  return cux * reg.inverse();
}

// S restricted to the plane of unit normal m and symmetrised, as a shape
// operator is.
Eigen::Matrix3d RegionSample::InPlane(const Eigen::Matrix3d& S, const Eigen::Vector3d& m)
{
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - m * m.transpose();
  const Eigen::Matrix3d St = P * S * P;
  return 0.5 * (St + St.transpose());
}

// How far the side's surface falls below its plane (centroid c, unit
// normal m) at p, relative to its mean fall over the samples (the plane
// passes through their centroid): 1/2 k (|d|^2 - tr Cov_t), d = p - c in
// the plane, k the side's curvature along the edge, taken as isotropic.
// k is the slope along the edge of the normal field's linear fit
// u(x) = mean + S (x - c): the normals, because a digital plane's
// staircase bends the positions but not the regularised normals; along
// the edge, because the normals next to AT's band still lean towards the
// other side (a slope across the edge, which a flat side must not read as
// curvature), and that lean does not change along the edge. The fall is
// shrunk to nothing when k is not significant against the fit's residual
// (James-Stein-like factor 1 - z^2 se^2 / fall^2, z = 3): noise alone
// must not bend a plane.
double RegionSample::Fall(const Vec3& m, const Vec3& p) const
{
  if (this->Count < 6)
    return 0;
  const double n = this->Count;
  const Eigen::Vector3d c(
    this->CentroidSum.x / n, this->CentroidSum.y / n, this->CentroidSum.z / n);
  const Eigen::Vector3d ubar(
    this->NormalSum.x / n, this->NormalSum.y / n, this->NormalSum.z / n);
  const Eigen::Matrix3d cov = this->Covariance();
  Eigen::Matrix3d cux;
  const Eigen::Matrix3d S = this->NormalSlope(cov, cux);
  const Eigen::Vector3d mm(m.x, m.y, m.z);
  const Eigen::Vector3d d0 = Eigen::Vector3d(p.x, p.y, p.z) - c;
  const Eigen::Vector3d d = d0 - mm * mm.dot(d0);
  if (!S.allFinite() || !(d.norm() > 1e-9))
    return 0;
  const Eigen::Vector3d e = mm.cross(d).normalized();
  const double k = e.dot(S * e);
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - mm * mm.transpose();
  const double spread = d.squaredNorm() - (P * cov * P).trace();
  const double fall = 0.5 * k * spread;
  // The slope's standard error: sigma / sqrt(n var_e(x)), sigma^2 the
  // residual variance per tangent component around the fit restricted to
  // the plane and symmetrised, as a shape operator is: what the raw fit
  // explains beyond it (the lean across the edge, a twist) is scatter.
  const Eigen::Matrix3d St = InPlane(S, mm);
  const double cuu = this->NormalSquares / n - ubar.squaredNorm();
  const double rss = std::max(
    0.0, cuu - 2 * (St * cux.transpose()).trace() + (St * cov * St.transpose()).trace());
  const double sigma2 = rss * n / std::max(1.0, 2.0 * (n - 4));
  const double se =
    0.5 * std::abs(spread) * std::sqrt(sigma2 / (n * std::max(e.dot(cov * e), 1e-12)));
  constexpr double z = 3.0;
  const double shrink = std::max(0.0, 1.0 - z * z * se * se / std::max(fall * fall, 1e-300));
  return std::isfinite(fall * shrink) ? fall * shrink : 0.0;
}

// The normal of the least-squares plane through the positions (the
// covariance's smallest eigenvector), turned to the side of the mean field
// normal; the mean field normal itself when the positions do not span a
// plane.
Vec3 RegionSample::PlaneNormal(double maxResidual2) const
{
  const Vec3 mean = this->NormalSum.Unit();
  if (this->Count < 3)
    return mean;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(this->Covariance());
  const Eigen::Vector3d ev = eig.eigenvalues();
  // A line of faces (second eigenvalue ~ 0) does not fix a plane.
  if (!(ev(1) > 1e-3 * std::max(ev(2), 1e-300)) || !(ev(0) <= maxResidual2))
    return mean;
  const Eigen::Vector3d e = eig.eigenvectors().col(0);
  Vec3 nrm(e(0), e(1), e(2));
  return nrm.Dot(mean) < 0 ? nrm * -1.0 : nrm;
}

// Planar regions: the least-squares plane through all a region's faces is
// the plane the voxels show, where a band face's few neighbours show a
// local tilt of it (staircase, noise). The turn is the slope of a linear
// fit of the normals to the positions, u(x) = mean + S (x - c): its largest
// in-plane curvature times the region's extent. AT's normals still lean
// towards the other side next to the band, so true planes measure 3-5
// degrees (cube and sphere's discs, 64^3, k = 0.3), their curved
// neighbours 9 and more.
std::vector<RegionPlane> FindPlanarRegions(const std::vector<int>& region, int regions,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& field, int minimumSize,
  double minimumExtent, double maximumTurnDegrees)
{
  std::vector<RegionPlane> planes(regions);
  std::vector<RegionSample> whole(regions);
  std::vector<Vec3> origin(regions);
  for (std::size_t f = 0; f < region.size(); ++f)
  {
    const int r = region[f];
    if (r < 0)
      continue;
    if (whole[r].Count == 0)
      origin[r] = centre[f]; // small numbers for the moments
    ++whole[r].Count;
    whole[r].AddPosition(centre[f] - origin[r]);
    whole[r].AddNormal(field[f], centre[f] - origin[r]);
  }
  vtkSMPTools::For(0, regions, [&](int b, int e) {
    for (int r = b; r < e; ++r)
    {
      const RegionSample& w = whole[r];
      if (w.Count < minimumSize)
        continue;
      const Eigen::Matrix3d cov = w.Covariance();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
      const Eigen::Vector3d ev = eig.eigenvalues();
      if (!(ev(1) > 1e-3 * std::max(ev(2), 1e-300)) || !(std::sqrt(ev(2)) >= minimumExtent))
        continue;
      const Eigen::Vector3d m = eig.eigenvectors().col(0);
      Eigen::Matrix3d cux;
      const Eigen::Matrix3d S = RegionSample::InPlane(w.NormalSlope(cov, cux), m);
      const Eigen::Vector3d k = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(S).eigenvalues();
      const double turn = std::max(std::abs(k(0)), std::abs(k(2))) * 2.0 * std::sqrt(ev(2));
      if (!(turn * 180.0 / M_PI < maximumTurnDegrees))
        continue;
      const Vec3 nrm(m(0), m(1), m(2));
      planes[r].Normal = nrm.Dot(w.NormalSum) < 0 ? nrm * -1.0 : nrm;
      planes[r].Point = origin[r] + w.CentroidSum * (1.0 / w.Count);
      planes[r].Planar = true;
    }
  });
  return planes;
}

namespace
{
using Vector10 = Eigen::Matrix<double, 10, 1>;

// The monomials of a quadric at y, and their gradients.
void QuadricRows(const Vec3& y, Vector10& value, Vector10& dx, Vector10& dy, Vector10& dz)
{
  value << y.x * y.x, y.y * y.y, y.z * y.z, y.x * y.y, y.x * y.z, y.y * y.z, y.x, y.y, y.z, 1;
  dx << 2 * y.x, 0, 0, y.y, y.z, 0, 1, 0, 0, 0;
  dy << 0, 2 * y.y, 0, y.x, 0, y.z, 0, 1, 0, 0;
  dz << 0, 0, 2 * y.z, 0, y.x, y.y, 0, 0, 1, 0;
}

using Matrix10 = Eigen::Matrix<double, 10, 10>;

// One face's rows of the least squares below, added to its normal equations
// (lower triangle).
void AddQuadricRows(Matrix10& normal, Vector10& rhs, const Vec3& y, const Vec3& n, double w)
{
  Vector10 value, dx, dy, dz;
  QuadricRows(y, value, dx, dy, dz);
  normal.selfadjointView<Eigen::Lower>().rankUpdate(value, w);
  normal.selfadjointView<Eigen::Lower>().rankUpdate(dx);
  normal.selfadjointView<Eigen::Lower>().rankUpdate(dy);
  normal.selfadjointView<Eigen::Lower>().rankUpdate(dz);
  rhs += n.x * dx + n.y * dy + n.z * dz;
}

void SolveQuadric(const Matrix10& normal, const Vector10& rhs, RegionQuadric& q)
{
  Matrix10 a = normal.selfadjointView<Eigen::Lower>();
  // A tiny ridge: a plane-like region leaves the quadratic terms
  // undetermined along the normal.
  a.diagonal().array() += 1e-9 * a.trace();
  const Eigen::LDLT<Matrix10> ldlt(a);
  if (ldlt.info() != Eigen::Success)
    return;
  q.Coefficients = ldlt.solve(rhs);
  q.Valid = q.Coefficients.allFinite();
}
} // namespace

double RegionQuadric::Distance(const Vec3& x) const
{
  Vector10 value, dx, dy, dz;
  QuadricRows((x - this->Centre) * (1.0 / this->Scale), value, dx, dy, dz);
  const Vec3 g(dx.dot(this->Coefficients), dy.dot(this->Coefficients), dz.dot(this->Coefficients));
  const double n = g.Norm();
  return n > 0 ? this->Scale * value.dot(this->Coefficients) / n : 0.0;
}

Vec3 RegionQuadric::Normal(const Vec3& x) const
{
  Vector10 value, dx, dy, dz;
  QuadricRows((x - this->Centre) * (1.0 / this->Scale), value, dx, dy, dz);
  return Vec3(dx.dot(this->Coefficients), dy.dot(this->Coefficients), dz.dot(this->Coefficients))
    .Unit();
}

namespace
{
// Each region's faces, in face order (the order the fits add them in).
struct RegionFaces
{
  std::vector<std::int64_t> Start, Faces;
};

RegionFaces ListRegionFaces(const std::vector<int>& region, int regions)
{
  RegionFaces lists;
  lists.Start.assign(regions + 1, 0);
  for (int r : region)
    if (r >= 0)
      ++lists.Start[r + 1];
  for (int r = 0; r < regions; ++r)
    lists.Start[r + 1] += lists.Start[r];
  lists.Faces.resize(lists.Start[regions]);
  std::vector<std::int64_t> next(lists.Start.begin(), lists.Start.end() - 1);
  for (std::size_t f = 0; f < region.size(); ++f)
    if (region[f] >= 0)
      lists.Faces[next[region[f]]++] = static_cast<std::int64_t>(f);
  return lists;
}
} // namespace

// Linear least squares in the ten coefficients of Q in the scaled
// coordinates y = (x - c) / s: sum over the faces of (s Q(y_i) / unit)^2 +
// |grad Q(y_i) - n_i|^2. The normals' term fixes the scale of Q (no
// trivial zero, no normalisation constraint to choose) and its sign (grad Q
// points outside); on a sphere of radius R, Q = (|x - c|^2 - R^2) / 2R
// makes both terms vanish. AT's normals are smooth where the positions
// carry the staircase and the noise, so both count: a position residual of
// one edge length weighs as a normal residual of one radian.
std::vector<RegionQuadric> FitRegionQuadrics(const std::vector<int>& region, int regions,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& field, const std::vector<char>& skip,
  int minimumSize, double minimumExtent, double unit)
{
  std::vector<RegionQuadric> quadrics(regions);
  const RegionFaces lists = ListRegionFaces(region, regions);
  // One region per task, its faces in face order: the sums are those of a
  // single pass over the faces.
  vtkSMPTools::For(0, regions, [&](int begin, int end) {
    for (int r = begin; r < end; ++r)
    {
      const std::int64_t* faces = lists.Faces.data() + lists.Start[r];
      const std::int64_t count = lists.Start[r + 1] - lists.Start[r];
      if (skip[r] || count == 0)
        continue;
      Vec3 sum;
      for (std::int64_t i = 0; i < count; ++i)
        sum += centre[faces[i]];
      RegionQuadric& q = quadrics[r];
      q.Centre = sum * (1.0 / static_cast<double>(count));
      double extent = 0;
      for (std::int64_t i = 0; i < count; ++i)
        extent = std::max(extent, (centre[faces[i]] - q.Centre).Norm());
      if (count < minimumSize || extent < minimumExtent || !(extent > 0))
        continue;
      q.Scale = extent;
      Matrix10 normal = Matrix10::Zero();
      Vector10 rhs = Vector10::Zero();
      for (std::int64_t i = 0; i < count; ++i)
        AddQuadricRows(normal, rhs, (centre[faces[i]] - q.Centre) * (1.0 / extent),
          field[faces[i]], extent * extent / (unit * unit));
      SolveQuadric(normal, rhs, q);
    }
  });
  return quadrics;
}

std::vector<RegionQuadric> FitQuadricSides(const std::vector<int>& region, int regions,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& field, const std::vector<char>& wanted,
  int minimumSize, double minimumExtent, double unit, double maxResidual)
{
  std::vector<char> skip(regions);
  for (int r = 0; r < regions; ++r)
    skip[r] = !wanted[r];
  std::vector<RegionQuadric> quadrics =
    FitRegionQuadrics(region, regions, centre, field, skip, minimumSize, minimumExtent, unit);
  const std::int64_t F = static_cast<std::int64_t>(region.size());
  std::vector<double> distance2(F, 0.0);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
      if (region[f] >= 0 && quadrics[region[f]].Valid)
      {
        const double d = quadrics[region[f]].Distance(centre[f]);
        distance2[f] = d * d;
      }
  });
  std::vector<double> sum2(regions, 0.0);
  std::vector<std::int64_t> count(regions, 0);
  for (std::int64_t f = 0; f < F; ++f)
    if (region[f] >= 0)
    {
      sum2[region[f]] += distance2[f];
      ++count[region[f]];
    }
  for (int r = 0; r < regions; ++r)
    quadrics[r].Valid =
      quadrics[r].Valid && count[r] > 0 && std::sqrt(sum2[r] / count[r]) <= maxResidual;
  return quadrics;
}

RegionQuadric FitQuadric(const std::vector<std::int64_t>& faces, const std::vector<Vec3>& centre,
  const std::vector<Vec3>& field, double unit)
{
  RegionQuadric q;
  if (faces.size() < 10)
    return q;
  Vec3 sum;
  for (std::int64_t f : faces)
    sum += centre[f];
  q.Centre = sum * (1.0 / static_cast<double>(faces.size()));
  double extent = 0;
  for (std::int64_t f : faces)
    extent = std::max(extent, (centre[f] - q.Centre).Norm());
  if (!(extent > 0))
    return q;
  q.Scale = extent;
  Matrix10 normal = Matrix10::Zero();
  Vector10 rhs = Vector10::Zero();
  for (std::int64_t f : faces)
    AddQuadricRows(normal, rhs, (centre[f] - q.Centre) * (1.0 / extent), field[f],
      extent * extent / (unit * unit));
  SolveQuadric(normal, rhs, q);
  return q;
}

} // namespace sharp
} // namespace dg
