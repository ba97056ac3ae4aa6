// The sharp-features stage's output normals: Ambrosio-Tortorelli's u-step
// with the discontinuity set fixed to the creases the stage kept
// (docs/sharp-features.md, step 10).
//
// AT's own u is terraced on curved parts where its v dropped along false
// lines; once the stage has decided which lines are creases, the field that
// AT's energy prefers for that discontinuity set is one linear solve:
//   (alpha I + B^T diag(M v)^2 B) u = alpha d,
// with v = 0 on the creases' vertices and 1 elsewhere, and d the data: the
// input estimator's normals, except near a crease, where they are blended
// across it and the stage's side normals are used instead.
#ifndef dgSharpFeaturesField_h
#define dgSharpFeaturesField_h

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dg
{

/// offsets/connectivity: the polygons (vtkCellArray's layout); creases:
/// point id pairs (the kept feature edges); data: 3 per face; alpha: AT's
/// data weight (grid units). normals gets 3 unit values per face. False
/// with a message when the complex cannot be built or the solve fails.
bool SolveFieldWithCreases(std::int64_t numberOfPoints, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity,
  const std::vector<std::array<std::int64_t, 2>>& creases, const std::vector<double>& data,
  double alpha, std::vector<double>& normals, std::string* error = nullptr);

} // namespace dg

#endif
