#include "dgGroundTruth.h"

#include "dgNoise.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSet.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace dgtest
{
namespace
{
using V3 = Eigen::Vector3d;
constexpr double Inf = std::numeric_limits<double>::infinity();
constexpr double SampleStep = 0.25; // polylines are this fine

double SegmentDistance(const V3& p, const V3& a, const V3& b)
{
  const V3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

struct Plane
{
  V3 N;     // unit outward normal
  double D; // n.(p - c) <= D inside
};

// Convex polyhedron as an intersection of half-spaces, optionally intersected
// with a sphere of the same centre.
class ConvexShape : public ImplicitShape
{
public:
  ConvexShape(std::string name, const V3& c, std::vector<Plane> planes, double sphereRadius = Inf)
    : NameText(std::move(name))
    , C(c)
    , Planes(std::move(planes))
    , R(sphereRadius)
  {
    this->BuildEdges();
  }
  std::string Name() const override { return this->NameText; }
  double Value(const V3& p) const override
  {
    double f = -Inf;
    for (const auto& pl : this->Planes)
    {
      f = std::max(f, pl.N.dot(p - this->C) - pl.D);
    }
    if (std::isfinite(this->R))
    {
      f = std::max(f, (p - this->C).norm() - this->R);
    }
    return f;
  }
  V3 Normal(const V3& p) const override
  {
    double f = -Inf;
    V3 n(0, 0, 1);
    for (const auto& pl : this->Planes)
    {
      const double v = pl.N.dot(p - this->C) - pl.D;
      if (v > f)
      {
        f = v;
        n = pl.N;
      }
    }
    if (std::isfinite(this->R) && (p - this->C).norm() - this->R > f)
    {
      n = (p - this->C).normalized();
    }
    return n;
  }

private:
  bool InsidePlanes(const V3& x, int skipA, int skipB) const
  {
    for (int k = 0; k < static_cast<int>(this->Planes.size()); ++k)
    {
      if (k != skipA && k != skipB && this->Planes[k].N.dot(x - this->C) > this->Planes[k].D + 1e-9)
      {
        return false;
      }
    }
    return true;
  }
  bool InsideSphere(const V3& x) const
  {
    return !std::isfinite(this->R) || (x - this->C).norm() <= this->R + 1e-9;
  }
  // Keeps the runs of consecutive samples that satisfy keep().
  template <typename Keep>
  void AddKeptRuns(const std::vector<V3>& samples, bool closed, Keep keep)
  {
    std::vector<V3> run;
    std::vector<std::vector<V3>> runs;
    for (const auto& s : samples)
    {
      if (keep(s))
      {
        run.push_back(s);
      }
      else if (!run.empty())
      {
        runs.push_back(run);
        run.clear();
      }
    }
    if (!run.empty())
    {
      if (closed && !runs.empty() && keep(samples.front()))
      {
        run.insert(run.end(), runs.front().begin(), runs.front().end());
        runs.front() = run;
      }
      else
      {
        if (closed && runs.empty() && run.size() == samples.size())
        {
          run.push_back(samples.front());
        }
        runs.push_back(run);
      }
    }
    for (auto& r : runs)
    {
      if (r.size() >= 2)
      {
        this->AddPolyline(r);
      }
    }
  }
  void BuildEdges()
  {
    const int n = static_cast<int>(this->Planes.size());
    for (int a = 0; a < n; ++a)
    {
      for (int b = a + 1; b < n; ++b)
      {
        const V3& na = this->Planes[a].N;
        const V3& nb = this->Planes[b].N;
        const V3 t = na.cross(nb);
        if (t.norm() < 1e-9)
        {
          continue;
        }
        // A point on both planes: minimum-norm solution of the 2x3 system.
        Eigen::Matrix<double, 2, 3> M;
        M.row(0) = na;
        M.row(1) = nb;
        const Eigen::Vector2d rhs(this->Planes[a].D, this->Planes[b].D);
        const V3 x0 = M.transpose() * (M * M.transpose()).inverse() * rhs;
        const V3 dir = t.normalized();
        // Clip the line by the other half-spaces.
        double lo = -1e6, hi = 1e6;
        bool empty = false;
        for (int k = 0; k < n && !empty; ++k)
        {
          if (k == a || k == b)
            continue;
          const double s = this->Planes[k].N.dot(dir);
          const double r = this->Planes[k].D - this->Planes[k].N.dot(x0);
          if (std::fabs(s) < 1e-12)
          {
            empty = r < 0;
          }
          else if (s > 0)
          {
            hi = std::min(hi, r / s);
          }
          else
          {
            lo = std::max(lo, r / s);
          }
        }
        if (empty || hi - lo < 1e-9)
        {
          continue;
        }
        std::vector<V3> samples;
        const int m = std::max(1, static_cast<int>(std::ceil((hi - lo) / SampleStep)));
        for (int s = 0; s <= m; ++s)
        {
          samples.push_back(this->C + x0 + (lo + (hi - lo) * s / m) * dir);
        }
        this->AddKeptRuns(samples, false, [&](const V3& x) { return this->InsideSphere(x); });
      }
    }
    if (!std::isfinite(this->R))
    {
      return;
    }
    // Circles where the sphere meets each face plane.
    for (int a = 0; a < n; ++a)
    {
      const V3& na = this->Planes[a].N;
      const double d = this->Planes[a].D;
      if (d >= this->R)
      {
        continue;
      }
      const double rho = std::sqrt(this->R * this->R - d * d);
      V3 u = na.unitOrthogonal();
      V3 w = na.cross(u);
      const int m = std::max(8, static_cast<int>(std::ceil(2 * M_PI * rho / SampleStep)));
      std::vector<V3> samples;
      for (int s = 0; s < m; ++s)
      {
        const double th = 2 * M_PI * s / m;
        samples.push_back(this->C + d * na + rho * (std::cos(th) * u + std::sin(th) * w));
      }
      this->AddKeptRuns(samples, true, [&](const V3& x) { return this->InsidePlanes(x, a, -1); });
    }
  }

  std::string NameText;
  V3 C;
  std::vector<Plane> Planes;
  double R;
};

class SphereShape : public ImplicitShape
{
public:
  SphereShape(const V3& c, double r)
    : C(c)
    , R(r)
  {
  }
  std::string Name() const override { return "sphere"; }
  double Value(const V3& p) const override { return (p - this->C).norm() - this->R; }
  V3 Normal(const V3& p) const override
  {
    const V3 d = p - this->C;
    return d.norm() > 0 ? V3(d.normalized()) : V3(0, 0, 1);
  }

private:
  V3 C;
  double R;
};

class CylinderShape : public ImplicitShape
{
public:
  CylinderShape(const V3& c, double r, double hz)
    : C(c)
    , R(r)
    , HZ(hz)
  {
    for (double sz : { -1.0, 1.0 })
    {
      const int m = static_cast<int>(std::ceil(2 * M_PI * r / SampleStep));
      std::vector<V3> line;
      for (int s = 0; s <= m; ++s)
      {
        const double th = 2 * M_PI * s / m;
        line.push_back(c + V3(r * std::cos(th), r * std::sin(th), sz * hz));
      }
      this->AddPolyline(line);
    }
  }
  std::string Name() const override { return "cylinder"; }
  double Value(const V3& p) const override
  {
    const V3 d = p - this->C;
    return std::max(std::hypot(d.x(), d.y()) - this->R, std::fabs(d.z()) - this->HZ);
  }
  V3 Normal(const V3& p) const override
  {
    const V3 d = p - this->C;
    const double radial = std::hypot(d.x(), d.y()) - this->R;
    const double axial = std::fabs(d.z()) - this->HZ;
    if (axial > radial)
    {
      return V3(0, 0, d.z() >= 0 ? 1 : -1);
    }
    const double rr = std::hypot(d.x(), d.y());
    return rr > 0 ? V3(d.x() / rr, d.y() / rr, 0) : V3(1, 0, 0);
  }

private:
  V3 C;
  double R, HZ;
};

} // namespace

void PolylineDistance::AddSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  this->A.push_back(a);
  this->B.push_back(b);
  this->BuildOnce = std::make_shared<std::once_flag>();
}

double PolylineDistance::TotalLength() const
{
  double l = 0;
  for (std::size_t s = 0; s < this->A.size(); ++s)
  {
    l += (this->B[s] - this->A[s]).norm();
  }
  return l;
}

void PolylineDistance::Build() const
{
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(Inf), hi = Eigen::Vector3d::Constant(-Inf);
  for (std::size_t s = 0; s < this->A.size(); ++s)
  {
    lo = lo.cwiseMin(this->A[s]).cwiseMin(this->B[s]);
    hi = hi.cwiseMax(this->A[s]).cwiseMax(this->B[s]);
  }
  for (int a = 0; a < 3; ++a)
  {
    this->GridMin[a] = static_cast<int>(std::floor(lo[a] / this->Cell)) - 1;
    this->GridSize[a] = static_cast<int>(std::floor(hi[a] / this->Cell)) + 2 - this->GridMin[a];
  }
  this->Buckets.assign(static_cast<std::size_t>(this->GridSize.prod()), {});
  for (std::size_t s = 0; s < this->A.size(); ++s)
  {
    const Eigen::Vector3d l = this->A[s].cwiseMin(this->B[s]);
    const Eigen::Vector3d h = this->A[s].cwiseMax(this->B[s]);
    Eigen::Vector3i c0, c1;
    for (int a = 0; a < 3; ++a)
    {
      c0[a] = static_cast<int>(std::floor(l[a] / this->Cell)) - this->GridMin[a];
      c1[a] = static_cast<int>(std::floor(h[a] / this->Cell)) - this->GridMin[a];
    }
    for (int z = c0[2]; z <= c1[2]; ++z)
      for (int y = c0[1]; y <= c1[1]; ++y)
        for (int x = c0[0]; x <= c1[0]; ++x)
        {
          this->Buckets[(static_cast<std::size_t>(z) * this->GridSize[1] + y) * this->GridSize[0] + x]
            .push_back(static_cast<int>(s));
        }
  }
}

double PolylineDistance::Distance(const Eigen::Vector3d& p, double maxDistance) const
{
  if (this->A.empty())
  {
    return Inf;
  }
  std::call_once(*this->BuildOnce, [this] { this->Build(); });
  Eigen::Vector3i c0, c1;
  for (int a = 0; a < 3; ++a)
  {
    c0[a] = std::max(0, static_cast<int>(std::floor((p[a] - maxDistance) / this->Cell)) - this->GridMin[a]);
    c1[a] = std::min(this->GridSize[a] - 1,
      static_cast<int>(std::floor((p[a] + maxDistance) / this->Cell)) - this->GridMin[a]);
  }
  double best = Inf;
  for (int z = c0[2]; z <= c1[2]; ++z)
    for (int y = c0[1]; y <= c1[1]; ++y)
      for (int x = c0[0]; x <= c1[0]; ++x)
      {
        for (int s :
          this->Buckets[(static_cast<std::size_t>(z) * this->GridSize[1] + y) * this->GridSize[0] + x])
        {
          best = std::min(best, SegmentDistance(p, this->A[s], this->B[s]));
        }
      }
  return best;
}

void ImplicitShape::AddPolyline(const std::vector<Eigen::Vector3d>& line)
{
  this->EdgePolylines.push_back(line);
  for (std::size_t s = 0; s + 1 < line.size(); ++s)
  {
    this->Edges.AddSegment(line[s], line[s + 1]);
  }
}

std::vector<Eigen::Vector3d> ImplicitShape::SharpEdgeSamples(double step) const
{
  std::vector<Eigen::Vector3d> out;
  for (const auto& line : this->EdgePolylines)
  {
    for (std::size_t s = 0; s + 1 < line.size(); ++s)
    {
      const double l = (line[s + 1] - line[s]).norm();
      const int m = std::max(1, static_cast<int>(std::ceil(l / step)));
      for (int t = 0; t < m; ++t)
      {
        out.push_back(line[s] + (line[s + 1] - line[s]) * (static_cast<double>(t) / m));
      }
    }
    out.push_back(line.back());
  }
  return out;
}

// Smooth shapes (issue 39): no sharp edge; each shape's Normal is the
// normal at the surface point nearest to p.
namespace
{
Eigen::Matrix3d Rotation(double ax, double ay, double az)
{
  const double d = M_PI / 180;
  return (Eigen::AngleAxisd(az * d, V3::UnitZ()) * Eigen::AngleAxisd(ay * d, V3::UnitY()) *
    Eigen::AngleAxisd(ax * d, V3::UnitX()))
    .toRotationMatrix();
}

class TorusShape : public ImplicitShape
{
public:
  TorusShape(const V3& c, const Eigen::Matrix3d& r, double major, double minor)
    : C(c)
    , R(r)
    , Major(major)
    , Minor(minor)
  {
  }
  std::string Name() const override { return "torus"; }
  double Value(const V3& p) const override
  {
    const V3 q = this->R.transpose() * (p - this->C);
    return std::hypot(std::hypot(q.x(), q.y()) - this->Major, q.z()) - this->Minor;
  }
  V3 Normal(const V3& p) const override
  {
    const V3 q = this->R.transpose() * (p - this->C);
    const double rho = std::hypot(q.x(), q.y());
    const V3 ring = rho > 0 ? V3(q.x() / rho * this->Major, q.y() / rho * this->Major, 0)
                            : V3(this->Major, 0, 0);
    const V3 d = q - ring;
    return this->R * (d.norm() > 0 ? V3(d.normalized()) : V3(0, 0, 1));
  }

private:
  V3 C;
  Eigen::Matrix3d R;
  double Major, Minor;
};

class EllipsoidShape : public ImplicitShape
{
public:
  EllipsoidShape(const V3& c, const Eigen::Matrix3d& r, const V3& axes)
    : C(c)
    , R(r)
    , A(axes)
  {
  }
  std::string Name() const override { return "ellipsoid"; }
  // First-order distance |x/a| - 1 scaled by the gradient: < 0 inside.
  double Value(const V3& p) const override
  {
    const V3 q = this->R.transpose() * (p - this->C);
    const double k0 = q.cwiseQuotient(this->A).norm();
    const double k1 = q.cwiseQuotient(this->A.cwiseProduct(this->A)).norm();
    return k1 > 0 ? k0 * (k0 - 1) / k1 : -this->A.minCoeff();
  }
  // The nearest surface point x_i = q_i a_i^2 / (a_i^2 + t), Newton on t.
  V3 Normal(const V3& p) const override
  {
    const V3 q = this->R.transpose() * (p - this->C);
    const V3 a2 = this->A.cwiseProduct(this->A);
    double t = 0;
    for (int it = 0; it < 50; ++it)
    {
      double f = -1, df = 0;
      for (int i = 0; i < 3; ++i)
      {
        const double s = a2[i] + t;
        f += q[i] * q[i] * a2[i] / (s * s);
        df += -2 * q[i] * q[i] * a2[i] / (s * s * s);
      }
      if (df == 0)
        break;
      t = std::max(t - f / df, -0.999 * a2.minCoeff());
    }
    V3 n;
    for (int i = 0; i < 3; ++i)
      n[i] = q[i] / (a2[i] + t);
    return this->R * (n.norm() > 0 ? V3(n.normalized()) : V3(0, 0, 1));
  }

private:
  V3 C;
  Eigen::Matrix3d R;
  V3 A;
};

// A box whose edges and corners are rounded with radius rho (the set of
// points within rho of the box shrunk by rho): its signed distance is exact.
class RoundedBoxShape : public ImplicitShape
{
public:
  RoundedBoxShape(const V3& c, const Eigen::Matrix3d& r, const V3& half, double rho)
    : C(c)
    , R(r)
    , Inner(half - V3::Constant(rho))
    , Rho(rho)
  {
  }
  std::string Name() const override { return "rounded box"; }
  double Value(const V3& p) const override
  {
    const V3 q = (this->R.transpose() * (p - this->C)).cwiseAbs() - this->Inner;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - this->Rho;
  }
  V3 Normal(const V3& p) const override
  {
    const V3 l = this->R.transpose() * (p - this->C);
    const V3 q = l.cwiseAbs() - this->Inner;
    V3 n = q.cwiseMax(0.0);
    if (n.norm() == 0)
    {
      Eigen::Index i;
      q.maxCoeff(&i);
      n = V3::Unit(i);
    }
    n.normalize();
    for (int i = 0; i < 3; ++i)
      n[i] = l[i] < 0 ? -n[i] : n[i];
    return this->R * n;
  }

private:
  V3 C;
  Eigen::Matrix3d R;
  V3 Inner;
  double Rho;
};

// A box (half sides a, b, c along its local x, y, z) whose eight edges
// around its two z faces are rounded with radius rho and whose four edges
// along z are sharp: the intersection of two extruded rounded rectangles,
// one in (x, z), one in (y, z). Each is a distance, their maximum is one
// inside and on the surface; the normal is the larger one's. The sharp
// edges run where both are flat, |z| <= c - rho; past that the two fillets
// meet along a crease that fades from 90 degrees to none at the z faces,
// which the edge list leaves out.
class MixedBoxShape : public ImplicitShape
{
public:
  MixedBoxShape(const V3& c, const Eigen::Matrix3d& r, const V3& half, double rho)
    : C(c)
    , R(r)
    , Half(half)
    , Rho(rho)
  {
    for (double sx : { -1.0, 1.0 })
      for (double sy : { -1.0, 1.0 })
        this->AddPolyline({ c + r * V3(sx * half.x(), sy * half.y(), -(half.z() - rho)),
          c + r * V3(sx * half.x(), sy * half.y(), half.z() - rho) });
  }
  std::string Name() const override { return "box with sharp and rounded edges"; }
  double Value(const V3& p) const override
  {
    const V3 l = this->R.transpose() * (p - this->C);
    return std::max(this->Profile(l.x(), l.z(), this->Half.x()).first,
      this->Profile(l.y(), l.z(), this->Half.y()).first);
  }
  V3 Normal(const V3& p) const override
  {
    const V3 l = this->R.transpose() * (p - this->C);
    const auto x = this->Profile(l.x(), l.z(), this->Half.x());
    const auto y = this->Profile(l.y(), l.z(), this->Half.y());
    const V3 n = x.first >= y.first ? V3(x.second.x(), 0, x.second.y()) : V3(0, y.second.x(), y.second.y());
    return this->R * n;
  }

private:
  // The signed distance to the rectangle |u| <= hu, |v| <= Half.z with
  // rounded corners, and its outward unit gradient.
  std::pair<double, Eigen::Vector2d> Profile(double u, double v, double hu) const
  {
    const Eigen::Vector2d q(std::abs(u) - (hu - this->Rho), std::abs(v) - (this->Half.z() - this->Rho));
    Eigen::Vector2d g = q.cwiseMax(0.0);
    double d = g.norm() + std::min(q.maxCoeff(), 0.0) - this->Rho;
    if (g.norm() > 0)
      g.normalize();
    else
      g = q.x() > q.y() ? Eigen::Vector2d(1, 0) : Eigen::Vector2d(0, 1);
    g.x() = u < 0 ? -g.x() : g.x();
    g.y() = v < 0 ? -g.y() : g.y();
    return { d, g };
  }
  V3 C;
  Eigen::Matrix3d R;
  V3 Half;
  double Rho;
};

// A right prism over a regular polygon of `sides` sides (apothem `apothem`,
// axis z, half height `halfZ`) whose edges and corners are rounded with
// `rho`: the points within rho of the prism shrunk by rho. The nearest point
// of a product of convex sets is the product of the nearest points, so the
// distance is exact: the polygon's in the plane, the clamp along z.
class RoundedPrismShape : public ImplicitShape
{
public:
  RoundedPrismShape(const V3& c, const Eigen::Matrix3d& r, int sides, double apothem, double halfZ, double rho)
    : C(c)
    , R(r)
    , Sides(sides)
    , Apothem(apothem - rho)
    , HalfZ(halfZ - rho)
    , Rho(rho)
  {
  }
  std::string Name() const override { return "rounded prism"; }
  double Value(const V3& p) const override
  {
    const V3 l = this->R.transpose() * (p - this->C);
    const V3 q = this->Nearest(l);
    const double outside = (l - q).norm();
    if (outside > 0)
      return outside - this->Rho;
    return std::max(this->Inside(l).first, std::abs(l.z()) - this->HalfZ) - this->Rho;
  }
  V3 Normal(const V3& p) const override
  {
    const V3 l = this->R.transpose() * (p - this->C);
    V3 n = l - this->Nearest(l);
    if (n.norm() == 0)
    {
      const auto side = this->Inside(l);
      n = std::abs(l.z()) - this->HalfZ > side.first ? V3(0, 0, l.z() < 0 ? -1 : 1) : side.second;
    }
    return this->R * n.normalized();
  }

private:
  // The largest signed distance to the polygon's edge lines, and that
  // edge's outward normal.
  std::pair<double, V3> Inside(const V3& l) const
  {
    std::pair<double, V3> best(-std::numeric_limits<double>::infinity(), V3::UnitX());
    for (int i = 0; i < this->Sides; ++i)
    {
      const double a = 2 * M_PI * i / this->Sides;
      const V3 n(std::cos(a), std::sin(a), 0);
      const double d = n.dot(V3(l.x(), l.y(), 0)) - this->Apothem;
      if (d > best.first)
        best = { d, n };
    }
    return best;
  }
  V3 Nearest(const V3& l) const
  {
    const double z = std::max(-this->HalfZ, std::min(this->HalfZ, l.z()));
    const Eigen::Vector2d x(l.x(), l.y());
    if (this->Inside(l).first <= 0)
      return V3(x.x(), x.y(), z);
    // Outside the polygon: the nearest point of its edges.
    const double corner = this->Apothem / std::cos(M_PI / this->Sides);
    Eigen::Vector2d best = x;
    double bestD = std::numeric_limits<double>::infinity();
    for (int i = 0; i < this->Sides; ++i)
    {
      const double a0 = 2 * M_PI * (i - 0.5) / this->Sides, a1 = 2 * M_PI * (i + 0.5) / this->Sides;
      const Eigen::Vector2d u(corner * std::cos(a0), corner * std::sin(a0));
      const Eigen::Vector2d v(corner * std::cos(a1), corner * std::sin(a1));
      const double t = std::max(0.0, std::min(1.0, (x - u).dot(v - u) / (v - u).squaredNorm()));
      const Eigen::Vector2d e = u + t * (v - u);
      if ((x - e).squaredNorm() < bestD)
      {
        bestD = (x - e).squaredNorm();
        best = e;
      }
    }
    return V3(best.x(), best.y(), z);
  }

  V3 C;
  Eigen::Matrix3d R;
  int Sides;
  double Apothem, HalfZ, Rho;
};

// The soft minimum of the balls' distances. It is not a distance (it lies
// below the true one by at most s log m), so Normal projects p onto the
// zero set along the gradient before it reads the normal there.
class BlobsShape : public ImplicitShape
{
public:
  BlobsShape(const std::vector<V3>& c, const std::vector<double>& r, double s)
    : C(c)
    , R(r)
    , S(s)
  {
  }
  std::string Name() const override { return "blobs"; }
  double Value(const V3& p) const override
  {
    V3 g;
    return this->Evaluate(p, g);
  }
  V3 Normal(const V3& p) const override
  {
    V3 x = p, g;
    for (int it = 0; it < 30; ++it)
    {
      const double f = this->Evaluate(x, g);
      const double g2 = g.squaredNorm();
      if (g2 == 0 || std::abs(f) < 1e-10)
        break;
      x -= f / g2 * g;
    }
    this->Evaluate(x, g);
    return g.norm() > 0 ? V3(g.normalized()) : V3(0, 0, 1);
  }

private:
  double Evaluate(const V3& p, V3& gradient) const
  {
    double lo = std::numeric_limits<double>::infinity();
    std::vector<double> d(this->C.size());
    for (std::size_t i = 0; i < this->C.size(); ++i)
    {
      d[i] = (p - this->C[i]).norm() - this->R[i];
      lo = std::min(lo, d[i]);
    }
    double sum = 0;
    gradient.setZero();
    for (std::size_t i = 0; i < this->C.size(); ++i)
    {
      const double w = std::exp(-(d[i] - lo) / this->S);
      sum += w;
      const V3 u = p - this->C[i];
      if (u.norm() > 0)
        gradient += w * u.normalized();
    }
    gradient /= sum;
    return lo - this->S * std::log(sum);
  }

  std::vector<V3> C;
  std::vector<double> R;
  double S;
};

} // namespace

std::unique_ptr<ImplicitShape> MakeBlobs(
  const std::vector<Eigen::Vector3d>& centers, const std::vector<double>& radii, double blend)
{
  return std::make_unique<BlobsShape>(centers, radii, blend);
}

std::unique_ptr<ImplicitShape> MakeSmoothShape(const std::string& name, int n)
{
  using V3 = Eigen::Vector3d;
  // Off the grid's symmetry so that no digitisation is exactly symmetric.
  const V3 c = V3::Constant(0.5 * (n - 1)) + V3(0.13, 0.07, 0.11);
  const double s = n / 64.0;
  if (name == "torus")
    return MakeTorus(c, 0.3 * n, 0.16 * n, 20, 30, 10);
  if (name == "torus2")
    return MakeTorus(c, 0.3 * n, 0.16 * n, 35, 10, 50);
  if (name == "sphere")
    return MakeSphere(c, 0.19 * n);
  if (name == "ellipsoid")
    return MakeEllipsoid(c, V3(26, 20, 16) * s, 20, 30, 10);
  if (name == "ellipsoid2")
    return MakeEllipsoid(c, V3(26, 20, 16) * s, 35, 10, 50);
  if (name == "blobs")
  {
    // Blend 4 voxels at 64^3: the smallest curvature radius (at the
    // necks' saddles) is 7.0 voxels, measured on a 0.05-voxel grid; blend
    // 3 gives 3.2, below what the issue calls smooth.
    const std::vector<V3> offsets = { V3(0, 0, 0), V3(15, 3, -2), V3(-9, 13, 4), V3(-6, -12, 9),
      V3(3, -2, -15) };
    const std::vector<double> radii = { 12, 8, 7.5, 7, 8 };
    std::vector<V3> centers;
    std::vector<double> scaled;
    for (std::size_t i = 0; i < offsets.size(); ++i)
    {
      centers.push_back(c + s * offsets[i]);
      scaled.push_back(s * radii[i]);
    }
    return MakeBlobs(centers, scaled, 4 * s);
  }
  for (int sides : { 6, 8, 12 })
    for (int radius = 2; radius <= 12; ++radius)
      if (name == "prism" + std::to_string(sides) + "r" + std::to_string(radius))
        return std::make_unique<RoundedPrismShape>(
          c, Rotation(20, 30, 10), sides, 0.3 * n, 0.22 * n, radius);
  for (int radius = 2; radius <= 12; ++radius)
    if (name == "fillet" + std::to_string(radius))
    {
      const V3 half = V3(0.3, 0.26, 0.22) * n;
      // Two orientations among the radii, as for the tori.
      return radius == 10 ? MakeRoundedBox(c, half, radius, 35, 10, 50)
                          : MakeRoundedBox(c, half, radius, 20, 30, 10);
    }
  return nullptr;
}

std::unique_ptr<ImplicitShape> MakeTorus(
  const Eigen::Vector3d& center, double major, double minor, double ax, double ay, double az)
{
  return std::make_unique<TorusShape>(center, Rotation(ax, ay, az), major, minor);
}

std::unique_ptr<ImplicitShape> MakeEllipsoid(
  const Eigen::Vector3d& center, const Eigen::Vector3d& axes, double ax, double ay, double az)
{
  return std::make_unique<EllipsoidShape>(center, Rotation(ax, ay, az), axes);
}

std::unique_ptr<ImplicitShape> MakeMixedBox(const Eigen::Vector3d& center,
  const Eigen::Vector3d& half, double radius, double ax, double ay, double az)
{
  return std::make_unique<MixedBoxShape>(center, Rotation(ax, ay, az), half, radius);
}

std::unique_ptr<ImplicitShape> MakeRoundedBox(const Eigen::Vector3d& center,
  const Eigen::Vector3d& half, double radius, double ax, double ay, double az)
{
  return std::make_unique<RoundedBoxShape>(center, Rotation(ax, ay, az), half, radius);
}

std::unique_ptr<ImplicitShape> MakeSphere(const Eigen::Vector3d& center, double radius)
{
  return std::make_unique<SphereShape>(center, radius);
}

std::unique_ptr<ImplicitShape> MakeRotatedCube(
  const Eigen::Vector3d& center, double h, double ax, double ay, double az)
{
  const double d = M_PI / 180;
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(az * d, V3::UnitZ()) *
    Eigen::AngleAxisd(ay * d, V3::UnitY()) * Eigen::AngleAxisd(ax * d, V3::UnitX()))
                              .toRotationMatrix();
  std::vector<Plane> planes;
  for (int a = 0; a < 3; ++a)
  {
    planes.push_back({ R.col(a), h });
    planes.push_back({ -R.col(a), h });
  }
  return std::make_unique<ConvexShape>("rotated cube", center, planes);
}

