// Crease or bend: the sharp-features stage's test of every line left
// between two smooth parts (docs/sharp-features.md, step 7). Internal to
// that stage.
//
// The input estimator's normals blur a crease over its radius but follow a
// bend exactly. So each side's input normal field is fitted (linearly in
// the position) on that side's faces between Near and Far from the line,
// beyond most of the blur, and extrapolated to the line: across a crease the
// two extrapolations differ by its dihedral angle, across a bend they agree
// but for what the fits cannot follow (a change of curvature within Near,
// noise). A line is a crease when the median jump along it exceeds the
// minimum angle by more than
//  - what the more curved side's turn towards the other side, continued
//    over Near, could explain, and
//  - NoiseFactor times the fits' RMS residual,
// and when the surface reaches the corner its two sides make (the band
// faces' corner depth below CornerDepth): a fillet swallowed by AT's band
// leaves sides that meet at a steep angle, but its voxels cut the corner off.
// Sides facing apart (the stage's side normals 120 degrees or more apart:
// the two faces of a slab thinner than AT's band) make no corner, and only
// the jump decides. A line whose sides cannot be fitted beyond the blur
// shows no crease and is a bend.
//
// Last, the voxels themselves: a crease turns at the line, a bend all along
// its width. Each side's mean normal near the line (TurnNear) and farther
// out (TurnFar) is the sum of its faces' area vectors, which noise leaves
// alone (a bump's faces add up to nothing but its rim). A crease's sides
// meet near the line at most of the angle they make farther out; a bend of
// radius rho turns by about 2 s / rho within s of its middle. A line whose
// near angle is below MinimumTurnShare of its far angle is a bend.
//
// A line is the whole boundary between two groups, and two groups can meet
// along a crease and a bend at once: a sharp edge that ends where fillets
// round the part's other edges, whose sides have merged with the fillets'
// far side, meets it along the fillets too. So each edge of a line is also
// judged on the stretch of the line within Stretch of it, by the same
// rule. On a line that is a crease, a stretch whose voxels cut the corner
// (deep) is a bend and is not drawn; a line that is a bend keeps its sides
// apart when a stretch is clearly a crease (twice the margins: jump,
// corner depth, turn share), and only that stretch is drawn. Either kind
// counts only as a stretch of at least MinimumStretchEdges edges: a few
// edges' stretches tip either way under noise.
#ifndef dgSharpFeaturesCreases_h
#define dgSharpFeaturesCreases_h

#include "dgSharpFeaturesGraph.h"

#include <map>
#include <utility>
#include <vector>

namespace dg
{
namespace sharp
{

struct CreaseTestSettings
{
  double Near = 3, Far = 8;   // distances to the line of the faces fitted (lengths)
  double MinimumAngle = 15;   // degrees
  double CornerDepth = 0.6;   // length; deeper cuts are bends
  double NoiseFactor = 0.5;   // times the fits' RMS residual (degrees)
  int MinimumSamples = 5;     // boundary edges with both extrapolations
  int MinimumFit = 12;        // faces per side fit
  double EdgeLength = 1;      // the mesh's mean edge length
  // The voxel-scale turn (lengths from the line faces' centres; the slab
  // along the line each sample takes).
  double TurnNear = 2.5, TurnFarFrom = 4.5, TurnFar = 9.5, TurnSlab = 2.5;
  double MinimumTurnShare = 0.5;
  // Stretches: each edge judged on the line's edges within Stretch (a
  // length) of it, a stretch counting from MinimumStretchEdges edges.
  double Stretch = 8;
  int MinimumStretchEdges = 12;
};

struct CreaseVerdict
{
  int A = -1, B = -1;  // the two groups
  bool Crease = false; // else a bend (or too little evidence of a crease)
  double Jump = 0;     // median extrapolated jump (degrees; NaN without samples)
  double Allowance = 0; // what curvature and noise could explain (degrees)
  double Depth = 0;     // median corner depth (length; NaN without samples)
  double TurnShare = 0; // median near angle over median far angle (NaN without samples)
  int Edges = 0;
  bool Deep = false;    // the voxels cut the corner (a bend, whatever the jump)
};

/// group: per face, its smooth part (-1: none); centre, area, input, sides:
/// per face, its centre, area vector, unit input normal and the stage's side
/// normal so far;
/// cornerDepth: per face, how far inside
/// the corner of its two nearest sides it lies (NaN when not measured).
/// known: verdicts that still hold, by (A, B): a verdict depends only on
/// its two groups' faces, so a line between groups that have not changed
/// since it was tested is not tested again.
/// edgeCrease: per graph edge, set for the edges of every line tested now:
/// 1 where the line is drawn (a crease's stretch), 0 where it is not.
/// One verdict per pair of groups that share an edge, in (A, B) order.
std::vector<CreaseVerdict> TestCreases(const FaceGraph& graph, const std::vector<Vec3>& centre,
  const std::vector<Vec3>& area, const std::vector<Vec3>& input, const std::vector<Vec3>& sides,
  const std::vector<int>& group, const std::vector<double>& cornerDepth, const CreaseTestSettings& settings,
  const std::map<std::pair<int, int>, CreaseVerdict>& known, std::vector<signed char>& edgeCrease);

} // namespace sharp
} // namespace dg

#endif
