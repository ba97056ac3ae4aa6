#include "dgSharpFeaturesField.h"

#include "dgATOperators.h"
#include "dgATSolver.h"

namespace dg
{

bool SolveFieldWithCreases(std::int64_t numberOfPoints, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity,
  const std::vector<std::array<std::int64_t, 2>>& creases, const std::vector<double>& data,
  double alpha, std::vector<double>& normals, std::string* error)
{
  const std::int64_t F = static_cast<std::int64_t>(offsets.size()) - 1;
  if (F < 1 || static_cast<std::int64_t>(data.size()) != 3 * F)
  {
    if (error)
      *error = "the field's data does not match the faces";
    return false;
  }
  ATComplex complex;
  if (!complex.Build(numberOfPoints, offsets, connectivity, error))
    return false;
  ATParameters p;
  p.Alpha = alpha;
  ATSolver solver(complex, p, ATSolver::TakePatterns);
  Eigen::MatrixXd g(F, 3);
  for (std::int64_t f = 0; f < F; ++f)
    for (int c = 0; c < 3; ++c)
      g(f, c) = data[3 * f + c];
  solver.Initialize(std::move(g));
  // v = 0 on the creases' vertices: their edges carry no smoothness term,
  // the edges leaving the line a quarter of it (AT's own M v average).
  Eigen::VectorXd& v = solver.V();
  v.setOnes();
  for (const auto& e : creases)
    for (std::int64_t p : e)
      if (p >= 0 && p < v.size())
        v[p] = 0.0;
  const Eigen::VectorXd cut = v;
  if (!solver.StepU())
  {
    if (error)
      *error = solver.Error().empty() ? "the field's linear solve failed" : solver.Error();
    return false;
  }
  // Twicing: u += S (d - u), S the same smoothing. A screened smoothing of
  // the normals bends them towards their neighbours' on a curved part by
  // O(1/alpha) times the field's second derivatives; smoothing the residual
  // and adding it back leaves O(1/alpha^2) of that bias (a 96^3 fillet of
  // radius 6 at alpha 0.05: 10.4 -> 6.5 degrees mean error, noisy spheres
  // unchanged), for one more solve.
  const Eigen::MatrixXd first = solver.U();
  Eigen::MatrixXd residual(F, 3);
  for (std::int64_t f = 0; f < F; ++f)
    for (int c = 0; c < 3; ++c)
      residual(f, c) = data[3 * f + c] - first(f, c);
  solver.Initialize(std::move(residual));
  solver.V() = cut;
  if (!solver.StepU())
  {
    if (error)
      *error = solver.Error().empty() ? "the field's linear solve failed" : solver.Error();
    return false;
  }
  solver.U() += first;
  solver.NormalizeU();
  const Eigen::MatrixXd& u = solver.U();
  normals.resize(3 * F);
  for (std::int64_t f = 0; f < F; ++f)
    for (int c = 0; c < 3; ++c)
      normals[3 * f + c] = u(f, c);
  return true;
}

} // namespace dg
