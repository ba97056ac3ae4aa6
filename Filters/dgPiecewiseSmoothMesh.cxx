#include "dgPiecewiseSmoothMesh.h"

#include "dgATBlocks.h"
#include "dgATLinearSystems.h"
#include "dgATOperators.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace dg
{

void SurfaceFrame::ToGrid(const double* world, double* grid) const
{
  const Eigen::Map<const Eigen::Matrix3d> a(this->Axes);
  const Eigen::Vector3d x(world[0] - this->Origin[0], world[1] - this->Origin[1], world[2] - this->Origin[2]);
  Eigen::Map<Eigen::Vector3d> out(grid);
  out = a.inverse() * x;
}

void SurfaceFrame::ToWorld(const double* grid, double* world) const
{
  const Eigen::Map<const Eigen::Matrix3d> a(this->Axes);
  const Eigen::Vector3d x = a * Eigen::Map<const Eigen::Vector3d>(grid);
  for (int i = 0; i < 3; ++i)
    world[i] = this->Origin[i] + x[i];
}

void SurfaceFrame::NormalToGrid(const double* world, double* grid) const
{
  const Eigen::Map<const Eigen::Matrix3d> a(this->Axes);
  Eigen::Vector3d n = a.transpose() * Eigen::Map<const Eigen::Vector3d>(world);
  const double l = n.norm();
  Eigen::Map<Eigen::Vector3d> out(grid);
  out = l > 0 ? Eigen::Vector3d(n / l) : n;
}

bool FindSurfaceFrame(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  SurfaceFrame& frame, std::string& error)
{
  const std::int64_t nf = offsets.empty() ? 0 : static_cast<std::int64_t>(offsets.size()) - 1;
  if (nf == 0 || numberOfPoints == 0)
  {
    error = "the surface has no polygons";
    return false;
  }
  auto side = [&](std::int64_t f, std::int64_t i) -> Eigen::Vector3d
  {
    const std::int64_t m = offsets[f + 1] - offsets[f];
    const std::int64_t a = connectivity[offsets[f] + i], b = connectivity[offsets[f] + (i + 1) % m];
    return Eigen::Map<const Eigen::Vector3d>(points + 3 * b) -
      Eigen::Map<const Eigen::Vector3d>(points + 3 * a);
  };
  // The first side, the first side not parallel to it, the first side out
  // of their plane: the three voxel steps (signs made canonical below).
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  int found = 0;
  for (std::int64_t f = 0; f < nf && found < 3; ++f)
  {
    for (std::int64_t i = 0; i < offsets[f + 1] - offsets[f] && found < 3; ++i)
    {
      const Eigen::Vector3d e = side(f, i);
      const double l = e.norm();
      if (!(l > 0) || !std::isfinite(l))
        continue;
      if (found == 1 && e.cross(axes.col(0)).norm() <= 1e-6 * l * axes.col(0).norm())
        continue;
      if (found == 2 &&
        std::abs(e.dot(axes.col(0).cross(axes.col(1)).normalized())) <= 1e-6 * l)
        continue;
      axes.col(found++) = e;
    }
  }
  if (found < 3)
  {
    error = "the polygons' sides do not span three directions: not the surface of a set of voxels";
    return false;
  }
  for (int c = 0; c < 3; ++c)
  {
    Eigen::Index k;
    axes.col(c).cwiseAbs().maxCoeff(&k);
    if (axes(k, c) < 0)
      axes.col(c) = -axes.col(c);
  }
  const Eigen::Matrix3d inverse = axes.inverse();
  for (std::int64_t f = 0; f < nf; ++f)
  {
    for (std::int64_t i = 0; i < offsets[f + 1] - offsets[f]; ++i)
    {
      const Eigen::Vector3d g = inverse * side(f, i);
      const Eigen::Vector3d a = g.cwiseAbs();
      const double big = a.maxCoeff();
      if (!(std::abs(big - 1) <= 1e-6 && a.sum() - big <= 1e-6))
      {
        std::ostringstream s;
        s << "side " << i << " of polygon " << f
          << " is not one voxel step along an axis of the grid the other sides define: the input "
             "is not the surface of a set of voxels (vtkDigitalSurfaceFilter's output)";
        error = s.str();
        return false;
      }
    }
  }
  std::copy(points, points + 3, frame.Origin);
  Eigen::Map<Eigen::Matrix3d>(frame.Axes) = axes;
  return true;
}

std::string MeshParameters::Check() const
{
  std::ostringstream s;
  if (!(this->DataWeight > 0) || !std::isfinite(this->DataWeight))
    s << "DataWeight must be positive and finite (got " << this->DataWeight << "). ";
  if (!(this->TangentialWeight > 0) || !std::isfinite(this->TangentialWeight))
    s << "TangentialWeight must be positive and finite (got " << this->TangentialWeight << "). ";
  if (!(this->CreaseWeight >= 0) || !std::isfinite(this->CreaseWeight))
    s << "CreaseWeight must be non-negative and finite (got " << this->CreaseWeight << "). ";
  if (!(this->CreaseMinimumAngle >= 0 && this->CreaseMinimumAngle < 90))
    s << "CreaseMinimumAngle must lie in [0, 90) degrees (got " << this->CreaseMinimumAngle << "). ";
  if (!(this->BoxHalfWidth > 0 && this->BoxHalfWidth <= 0.5))
    s << "BoxHalfWidth must lie in (0, 0.5] voxel (got " << this->BoxHalfWidth << "). ";
  if (!(this->Tolerance > 0 && this->Tolerance < 1))
    s << "Tolerance must lie in (0, 1) (got " << this->Tolerance << "). ";
  if (this->MaximumIterations < 1 || this->MaximumRounds < 1 || this->Iterations < 1)
    s << "Iterations, MaximumIterations and MaximumRounds must be at least 1. ";
  std::string r = s.str();
  if (!r.empty())
    r.pop_back();
  return r;
}

namespace
{
// The edges whose faces lie in two or more regions, by ATComplex edge id.
std::vector<char> CreaseFlags(const ATComplex& K, const int* region)
{
  const std::int64_t ne = K.NumberOfEdges();
  std::vector<char> crease(ne, 0);
  if (!region)
    return crease;
  for (std::int64_t e = 0; e < ne; ++e)
  {
    const int r0 = region[K.EdgeFaces[K.EdgeFacePtr[e]]];
    for (int j = K.EdgeFacePtr[e] + 1; j < K.EdgeFacePtr[e + 1]; ++j)
      crease[e] |= region[K.EdgeFaces[j]] != r0;
  }
  return crease;
}
}

std::vector<std::int64_t> CreaseEdges(const MeshInput& in)
{
  std::vector<std::int64_t> edges;
  ATComplex K;
  std::string error;
  if (!K.Build(in.NumberOfPoints, *in.Offsets, *in.Connectivity, &error))
    return edges;
  const std::vector<char> crease = CreaseFlags(K, in.FaceRegion);
  for (std::int64_t e = 0; e < K.NumberOfEdges(); ++e)
  {
    if (crease[e])
    {
      edges.push_back(K.EdgeVertices[2 * e]);
      edges.push_back(K.EdgeVertices[2 * e + 1]);
    }
  }
  return edges;
}

bool RegularizeMesh(const MeshInput& in, const MeshParameters& p, std::vector<double>& displacement,
  MeshStatistics& stats, std::string& error, const std::function<bool(double)>& progress)
{
  const auto start = std::chrono::steady_clock::now();
  stats = MeshStatistics();
  error = p.Check();
  if (!error.empty())
    return false;
  ATComplex K;
  if (!K.Build(in.NumberOfPoints, *in.Offsets, *in.Connectivity, &error))
    return false;
  const std::int64_t nv = K.NumberOfVertices(), ne = K.NumberOfEdges(), nf = K.NumberOfFaces();
  const std::vector<std::int64_t>& offsets = *in.Offsets;
  const std::vector<std::int64_t>& conn = *in.Connectivity;
  auto point = [&](std::int64_t v) { return Eigen::Map<const Eigen::Vector3d>(in.Points + 3 * v); };
  auto normal = [&](std::int64_t f)
  { return Eigen::Map<const Eigen::Vector3d>(in.FaceNormals + 3 * f); };

  // Edge weights and the crease terms: the crease direction from the pair
  // of faces in different regions whose normals differ most.
  const std::vector<char> crease = CreaseFlags(K, in.FaceRegion);
  const double beta = p.CreaseWeight;
  const double minimumSine = std::sin(p.CreaseMinimumAngle * M_PI / 180.0);
  std::vector<double> weight(ne);
  std::vector<std::pair<std::int64_t, Eigen::Vector3d>> creaseDirection;
  for (std::int64_t e = 0; e < ne; ++e)
  {
    const int j0 = K.EdgeFacePtr[e], j1 = K.EdgeFacePtr[e + 1];
    weight[e] = j1 - j0;
    if (!crease[e] || beta == 0)
      continue;
    Eigen::Vector3d k = Eigen::Vector3d::Zero();
    for (int i = j0; i < j1; ++i)
    {
      for (int j = i + 1; j < j1; ++j)
      {
        const int f = K.EdgeFaces[i], g = K.EdgeFaces[j];
        if (in.FaceRegion[f] == in.FaceRegion[g])
          continue;
        const Eigen::Vector3d c = normal(f).cross(normal(g));
        if (c.norm() > k.norm())
          k = c;
      }
    }
    if (!(k.norm() >= minimumSine) || k.norm() == 0)
      continue;
    creaseDirection.emplace_back(e, k.normalized());
    weight[e] += beta;
    ++stats.CreaseEdges;
  }
  displacement.assign(3 * nv, 0.0);
  auto edgeNow = [&](std::int64_t a, std::int64_t c) -> Eigen::Vector3d
  {
    return point(c) - point(a) + Eigen::Map<const Eigen::Vector3d>(&displacement[3 * c]) -
      Eigen::Map<const Eigen::Vector3d>(&displacement[3 * a]);
  };
  // Right-hand sides: each face side's target is its current vector
  // without its component along the face's normal, a crease edge's its
  // current vector's component along the crease (as targets for d_b - d_a:
  // minus the digital surface's own side).
  // Vertex normals: the area-free mean of the normals of the faces around.
  Eigen::MatrixXd vertexNormal = Eigen::MatrixXd::Zero(nv, 3);
  for (std::int64_t f = 0; f < nf; ++f)
    for (std::int64_t i = offsets[f]; i < offsets[f + 1]; ++i)
      vertexNormal.row(conn[i]) += normal(f).transpose();
  for (std::int64_t v = 0; v < nv; ++v)
  {
    const double l = vertexNormal.row(v).norm();
    if (l > 0)
      vertexNormal.row(v) /= l;
  }
  Eigen::MatrixXd b(nv, 3);
  auto assemble = [&]()
  {
    // The data term alpha_n (n_v . d)^2 + alpha_t |d - (n_v . d) n_v|^2, as
    // targets from the previous pass (the same gradient where they agree).
    for (std::int64_t v = 0; v < nv; ++v)
    {
      const Eigen::Vector3d d = Eigen::Map<const Eigen::Vector3d>(&displacement[3 * v]);
      const Eigen::Vector3d nv_ = vertexNormal.row(v).transpose();
      const Eigen::Vector3d along = nv_.dot(d) * nv_;
      b.row(v) = (p.TangentialWeight * along + p.DataWeight * (d - along)).transpose();
    }
    for (const auto& ck : creaseDirection)
    {
      const std::int64_t e = ck.first;
      const Eigen::Vector3d& k = ck.second;
      const std::int64_t lo = K.EdgeVertices[2 * e], hi = K.EdgeVertices[2 * e + 1];
      const Eigen::Vector3d now = edgeNow(lo, hi);
      const Eigen::Vector3d c = k.dot(now) * k - (point(hi) - point(lo));
      b.row(lo) -= beta * c.transpose();
      b.row(hi) += beta * c.transpose();
    }
    for (std::int64_t f = 0; f < nf; ++f)
    {
      const std::int64_t m = offsets[f + 1] - offsets[f];
      const Eigen::Vector3d n = normal(f);
      for (std::int64_t i = 0; i < m; ++i)
      {
        const std::int64_t a = conn[offsets[f] + i], c = conn[offsets[f] + (i + 1) % m];
        if (a == c)
          continue;
        const Eigen::Vector3d now = edgeNow(a, c);
        const Eigen::Vector3d t = now - n.dot(now) * n - (point(c) - point(a));
        b.row(a) -= t.transpose();
        b.row(c) += t.transpose();
      }
    }
  };
  // The system's diagonal (without the bound) and each non-zero's edge.
  ATPattern& P = K.VPattern;
  const int* outer = P.Outer.data();
  const int* inner = P.Inner.data();
  std::vector<int> entryEdge(P.NonZeros(), -1);
  std::vector<double> diagonal(nv, p.DataWeight + p.TangentialWeight);
  for (std::int64_t a = 0; a < nv; ++a)
  {
    int j = K.VertexEdgePtr[a];
    for (int k = outer[a]; k < outer[a + 1]; ++k)
    {
      if (inner[k] != a)
      {
        entryEdge[k] = K.VertexEdges[j++];
        diagonal[a] += weight[entryEdge[k]];
      }
    }
  }

  std::unique_ptr<ATLinearSystem> system =
    MakeICSystem(p.Tolerance, p.MaximumIterations, nullptr, 1, false);
  std::vector<double> values(P.NonZeros());
  const double h = p.BoxHalfWidth;
  Eigen::VectorXd x(nv), rhs(nv);
  std::vector<signed char> bound(nv);
  std::vector<signed char> bounds(3 * nv, 0);
  for (int pass = 0; pass < p.Iterations; ++pass)
  {
  assemble();
  stats.BoundCoordinates = 0;
  for (int c = 0; c < 3; ++c)
  {
    for (std::int64_t a = 0; a < nv; ++a)
    {
      x[a] = displacement[3 * a + c];
      bound[a] = bounds[3 * a + c];
    }
    bool settled = false;
    for (int round = 0; round < p.MaximumRounds && !settled; ++round)
    {
      ++stats.Rounds[c];
      // Rows held at the box become x = bound; their columns move to the
      // right-hand side, so the matrix stays symmetric.
      ForBlocks(nv,
        [&](std::int64_t, std::int64_t a0, std::int64_t a1)
        {
          for (std::int64_t a = a0; a < a1; ++a)
          {
            if (bound[a])
            {
              for (int k = outer[a]; k < outer[a + 1]; ++k)
                values[k] = inner[k] == a ? 1.0 : 0.0;
              rhs[a] = bound[a] * h;
              continue;
            }
            double r = b(a, c);
            for (int k = outer[a]; k < outer[a + 1]; ++k)
            {
              const int j = inner[k];
              if (j == a)
                values[k] = diagonal[a];
              else if (bound[j])
              {
                values[k] = 0;
                r += weight[entryEdge[k]] * bound[j] * h;
              }
              else
                values[k] = -weight[entryEdge[k]];
            }
            rhs[a] = r;
          }
        });
      const ATSystemView m = P.View(values.data());
      const std::int64_t it0 = system->Iterations;
      if (!system->Analyzed)
        system->Analyzed = system->Analyze(m);
      const bool ok = system->Analyzed && system->Factorize(m) &&
        system->Solve(m, ATRhs::Of(rhs), ATColumns(x));
      stats.CGIterations += system->Iterations - it0;
      if (!ok)
      {
        stats.Converged = false;
        if (!x.allFinite())
        {
          error = "the linear solve failed (non-finite result)";
          return false;
        }
      }
      // New bounds where the solution leaves the box; bounds released where
      // the energy's gradient points back into it (KKT). After half the
      // rounds only new bounds are taken, so the sets cannot cycle.
      const bool release = round < p.MaximumRounds / 2;
      std::int64_t changes = 0;
      for (std::int64_t a = 0; a < nv; ++a)
      {
        if (!bound[a])
        {
          if (std::abs(x[a]) > h)
          {
            bound[a] = x[a] > 0 ? 1 : -1;
            x[a] = bound[a] * h;
            ++changes;
          }
          continue;
        }
        if (!release)
          continue;
        double g = diagonal[a] * x[a] - b(a, c);
        for (int k = outer[a]; k < outer[a + 1]; ++k)
        {
          if (inner[k] != a)
            g -= weight[entryEdge[k]] * x[inner[k]];
        }
        if (bound[a] * g > 1e-12 * (1 + std::abs(b(a, c))))
        {
          bound[a] = 0;
          ++changes;
        }
      }
      settled = changes == 0;
      if (progress &&
        !progress((3 * pass + c + std::min(1.0, (round + 1) / 4.0)) / (3.0 * p.Iterations)))
      {
        error = "aborted";
        return false;
      }
    }
    stats.Converged &= settled;
    for (std::int64_t a = 0; a < nv; ++a)
    {
      displacement[3 * a + c] = std::max(-h, std::min(h, x[a]));
      bounds[3 * a + c] = bound[a];
      stats.BoundCoordinates += bound[a] != 0;
    }
  }
  }
  stats.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}

std::vector<unsigned char> QuadDiagonals(const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* faceNormals)
{
  const std::int64_t nf = offsets.empty() ? 0 : static_cast<std::int64_t>(offsets.size()) - 1;
  std::vector<unsigned char> diagonal(nf, 0);
  auto x = [&](std::int64_t v) { return Eigen::Map<const Eigen::Vector3d>(points + 3 * v); };
  vtkSMPTools::For(0, nf,
    [&](std::int64_t f0, std::int64_t f1)
    {
      for (std::int64_t f = f0; f < f1; ++f)
      {
        if (offsets[f + 1] - offsets[f] != 4)
          continue;
        const std::int64_t* q = connectivity.data() + offsets[f];
        const Eigen::Vector3d n = Eigen::Map<const Eigen::Vector3d>(faceNormals + 3 * f);
        // Twice the area-weighted (1 - cos) of a triangle's normal against n.
        auto misfit = [&](std::int64_t a, std::int64_t b, std::int64_t c)
        {
          const Eigen::Vector3d t = (x(b) - x(a)).cross(x(c) - x(a));
          return t.norm() - t.dot(n);
        };
        const double s0 = misfit(q[0], q[1], q[2]) + misfit(q[0], q[2], q[3]);
        const double s1 = misfit(q[0], q[1], q[3]) + misfit(q[1], q[2], q[3]);
        diagonal[f] = s1 < s0 ? 1 : 0;
      }
    });
  return diagonal;
}

void SplitPointsByRegion(std::int64_t numberOfPoints, const std::vector<std::int64_t>& offsets,
  std::vector<std::int64_t>& connectivity, const int* faceRegion, std::vector<std::int64_t>& copyOf)
{
  const std::int64_t nf = offsets.empty() ? 0 : static_cast<std::int64_t>(offsets.size()) - 1;
  copyOf.clear();
  if (!faceRegion)
  {
    copyOf.resize(numberOfPoints);
    for (std::int64_t v = 0; v < numberOfPoints; ++v)
      copyOf[v] = v;
    return;
  }
  // (point, region, corner) sorted: one copy per distinct (point, region).
  struct Corner
  {
    std::int64_t Point;
    int Region;
    std::int64_t Index;
  };
  std::vector<Corner> corners;
  corners.reserve(connectivity.size());
  for (std::int64_t f = 0; f < nf; ++f)
  {
    for (std::int64_t i = offsets[f]; i < offsets[f + 1]; ++i)
      corners.push_back({ connectivity[i], faceRegion[f], i });
  }
  std::sort(corners.begin(), corners.end(),
    [](const Corner& a, const Corner& b)
    { return a.Point != b.Point ? a.Point < b.Point : a.Region < b.Region; });
  std::vector<char> used(numberOfPoints, 0);
  for (std::size_t i = 0; i < corners.size(); ++i)
  {
    if (i == 0 || corners[i].Point != corners[i - 1].Point ||
      corners[i].Region != corners[i - 1].Region)
    {
      copyOf.push_back(corners[i].Point);
      used[corners[i].Point] = 1;
    }
    connectivity[corners[i].Index] = static_cast<std::int64_t>(copyOf.size()) - 1;
  }
  // Points no polygon uses keep one copy, after the others.
  for (std::int64_t v = 0; v < numberOfPoints; ++v)
  {
    if (!used[v])
      copyOf.push_back(v);
  }
}

} // namespace dg
