// Feature and normal metrics against a shape's ground truth (issue 15's
// definitions), shared by the tests and the quality benchmark. Grid
// coordinates (image origin 0, spacing 1).
//
// - multiplicity: total length of the feature segments whose midpoint lies
//   within 1.5 voxels of a true sharp edge, over the true edges' length
//   (one staircase line along an edge is 1 to 1.73);
// - offset: mean distance of those midpoints to the true edge;
// - precision: share of the feature length within 1.5 voxels of a true edge;
// - recall: share of the true edges' length (sampled every 0.25 voxel) with
//   a feature segment within 1.5 voxels;
// - normal errors: unoriented angle (0..90 degrees) to the true normal on the
//   surfels whose centre is within 2 voxels of the true surface; mean over
//   all of them and over those within 1 and 3 voxels of a true edge
//   (distance of the centre projected onto the true surface).
#ifndef dgFeatureMetrics_h
#define dgFeatureMetrics_h

#include "dgGroundTruth.h"

#include <string>

class vtkPolyData;

namespace dgtest
{

struct FeatureMetrics
{
  double Length = 0, Multiplicity = 0, Offset = 0, Precision = 0, Recall = 0;
  double MeanError = 0, Error1 = 0, Error3 = 0;
  std::string Describe() const;
};

/// surface: a digital surface (InsideVoxel and SurfelDirection cell arrays)
/// carrying the cell normal array `normals`; lines: feature segments on
/// grid coordinates.
FeatureMetrics MeasureFeatures(const ImplicitShape& shape, vtkPolyData* surface,
  const char* normals, vtkPolyData* lines);

/// On shapes with no sharp edge (issue 39): the feature length per 1000
/// surfels, the output normals' error against the true normal at each
/// quad's centre (mean, 95th percentile, largest; degrees, unoriented), the
/// input normals' mean and 95th percentile, and the share of quads (%) whose
/// output normal is 10 degrees or more worse than their input normal.
struct SmoothMetrics
{
  double FeaturesPer1000 = 0, Mean = 0, P95 = 0, Max = 0, InputMean = 0, InputP95 = 0;
  double WorseShare = 0;
  std::string Describe() const;
};
SmoothMetrics MeasureSmooth(const ImplicitShape& shape, vtkPolyData* surface,
  const char* outputNormals, const char* inputNormals, vtkPolyData* lines);

} // namespace dgtest

#endif
