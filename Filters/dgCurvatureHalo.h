// The corrected-curvature stage over pieces (docs/curvature-measures.md,
// "Pieces"): each process receives, from every other, the faces whose
// centres lie within `reach` of its own faces' bounding box, so that every
// ball around one of its faces, and every corner normal of a face in such a
// ball, sees the same faces as in one process. Faces are matched by their
// global ids and points by theirs; a face is owned by exactly one process
// (its input's non-ghost cells), which alone sends it.
#ifndef dgCurvatureHalo_h
#define dgCurvatureHalo_h

#include <cstdint>
#include <string>
#include <vector>

class vtkMultiProcessController;

namespace dg
{
/// A piece's polygons: its own first, then (after GatherCurvatureHalo) the
/// ghost faces received from the others.
struct CurvatureMesh
{
  std::vector<double> Points;               // 3 per point
  std::vector<std::int64_t> PointIds;       // global id per point
  std::vector<std::int64_t> Offsets{ 0 }, Connectivity;
  std::vector<double> Normals;              // 3 per face
  std::vector<int> Region;                  // one per face, or empty
  std::vector<unsigned char> CreaseSides;   // one per face, or empty
  std::vector<std::int64_t> FaceIds;        // global id per face
  std::vector<unsigned char> Ghost;         // one per face
  std::int64_t OwnFaces = 0, OwnPoints = 0;
};

/// Adds the other processes' faces within `reach` of this piece's faces'
/// bounding box to `mesh` (collective: every process calls it, pieces
/// without faces too). Returns false on every process when the pieces'
/// arrays disagree (a region array on some pieces only).
bool GatherCurvatureHalo(vtkMultiProcessController* controller, double reach, CurvatureMesh& mesh,
  std::string& error);

/// Sums `values` over all processes, in rank order (the same bits on every
/// process, whatever the timing).
void SumOverPieces(vtkMultiProcessController* controller, double* values, int count);
} // namespace dg

#endif
