#include "dgSharpFeaturesField.h"

#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>

namespace dg
{
namespace sharp
{
namespace
{

// Faces grouped in cubes one width wide: one search per cube (and per
// part of it that creases separate) finds every face any of its faces can
// reach, instead of one search per face (fandisk 256^3 at k = 0.3, width
// 2.5: 10.3-11.2 s with a search per face, docs/sharp-features.md has the
// figure with the cubes).
struct Tiles
{
  std::vector<std::int64_t> Ptr;   // faces of tile t: Faces[Ptr[t] .. Ptr[t + 1])
  std::vector<std::int64_t> Faces;
};

Tiles MakeTiles(const std::vector<Vec3>& centre, double size)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  std::vector<std::tuple<std::int64_t, std::int64_t, std::int64_t>> key(F);
  for (std::int64_t f = 0; f < F; ++f)
    key[f] = { static_cast<std::int64_t>(std::floor(centre[f].x / size)),
      static_cast<std::int64_t>(std::floor(centre[f].y / size)),
      static_cast<std::int64_t>(std::floor(centre[f].z / size)) };
  Tiles t;
  t.Faces.resize(F);
  std::iota(t.Faces.begin(), t.Faces.end(), 0);
  std::stable_sort(t.Faces.begin(), t.Faces.end(),
    [&](std::int64_t a, std::int64_t b) { return key[a] < key[b]; });
  for (std::int64_t i = 0; i < F; ++i)
    if (i == 0 || key[t.Faces[i]] != key[t.Faces[i - 1]])
      t.Ptr.push_back(i);
  t.Ptr.push_back(F);
  return t;
}

struct Search
{
  std::vector<std::int64_t> Stamp; // the search that last reached a face
  std::vector<std::int64_t> Queue;
  std::vector<double> Weight;
  std::vector<char> Done; // per face of the tile: its part is done
  std::vector<Vec3> Centre, Data, In;
};

// exp(-x / 2) for x = d^2 / width^2 in [0, 6.25] (the cut at 2.5 widths),
// 0 beyond, from a table: the field's weights are most of its cost.
class Gaussian
{
public:
  explicit Gaussian(double width)
    : Scale(Bins / (6.25 * width * width))
  {
    for (int i = 0; i <= Bins + 1; ++i)
      this->Table[i] = std::exp(-0.5 * 6.25 * i / Bins);
  }
  double operator()(double d2) const
  {
    const double x = d2 * this->Scale;
    if (x >= Bins)
      return 0.0;
    const int i = static_cast<int>(x);
    return this->Table[i] + (x - i) * (this->Table[i + 1] - this->Table[i]);
  }

private:
  static constexpr int Bins = 1024;
  double Scale;
  double Table[Bins + 2];
};

// out[f] = the Gaussian-weighted mean of in over the faces f's side reaches
// (dgSharpFeaturesField.h).
void Convolve(const std::vector<std::int64_t>& ptr, const std::vector<std::int64_t>& next,
  const Tiles& tiles, const std::vector<Vec3>& centre, const std::vector<Vec3>& data,
  double width, const std::vector<Vec3>& in, std::vector<Vec3>& out,
  const std::vector<char>* want = nullptr)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  const std::int64_t T = static_cast<std::int64_t>(tiles.Ptr.size()) - 1;
  const double reach = 2.5 * width, reach2 = reach * reach;
  const Gaussian gauss(width);
  vtkSMPThreadLocal<Search> local;
  vtkSMPTools::For(0, T, [&](std::int64_t t0, std::int64_t t1) {
    Search& s = local.Local();
    if (s.Stamp.empty())
      s.Stamp.assign(F, -1);
    for (std::int64_t t = t0; t < t1; ++t)
    {
      // The tile's box grown by the reach bounds what its faces can reach.
      Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
      for (std::int64_t i = tiles.Ptr[t]; i < tiles.Ptr[t + 1]; ++i)
      {
        const Vec3& c = centre[tiles.Faces[i]];
        lo = Vec3(std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z));
        hi = Vec3(std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z));
      }
      auto near = [&](const Vec3& c) {
        const double dx = std::max({ 0.0, lo.x - c.x, c.x - hi.x });
        const double dy = std::max({ 0.0, lo.y - c.y, c.y - hi.y });
        const double dz = std::max({ 0.0, lo.z - c.z, c.z - hi.z });
        return dx * dx + dy * dy + dz * dz <= reach2;
      };
      const std::int64_t first = tiles.Ptr[t];
      s.Done.assign(tiles.Ptr[t + 1] - first, 0);
      for (std::int64_t i = first; i < tiles.Ptr[t + 1]; ++i)
      {
        const std::int64_t seed = tiles.Faces[i];
        if (s.Done[i - first] || (want && !(*want)[seed]))
          continue;
        // One part of the tile: the faces reached from seed without crossing
        // a crease (a stamp per tile and part: t F + seed).
        const std::int64_t stamp = F * t + seed;
        s.Queue.assign(1, seed);
        s.Stamp[seed] = stamp;
        for (std::size_t h = 0; h < s.Queue.size(); ++h)
          for (std::int64_t k = ptr[s.Queue[h]]; k < ptr[s.Queue[h] + 1]; ++k)
          {
            const std::int64_t n = next[k];
            if (s.Stamp[n] != stamp)
            {
              s.Stamp[n] = stamp;
              if (near(centre[n]))
                s.Queue.push_back(n);
            }
          }
        // The part's faces in contiguous arrays: every face of the part reads
        // them all.
        const std::size_t q = s.Queue.size();
        s.Centre.resize(q);
        s.Data.resize(q);
        s.In.resize(q);
        for (std::size_t h = 0; h < q; ++h)
        {
          s.Centre[h] = centre[s.Queue[h]];
          s.Data[h] = data[s.Queue[h]];
          s.In[h] = in[s.Queue[h]];
        }
        s.Weight.resize(q);
        for (std::int64_t j = i; j < tiles.Ptr[t + 1]; ++j)
        {
          const std::int64_t f = tiles.Faces[j];
          if (s.Stamp[f] != stamp)
            continue; // another part of the tile
          s.Done[j - first] = 1;
          if (want && !(*want)[f])
            continue;
          // The faces on f's side of a thin part: those whose data lie
          // within 90 degrees of f's, unless f's own datum is the odd one
          // out (a noise pit's faces, whose input points across the
          // surface), where the mean of all reached faces says where f faces.
          // One pass sums both; the odd ones out take a second.
          Vec3 all, sum;
          double weights = 0;
          const Vec3& own = data[f];
          for (std::size_t h = 0; h < q; ++h)
          {
            const Vec3 d = s.Centre[h] - centre[f];
            const double w = gauss(d.Dot(d));
            s.Weight[h] = w;
            if (w == 0)
              continue; // beyond the cut: about half the tile's reach
            all += s.Data[h] * w;
            if (s.Data[h].Dot(own) >= 0)
            {
              sum += s.In[h] * w;
              weights += w;
            }
          }
          if (own.Dot(all) < 0)
          {
            sum = Vec3();
            weights = 0;
            for (std::size_t h = 0; h < q; ++h)
            {
              const double w = s.Data[h].Dot(all) >= 0 ? s.Weight[h] : 0.0;
              sum += s.In[h] * w;
              weights += w;
            }
          }
          out[f] = weights > 0 ? sum * (1.0 / weights) : in[f];
        }
      }
    }
  });
}

