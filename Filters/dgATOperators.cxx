#include "dgATOperators.h"

#include "dgHugePages.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>

namespace dg
{
namespace
{
// One polygon side seen from its lower vertex.
struct Side
{
  int High = 0;
  int Face = 0;
  signed char Sign = 0; // +1 when the face runs low -> high along it
  bool operator<(const Side& o) const
  {
    return this->High != o.High ? this->High < o.High : this->Face < o.Face;
  }
};

// Exclusive prefix sum in place; appends and returns the total.
template <class T>
std::int64_t PrefixSum(std::vector<T>& a)
{
  std::int64_t s = 0;
  for (auto& x : a)
  {
    const std::int64_t c = x;
    x = static_cast<T>(s);
    s += c;
  }
  a.push_back(static_cast<T>(s));
  return s;
}

// An n x n pattern, its column starts from ptr; the caller fills the row
// indices in place.
void StartPattern(ATPattern& m, std::int64_t n, const std::vector<int>& ptr)
{
  m.N = n;
  AssignHuge(m.Outer, ptr.begin(), ptr.begin() + n + 1);
  AssignHuge(m.Inner, static_cast<std::size_t>(ptr[n]), 0);
}
} // namespace

bool ATComplex::Build(std::int64_t numberOfVertices, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity, std::string* error)
{
  auto fail = [error](const std::string& what) {
    if (error)
    {
      *error = what;
    }
    return false;
  };
  const std::int64_t nFaces = offsets.empty() ? 0 : static_cast<std::int64_t>(offsets.size()) - 1;
  // Everything is indexed with int, as Eigen's default sparse storage; a
  // surface that large (2^31 edges) would not fit in memory anyway. The
  // sides (hence the incidences) are at most 2^30, so their offsets are int.
  const std::int64_t intMax = std::numeric_limits<int>::max();
  if (numberOfVertices > intMax || nFaces > intMax ||
    static_cast<std::int64_t>(connectivity.size()) > intMax / 2)
  {
    return fail("the complex is too large (more than 2^31 elements)");
  }
  this->NVertices = numberOfVertices;
  this->NFaces = nFaces;
  const std::int64_t nv = numberOfVertices;

  // 1. Sides bucketed by their lower vertex. The fill is sequential (cheap),
  // the per-bucket sort makes the order independent of how it was filled.
  std::vector<int> bucket;
  AssignHuge(bucket, static_cast<std::size_t>(nv), 0, nv + 1);
  for (std::int64_t f = 0; f < nFaces; ++f)
  {
    const std::int64_t b = offsets[f], e = offsets[f + 1];
    int sides = 0;
    for (std::int64_t k = b; k < e; ++k)
    {
      const std::int64_t p = connectivity[k], q = connectivity[k + 1 < e ? k + 1 : b];
      if (p < 0 || p >= nv)
      {
        return fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(p) +
          ", out of range [0, " + std::to_string(nv) + ")");
      }
      if (p != q)
      {
        ++bucket[std::min(p, q)];
        ++sides;
      }
    }
    if (sides < 2)
    {
      return fail("face " + std::to_string(f) + " is degenerate (fewer than 2 distinct vertices)");
    }
  }
  const std::int64_t nSides = PrefixSum(bucket);
  std::vector<Side> sides;
  AssignHuge(sides, static_cast<std::size_t>(nSides), Side{});
  {
    std::vector<int> fill;
    AssignHuge(fill, bucket.begin(), bucket.end() - 1);
    for (std::int64_t f = 0; f < nFaces; ++f)
    {
      const std::int64_t b = offsets[f], e = offsets[f + 1];
      for (std::int64_t k = b; k < e; ++k)
      {
        const std::int64_t p = connectivity[k], q = connectivity[k + 1 < e ? k + 1 : b];
        if (p != q)
        {
          const std::int64_t lo = std::min(p, q);
          sides[fill[lo]++] = { static_cast<int>(std::max(p, q)), static_cast<int>(f),
            static_cast<signed char>(p < q ? 1 : -1) };
        }
      }
    }
  }

