// Step 3 of the sharp-features stage (dgSharpFeatures.h): each face of
// AT's bands joins one of the smooth regions around it, the one whose local
// model puts the face's outside voxel outside, and takes that side's
// normal. Internal to that stage; docs/sharp-features.md says why.
#ifndef dgSharpFeaturesSides_h
#define dgSharpFeaturesSides_h

#include "dgSharpFeatures.h"
#include "dgSharpFeaturesGraph.h"
#include "dgSharpFeaturesRegionFits.h"

#include <vector>

namespace dg
{
namespace sharp
{

// Per-thread scratch of the band faces' searches.
struct SearchScratch : BreadthScratch
{
  std::vector<RegionSample> Samples;
  std::vector<std::int64_t> Fit;
};

/// bandFaces: the faces to place; region: per face, its region (-1 in the
/// band); planes, quadrics: the whole-region models (invalid where none);
/// quadricDistance: per face, its distance to its own region's quadric
/// (empty without quadrics); centre, polyNormal, field: per face, its
/// centre, polygon normal and unit field normal; meanEdge2: the mean edge
/// length.
/// assigned, out: per face, its region and normal, updated for the band
/// faces that met a region (a copy of region and field on entry);
/// cornerDepth: per band face that met two sides or more, how far inside
/// the corner the two sides' models make it lies (> 0: the surface cuts
/// the corner off), NaN elsewhere.
void ChooseSides(const FaceGraph& graph, const std::vector<std::int64_t>& bandFaces,
  const std::vector<int>& region, const std::vector<RegionPlane>& planes,
  const std::vector<RegionQuadric>& quadrics, const std::vector<double>& quadricDistance,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& polyNormal,
  const std::vector<Vec3>& field, double meanEdge2, const SharpFeatureParameters& par,
  std::vector<int>& assigned, std::vector<Vec3>& out, std::vector<double>& cornerDepth);

} // namespace sharp
} // namespace dg

#endif
