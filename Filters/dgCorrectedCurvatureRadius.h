// The ball radius per face of the corrected curvature stage
// (docs/curvature-measures.md, "The ball radius per face"): the faces'
// groups and their representatives, the representatives' balls of R to 3 R,
// the noise and the variation of the curvature they measure, and each
// face's radius and sums from them. Internal to that stage.
#ifndef dgCorrectedCurvatureRadius_h
#define dgCorrectedCurvatureRadius_h

#include "dgCorrectedCurvatureBalls.h"

namespace dg
{
namespace curvature
{

// The faces of each cell and region are a group, with their interior
// faces' sums and mean centre, and a representative face, the one nearest
// the cell's centre (ties: the smaller global id), whose balls of R to 3 R
// give the noise and the variation of the curvature around it.
struct FaceGroups
{
  std::vector<std::int64_t> CellGroupStart, BlockGroupStart; // first group of each cell, block
  std::vector<std::int64_t> Rep; // the representative's position in cell order
  std::vector<int> Region;
  std::vector<double> Sums; // SUMS per group: its interior faces' measures
  std::vector<V3> Centre;   // its interior faces' mean centre
  std::int64_t Size() const { return static_cast<std::int64_t>(this->Rep.size()); }
};

/// The groups of cells sorted with blocks. faceIds: global ids or null.
void GroupFaces(const FaceCells& cells, const std::int64_t* faceIds, FaceGroups& groups);

/// Each face's radius and its curvatures over the ball of that radius, from
/// every face's first pass (firstSums: SUMS per position of `cells`, the
/// ball of R; keepRadius: per position, the ball of R is not a whole disc
/// of its region's interior faces, so the face keeps R). Faces with a
/// result (BallRadius > 0) get their directions here.
void ChooseBallRadii(const FaceCells& cells, const FaceGroups& groups,
  const double* firstSums, const std::vector<char>& keepRadius,
  const unsigned char* ghost, double R, CurvatureResult& result);

} // namespace curvature
} // namespace dg

#endif