  // 2. Unique edges per bucket and unique (edge, face) incidences; a face
  // that runs twice along the same edge gets the sum of its signs.
  std::vector<int> edgeCount, incidenceCount;
  AssignHuge(edgeCount, static_cast<std::size_t>(nv), 0, nv + 1);
  AssignHuge(incidenceCount, static_cast<std::size_t>(nv), 0, nv + 1);
  vtkSMPTools::For(0, nv, [&](std::int64_t vb, std::int64_t ve) {
    for (std::int64_t v = vb; v < ve; ++v)
    {
      std::sort(sides.begin() + bucket[v], sides.begin() + bucket[v + 1]);
      int ne = 0, ni = 0;
      for (std::int64_t s = bucket[v]; s < bucket[v + 1]; ++s)
      {
        const bool newEdge = s == bucket[v] || sides[s].High != sides[s - 1].High;
        ne += newEdge;
        ni += newEdge || sides[s].Face != sides[s - 1].Face;
      }
      edgeCount[v] = ne;
      incidenceCount[v] = ni;
    }
  });
  const std::int64_t nEdges = PrefixSum(edgeCount);
  const std::int64_t nIncidences = PrefixSum(incidenceCount);
  if (nEdges > intMax / 2)
  {
    return fail("the complex is too large (more than 2^30 edges)");
  }
  AssignHuge(this->EdgeVertices, static_cast<std::size_t>(2 * nEdges), 0);
  AssignHuge(this->EdgeFacePtr, static_cast<std::size_t>(nEdges + 1), 0);
  AssignHuge(this->EdgeFaces, static_cast<std::size_t>(nIncidences), 0);
  AssignHuge(
    this->EdgeFaceSigns, static_cast<std::size_t>(nIncidences), static_cast<signed char>(0));
  vtkSMPTools::For(0, nv, [&](std::int64_t vb, std::int64_t ve) {
    for (std::int64_t v = vb; v < ve; ++v)
    {
      int e = edgeCount[v] - 1, i = incidenceCount[v] - 1;
      for (std::int64_t s = bucket[v]; s < bucket[v + 1]; ++s)
      {
        const bool newEdge = s == bucket[v] || sides[s].High != sides[s - 1].High;
        if (newEdge)
        {
          ++e;
          this->EdgeVertices[2 * e] = static_cast<int>(v);
          this->EdgeVertices[2 * e + 1] = sides[s].High;
          this->EdgeFacePtr[e] = i + 1;
        }
        if (newEdge || sides[s].Face != sides[s - 1].Face)
        {
          ++i;
          this->EdgeFaces[i] = sides[s].Face;
        }
        this->EdgeFaceSigns[i] = static_cast<signed char>(this->EdgeFaceSigns[i] + sides[s].Sign);
      }
    }
  });
  this->EdgeFacePtr[nEdges] = static_cast<int>(nIncidences);
  // Freed before the larger arrays below are made, so that they reuse it.
  std::vector<Side>().swap(sides);
  std::vector<int>().swap(bucket);

  // 3. Vertex -> edges (filled in edge order, so ascending). A vertex's
  // edges as the lower end are the contiguous run edgeCount[v]...: only
  // the edges it ends are scattered.
  AssignHuge(this->VertexEdgePtr, static_cast<std::size_t>(nv), 0, nv + 1);
  for (std::int64_t e = 0; e < nEdges; ++e)
  {
    ++this->VertexEdgePtr[this->EdgeVertices[2 * e + 1]];
  }
  for (std::int64_t v = 0; v < nv; ++v)
  {
    this->VertexEdgePtr[v] += edgeCount[v + 1] - edgeCount[v];
  }
  PrefixSum(this->VertexEdgePtr);
  AssignHuge(this->VertexEdges, static_cast<std::size_t>(2 * nEdges), 0);
  {
    // Edges ending at v come first (their lower ends are below v), in edge
    // order; then v's own run.
    std::vector<int> fill;
    AssignHuge(fill, this->VertexEdgePtr.begin(), this->VertexEdgePtr.end() - 1);
    for (std::int64_t e = 0; e < nEdges; ++e)
    {
      this->VertexEdges[fill[this->EdgeVertices[2 * e + 1]]++] = static_cast<int>(e);
    }
    vtkSMPTools::For(0, nv, [&](std::int64_t vb, std::int64_t ve) {
      for (std::int64_t v = vb; v < ve; ++v)
      {
        int k = fill[v];
        for (int e = edgeCount[v]; e < edgeCount[v + 1]; ++e)
        {
          this->VertexEdges[k++] = e;
        }
      }
    });
  }
  std::vector<int>().swap(edgeCount);
  std::vector<int>().swap(incidenceCount);
  this->BuildSystemPatterns();
  return true;
}