// The faces next to each face across an edge that is not a crease.
void Neighbours(const FaceGraph& graph, const std::vector<char>& crease, std::int64_t F,
  std::vector<std::int64_t>& ptr, std::vector<std::int64_t>& next)
{
  ptr.assign(F + 1, 0);
  next.clear();
  next.reserve(4 * F);
  for (std::int64_t f = 0; f < F; ++f)
  {
    for (std::int64_t j = graph.FaceEdgePtr[f]; j < graph.FaceEdgePtr[f + 1]; ++j)
    {
      const std::int64_t e = graph.FaceEdges[j];
      if (!crease[e])
        for (std::int64_t i = graph.EdgeFacePtr[e]; i < graph.EdgeFacePtr[e + 1]; ++i)
          if (graph.EdgeFaces[i] != f)
            next.push_back(graph.EdgeFaces[i]);
    }
    ptr[f + 1] = static_cast<std::int64_t>(next.size());
  }
}

} // namespace

bool UndoBlurWithinSides(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& data, double width, double gain,
  std::vector<Vec3>& normals, const std::vector<char>* where)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  if (!(width > 0))
    return false;
  std::vector<std::int64_t> ptr, next;
  Neighbours(graph, crease, F, ptr, next);
  std::vector<Vec3> blurred(F);
  Convolve(ptr, next, MakeTiles(centre, width), centre, data, width, data, blurred, where);
  normals.resize(F);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      const Vec3 d = data[f] + (data[f] - blurred[f].Unit()) * gain;
      normals[f] = (!where || (*where)[f]) && d.Norm() > 0 ? d.Unit() : data[f];
    }
  });
  return true;
}

bool SmoothFieldWithinSides(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& data, double width,
  std::vector<Vec3>& normals, const std::vector<char>* where, double edge)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  if (!(width > 0))
    return false;
  std::vector<std::int64_t> ptr, next;
  Neighbours(graph, crease, F, ptr, next);
  const Tiles tiles = MakeTiles(centre, 1.0 * width);
  // With a mask, the first pass covers the masked faces and every face a
  // few reaches of steps around them: the second pass at a masked face
  // reads the first's residual within its reach. (A face the search
  // reaches by a longer walk has no residual: its correction is left out.)
  std::vector<char> around;
  if (where)
  {
    around = *where;
    std::vector<std::int64_t> front, grown;
    for (std::int64_t f = 0; f < F; ++f)
      if (around[f])
        front.push_back(f);
    const int depth = static_cast<int>(std::ceil(3.0 * width / std::max(1e-12, edge))) + 2;
    for (int d = 0; d < depth && !front.empty(); ++d)
    {
      grown.clear();
      for (std::int64_t f : front)
        for (std::int64_t k = ptr[f]; k < ptr[f + 1]; ++k)
          if (!around[next[k]])
          {
            around[next[k]] = 1;
            grown.push_back(next[k]);
          }
      front.swap(grown);
    }
  }
  std::vector<Vec3> first(data), residual(F), second(F);
  Convolve(ptr, next, tiles, centre, data, width, data, first, where ? &around : nullptr);
  for (std::int64_t f = 0; f < F; ++f)
    residual[f] = data[f] - first[f];
  Convolve(ptr, next, tiles, centre, data, width, residual, second, where);
  normals.resize(F);
  for (std::int64_t f = 0; f < F; ++f)
  {
    const Vec3 u = first[f] + second[f];
    normals[f] = u.Norm() > 0 ? u.Unit() : data[f];
  }
  return true;
}

} // namespace sharp
} // namespace dg
