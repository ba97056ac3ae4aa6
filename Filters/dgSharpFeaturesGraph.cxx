#include "dgSharpFeaturesGraph.h"

#include <algorithm>

namespace dg
{
namespace sharp
{

void FaceGraph::Build(const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& conn)
{
  const std::int64_t F = static_cast<std::int64_t>(offsets.size()) - 1;
  struct Side
  {
    std::int64_t A, B, Face;
  };
  std::vector<Side> sides;
  sides.reserve(conn.size());
  for (std::int64_t f = 0; f < F; ++f)
  {
    const std::int64_t b = offsets[f], e = offsets[f + 1];
    for (std::int64_t k = b; k < e; ++k)
    {
      const std::int64_t p = conn[k], q = conn[k + 1 < e ? k + 1 : b];
      if (p != q)
        sides.push_back({ std::min(p, q), std::max(p, q), f });
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& s, const Side& t) {
    return s.A != t.A ? s.A < t.A : s.B != t.B ? s.B < t.B : s.Face < t.Face;
  });
  this->EdgeFacePtr.assign(1, 0);
  std::vector<std::int64_t> faceEdgeCount(F + 1, 0);
  std::vector<std::pair<std::int64_t, std::int64_t>> faceEdge; // (face, edge)
  faceEdge.reserve(sides.size());
  for (std::size_t i = 0; i < sides.size();)
  {
    std::size_t j = i;
    const std::int64_t e = static_cast<std::int64_t>(this->Edges.size());
    this->Edges.push_back({ sides[i].A, sides[i].B });
    for (; j < sides.size() && sides[j].A == sides[i].A && sides[j].B == sides[i].B; ++j)
    {
      // A face that runs twice along the same edge counts once.
      if (j == i || sides[j].Face != sides[j - 1].Face)
      {
        this->EdgeFaces.push_back(sides[j].Face);
        faceEdge.emplace_back(sides[j].Face, e);
        ++faceEdgeCount[sides[j].Face + 1];
      }
    }
    this->EdgeFacePtr.push_back(static_cast<std::int64_t>(this->EdgeFaces.size()));
    i = j;
  }
  std::partial_sum(faceEdgeCount.begin(), faceEdgeCount.end(), faceEdgeCount.begin());
  this->FaceEdgePtr = faceEdgeCount;
  this->FaceEdges.assign(faceEdge.size(), 0);
  std::vector<std::int64_t> fill(faceEdgeCount.begin(), faceEdgeCount.end() - 1);
  for (const auto& fe : faceEdge)
    this->FaceEdges[fill[fe.first]++] = fe.second;
}

} // namespace sharp
} // namespace dg