std::unique_ptr<ImplicitShape> MakeCubeSphere(const Eigen::Vector3d& center, double h, double r)
{
  return MakeCubeSphere(center, { h, h, h, h, h, h }, r);
}

std::unique_ptr<ImplicitShape> MakeCubeSphere(
  const Eigen::Vector3d& center, const std::array<double, 6>& h, double r)
{
  std::vector<Plane> planes;
  for (int a = 0; a < 3; ++a)
  {
    planes.push_back({ V3::Unit(a), h[2 * a] });
    planes.push_back({ -V3::Unit(a), h[2 * a + 1] });
  }
  return std::make_unique<ConvexShape>("cube-sphere", center, planes, r);
}

std::unique_ptr<ImplicitShape> MakeCylinder(const Eigen::Vector3d& center, double r, double hz)
{
  return std::make_unique<CylinderShape>(center, r, hz);
}

std::unique_ptr<ImplicitShape> MakeOctahedron(const Eigen::Vector3d& center, double a)
{
  std::vector<Plane> planes;
  for (int s = 0; s < 8; ++s)
  {
    const V3 n((s & 1) ? 1 : -1, (s & 2) ? 1 : -1, (s & 4) ? 1 : -1);
    planes.push_back({ n / std::sqrt(3.0), a / std::sqrt(3.0) });
  }
  return std::make_unique<ConvexShape>("octahedron", center, planes);
}

