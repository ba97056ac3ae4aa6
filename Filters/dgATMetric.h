// The metric of the Ambrosio-Tortorelli operators (docs/at-metric.md).
//
// The paper's operators use the identity metric: every face, edge and
// vertex weighs 1, so alpha, lambda and epsilon are in grid units and the
// same shape digitised at two resolutions, or on an anisotropic grid, is
// smoothed differently. The world metric weighs each term of the energy by
// the discrete Hodge stars of the surface's own geometry (its points in
// world coordinates):
//
//   AT = alpha sum_f |f| |u_f - g_f|^2 + sum_e r_e (Mv)_e^2 |(Bu)_e|^2
//      + lambda eps sum_e (1 / r_e) (Av)_e^2 + lambda / (4 eps) sum_v |v*| (1 - v)^2
//
// |f| the face's area, r_e = |e| / |e*| the ratio of the primal edge's
// length to its dual edge's (face centre to edge midpoint to face centre),
// |v*| the vertex's dual area (1/k of each incident k-gon). Then alpha is in
// 1 / length^2, lambda in 1 / length and epsilon in length, all world: the
// energy is a discretisation of the continuous AT functional, whose
// parameters do not depend on the sampling.
#ifndef dgATMetric_h
#define dgATMetric_h

#include "dgATOperators.h"

#include <string>
#include <vector>

class vtkPoints;

namespace dg
{

struct ATMetric
{
  std::vector<double> FaceArea;   // per face
  std::vector<double> EdgeRatio;  // per edge: |e| / |e*|
  std::vector<double> VertexArea; // per vertex: dual area (1 for a point in no face)

  /// From the complex, the polygons it was built from and 3 world
  /// coordinates per vertex. False (with a message) when a face has no
  /// area, an edge no length or a dual edge no length: degenerate geometry
  /// would give infinite or zero weights.
  bool Compute(const ATComplex& complex, const std::vector<std::int64_t>& offsets,
    const std::vector<std::int64_t>& connectivity, const double* points, std::string* error);
};

/// The world metric of a complex whose vertex k is point rows[k] of
/// `points` (rows null: point k). False with a message when there are no
/// points or the geometry is degenerate.
bool ComputeWorldMetric(vtkPoints* points, const std::vector<std::int64_t>* rows,
  const ATComplex& complex, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity, ATMetric& metric, std::string& error);

} // namespace dg

#endif