void ATComplex::BuildSystemPatterns()
{
  const std::int64_t nf = this->NFaces, nv = this->NVertices;
  const std::int64_t ne = this->NumberOfEdges();

  // Face -> edges, from the edge -> face incidences (ascending edges).
  AssignHuge(this->FaceEdgePtr, static_cast<std::size_t>(nf), 0, nf + 1);
  for (int i = 0; i < this->EdgeFacePtr[ne]; ++i)
  {
    ++this->FaceEdgePtr[this->EdgeFaces[i]];
  }
  PrefixSum(this->FaceEdgePtr);
  AssignHuge(this->FaceEdges, static_cast<std::size_t>(this->FaceEdgePtr[nf]), 0);
  {
    std::vector<int> fill;
    AssignHuge(fill, this->FaceEdgePtr.begin(), this->FaceEdgePtr.end() - 1);
    for (std::int64_t e = 0; e < ne; ++e)
    {
      for (int i = this->EdgeFacePtr[e]; i < this->EdgeFacePtr[e + 1]; ++i)
      {
        this->FaceEdges[fill[this->EdgeFaces[i]]++] = static_cast<int>(e);
      }
    }
  }

  // u-system: row f couples f with every face sharing an interior edge with
  // it. Two passes (count, then fill) keep the output independent of the
  // threads.
  auto rowColumns = [&](std::int64_t f, std::vector<int>& columns) {
    columns.clear();
    columns.push_back(static_cast<int>(f)); // a face always has its diagonal (alpha I)
    for (int k = this->FaceEdgePtr[f]; k < this->FaceEdgePtr[f + 1]; ++k)
    {
      const int e = this->FaceEdges[k];
      if (this->EdgeFacePtr[e + 1] - this->EdgeFacePtr[e] < 2)
      {
        continue; // boundary edge: no jump (see the header)
      }
      columns.insert(columns.end(), this->EdgeFaces.begin() + this->EdgeFacePtr[e],
        this->EdgeFaces.begin() + this->EdgeFacePtr[e + 1]);
    }
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
  };
  std::vector<int> rowPtr;
  AssignHuge(rowPtr, static_cast<std::size_t>(nf), 0, nf + 1);
  vtkSMPTools::For(0, nf, [&](std::int64_t fb, std::int64_t fe) {
    std::vector<int> columns;
    for (std::int64_t f = fb; f < fe; ++f)
    {
      rowColumns(f, columns);
      rowPtr[f] = static_cast<int>(columns.size());
    }
  });
  PrefixSum(rowPtr);
  StartPattern(this->UPattern, nf, rowPtr);
  int* uInner = this->UPattern.Inner.data();
  vtkSMPTools::For(0, nf, [&](std::int64_t fb, std::int64_t fe) {
    std::vector<int> columns;
    for (std::int64_t f = fb; f < fe; ++f)
    {
      rowColumns(f, columns);
      std::copy(columns.begin(), columns.end(), uInner + rowPtr[f]);
    }
  });
  std::vector<int>().swap(rowPtr);
  AssignHuge(this->FaceEdgeCode, this->FaceEdges.size(), FaceEdgeGeneral);
  vtkSMPTools::For(0, nf, [&](std::int64_t fb, std::int64_t fe) {
    for (std::int64_t f = fb; f < fe; ++f)
    {
      const int* r0 = uInner + this->UPattern.Outer[f];
      const int* r1 = uInner + this->UPattern.Outer[f + 1];
      for (int j = this->FaceEdgePtr[f]; j < this->FaceEdgePtr[f + 1]; ++j)
      {
        const int e = this->FaceEdges[j], i0 = this->EdgeFacePtr[e];
        const int n = this->EdgeFacePtr[e + 1] - i0;
        if (n < 2)
        {
          this->FaceEdgeCode[j] = FaceEdgeBoundary;
          continue;
        }
        const int self = this->EdgeFaces[i0] == f ? i0 : i0 + 1, other = 2 * i0 + 1 - self;
        const signed char sf = this->EdgeFaceSigns[self], so = this->EdgeFaceSigns[other];
        const std::ptrdiff_t pos = std::lower_bound(r0, r1, this->EdgeFaces[other]) - r0;
        if (n == 2 && (sf == 1 || sf == -1) && (so == 1 || so == -1) && pos < 16)
        {
          this->FaceEdgeCode[j] =
            static_cast<unsigned char>(pos | (sf < 0 ? 0x10 : 0) | (so < 0 ? 0x20 : 0));
        }
      }
    }
  });

  // v-system: the vertex graph plus the diagonal. A vertex's edges give its
  // neighbours ascending (see the header): no sort.
  std::vector<int> vPtr;
  AssignHuge(vPtr, static_cast<std::size_t>(nv), 0, nv + 1);
  for (std::int64_t v = 0; v < nv; ++v)
  {
    vPtr[v] = this->VertexEdgePtr[v + 1] - this->VertexEdgePtr[v] + 1;
  }
  PrefixSum(vPtr);
  StartPattern(this->VPattern, nv, vPtr);
  int* vInner = this->VPattern.Inner.data();
  vtkSMPTools::For(0, nv, [&](std::int64_t vb, std::int64_t ve) {
    for (std::int64_t v = vb; v < ve; ++v)
    {
      int k = vPtr[v];
      bool diagonal = false;
      for (int j = this->VertexEdgePtr[v]; j < this->VertexEdgePtr[v + 1]; ++j)
      {
        const int e = this->VertexEdges[j];
        const int a = this->EdgeVertices[2 * e], b = this->EdgeVertices[2 * e + 1];
        const int other = a == v ? b : a;
        if (!diagonal && other > v)
        {
          vInner[k++] = static_cast<int>(v);
          diagonal = true;
        }
        vInner[k++] = other;
      }
      if (!diagonal)
      {
        vInner[k] = static_cast<int>(v);
      }
    }
  });
}

