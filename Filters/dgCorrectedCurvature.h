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

struct CurvatureParameters
{
  double Radius = 3.0; // ball radius, the positions' units
};

struct CurvatureResult
{
  // Per face, over the ball around its centre.
  std::vector<double> Mean;     // H = (k1 + k2) / 2; positive on a sphere with outward normals
  std::vector<double> Gaussian; // G = k1 k2
  std::vector<double> K1, K2;   // k1 >= k2
  std::vector<double> D1, D2;   // 3 per face: unit principal directions
  // Whole surface (each face once).
  double Area = 0;              // sum of mu0
  double TotalMean = 0;         // integral of H: sum of mu1 / 2
  double TotalGaussian = 0;     // integral of G: sum of mu2
};

/// points: 3 per point; polygons as offsets/connectivity (VTK's layout);
/// normals: 3 per face, unit; region: one per face or null (one region).
/// Returns false with a message on inconsistent input.
bool ComputeCorrectedCurvatures(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* normals, const int* region, const CurvatureParameters& parameters,
  CurvatureResult& result, std::string* error = nullptr);

} // namespace dg

#endif
