#include "dgPiecewiseSmoothMesh.h"

#include "dgATBlocks.h"
#include "dgATLinearSystems.h"
#include "dgATOperators.h"
#include "dgATSolver.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
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
  // Canonical: each axis's largest component positive, the axes in the
  // order of those components, and a right-handed frame (so that the
  // polygons keep their orientation in grid coordinates).
  int dominant[3];
  for (int c = 0; c < 3; ++c)
  {
    Eigen::Index k;
    axes.col(c).cwiseAbs().maxCoeff(&k);
    dominant[c] = static_cast<int>(k);
    if (axes(k, c) < 0)
      axes.col(c) = -axes.col(c);
  }
  {
    int order[3] = { 0, 1, 2 };
    std::sort(order, order + 3, [&](int a, int b) { return dominant[a] < dominant[b]; });
    const Eigen::Matrix3d sorted = (Eigen::Matrix3d() << axes.col(order[0]), axes.col(order[1]),
      axes.col(order[2])).finished();
    axes = sorted;
  }
  if (axes.determinant() < 0)
    axes.col(2) = -axes.col(2);
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
  if (!(this->BoxHalfWidth > 0 && this->BoxHalfWidth < 0.5))
    s << "BoxHalfWidth must lie in (0, 0.5) voxel (got " << this->BoxHalfWidth << "). ";
  if (!(this->Tolerance > 0 && this->Tolerance < 1) || !(this->EarlyTolerance > 0 && this->EarlyTolerance < 1))
    s << "SolverTolerance must lie in (0, 1) (got " << this->EarlyTolerance << "). ";
  if (!(this->Penalty > 0) || !std::isfinite(this->Penalty))
    s << "Penalty must be positive and finite (got " << this->Penalty << "). ";
  if (this->MaximumIterations < 1 || this->Iterations < 1)
    s << "Iterations and MaximumIterations must be at least 1. ";
  std::string r = s.str();
  if (!r.empty())
    r.pop_back();
  return r;
}

namespace
{
// The crease edges, by ATComplex edge id: 1 where faces of two regions
// meet, 2 where a face flags it as a crease side (bit i: side i, corners i
// and i + 1), 3 both. `oneSided` counts the edges of two faces that only
// one of them flags: flags that no longer match the corners (a filter
// reordered them after the sharp stage, which flags an edge on every face
// along it).
std::vector<char> CreaseFlags(const ATComplex& K, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity, const int* region, const unsigned char* sides,
  std::int64_t& oneSided)
{
  const std::int64_t ne = K.NumberOfEdges();
  std::vector<char> crease(ne, 0);
  std::vector<unsigned char> flags(sides ? ne : 0, 0);
  oneSided = 0;
  if (region)
    for (std::int64_t e = 0; e < ne; ++e)
    {
      const int r0 = region[K.EdgeFaces[K.EdgeFacePtr[e]]];
      for (int j = K.EdgeFacePtr[e] + 1; j < K.EdgeFacePtr[e + 1]; ++j)
        crease[e] |= region[K.EdgeFaces[j]] != r0;
    }
  if (sides)
    for (std::int64_t f = 0; f < K.NumberOfFaces(); ++f)
    {
      const std::int64_t b = offsets[f], m = offsets[f + 1] - b;
      for (std::int64_t i = 0; i < m && i < 8 && sides[f]; ++i)
      {
        if (!(sides[f] & (1u << i)))
          continue;
        const std::int64_t p = connectivity[b + i], q = connectivity[b + (i + 1) % m];
        for (int k = K.FaceEdgePtr[f]; k < K.FaceEdgePtr[f + 1]; ++k)
        {
          const int e = K.FaceEdges[k];
          if (K.EdgeVertices[2 * e] == std::min(p, q) && K.EdgeVertices[2 * e + 1] == std::max(p, q))
          {
            crease[e] |= 2;
            flags[e] = static_cast<unsigned char>(std::min(255, flags[e] + 1));
          }
        }
      }
    }
  for (std::int64_t e = 0; e < static_cast<std::int64_t>(flags.size()); ++e)
    oneSided += flags[e] == 1 && K.EdgeFacePtr[e + 1] - K.EdgeFacePtr[e] == 2;
  return crease;
}
}