namespace
{
template <typename T>
std::size_t Bytes(const std::vector<T>& v)
{
  return v.capacity() * sizeof(T);
}
} // namespace

void ATComplex::Memory(ATMemoryParts& parts) const
{
  parts.emplace_back("complex: edge vertices", Bytes(this->EdgeVertices));
  parts.emplace_back("complex: edge -> faces (ptr, faces, signs)",
    Bytes(this->EdgeFacePtr) + Bytes(this->EdgeFaces) + Bytes(this->EdgeFaceSigns));
  parts.emplace_back(
    "complex: vertex -> edges (ptr, edges)", Bytes(this->VertexEdgePtr) + Bytes(this->VertexEdges));
  parts.emplace_back("complex: face -> edges (ptr, edges, codes; u assembly)",
    Bytes(this->FaceEdgePtr) + Bytes(this->FaceEdges) + Bytes(this->FaceEdgeCode));
  parts.emplace_back("complex: u pattern (indices)", this->UPattern.Bytes());
  parts.emplace_back("complex: v pattern (indices)", this->VPattern.Bytes());
}

ATSparse ATComplex::MatrixA() const
{
  const std::int64_t ne = this->NumberOfEdges();
  ATSparse a(static_cast<int>(ne), static_cast<int>(this->NVertices));
  a.resizeNonZeros(2 * ne);
  for (std::int64_t e = 0; e <= ne; ++e)
  {
    a.outerIndexPtr()[e] = static_cast<int>(2 * e);
  }
  for (std::int64_t e = 0; e < ne; ++e)
  {
    a.innerIndexPtr()[2 * e] = this->EdgeVertices[2 * e];
    a.innerIndexPtr()[2 * e + 1] = this->EdgeVertices[2 * e + 1];
    a.valuePtr()[2 * e] = -1.0;
    a.valuePtr()[2 * e + 1] = 1.0;
  }
  return a;
}

ATSparse ATComplex::MatrixM() const
{
  ATSparse m = this->MatrixA();
  std::fill(m.valuePtr(), m.valuePtr() + m.nonZeros(), 0.5);
  return m;
}

ATSparse ATComplex::MatrixB() const
{
  const std::int64_t ne = this->NumberOfEdges();
  ATSparse b(static_cast<int>(ne), static_cast<int>(this->NFaces));
  b.resizeNonZeros(static_cast<Eigen::Index>(this->EdgeFaces.size()));
  for (std::int64_t e = 0; e <= ne; ++e)
  {
    b.outerIndexPtr()[e] = static_cast<int>(this->EdgeFacePtr[e]);
  }
  for (std::size_t i = 0; i < this->EdgeFaces.size(); ++i)
  {
    b.innerIndexPtr()[i] = this->EdgeFaces[i];
    b.valuePtr()[i] = this->EdgeFaceSigns[i];
  }
  return b;
}

} // namespace dg
