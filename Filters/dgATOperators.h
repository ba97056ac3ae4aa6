// Discrete operators of the Ambrosio-Tortorelli functional (docs/method.md section 2)
// on any polygonal complex, and the sparsity structure of the two linear
// systems of the alternating minimisation (docs/method.md section 4).
//
// Plain C++ and Eigen: the complex is given as polygon offsets/connectivity
// (VTK's vtkCellArray layout), so that the core is testable and benchmarkable
// without a VTK pipeline. Faces carry u (one value per polygon), vertices carry
// v; the metric is the identity, so every quantity is in grid units.
//
// Edges are numbered by (low vertex id, high vertex id) in lexicographic order
// and oriented low -> high. A face's sides are oriented by the polygon's vertex
// order (counter-clockwise seen from outside for the digital surface), which
// gives the sign of B. Non-manifold edges (shared by 3+ faces) and boundary
// edges (1 face) are kept: the operators stay well defined.
//
// *choice* On a boundary edge, (B u)_e = +-u(f) compares u with an implicit
// zero outside the surface, which would mark every boundary of an open mesh
// as a discontinuity wherever u != 0. The AT systems and energy therefore
// leave boundary edges out of the jump term |diag(Mv) B u|^2 (a free,
// Neumann-like boundary); MatrixB() itself keeps them, as docs/method.md defines
// it. Closed surfaces (every digital surface) are not affected.
#ifndef dgATOperators_h
#define dgATOperators_h

#include <Eigen/Sparse>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace dg
{

using ATSparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
/// The system matrices are symmetric: stored full (both triangles), column
/// major, so that the same arrays serve a row-wise product and the direct
/// solvers (which read one triangle).
using ATSystemMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
/// A system matrix over a pattern and values held elsewhere: the solver's
/// two systems share one values buffer (ATSolver).
using ATSystemView = Eigen::Map<ATSystemMatrix>;

/// Bytes held per named structure (allocated capacity), for memory tables.
using ATMemoryParts = std::vector<std::pair<std::string, std::size_t>>;

/// The sparsity pattern of an n x n system matrix, without values: column
/// starts and row indices of the compressed column-major form.
struct ATPattern
{
  std::int64_t N = 0;
  std::vector<int> Outer, Inner;
  std::int64_t NonZeros() const { return this->Outer.empty() ? 0 : this->Outer.back(); }
  /// The matrix of this pattern with the given values (NonZeros() of them).
  ATSystemView View(double* values)
  {
    return ATSystemView(static_cast<Eigen::Index>(this->N), static_cast<Eigen::Index>(this->N),
      static_cast<Eigen::Index>(this->NonZeros()), this->Outer.data(), this->Inner.data(), values);
  }
  std::size_t Bytes() const
  {
    return (this->Outer.capacity() + this->Inner.capacity()) * sizeof(int);
  }
};

/// Combinatorics of a polygonal complex: faces, unique edges and their
/// incidences, plus the fixed sparsity patterns of both AT systems.
class ATComplex
{
public:
  /// Builds the complex from polygons in offsets/connectivity form
  /// (offsets has numberOfFaces + 1 entries). Consecutive repeated vertices
  /// (degenerate sides) are ignored. Returns false (with a message) when a
  /// vertex id is out of range or a face has fewer than 2 distinct sides.
  bool Build(std::int64_t numberOfVertices, const std::vector<std::int64_t>& offsets,
    const std::vector<std::int64_t>& connectivity, std::string* error = nullptr);

  std::int64_t NumberOfVertices() const { return this->NVertices; }
  std::int64_t NumberOfEdges() const { return static_cast<std::int64_t>(this->EdgeVertices.size() / 2); }
  std::int64_t NumberOfFaces() const { return this->NFaces; }

  /// 2 per edge: low id, high id (the edge's orientation runs low -> high).
  std::vector<int> EdgeVertices;
  /// Edge -> incident faces with the sign of B (CSR, faces ascending). The
  /// offsets are int: they count at most the polygons' sides, which Build
  /// bounds by 2^30.
  std::vector<int> EdgeFacePtr;
  std::vector<int> EdgeFaces;
  std::vector<signed char> EdgeFaceSigns;
  /// Vertex -> incident edges (CSR, edges ascending). As edges are numbered
  /// by (low, high), a vertex's neighbours come out ascending in this order:
  /// row a of VPattern is its edges' other ends with a inserted in order,
  /// which is how the v-assembly finds the edge of each non-zero.
  std::vector<int> VertexEdgePtr;
  std::vector<int> VertexEdges;
  /// Face -> its edges (CSR, edges ascending): the transpose of edge ->
  /// faces, which the u-assembly walks (the signs are read from there).
  std::vector<int> FaceEdgePtr;
  std::vector<int> FaceEdges;
  /// For each FaceEdges entry (face f, edge e), how e enters row f of the
  /// u-system when e has exactly 2 faces f, g with signs +-1 (the digital
  /// surfaces' only case): the position of g in the row (low 4 bits), f's
  /// sign negative (bit 4), g's sign negative (bit 5). FaceEdgeBoundary
  /// marks a boundary edge (no term), FaceEdgeGeneral any other edge
  /// (ATSolver::AssembleU then reads the incidences).
  std::vector<unsigned char> FaceEdgeCode;
  static constexpr unsigned char FaceEdgeBoundary = 0x40, FaceEdgeGeneral = 0x80;

  /// The operators of docs/method.md section 2, as sparse matrices (for tests, the
  /// energy and external use; the solver works from the arrays above).
  ATSparse MatrixA() const; // E x N, d0
  ATSparse MatrixB() const; // E x F, dual derivative
  ATSparse MatrixM() const; // E x N, 1/2 |A|

  /// False once a solver has taken the system patterns
  /// (ATSolver::TakePatterns).
  bool HasSystemPatterns() const
  {
    return this->UPattern.N == this->NFaces && this->VPattern.N == this->NVertices &&
      !this->UPattern.Outer.empty() && !this->VPattern.Outer.empty();
  }

  /// The bytes of every array above, by name.
  void Memory(ATMemoryParts& parts) const;

  /// Pattern of the u-system alpha I + B^T diag(w) B (F x F): row f holds f
  /// and every face sharing an interior edge with f, columns ascending. Its
  /// values are assembled from FaceEdges and EdgeFaces (ATSolver::AssembleU):
  /// no per-non-zero map is stored (it took 84 bytes per face).
  ATPattern UPattern;

  /// Pattern of the v-system (N x N): the vertex graph plus the diagonal
  /// (the k-th off-diagonal entry of row a comes from VertexEdges' k-th edge
  /// of a, see above).
  ATPattern VPattern;

private:
  void BuildSystemPatterns();
  std::int64_t NVertices = 0;
  std::int64_t NFaces = 0;
};

} // namespace dg

#endif
