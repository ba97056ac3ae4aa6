#include "dgATOperators.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <limits>

namespace dg
{
namespace
{
// One polygon side seen from its lower vertex.
struct Side
{
  int High;
  int Face;
  signed char Sign; // +1 when the face runs low -> high along it
  bool operator<(const Side& o) const
  {
    return this->High != o.High ? this->High < o.High : this->Face < o.Face;
  }
};

// Exclusive prefix sum in place; returns the total.
std::int64_t PrefixSum(std::vector<std::int64_t>& a)
{
  std::int64_t s = 0;
  for (auto& x : a)
  {
    const std::int64_t c = x;
    x = s;
    s += c;
  }
  a.push_back(s);
  return s;
}

void SetPattern(ATSystemMatrix& m, std::int64_t n, const std::vector<std::int64_t>& ptr,
  const std::vector<int>& columns)
{
  m.resize(static_cast<int>(n), static_cast<int>(n));
  m.resizeNonZeros(static_cast<Eigen::Index>(columns.size()));
  for (std::int64_t i = 0; i <= n; ++i)
  {
    m.outerIndexPtr()[i] = static_cast<int>(ptr[i]);
  }
  std::copy(columns.begin(), columns.end(), m.innerIndexPtr());
  std::fill(m.valuePtr(), m.valuePtr() + columns.size(), 0.0);
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
  // surface that large (2^31 edges) would not fit in memory anyway.
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
  std::vector<std::int64_t> bucket(nv, 0);
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
  std::vector<Side> sides(nSides);
  {
    std::vector<std::int64_t> fill(bucket.begin(), bucket.end() - 1);
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
  std::vector<std::int64_t> edgeCount(nv), incidenceCount(nv);
  vtkSMPTools::For(0, nv, [&](std::int64_t vb, std::int64_t ve) {
    for (std::int64_t v = vb; v < ve; ++v)
    {
      std::sort(sides.begin() + bucket[v], sides.begin() + bucket[v + 1]);
      std::int64_t ne = 0, ni = 0;
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
  this->EdgeVertices.assign(2 * nEdges, 0);
  this->EdgeFacePtr.assign(nEdges + 1, 0);
  this->EdgeFaces.assign(nIncidences, 0);
  this->EdgeFaceSigns.assign(nIncidences, 0);
  vtkSMPTools::For(0, nv, [&](std::int64_t vb, std::int64_t ve) {
    for (std::int64_t v = vb; v < ve; ++v)
    {
      std::int64_t e = edgeCount[v] - 1, i = incidenceCount[v] - 1;
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
  this->EdgeFacePtr[nEdges] = nIncidences;
  sides = std::vector<Side>();

  // 3. Vertex -> edges (filled in edge order, so ascending).
  this->VertexEdgePtr.assign(nv, 0);
  for (std::int64_t e = 0; e < nEdges; ++e)
  {
    ++this->VertexEdgePtr[this->EdgeVertices[2 * e]];
    ++this->VertexEdgePtr[this->EdgeVertices[2 * e + 1]];
  }
  PrefixSum(this->VertexEdgePtr);
  this->VertexEdges.assign(2 * nEdges, 0);
  {
    std::vector<std::int64_t> fill(this->VertexEdgePtr.begin(), this->VertexEdgePtr.end() - 1);
    for (std::int64_t e = 0; e < nEdges; ++e)
    {
      this->VertexEdges[fill[this->EdgeVertices[2 * e]]++] = static_cast<int>(e);
      this->VertexEdges[fill[this->EdgeVertices[2 * e + 1]]++] = static_cast<int>(e);
    }
  }
  this->BuildSystemPatterns();
  return true;
}

void ATComplex::BuildSystemPatterns()
{
  const std::int64_t nf = this->NFaces, nv = this->NVertices;
  const std::int64_t ne = this->NumberOfEdges();

  // Face -> (edge, sign), from the edge -> face incidences (ascending edges).
  std::vector<std::int64_t> faceEdgePtr(nf, 0);
  for (std::int64_t i = 0; i < this->EdgeFacePtr[ne]; ++i)
  {
    ++faceEdgePtr[this->EdgeFaces[i]];
  }
  PrefixSum(faceEdgePtr);
  std::vector<int> faceEdges(faceEdgePtr[nf]);
  std::vector<signed char> faceSigns(faceEdgePtr[nf]);
  {
    std::vector<std::int64_t> fill(faceEdgePtr.begin(), faceEdgePtr.end() - 1);
    for (std::int64_t e = 0; e < ne; ++e)
    {
      for (std::int64_t i = this->EdgeFacePtr[e]; i < this->EdgeFacePtr[e + 1]; ++i)
      {
        const std::int64_t k = fill[this->EdgeFaces[i]]++;
        faceEdges[k] = static_cast<int>(e);
        faceSigns[k] = this->EdgeFaceSigns[i];
      }
    }
  }

  // u-system: row f couples f with every face sharing one of its edges;
  // entry (f, g) collects s_f(e) s_g(e) w(e) over the shared edges e. Two
  // passes (count, then fill) keep the output independent of the threads.
  struct Entry
  {
    int Column, Edge;
    signed char Coef;
    bool operator<(const Entry& o) const
    {
      return this->Column != o.Column ? this->Column < o.Column : this->Edge < o.Edge;
    }
  };
  auto rowEntries = [&](std::int64_t f, std::vector<Entry>& entries) {
    entries.clear();
    for (std::int64_t k = faceEdgePtr[f]; k < faceEdgePtr[f + 1]; ++k)
    {
      const int e = faceEdges[k];
      if (this->EdgeFacePtr[e + 1] - this->EdgeFacePtr[e] < 2)
      {
        continue; // boundary edge: no jump (see the header)
      }
      for (std::int64_t i = this->EdgeFacePtr[e]; i < this->EdgeFacePtr[e + 1]; ++i)
      {
        entries.push_back({ this->EdgeFaces[i], e,
          static_cast<signed char>(faceSigns[k] * this->EdgeFaceSigns[i]) });
      }
    }
    // A face always has its diagonal, even with no edge (alpha I).
    entries.push_back({ static_cast<int>(f), -1, 0 });
    std::sort(entries.begin(), entries.end());
  };
  std::vector<std::int64_t> rowNnz(nf), rowContrib(nf);
  vtkSMPTools::For(0, nf, [&](std::int64_t fb, std::int64_t fe) {
    std::vector<Entry> entries;
    for (std::int64_t f = fb; f < fe; ++f)
    {
      rowEntries(f, entries);
      std::int64_t n = 0;
      for (std::size_t j = 0; j < entries.size(); ++j)
      {
        n += j == 0 || entries[j].Column != entries[j - 1].Column;
      }
      rowNnz[f] = n;
      rowContrib[f] = static_cast<std::int64_t>(entries.size()) - 1;
    }
  });
  const std::int64_t nnzU = PrefixSum(rowNnz);
  const std::int64_t nContrib = PrefixSum(rowContrib);
  std::vector<int> columns(nnzU);
  this->UContribPtr.assign(nnzU + 1, 0);
  this->UContribEdge.assign(nContrib, 0);
  this->UContribCoef.assign(nContrib, 0);
  this->UDiagonal.assign(nf, 0);
  vtkSMPTools::For(0, nf, [&](std::int64_t fb, std::int64_t fe) {
    std::vector<Entry> entries;
    for (std::int64_t f = fb; f < fe; ++f)
    {
      rowEntries(f, entries);
      std::int64_t k = rowNnz[f] - 1, c = rowContrib[f];
      for (std::size_t j = 0; j < entries.size(); ++j)
      {
        if (j == 0 || entries[j].Column != entries[j - 1].Column)
        {
          ++k;
          columns[k] = entries[j].Column;
          this->UContribPtr[k] = c;
          if (entries[j].Column == f)
          {
            this->UDiagonal[f] = static_cast<int>(k);
          }
        }
        if (entries[j].Edge >= 0)
        {
          this->UContribEdge[c] = entries[j].Edge;
          this->UContribCoef[c] = entries[j].Coef;
          ++c;
        }
      }
    }
  });
  this->UContribPtr[nnzU] = nContrib;
  SetPattern(this->UPattern, nf, rowNnz, columns);

  // v-system: the vertex graph plus the diagonal. Edges are unique vertex
  // pairs, so each off-diagonal entry comes from exactly one edge.
  std::vector<std::int64_t> vPtr(nv);
  for (std::int64_t v = 0; v < nv; ++v)
  {
    vPtr[v] = this->VertexEdgePtr[v + 1] - this->VertexEdgePtr[v] + 1;
  }
  const std::int64_t nnzV = PrefixSum(vPtr);
  std::vector<int> vColumns(nnzV);
  this->VEdge.assign(nnzV, -1);
  vtkSMPTools::For(0, nv, [&](std::int64_t vb, std::int64_t ve) {
    std::vector<std::pair<int, int>> row;
    for (std::int64_t v = vb; v < ve; ++v)
    {
      row.clear();
      row.push_back({ static_cast<int>(v), -1 });
      for (std::int64_t k = this->VertexEdgePtr[v]; k < this->VertexEdgePtr[v + 1]; ++k)
      {
        const int e = this->VertexEdges[k];
        const int a = this->EdgeVertices[2 * e], b = this->EdgeVertices[2 * e + 1];
        row.push_back({ a == v ? b : a, e });
      }
      std::sort(row.begin(), row.end());
      for (std::size_t j = 0; j < row.size(); ++j)
      {
        vColumns[vPtr[v] + j] = row[j].first;
        this->VEdge[vPtr[v] + j] = row[j].second;
      }
    }
  });
  SetPattern(this->VPattern, nv, vPtr, vColumns);
}

namespace
{
template <typename T>
std::size_t Bytes(const std::vector<T>& v)
{
  return v.capacity() * sizeof(T);
}
} // namespace

std::size_t MatrixBytes(const ATSystemMatrix& m)
{
  return static_cast<std::size_t>(m.nonZeros()) * (sizeof(double) + sizeof(int)) +
    static_cast<std::size_t>(m.outerSize() + 1) * sizeof(int);
}

void ATComplex::Memory(ATMemoryParts& parts) const
{
  parts.emplace_back("complex: edge vertices", Bytes(this->EdgeVertices));
  parts.emplace_back("complex: edge -> faces (ptr, faces, signs)",
    Bytes(this->EdgeFacePtr) + Bytes(this->EdgeFaces) + Bytes(this->EdgeFaceSigns));
  parts.emplace_back(
    "complex: vertex -> edges (ptr, edges)", Bytes(this->VertexEdgePtr) + Bytes(this->VertexEdges));
  parts.emplace_back("complex: u pattern (zero values + indices)", MatrixBytes(this->UPattern));
  parts.emplace_back("complex: u assembly map (ptr, edge, coefficient, diagonal)",
    Bytes(this->UContribPtr) + Bytes(this->UContribEdge) + Bytes(this->UContribCoef) +
      Bytes(this->UDiagonal));
  parts.emplace_back("complex: v pattern (zero values + indices)", MatrixBytes(this->VPattern));
  parts.emplace_back("complex: v edge of each non-zero", Bytes(this->VEdge));
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
