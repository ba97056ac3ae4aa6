// The face graph of a polygon mesh and the breadth-first searches over it
// that the sharp-features stage (dgSharpFeatures.h) is made of. Internal to
// that stage.
#ifndef dgSharpFeaturesGraph_h
#define dgSharpFeaturesGraph_h

#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace dg
{
namespace sharp
{

struct Vec3
{
  double x = 0, y = 0, z = 0;
  Vec3() = default;
  Vec3(double a, double b, double c)
    : x(a)
    , y(b)
    , z(c)
  {
  }
  Vec3 operator+(const Vec3& o) const { return { x + o.x, y + o.y, z + o.z }; }
  Vec3 operator-(const Vec3& o) const { return { x - o.x, y - o.y, z - o.z }; }
  Vec3 operator*(double s) const { return { x * s, y * s, z * s }; }
  Vec3& operator+=(const Vec3& o)
  {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  double Dot(const Vec3& o) const { return x * o.x + y * o.y + z * o.z; }
  Vec3 Cross(const Vec3& o) const
  {
    return { y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x };
  }
  double Norm() const { return std::sqrt(this->Dot(*this)); }
  Vec3 Unit() const
  {
    const double n = this->Norm();
    return n > 0 ? *this * (1.0 / n) : Vec3();
  }
};

inline double AngleDegrees(const Vec3& a, const Vec3& b)
{
  // atan2 of |a x b| and a.b: accurate for small angles, unlike acos.
  return std::atan2(a.Cross(b).Norm(), a.Dot(b)) * 180.0 / M_PI;
}

// Faces around each edge (CSR) and edges of each face, from the polygons'
// sides; an edge is an unordered point pair.
struct FaceGraph
{
  std::vector<std::array<std::int64_t, 2>> Edges;
  std::vector<std::int64_t> EdgeFacePtr;
  std::vector<std::int64_t> EdgeFaces;
  std::vector<std::int64_t> FaceEdgePtr;
  std::vector<std::int64_t> FaceEdges;

  void Build(const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& conn);
};

struct UnionFind
{
  std::vector<int> Parent;
  explicit UnionFind(int n)
    : Parent(n)
  {
    std::iota(this->Parent.begin(), this->Parent.end(), 0);
  }
  int Find(int a)
  {
    while (this->Parent[a] != a)
      a = this->Parent[a] = this->Parent[this->Parent[a]];
    return a;
  }
  bool Unite(int a, int b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a == b)
      return false;
    this->Parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

// A search's visited stamps and queue, kept per thread between searches.
struct BreadthScratch
{
  std::vector<std::uint32_t> Stamp;
  std::uint32_t Current = 0;
  std::vector<std::pair<std::int64_t, int>> Queue;
};

// Breadth-first search over the face graph from f0, through the faces that
// pass(face) accepts, at most `limit` steps; visit(face, depth, limit) sees
// every face reached in order of depth and returns the limit (it may lower
// it). The scratch's stamps make each search O(faces reached).
template<class Pass, class Visit>
void Breadth(const FaceGraph& graph, BreadthScratch& s, std::int64_t f0, int limit,
  const Pass& pass, const Visit& visit)
{
  if (s.Stamp.empty())
    s.Stamp.assign(graph.FaceEdgePtr.size() - 1, 0);
  if (++s.Current == 0)
  {
    std::fill(s.Stamp.begin(), s.Stamp.end(), 0);
    s.Current = 1;
  }
  s.Queue.assign(1, { f0, 0 });
  s.Stamp[f0] = s.Current;
  for (std::size_t head = 0; head < s.Queue.size(); ++head)
  {
    const std::int64_t f = s.Queue[head].first;
    const int depth = s.Queue[head].second;
    if (depth > limit)
      break;
    limit = visit(f, depth, limit);
    if (depth >= limit)
      continue;
    for (std::int64_t k = graph.FaceEdgePtr[f]; k < graph.FaceEdgePtr[f + 1]; ++k)
    {
      const std::int64_t e = graph.FaceEdges[k];
      for (std::int64_t j = graph.EdgeFacePtr[e]; j < graph.EdgeFacePtr[e + 1]; ++j)
      {
        const std::int64_t g = graph.EdgeFaces[j];
        if (s.Stamp[g] != s.Current && pass(g))
        {
          s.Stamp[g] = s.Current;
          s.Queue.emplace_back(g, depth + 1);
        }
      }
    }
  }
}

} // namespace sharp
} // namespace dg

#endif
