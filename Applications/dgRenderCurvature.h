// The program's curvature picture (--curvature): the surface coloured by
// its corrected mean curvature H (a diverging map, blue concave, red convex,
// a range symmetric about 0) with the creases drawn over it, beside the
// interface shape distribution: the 2-D histogram of the principal
// curvatures (k1, k2) over the surface's area, as materials scientists plot
// it. Width x Width / 2 pixels.
#ifndef dgRenderCurvature_h
#define dgRenderCurvature_h

#include <vtkPolyData.h>

#include <string>

namespace dg
{
/// surface carries the cell arrays CorrectedMeanCurvature, CorrectedK1 and
/// CorrectedK2 (vtkCorrectedCurvatureFilter's port 0); creases (may be null
/// or empty) holds line cells on its points. Writes a PNG; false with error
/// set when it cannot.
bool RenderCurvaturePicture(vtkPolyData* surface, vtkPolyData* creases, int width,
  const std::string& pngPath, std::string& error);

/// The summary's words for the curvature's balls: "ball R voxels", or with
/// a radius per face "ball radius per face from R voxels", followed, when
/// surface (port 0, with CorrectedBallRadius) is given, by the radii's 10th,
/// 50th and 90th percentiles over its faces, in voxels (usedRadius: R in
/// world units, the filter's UsedRadius).
std::string CurvatureBallText(
  double radiusVoxels, bool adaptive, double usedRadius, vtkPolyData* surface);
}

#endif
