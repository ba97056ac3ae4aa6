// Discrete operators of the Ambrosio-Tortorelli functional (MATH.md section 2)
// on any polygonal complex, and the sparsity structure of the two linear
// systems of the alternating minimisation (MATH.md section 4).
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
// Neumann-like boundary); MatrixB() itself keeps them, as MATH.md defines
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

/// Bytes held per named structure (allocated capacity), for memory tables.
using ATMemoryParts = std::vector<std::pair<std::string, std::size_t>>;
/// Bytes of a sparse matrix's values, inner indices and column starts.
std::size_t MatrixBytes(const ATSystemMatrix& m);

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
  /// Edge -> incident faces with the sign of B (CSR, faces ascending).
  std::vector<std::int64_t> EdgeFacePtr;
  std::vector<int> EdgeFaces;
  std::vector<signed char> EdgeFaceSigns;
  /// Vertex -> incident edges (CSR, edges ascending).
  std::vector<std::int64_t> VertexEdgePtr;
  std::vector<int> VertexEdges;

  /// The operators of MATH.md section 2, as sparse matrices (for tests, the
  /// energy and external use; the solver works from the arrays above).
  ATSparse MatrixA() const; // E x N, d0
  ATSparse MatrixB() const; // E x F, dual derivative
  ATSparse MatrixM() const; // E x N, 1/2 |A|

  /// False once a solver has taken the system patterns
  /// (ATSolver::TakePatterns).
  bool HasSystemPatterns() const
  {
    return this->UPattern.rows() == this->NFaces && this->VPattern.rows() == this->NVertices;
  }

  /// The bytes of every array above, by name.
  void Memory(ATMemoryParts& parts) const;

  /// Pattern of the u-system alpha I + B^T diag(w) B (F x F) and, for every
  /// stored non-zero k, the contributions w[ContribEdge[j]] * ContribCoef[j]
  /// for j in [UContribPtr[k], UContribPtr[k+1]). The coefficients are
  /// products of two signs of B, so +1 or -1: one byte each.
  ATSystemMatrix UPattern;
  std::vector<std::int64_t> UContribPtr;
  std::vector<int> UContribEdge;
  std::vector<signed char> UContribCoef;
  std::vector<int> UDiagonal; // index of (f, f) in UPattern's value array

  /// Pattern of the v-system (N x N): the vertex graph plus the diagonal;
  /// VEdge[k] is the edge joining the two vertices of non-zero k, or -1 on
  /// the diagonal.
  ATSystemMatrix VPattern;
  std::vector<int> VEdge;

private:
  void BuildSystemPatterns();
  std::int64_t NVertices = 0;
  std::int64_t NFaces = 0;
};

} // namespace dg

#endif
