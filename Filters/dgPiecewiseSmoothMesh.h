// A piecewise-smooth mesh from a digital surface and a normal field
// (issue 36, docs/mesh.md): the surface's vertices move so that every face
// is orthogonal to its normal, the crease lines (the sharp stage's drawn
// edges, or the edges between feature regions) straighten along their
// direction, and each vertex stays within its voxel corner's cell.
//
// Plain C++ core on the surface's own arrays, in grid units (a voxel side
// is 1 along each axis: FindSurfaceFrame gives the map from world
// coordinates). With d the displacement of the vertices from the digital
// surface's corners p0 and E_ab = p0_b - p0_a + d_b - d_a a side's vector,
// the energy is
//
//   E(d) = sum over faces f, sides (a, b) of f:  (n_f . E_ab)^2
//        + beta sum over crease edges (a, b):   |E_ab - (k . E_ab) k|^2
//        + sum over vertices v:  alpha_n (m_v . d_v)^2 + alpha_t |d_v - (m_v . d_v) m_v|^2
//
// (n_f the face's normal, k the crease's direction n_f x n_g / |n_f x n_g|
// for the two faces across it, m_v the mean normal at the vertex): faces
// orthogonal to their normals, creases straight, each vertex held along
// its normal (alpha_n) more than across it (alpha_t), under the bound
// |d_v|_inf <= h < 1/2 (within its voxel corner's cell).
//
// The normal parts couple x, y and z. Each iteration therefore solves a
// separable surrogate with the same gradient at the current positions:
// every side's target is its current vector minus its component along the
// face's normal (the crease's: its component along the crease), every
// vertex's its current displacement minus the part its data term damps.
// That is one graph Laplacian (edge weight: the number of face sides on
// the edge, plus beta on a crease) plus (alpha_n + alpha_t) I, the same
// for x, y and z: three right-hand sides, conjugate gradients with the
// module's IC(0) preconditioner. The bound is kept by ADMM on the split
// d = z, z in the box, one ADMM step per iteration: the matrix gains rho I
// and never changes, so it is factorised once and the three coordinates
// share every sweep over it; z, the result, is always in the box
// (docs/mesh.md says why and what each part does).
#ifndef dgPiecewiseSmoothMesh_h
#define dgPiecewiseSmoothMesh_h

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace dg
{
class ATDistribution;

/// The grid behind a digital surface: world = Origin + Axes * grid, with the
/// columns of Axes (column-major, 3 x 3) the world vectors of one voxel step
/// along each image axis.
struct SurfaceFrame
{
  double Origin[3] = { 0, 0, 0 };
  double Axes[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  void ToGrid(const double* world, double* grid) const;
  void ToWorld(const double* grid, double* world) const;
  /// A world normal as a unit normal of the grid frame (normals map by the
  /// transpose of Axes).
  void NormalToGrid(const double* world, double* grid) const;
};

/// The frame from the surface's own edges: every polygon side must be one
/// voxel step along one of three independent directions (a digital surface
/// of any origin, spacing and orientation). False with a message otherwise.
bool FindSurfaceFrame(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  SurfaceFrame& frame, std::string& error);

struct MeshParameters
{
  // alpha_n: how strongly each vertex stays at its digital surface corner
  // along its normal, against the faces' weight 1 per side. It fixes where
  // each smooth part lies (the mean of its corners); too little and the
  // creases' staircase pulls whole faces inwards (a rotated cube loses
  // 1.6 % of its volume at 0.01, 0.1 % at 0.1, with the true normals).
  double DataWeight = 0.05;
  // alpha_t: the same across the normal (vertices slide freely along the
  // surface, within their cell).
  double TangentialWeight = 0.01;
  // beta: the weight of a crease edge's straightness, against 1 per face
  // side.
  double CreaseWeight = 1.0;
  // A crease edge whose two faces' normals make less than this angle
  // (degrees) has no direction to keep: it gets no crease term.
  double CreaseMinimumAngle = 5.0;
  // The bound on each coordinate of a displacement (grid units). Below
  // 1/2, two faces that share no corner cannot meet: their corners' cells
  // are apart by 1 - 2 h along some axis (docs/mesh.md). At 1/2 the two
  // sides of a sheet one voxel thin can meet in its middle.
  double BoxHalfWidth = 0.49;
  // Conjugate gradients' relative residual in the last iteration.
  double Tolerance = 1e-5;
  // The same for the iterations before the last.
  double EarlyTolerance = 1e-3;
  int MaximumIterations = 5000;
  // ADMM's penalty on d - z (against the faces' weight 1 per side).
  double Penalty = 1.0;
  // Iterations of the surrogate (each a solve from the previous one's
  // positions).
  int Iterations = 16;

  /// Empty when valid, else what is wrong.
  std::string Check() const;
};

struct MeshStatistics
{
  std::int64_t CGIterations = 0;     // all solves
  std::int64_t BoundCoordinates = 0; // coordinates held at the box at the end
  std::int64_t CreaseEdges = 0;      // edges with a crease term
  bool Converged = true;             // every solve converged
  double PrimalResidual = 0;         // max |d - z| of the last ADMM iteration (grid units)
  double Seconds = 0;
};

/// Vertex and face inputs of RegularizeMesh, on the caller's arrays.
struct MeshInput
{
  std::int64_t NumberOfPoints = 0;
  const double* Points = nullptr; // 3 per point, grid units
  const std::vector<std::int64_t>* Offsets = nullptr;
  const std::vector<std::int64_t>* Connectivity = nullptr;
  const double* FaceNormals = nullptr; // 3 per face, unit, grid frame
  const int* FaceRegion = nullptr;     // 1 per face, or null: no crease
  // 1 per face, or null: bit i marks side i (corners i, i + 1) as a crease,
  // whatever the regions (the sharp stage's drawn edges, which may end
  // where two regions still meet).
  const unsigned char* FaceCreaseSides = nullptr;
  // With pieces: the vertex rows' distribution (dgATHalo: the points are
  // its rows, owned first, and the polygons every one around an owned
  // point); the result's owned rows then equal one process's.
  const ATDistribution* Distribution = nullptr;
};

struct MeshResult
{
  std::vector<double> Displacement; // 3 per point, grid units
  // The edges between faces of two regions (or more, where labels meet),
  // 4 values each: low and high point, and the two faces across the edge
  // whose normals differ most; ascending by (low, high).
  std::vector<std::int64_t> Creases;
  MeshStatistics Statistics;
};

/// Minimises E under the box bound. Returns false with a message when the
/// input is not usable.
bool RegularizeMesh(const MeshInput& in, const MeshParameters& p, MeshResult& result,
  std::string& error, const std::function<bool(double)>& progress = nullptr);

/// For each quad, which diagonal splits it: 0 for (0, 2), 1 for (1, 3):
/// the one whose two triangles' normals stay closest to the face's normal
/// (the least sum of (1 - cos) weighted by area). Other polygons get 0.
std::vector<unsigned char> QuadDiagonals(const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* faceNormals);

/// One copy of each point per fan of faces around it, fans being separated
/// by the creases (edges whose two faces lie in different regions, or that
/// a face's `creaseSides` bits flag, as MeshInput::FaceCreaseSides) and by
/// edges with other than two faces: `copyOf` gets the input point of each
/// output point, `connectivity` is rewritten onto the copies. A point with
/// no crease around it keeps one copy, and so does a point where a crease
/// ends; copies are numbered in point order. Without regions and flags only
/// the non-manifold edges separate fans.
void SplitPointsAtCreases(std::int64_t numberOfPoints, const std::vector<std::int64_t>& offsets,
  std::vector<std::int64_t>& connectivity, const int* faceRegion, const unsigned char* creaseSides,
  std::vector<std::int64_t>& copyOf);

} // namespace dg

#endif
