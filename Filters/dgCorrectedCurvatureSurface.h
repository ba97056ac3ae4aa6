// The whole-surface figures of the corrected curvature stage
// (dgCorrectedCurvature.h, docs/curvature-measures.md "Whole-surface
// figures" and "Creases"): the faces' complex as a 2-manifold and its Euler
// characteristic, the integral of G as the solid angle the continuous field
// sweeps, the area and the enclosed volume, and the crease edges between
// regions with their angle and length. Internal to that stage.
#ifndef dgCorrectedCurvatureSurface_h
#define dgCorrectedCurvatureSurface_h

#include "dgCorrectedCurvatureBalls.h"

namespace dg
{
namespace curvature
{

// A polygon surface as the stage reads it.
struct Surface
{
  const double* Points = nullptr;                        // 3 per point
  const std::vector<std::int64_t>* Offsets = nullptr;      // VTK's layout
  const std::vector<std::int64_t>* Connectivity = nullptr;
  const double* Normals = nullptr; // 3 per face, unit
  const int* Region = nullptr;     // per face or null
  // Per face or null: bit i, the side from corner i to i + 1 is a crease.
  const unsigned char* CreaseSides = nullptr;
  // With CreaseSides: per point, whether a crease side ends there.
  std::vector<char> OnCrease;
  const unsigned char* Ghost = nullptr;
  const std::int64_t* FaceIds = nullptr;
  // The faces around each point (CSR), and the corners (positions in
  // Connectivity) by which they hold it.
  std::vector<std::int64_t> Start, Around, AroundCorner;

  std::int64_t Faces() const { return static_cast<std::int64_t>(this->Offsets->size()) - 1; }
  bool IsGhost(std::int64_t f) const { return this->Ghost && this->Ghost[f] != 0; }
  /// Whether face g counts on face f's side at point p: always without
  /// regions, and at a point no crease side touches.
  bool SameSide(std::int64_t f, std::int64_t g, std::int64_t p) const
  {
    return !this->Region || this->Region[f] == this->Region[g] ||
      (this->CreaseSides && !this->OnCrease[p]);
  }
  /// Whether face f flags its side between corners ka and kb (positions in
  /// Connectivity, neighbours in f) as a crease.
  bool FlagsSide(std::int64_t f, std::int64_t ka, std::int64_t kb) const;
  /// The normal of side `f` at point p: the mean of the faces around p on
  /// f's side.
  V3 CornerNormal(std::int64_t f, std::int64_t p) const;
};

// An edge between faces of two regions, reported by the piece owning F,
// the face of smaller global id.
struct Crease
{
  std::int64_t A, B, F, G;
};

/// The figures over the faces this call owns (not ghost) into result:
/// Area, TotalGaussian, EulerCharacteristic, EulerShare, BoundaryEdges,
/// Volume; the crease edges between regions (with CreaseSides, only those
/// a face flags) into creases. Returns the mean edge length (1 without
/// edges).
double WholeSurfaceFigures(const Surface& surface, const std::vector<V3>& centre,
  const std::vector<CorrectedMeasures>& measures, CurvatureResult& result,
  std::vector<Crease>& creases);

/// Each crease edge's angle and length into result (CreaseEdges,
/// CreaseAngle, CreaseLength, CreaseTotalMean).
void MeasureCreases(const Surface& surface, const std::vector<V3>& centre,
  const std::vector<Crease>& creases, CurvatureResult& result);

} // namespace curvature
} // namespace dg

#endif