std::unique_ptr<ImplicitShape> MakeWedge(const Eigen::Vector3d& center, double h)
{
  const double t = std::tan(15 * M_PI / 180);
  const double len = std::sqrt(1 + t * t);
  std::vector<Plane> planes = { { V3(1, 0, 0), h }, { V3(-1, 0, 0), h }, { V3(0, 1, 0), h },
    { V3(0, -1, 0), h }, { V3(0, 0, -1), h }, { V3(t, 0, 1) / len, h / len },
    { V3(-t, 0, 1) / len, h / len } };
  return std::make_unique<ConvexShape>("wedge", center, planes);
}

vtkSmartPointer<vtkImageData> Digitize(const ImplicitShape& shape, int n)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(n, n, n);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  auto* s = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  s->SetName("Inside");
  vtkIdType id = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        s->SetValue(id++, shape.Inside(V3(i, j, k)) ? 1 : 0);
      }
  return image;
}

vtkSmartPointer<vtkImageData> NoisyDigitize(
  const ImplicitShape& shape, int n, double k, std::uint64_t seed)
{
  auto image = Digitize(shape, n);
  auto* s = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  std::vector<std::uint8_t> m(s->GetPointer(0), s->GetPointer(0) + s->GetNumberOfValues());
  const int dims[3] = { n, n, n };
  dg::ApplyNoise(m, dims, k, seed);
  std::copy(m.begin(), m.end(), s->GetPointer(0));
  return image;
}

std::vector<Eigen::Vector3d> SurfelCenters(vtkDataObject* digitalSurface)
{
  std::vector<Eigen::Vector3d> out;
  auto* ds = vtkDataSet::SafeDownCast(digitalSurface);
  if (!ds)
  {
    return out;
  }
  vtkDataArray* vox = ds->GetCellData()->GetArray("InsideVoxel");
  vtkDataArray* dir = ds->GetCellData()->GetArray("SurfelDirection");
  if (!vox || !dir)
  {
    return out;
  }
  out.resize(static_cast<std::size_t>(vox->GetNumberOfTuples()));
  for (vtkIdType c = 0; c < vox->GetNumberOfTuples(); ++c)
  {
    const int d = static_cast<int>(dir->GetTuple1(c));
    V3 p(vox->GetComponent(c, 0), vox->GetComponent(c, 1), vox->GetComponent(c, 2));
    p[d / 2] += (d & 1) ? 0.5 : -0.5;
    out[c] = p;
  }
  return out;
}

double AngleDegrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  const double na = a.norm(), nb = b.norm();
  if (na == 0 || nb == 0)
  {
    return 180.0;
  }
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

} // namespace dgtest
