// The sharp-features stage's output normals (docs/sharp-features.md, step
// 10): once the stage has decided which lines are creases, each face gets a
// weighted mean of the data normals of the faces around it on its own side
// of every crease.
//
// The weights are a Gaussian of the Euclidean distance between face centres
// (standard deviation `width`, cut at 2.5 widths), over the faces reached
// from the face through face edges that are not creases: a crease's two
// sides never mix, and a line that ends lets the field round its end, as
// the surface does. A Gaussian in space, not a smoothing along the face
// graph, because the graph of a voxel surface is a staircase: its steps
// make graph distances anisotropic, and a graph smoothing leaves a
// direction-dependent error that a ball does not (docs/sharp-features.md).
// The smoothing is twiced, u = K d + K (d - K d), which cancels the
// leading bias of K on a curved field; faces whose data point more than
// 90 degrees from the face's own (the other side of a thin part), or from
// the mean of all where the face's own is the odd one out, are not
// weighted. Where the surface is evenly curved (the lean that
// UndoBlurWithinSides measures is small) the same twicing runs with K K,
// a Gaussian about 1.4 times as wide.
#ifndef dgSharpFeaturesField_h
#define dgSharpFeaturesField_h

#include "dgSharpFeaturesGraph.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace dg
{
namespace sharp
{

/// The faces next to each face across an edge that is not a crease:
/// Next[Ptr[f] .. Ptr[f + 1]) (fewer than 2^32 faces).
struct SideNeighbours
{
  std::vector<std::int64_t> Ptr;
  std::vector<std::uint32_t> Next;
  void Build(const FaceGraph& graph, const std::vector<char>& crease, std::int64_t faces);
};

/// What each face's Gaussian may read, found once and read by every pass
/// that reaches no farther: the faces grouped in cubes, and for each cube
/// and each part of it that creases separate, the faces that part reaches
/// through face edges that are not creases, within Reach of the cube.
/// Finding them is most of a pass's cost; the output field's passes share
/// one set, and sets of other widths share its Sides.
struct FieldSearches
{
  std::shared_ptr<const SideNeighbours> Sides;
  double Reach = 0;
  std::vector<std::int64_t> TilePtr;   // faces of cube t: TileFaces[TilePtr[t] .. TilePtr[t + 1])
  std::vector<std::int64_t> TileFaces; // only the faces the set was found for
  struct Cube
  {
    std::vector<std::uint32_t> Members;   // the parts' faces, part after part
    std::vector<std::uint32_t> PartStart; // part p: Members[PartStart[p] .. PartStart[p + 1])
    std::vector<std::int32_t> Part;       // per face of the cube, in TileFaces' order
  };
  std::vector<Cube> Cubes;
};

/// The searches for Gaussians of standard deviation up to `width` (cut at
/// 2.5 widths; cubes 2 widths wide), for the faces `where` marks (every
/// face when null). Sides are built unless searches already holds them
/// (from a set for the same creases). False when width is not positive,
/// the surface has 2^32 faces or more, or spans 2^21 cubes.
bool FindFieldSearches(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, double width, FieldSearches& searches,
  const std::vector<char>* where = nullptr);

/// graph: the faces' edges; crease: per graph edge, nonzero where the field
/// must not pass; centre and data: per face (data unit or zero); width in
/// the centres' units. normals gets one unit vector per face (the data where
/// the mean is zero). where, when given, marks the faces whose normals are
/// needed (the others get theirs only where that costs nothing; edge: the
/// mean edge length, which sizes the margin the first pass needs).
/// leanDegrees (without a mask): UndoBlurWithinSides' lean per face; where
/// its mean over the Gaussian is small (below WideStartDegrees: an evenly
/// curved part, far from any change of curvature) the field is the same
/// twicing with K K, about 1.4 times as wide, blended into the narrower up
/// to WideFullDegrees. shared,
/// when given: searches for the same creases, read when found for this
/// width to twice it over every face (not only the masked ones; else only
/// their Sides are). False when width is not positive.
bool SmoothFieldWithinSides(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& data, double width,
  std::vector<Vec3>& normals, const std::vector<char>* where = nullptr, double edge = 1.0,
  const FieldSearches* shared = nullptr, const std::vector<double>* leanDegrees = nullptr);

/// The gate of UndoBlurWithinSides, in degrees: the step's correction
/// averaged over the gate's Gaussian turns the face by GateStartDegrees
/// (the step stays off) to GateFullDegrees (the step acts in full). Where
/// the surface is evenly curved the averaged correction is the
/// digitisation's wiggle, which the step would double: 0.5-0.8 degrees at
/// the 99th percentile on spheres, tori and ellipsoids (II radius 4, 64^3
/// and 128^3); where the curvature changes (a fillet meeting a plane) it is
/// the blur's lean, 1-3 degrees (docs/sharp-features.md, step 10).
constexpr double GateStartDegrees = 0.5;
constexpr double GateFullDegrees = 1.0;

/// How much higher the gate's thresholds are for an averaged correction
/// (UndoBlurWithinSides' averaged = 1): measured at k = 0.3, 64^3, the
/// sphere, ellipsoid and torus stay within 0.02 degrees of the step off
/// with 1.5 times the thresholds, and lose up to 0.05 with 1 times.
constexpr double AveragedGateRaise = 0.5;

/// The wider field of SmoothFieldWithinSides where the lean, averaged over
/// the field's Gaussian, stays below WideStartDegrees (the 90th percentile
/// of that average on spheres, tori and ellipsoids, 64^3 and 128^3, is
/// 0.25-0.57 degrees), the narrower from WideFullDegrees (their 99th:
/// 0.45-0.80; next to a fillet of radius 4 it is 1.4 at the median).
constexpr double WideStartDegrees = 0.4;
constexpr double WideFullDegrees = 0.8;

/// One Van Cittert step against a blur of the data by the same faces'
/// Gaussian of standard deviation `width` (not twiced): normals gets
/// unit(d + gain c), c = d - unit(G d), on the faces `where` marks (every
/// face when null) and the data elsewhere. Where the data are a normal field
/// blurred by about that Gaussian (an estimator's ball), the step takes out
/// the blur's leading term. With gateWidth > 0 the gain is scaled per face
/// by the gate above, c averaged by a Gaussian of that width, its
/// thresholds times gateScale, and leanDegrees, when given, gets that
/// average's size per face divided by gateScale (0 without a gate). The
/// thresholds are for II of radius 4; the digitisation's wiggle in an
/// estimator's normals falls about as the inverse of its radius r, and 4 /
/// r keeps DGtal's goursat surface at r 8 and 16 where it was without the
/// gate (docs/sharp-features.md, step 10). shared as for
/// SmoothFieldWithinSides. averaged (0-1, with a gate only): the share
/// of c replaced by its average over three passes of the gate's Gaussian,
/// and the gate's thresholds raised by AveragedGateRaise times that share
/// (for noisy data, whose raw correction is mostly noise). False when width
/// is not positive.
bool UndoBlurWithinSides(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& data, double width, double gain,
  std::vector<Vec3>& normals, const std::vector<char>* where = nullptr,
  const FieldSearches* shared = nullptr, double gateWidth = 0,
  std::vector<double>* leanDegrees = nullptr, double gateScale = 1.0, double averaged = 0.0);

} // namespace sharp
} // namespace dg

#endif
