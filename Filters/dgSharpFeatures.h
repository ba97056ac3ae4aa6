// One line per sharp edge, on the edge, and the normal of its own side on
// every face up to it: a stage after Ambrosio-Tortorelli (docs/sharp-features.md).
//
// AT leaves a band of low v along each sharp edge, a few faces wide (two
// vertex lines either side of the edge with rungs between them, and the
// faces between them keeping the input estimator's blended normal). This
// core reads the band as "here is a discontinuity, somewhere inside" and
// decides where, from the smooth parts on either side:
//
// 1. Band faces: faces with a vertex whose v is below FeatureThreshold.
// 2. Regions: connected components of the other faces (through shared
//    edges). Regions with fewer than MinimumRegionSize faces (the inside of
//    AT's loops around noise bumps) are dissolved into the band.
// 3. Each band face looks for the regions around it: a breadth-first search
//    over the face graph collects region faces up to SearchDepth steps
//    beyond the first one it meets. Every region met (with at least
//    MinimumSupport faces) gives a local plane: the centroid of those faces
//    and the normalised mean of their normals. The face joins the side
//    that puts its outside voxel outside (signed distances to the planes;
//    only regions whose normal faces the same way as the face's own polygon
//    take part; with CurvedSides, a side's plane bends by the curvature its
//    normals show along the edge; a region whose normal field turns by
//    less than PlanarRegionAngle across it takes part with the plane
//    fitted to all its faces; with QuadricSides, another region larger
//    than three searches with the quadric fitted to all its faces, where
//    that quadric passes within an edge length of the faces found near
//    the band face) and takes that side's fitted normal. A
//    band face that meets no region keeps its normal and region -1.
// 4. Regions meeting along a boundary whose mean normal jump (over the
//    boundary's edges) is below MinimumFeatureAngle are merged: AT's false
//    bands inside a smooth part give no line. Weakest boundaries first, and
//    no chain of merges joins two regions whose own boundary jumps by
//    StrongFeatureAngle or more.
//    Then a boundary whose jump lies between the two angles merges when
//    everything already merged with its smaller side lies on the larger
//    side's whole-region quadric (QuadricMergeFactor): under noise AT
//    flattens patches of a curved surface into facets. The merged side's
//    faces take the quadric's normal (within StrongFeatureAngle of theirs).
// 5. Creases and bends (dgSharpFeaturesCreases.h): every line left between
//    two merged parts is kept only when the input estimator's normals,
//    fitted on each side beyond 0.75 InputRadius and extrapolated to the
//    line, jump by more than MinimumFeatureAngle plus what the sides'
//    curvature and noise explain, and the band's voxels reach the corner
//    its sides make (CornerDepth), and the voxels turn at the line: the
//    two sides' summed face area vectors within 2.5 edges of it meet at
//    MinimumTurnShare or more of their angle 4.5-9.5 edges out. The
//    others (AT's terraces on curved parts, fillets) merge, and the lines
//    left between the larger parts are tested again (up to 3 rounds).
// 6. Features: the edges between faces of two different (merged) regions.
//    The line runs where the two sides' faces meet: one staircase line.
// 7. The output field (dgSharpFeaturesField.h): a twiced Gaussian mean of
//    the input normals (the side normals near a line; with QuadricSides,
//    the normal of a side that is a quadric to within FitResidual; away
//    from the lines and AT's band, the input blended with AT's u by the
//    noise share, min(1, NoiseShare / 0.22)) over
//    the faces on the same side of every kept line, as wide as the noise
//    the surface shows calls for (FieldWidth). The data away from the
//    lines first undo the input's own blur where it leans them
//    (UndoInputBlur: one Van Cittert step with a Gaussian of
//    sqrt((0.375 InputRadius)^2 + 1.75) edges, gated by its own averaged
//    correction; under noise the correction itself averaged), and the
//    Gaussian is then at least 2 edges wide; where nothing leans, farther
//    than 2 SearchDepth from a line, it is 1.4 times as wide.
//
// Plain C++ on a polygon mesh in offsets/connectivity form (vtkCellArray's
// layout), testable without a pipeline.
#ifndef dgSharpFeatures_h
#define dgSharpFeatures_h

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace dg
{

struct SharpFeatureParameters
{
  double FeatureThreshold = 0.5; // v below it marks a band vertex
  int MinimumRegionSize = 30;    // faces; smaller regions join the band
  int SearchDepth = 5;           // face steps beyond the first region face met (fits)
  int SmoothingPasses = 2;       // majority votes over the band's labels
  int SmoothingDepth = 2;        // face steps of the vote's neighbourhood
  bool ExtrapolateSides = true;  // merges compare the sides' normal fields extrapolated to the boundary
  bool FitPlanes = true;         // local planes fitted to positions (else mean normals)
  bool CurvedSides = true;       // sides bend by their normals' curvature along the edge
  double FitResidual = 0.3;      // edge lengths: a fit with a larger RMS residual is not used
  int MinimumSupport = 3;        // region faces needed for a local plane
  int NormalSmoothingDepth = 3;  // final mean over the face's own region (0 = none)
  double MinimumFeatureAngle = 15.0; // degrees; weaker boundaries are merged
  double StrongFeatureAngle = 30.0;  // degrees; never merged, not even through other regions
  double ReferenceWeight = 0.2; // how fast a region's reference normal follows its faces
  double RegionEdgeAngle = 10.0; // degrees; a region does not grow across a larger jump
  double PlanarRegionAngle = 6.0; // degrees; regions whose normals turn less are planes (0: none)
  bool QuadricSides = true;       // large curved regions decide with their whole-region quadric,
                                  // and quadric sides give their normal near the lines
  double QuadricMergeFactor = 3.0; // a medium boundary merges when the smaller side lies on the
                                   // larger's quadric within this factor of its own RMS (0: never)
  double QuadricMergeDistance = 3.0; // edge lengths: ... and within this RMS distance
  double InputRadius = 4.0;  // edge lengths: how far the input normals blur a crease (II's radius)
  double CornerDepth = 0.6;  // edge lengths: a line whose band faces lie deeper inside the
                             // corner of its two sides is a bend (a fillet), not a crease
  double MinimumTurnShare = 0.5; // a line whose sides meet within 2.5 edges of it at less than
                                 // this share of their angle 4.5-9.5 edges out is a bend
  double FieldWidth = 0.0;   // edge lengths: the output field's Gaussian; 0: from the noise the
                             // surface shows; < 0: no field (the side and region normals as they are)
  bool UndoInputBlur = true; // the field's data undo the input's blur (a Gaussian of
                             // sqrt((0.375 InputRadius)^2 + 1.75) edges) where the blur
                             // leans them, with the correction averaged as the noise gauge
                             // grows (raw on a clean surface, averaged from k = 0.3);
                             // the field widens where nothing leans
};

struct SharpFeatureResult
{
  std::vector<double> Normals;  // 3 per face, unit
  std::vector<int> Region;      // per face: region id (0..NumberOfRegions-1) or -1
  std::vector<std::array<std::int64_t, 2>> FeatureEdges; // point id pairs
  std::vector<double> FeatureAngle; // per feature edge: normal jump (degrees)
  // Per face: bit i set when its side i (corners i, i + 1) is a feature edge
  // (sides past the eighth are not flagged).
  std::vector<unsigned char> CreaseSides;
  int NumberOfRegions = 0;
  std::int64_t NumberOfBandFaces = 0;
  std::int64_t NumberOfUnassignedFaces = 0; // band faces that met no region
  int NumberOfDissolvedRegions = 0;         // regions smaller than the minimum
  int NumberOfMergedBoundaries = 0;         // region pairs merged in step 4
  int NumberOfPlanarRegions = 0;            // regions whose whole plane decides their sides
  int NumberOfQuadricRegions = 0;           // regions whose whole quadric may decide their sides
  int NumberOfRefusedMerges = 0;            // weak boundaries left as lines: a strong one lies between
  int NumberOfQuadricMerges = 0;            // medium boundaries merged: one side on the other's quadric
  int NumberOfCreases = 0;                  // lines kept by the crease test
  int NumberOfBends = 0;                    // lines merged by it
  double NoiseShare = 0;                    // faces turned away from their input normal
  double FieldWidth = 0;                    // the output field's width, edge lengths (0: no field)
  double CreaseTestSeconds = 0;             // wall time of step 5, the crease test
  double FieldSeconds = 0;                  // wall time of step 7, the output field
};

/// points: 3 per point; normals: 3 per face (need not be unit; zero vectors
/// are allowed and count as "no direction"); v: one per point;
/// inputNormals: 3 per face, the input estimator's normals that AT
/// regularised (null: the crease test reads `normals` and no output field
/// is solved). Returns false
/// with a message on inconsistent input. `progress` (may be empty) gets a
/// fraction in [0, 1] and returns false to abort (then false, error empty).
bool ComputeSharpFeatures(std::int64_t numberOfPoints, const double* points,
  const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& connectivity,
  const double* normals, const double* v, const double* inputNormals,
  const SharpFeatureParameters& parameters,
  SharpFeatureResult& result, std::string* error = nullptr,
  const std::function<bool(double)>& progress = {});

} // namespace dg

#endif