bool RegularizeMesh(const MeshInput& in, const MeshParameters& p, MeshResult& result,
  std::string& error, const std::function<bool(double)>& progress)
{
  std::vector<double>& displacement = result.Displacement;
  MeshStatistics& stats = result.Statistics;
  result.Creases.clear();
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
  std::int64_t oneSided = 0;
  const std::vector<char> crease =
    CreaseFlags(K, *in.Offsets, *in.Connectivity, in.FaceRegion, in.FaceCreaseSides, oneSided);
  if (oneSided > 0)
  {
    error = "the crease sides do not match the faces' corners (" + std::to_string(oneSided) +
      " edges flagged by one of their two faces only): a filter after the sharp stage reordered "
      "the corners; drop the CreaseSides array or remap its bits";
    return false;
  }
  const double beta = p.CreaseWeight;
  const double minimumSine = std::sin(p.CreaseMinimumAngle * M_PI / 180.0);
  std::vector<double> weight(ne);
  std::vector<std::pair<std::int64_t, Eigen::Vector3d>> creaseDirection;
  for (std::int64_t e = 0; e < ne; ++e)
  {
    const int j0 = K.EdgeFacePtr[e], j1 = K.EdgeFacePtr[e + 1];
    weight[e] = j1 - j0;
    if (!crease[e])
      continue;
    Eigen::Vector3d k = Eigen::Vector3d::Zero();
    int across[2] = { -1, -1 };
    for (int i = j0; i < j1; ++i)
    {
      for (int j = i + 1; j < j1; ++j)
      {
        const int f = K.EdgeFaces[i], g = K.EdgeFaces[j];
        if (!(crease[e] & 2) && in.FaceRegion[f] == in.FaceRegion[g])
          continue;
        const Eigen::Vector3d c = normal(f).cross(normal(g));
        if (across[0] < 0 || c.norm() > k.norm())
        {
          k = c;
          across[0] = f;
          across[1] = g;
        }
      }
    }
    result.Creases.insert(result.Creases.end(),
      { K.EdgeVertices[2 * e], K.EdgeVertices[2 * e + 1], across[0], across[1] });
    if (beta == 0 || !(k.norm() >= minimumSine) || k.norm() == 0)
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
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertexNormal =
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>::Zero(nv, 3);
  for (std::int64_t f = 0; f < nf; ++f)
    for (std::int64_t i = offsets[f]; i < offsets[f + 1]; ++i)
      vertexNormal.row(conn[i]) += normal(f).transpose();
  for (std::int64_t v = 0; v < nv; ++v)
  {
    const double l = vertexNormal.row(v).norm();
    if (l > 0)
      vertexNormal.row(v) /= l;
  }
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> b(nv, 3);
  std::vector<int> creaseIndex(ne, -1);
  for (std::size_t i = 0; i < creaseDirection.size(); ++i)
    creaseIndex[creaseDirection[i].first] = static_cast<int>(i);
  // Each edge's target (low -> high end): the sum over its faces, plus its
  // crease term; then each vertex gathers its edges' (both in parallel).
  std::vector<double> edgeTarget(3 * ne);
  auto assemble = [&]()
  {
    ForBlocks(ne,
      [&](std::int64_t, std::int64_t e0, std::int64_t e1)
      {
        for (std::int64_t e = e0; e < e1; ++e)
        {
          const std::int64_t lo = K.EdgeVertices[2 * e], hi = K.EdgeVertices[2 * e + 1];
          const Eigen::Vector3d now = edgeNow(lo, hi);
          const Eigen::Vector3d side = point(hi) - point(lo);
          Eigen::Vector3d t = Eigen::Vector3d::Zero();
          for (int j = K.EdgeFacePtr[e]; j < K.EdgeFacePtr[e + 1]; ++j)
          {
            const Eigen::Vector3d n = normal(K.EdgeFaces[j]);
            t += now - n.dot(now) * n - side;
          }
          if (creaseIndex[e] >= 0)
          {
            const Eigen::Vector3d& k = creaseDirection[creaseIndex[e]].second;
            t += beta * (k.dot(now) * k - side);
          }
          Eigen::Map<Eigen::Vector3d> out(&edgeTarget[3 * e]);
          out = t;
        }
      });
    // The data term alpha_n (m_v . d)^2 + alpha_t |d - (m_v . d) m_v|^2, as
    // targets from the previous iteration (the same gradient where they agree).
    ForBlocks(nv,
      [&](std::int64_t, std::int64_t v0, std::int64_t v1)
      {
        for (std::int64_t v = v0; v < v1; ++v)
        {
          const Eigen::Vector3d d = Eigen::Map<const Eigen::Vector3d>(&displacement[3 * v]);
          const Eigen::Vector3d m = vertexNormal.row(v).transpose();
          const Eigen::Vector3d along = m.dot(d) * m;
          Eigen::Vector3d r = p.TangentialWeight * along + p.DataWeight * (d - along);
          for (int j = K.VertexEdgePtr[v]; j < K.VertexEdgePtr[v + 1]; ++j)
          {
            const int e = K.VertexEdges[j];
            const Eigen::Map<const Eigen::Vector3d> t(&edgeTarget[3 * e]);
            if (K.EdgeVertices[2 * e] == v)
              r -= t;
            else
              r += t;
          }
          b.row(v) = r.transpose();
        }
      });
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

  // The bound by ADMM on the split d = z, z in the box: each iteration
  // solves (L + (alpha_n + alpha_t + rho) I) d = b + rho (z - u) for x, y
  // and z at once (one matrix for the whole run: factorised once), then
  // z = clamp(d + u), u += d - z. The surrogate's targets are taken at z,
  // which is always in the box, and z is the result.
  const double rho = p.Penalty;
  std::vector<double> values(P.NonZeros());
  for (std::int64_t a = 0; a < nv; ++a)
  {
    for (int k = outer[a]; k < outer[a + 1]; ++k)
      values[k] = inner[k] == a ? diagonal[a] + rho : -weight[entryEdge[k]];
  }
  const ATSystemView m = P.View(values.data());
  // With pieces every process takes the same branches: a local failure
  // fails them all.
  const ATDistribution* dist = in.Distribution;
  auto agree = [dist](bool ok) { return dist ? dist->AllOk(ok) : ok; };
  const std::int64_t owned = dist ? dist->Owned(1) : nv;
  std::unique_ptr<ATLinearSystem> system =
    MakeICSystem(p.EarlyTolerance, p.MaximumIterations, dist, 1, false);
  if (!agree(system->Analyze(m) && system->Factorize(m)))
  {
    error = "the mesh's system could not be factorised";
    return false;
  }
  const double h = p.BoxHalfWidth;
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(nv, 3), u = Eigen::MatrixXd::Zero(nv, 3);
  Eigen::MatrixXd rhs(nv, 3);
  double residual = 0;
  for (int pass = 0; pass < p.Iterations; ++pass)
  {
    const bool last = pass + 1 == p.Iterations;
    system->SetTolerance(last ? p.Tolerance : p.EarlyTolerance);
    assemble();
    ForBlocks(nv,
      [&](std::int64_t, std::int64_t a0, std::int64_t a1)
      {
        for (std::int64_t a = a0; a < a1; ++a)
          for (int c = 0; c < 3; ++c)
            rhs(a, c) = b(a, c) + rho * (displacement[3 * a + c] - u(a, c));
      });
    const std::int64_t it0 = system->Iterations;
    const bool ok = system->Solve(m, ATRhs::Of(rhs), ATColumns(d));
    stats.CGIterations += system->Iterations - it0;
    if (!agree(ok))
    {
      stats.Converged = !last && stats.Converged;
      if (!agree(d.allFinite()))
      {
        error = "the linear solve failed (non-finite result)";
        return false;
      }
    }
    residual = 0;
    double held = 0;
    for (std::int64_t a = 0; a < owned; ++a)
    {
      for (int c = 0; c < 3; ++c)
      {
        const double w = d(a, c) + u(a, c);
        const double z = std::max(-h, std::min(h, w));
        held += z != w;
        u(a, c) = w - z;
        residual = std::max(residual, std::abs(d(a, c) - z));
        displacement[3 * a + c] = z;
      }
    }
    if (dist)
    {
      // The ghost rows' displacements from their owners, for the next
      // targets; the figures over all pieces.
      dist->UpdateGhosts(1, displacement.data(), 3);
      dist->SumAll(&held, 1);
      residual = dist->MaxAll(residual);
    }
    stats.BoundCoordinates = static_cast<std::int64_t>(held);
    // Progress only: an abort on one piece alone would leave the others
    // waiting.
    if (progress && !progress((pass + 1.0) / p.Iterations) && !dist)
    {
      error = "aborted";
      return false;
    }
  }
  stats.PrimalResidual = residual;
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

void SplitPointsAtCreases(std::int64_t numberOfPoints, const std::vector<std::int64_t>& offsets,
  std::vector<std::int64_t>& connectivity, const int* faceRegion, const unsigned char* creaseSides,
  std::vector<std::int64_t>& copyOf)
{
  const std::int64_t nf = offsets.empty() ? 0 : static_cast<std::int64_t>(offsets.size()) - 1;
  const std::int64_t nc = static_cast<std::int64_t>(connectivity.size());
  // Point -> corners (a polygon's use of a point), and each corner's face.
  std::vector<std::int64_t> start(numberOfPoints + 1, 0), corners(nc), faceOf(nc);
  for (std::int64_t f = 0; f < nf; ++f)
    for (std::int64_t i = offsets[f]; i < offsets[f + 1]; ++i)
    {
      faceOf[i] = f;
      ++start[connectivity[i] + 1];
    }
  for (std::int64_t v = 0; v < numberOfPoints; ++v)
    start[v + 1] += start[v];
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::int64_t i = 0; i < nc; ++i)
      corners[fill[connectivity[i]]++] = i;
  }
  auto next = [&](std::int64_t i)
  { return i + 1 < offsets[faceOf[i] + 1] ? i + 1 : offsets[faceOf[i]]; };
  auto previous = [&](std::int64_t i)
  { return i > offsets[faceOf[i]] ? i - 1 : offsets[faceOf[i] + 1] - 1; };
  auto flagged = [&](std::int64_t i)
  {
    const std::int64_t side = i - offsets[faceOf[i]];
    return side < 8 && (creaseSides[faceOf[i]] & (1u << side)) != 0;
  };
  // Corners of one fan: joined across every side shared by exactly two
  // faces of the same region that no face flags as a crease.
  std::vector<std::int64_t> parent(nc);
  for (std::int64_t i = 0; i < nc; ++i)
    parent[i] = i;
  auto find = [&](std::int64_t i)
  {
    while (parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  };
  for (std::int64_t i = 0; i < nc; ++i)
  {
    const std::int64_t a = connectivity[i], j = next(i), b = connectivity[j];
    if (a == b)
      continue;
    // The other faces' corners at a whose neighbour is b: the faces across.
    std::int64_t across = -1, count = 0;
    for (std::int64_t k = start[a]; k < start[a + 1]; ++k)
    {
      const std::int64_t c = corners[k];
      if (faceOf[c] == faceOf[i])
        continue;
      if (connectivity[next(c)] == b || connectivity[previous(c)] == b)
      {
        across = c;
        ++count;
      }
    }
    if (count != 1 || faceOf[across] < faceOf[i] ||
      (faceRegion && faceRegion[faceOf[across]] != faceRegion[faceOf[i]]))
      continue;
    const std::int64_t acrossB = connectivity[next(across)] == b ? next(across) : previous(across);
    // The side a-b is corner i's side in its face, and in the face across
    // the side of whichever of its two corners comes first.
    const std::int64_t acrossSide = connectivity[next(across)] == b ? across : acrossB;
    if (creaseSides && (flagged(i) || flagged(acrossSide)))
      continue;
    parent[find(i)] = find(across);
    parent[find(j)] = find(acrossB);
  }
  // One copy per fan, in point order (a point's copies in the order of its
  // corners); points no polygon uses keep one.
  copyOf.clear();
  copyOf.reserve(numberOfPoints + numberOfPoints / 8);
  std::vector<std::int64_t> copyOfRoot(nc, -1);
  for (std::int64_t v = 0; v < numberOfPoints; ++v)
  {
    if (start[v] == start[v + 1])
    {
      copyOf.push_back(v);
      continue;
    }
    for (std::int64_t k = start[v]; k < start[v + 1]; ++k)
    {
      const std::int64_t r = find(corners[k]);
      if (copyOfRoot[r] < 0)
      {
        copyOfRoot[r] = static_cast<std::int64_t>(copyOf.size());
        copyOf.push_back(v);
      }
      connectivity[corners[k]] = copyOfRoot[r];
    }
  }
}

} // namespace dg
