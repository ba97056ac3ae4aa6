// Corrected curvature measures (issue 37): the curvature of a polygonal
// surface whose own normals are replaced by a better field u.
//
// Plain C++ core, testable without a pipeline. For a face with corners
// x_0..x_{m-1} and corrected normals u_i at its corners, the face is cut
// into the m triangles (b, x_i, x_{i+1}) around its barycentre b (normal:
// the normalised mean of the u_i), u is interpolated linearly on each
// triangle (a, b, c) and the measures of the resulting normal current are,
// exactly:
//   mu0 = 1/2 <u_m, (b - a) x (c - a)>                      (area)
//   mu1 = 1/2 (<u_m, (u_c - u_b) x a> + <u_m, (u_a - u_c) x b>
//              + <u_m, (u_b - u_a) x c>)                    (2 H area)
//   mu2 = 1/2 <u_a, u_b x u_c>                              (G area)
//   muXY = 1/2 (det(u_m, <Y, u_c - u_a> X, b - a)
//               - det(u_m, <Y, u_b - u_a> X, c - a))        (anisotropic)
// with u_m = (u_a + u_b + u_c) / 3. Summed over the faces of a ball of
// radius R, H = mu1 / (2 mu0), G = mu2 / mu0 and the principal curvatures
// are the tangential eigenvalues of the symmetrised muXY / mu0.
//
// The corner normals are the normalised mean of the face normals around the
// corner; in the per-side mode (a region id per face) only the faces of the
// face's own region count, for the corner normals and for the ball, so that
// a ball never measures a crease between two regions.
#ifndef dgCorrectedCurvature_h
#define dgCorrectedCurvature_h

#include <cstdint>
#include <string>
#include <vector>

namespace dg
{

struct CorrectedMeasures
{
  double Mu0 = 0, Mu1 = 0, Mu2 = 0;
  double MuXY[9] = { 0, 0, 0, 0, 0, 0, 0, 0, 0 }; // row-major, not symmetrised
};

/// The measures of one polygon: corners (3 per corner) and corner normals
/// (3 per corner, any length; the interpolation is linear).
CorrectedMeasures PolygonMeasures(int corners, const double* x, const double* u);

/// With the per-face radius, each face's ball radius lies in
/// [kMinRadiusFactor, kMaxRadiusFactor] times CurvatureParameters::Radius.
constexpr double kMinRadiusFactor = 2.0 / 3.0;
constexpr double kMaxRadiusFactor = 3.0;

struct CurvatureParameters
{
  double Radius = 3.0; // ball radius, the positions' units
  // A ball radius per face (docs/curvature-measures.md, "The ball radius per
  // face"): Radius is the first pass's, and each face's radius is then
  // chosen from the noise and the variation of the curvature measured
  // around it, within [2/3, 3] Radius and below its smallest curvature
  // radius. Off: every ball has radius Radius.
  bool AdaptiveRadius = false;
  // The width of the ramp by which a face cut by the ball's sphere counts
  // (the positions' units); 0: the faces' mean edge length. Pieces of one
  // surface pass the whole surface's, so that they agree with one process.
  double EdgeLength = 0.0;
};

struct CurvatureResult
{
  // Per face, over the ball around its centre.
  std::vector<double> Mean;     // H = (k1 + k2) / 2; positive on a sphere with outward normals
  std::vector<double> Gaussian; // G = k1 k2
  std::vector<double> K1, K2;   // k1 >= k2
  std::vector<double> D1, D2;   // 3 per face: unit principal directions
  std::vector<double> BallNormal; // 3 per face: the normalised mean of u over the ball
  std::vector<double> BallRadius; // per face: the radius of its ball (0: no result)
  // Whole surface (each face once; per side where regions are given).
  double Area = 0;          // sum of mu0
  double TotalMean = 0;     // integral of H: faces' mu1 / 2, plus CreaseTotalMean per side
  double TotalGaussian = 0; // integral of G: the exact solid angle the continuous field
                            // sweeps (2 pi chi on a closed surface, creases and corners included)
  std::int64_t EulerCharacteristic = 0; // V - E + F of the faces' own complex
  double EulerShare = 0; // the same before rounding: a piece's share, which pieces add up
  std::int64_t BoundaryEdges = 0;       // edges used by one face only
  double Volume = 0; // enclosed by the faces (divergence theorem); NaN with boundary edges
  // Per-side mode: the edges between faces of two regions, each once, as
  // point pairs, with the angle (radians) by which the normal turns across
  // the edge, from one side's normal at the edge to the other's: positive
  // where the surface is convex (a cube's edges), negative where it is
  // concave; and the edge's length along the crease. The crease's mean
  // curvature measure is angle times length (mu1 concentrated on the line).
  std::vector<std::int64_t> CreaseEdges; // 2 per edge
  std::vector<double> CreaseAngle;       // 1 per edge, radians
  std::vector<double> CreaseLength;      // 1 per edge
  double CreaseTotalMean = 0;            // sum of angle * length / 2
};

/// How far from a face the measures of its ball reach (a piece's ghost
/// faces must cover this much around its own): the ball, its ramp, the
/// ring of faces its faces' corner normals need, and with the per-face
/// radius the largest ball of a representative face near it.
double CurvatureReach(const CurvatureParameters& parameters, double edgeLength);

/// points: 3 per point; polygons as offsets/connectivity (VTK's layout);
/// normals: 3 per face, unit; region: one per face or null (one region).
/// ghost: one per face or null; a ghost face (non-zero) lends its measures
/// to its neighbours' balls but gets no result of its own and is left out of
/// the whole-surface figures and the crease edges (a piece of a distributed
/// surface, whose ghost faces reach at least the ball's radius).
/// faceIds: one per face or null; global ids, so that pieces agree on which
/// of a crease edge's two faces reports it (the smaller id's owner).
/// creaseSides: one per face or null (with regions only): bit i marks the
/// face's side i (corners i, i + 1) as a drawn crease edge. The creases are
/// then those edges, not every edge between two regions: at a point no
/// drawn edge touches, the corner normals take all faces around it, so a
/// stretch of a region boundary the sharp stage left undrawn (a bend) is
/// measured as surface, not as a crease. The balls still keep to regions.
/// Returns false with a message on inconsistent input.
bool ComputeCorrectedCurvatures(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* normals, const int* region, const CurvatureParameters& parameters,
  CurvatureResult& result, std::string* error = nullptr, const unsigned char* ghost = nullptr,
  const std::int64_t* faceIds = nullptr, const unsigned char* creaseSides = nullptr);

} // namespace dg

#endif
