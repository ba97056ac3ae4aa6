/**
 * @class   vtkAmbrosioTortorelliFilter
 * @brief   Piecewise-smooth regularisation of a cell field on a polygonal
 *          surface, with its discontinuity set (Ambrosio-Tortorelli).
 *
 * The method of Coeurjolly, Foare, Gueth and Lachaud, "Piecewise smooth
 * reconstruction of normal vector field on digital data" (Pacific Graphics
 * 2016), as specified in docs/method.md sections 2-5: the input field g (one value
 * per polygon) is replaced by u, minimising
 *
 *   AT_eps(u, v) = Alpha |u - g|^2 + |diag(M v) B u|^2
 *                  + Lambda eps |A v|^2 + Lambda / (4 eps) |1 - v|^2
 *
 * where v (one value per point) is ~1 where u is smooth and ~0 on its
 * discontinuities; A, B, M are the discrete derivative, the dual derivative
 * and the edge average on the polygons' connectivity. eps decreases from
 * EpsilonStart to EpsilonEnd by EpsilonRatio; at each level at most
 * MaximumIterations pairs (u-step, v-step) of linear solves are made, until
 * max |v - v_prev| < Tolerance.
 *
 * Units (Metric): with METRIC_GRID (default, the paper's identity metric)
 * Alpha, Lambda and the epsilons are in "grid units": edge lengths and face
 * areas count as 1 whatever the point coordinates are. On a digital surface
 * a voxel side is 1 (spacing does not matter); on a triangle mesh, one edge
 * is one unit. With METRIC_WORLD every term is weighed by the surface's own
 * geometry (face areas, edge over dual-edge lengths, vertex dual areas; see
 * dgATMetric.h and docs/at-metric.md): the epsilons are then world lengths,
 * Lambda is per world length and Alpha per world area, so the same
 * parameters give the same result on one shape sampled at two resolutions
 * or on an anisotropic grid. On a digital surface of spacing 1 the two
 * metrics differ only at vertices where 3 or 5+ faces meet.
 *
 * Input: a vtkPolyData with polygons (quads of a digital surface, triangles,
 * any polygons; non-manifold and boundary edges are allowed). The field is
 * the cell array chosen with SetInputArrayToProcess (default: the active
 * cell normals), any number of components. Only the polygon cells take part;
 * other cells (verts, lines, strips) keep their input value.
 *
 * Normal fields and other fields: the field is a normal field when it is
 * the input's active cell normals, or when it has 3 components of unit
 * length (within 1e-3) on every polygon. A normal field gives "ATNormals",
 * set as the active normals and, with NormalizeVectorField on (default),
 * of unit length. Any other field (a scalar, a velocity, a 3-vector that is
 * not unit) gives "<input name>_AT", neither normalised nor made active.
 * The energy is not invariant to the field's scale (multiplying g by s is
 * the same as dividing Lambda by s^2), and Alpha and Lambda are tuned for
 * unit normals, whose components span [-1, 1]: with FieldScaling RANGE
 * (default) any other field is divided by half its largest component range
 * before the solve and multiplied back after, so the same features come out
 * whatever its unit; with FieldScaling NONE it is used as it is, and a
 * warning says when its half range is outside [0.1, 10].
 *
 * Output port 0: the input surface (shallow copy) plus
 * - cell data "ATNormals" or "<input name>_AT" (double), see above;
 * - point data "ATFeatureIndicator" (double): v, ~1 in smooth parts, ~0 on
 *   sharp features. It is the exact minimiser of the v-system, which is not
 *   an M-matrix (M^T diag(|Bu|^2) M has positive off-diagonal terms), so v
 *   can undershoot 0 slightly next to strong jumps (seen: -0.015 with raw
 *   trivial normals); it is not clamped.
 * The input arrays are kept (the input normals stay as an ordinary array).
 * Output port 1: the feature edges, every polygon edge whose two points both
 * have v < FeatureThreshold, as line cells sharing the surface's points, with
 * cell data "ATFeatureIndicator" = the larger v of the two end points (so
 * every point of the line is below that value).
 *
 * Bad parameters or input (no polygons, missing field, NaN or infinite
 * values, zero vectors in a normal field) give an error and empty outputs.
 * A failed linear solve gives a warning; that step keeps its previous
 * values. Surfaces on which AT cannot see some jumps give a warning too:
 * no interior edge at all, or boundary edges that lie on another polygon's
 * edge with other point ids (cells that do not share their points, e.g.
 * vtkPolyDataNormals with Splitting on, or a vtkCubeSource not passed
 * through vtkCleanPolyData): the warning says to merge the points first.
 *
 * Re-execution: the solved u and v are kept between executions, and only a
 * change of the input or of a solve parameter (Alpha, Lambda, the epsilons,
 * MaximumIterations, Tolerance, LinearSolver, SolverTolerance, FieldScaling,
 * Metric, the field selection) solves again; FeatureThreshold and
 * NormalizeVectorField only rebuild the outputs (GetNumberOfSolves() counts
 * the solves). The input counts as changed when its field array, its polygon
 * array (either object or its MTime) or its number of points changes (with
 * METRIC_WORLD also its points array or that array's MTime), so
 * ParaView's shallow copies of an unchanged upstream output reuse the solve.
 * The kept solution costs about 64 bytes per quad of a closed digital
 * surface (u, v and the edge list) and holds a reference to those two input
 * arrays.
 *
 * Progress is reported at every step of the solve; aborting (SetAbortExecute
 * from a progress observer) stops within one step and leaves empty outputs,
 * with no error, and the next Update solves again.
 *
 * The linear systems keep their sparsity pattern over the whole run; the
 * default solver is warm-started conjugate gradients with an incomplete
 * Cholesky preconditioner (parallel with vtkSMPTools, deterministic whatever
 * the thread count); see dgATSolver.h for the alternatives.
 */
#ifndef vtkAmbrosioTortorelliFilter_h
#define vtkAmbrosioTortorelliFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>

class vtkMultiProcessController;
namespace dg
{
struct ATParameters;
}

class VTKDIGITALGEOMETRY_EXPORT vtkAmbrosioTortorelliFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkAmbrosioTortorelliFilter* New();
  vtkTypeMacro(vtkAmbrosioTortorelliFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Weight of the data term |u - g|^2 (> 0, default 0.1). Smaller values
   * smooth more.
   */
  vtkSetMacro(Alpha, double);
  vtkGetMacro(Alpha, double);
  ///@}

  ///@{
  /**
   * Weight of the length of the discontinuity set (> 0, default 0.01).
   * Larger values give fewer, longer feature lines.
   */
  vtkSetMacro(Lambda, double);
  vtkGetMacro(Lambda, double);
  ///@}

  ///@{
  /**
   * The epsilon schedule, in grid units: from EpsilonStart (default 2) down
   * to EpsilonEnd (default 0.25, 0 < EpsilonEnd <= EpsilonStart), divided
   * by EpsilonRatio (> 1, default 2) at each level. eps is the width of the
   * transition of v across a feature.
   */
  vtkSetMacro(EpsilonStart, double);
  vtkGetMacro(EpsilonStart, double);
  vtkSetMacro(EpsilonEnd, double);
  vtkGetMacro(EpsilonEnd, double);
  vtkSetMacro(EpsilonRatio, double);
  vtkGetMacro(EpsilonRatio, double);
  ///@}

  ///@{
  /**
   * Maximum number of (u-step, v-step) pairs per epsilon level (>= 1,
   * default 5), and the convergence tolerance on max |v - v_prev| (default
   * 1e-4; 0 always makes MaximumIterations steps).
   */
  vtkSetMacro(MaximumIterations, int);
  vtkGetMacro(MaximumIterations, int);
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /**
   * An edge is a feature edge when both its points have v below this value
   * (in (0, 1), default 0.5). An output parameter: changing it does not
   * solve again.
   */
  vtkSetMacro(FeatureThreshold, double);
  vtkGetMacro(FeatureThreshold, double);
  ///@}

  ///@{
  /**
   * Normalise the result to unit length when the field is a normal field
   * (default on; see the class description). Ignored for other fields. An
   * output parameter: changing it does not solve again.
   */
  vtkSetMacro(NormalizeVectorField, bool);
  vtkGetMacro(NormalizeVectorField, bool);
  vtkBooleanMacro(NormalizeVectorField, bool);
  ///@}

  enum LinearSolvers
  {
    CONJUGATE_GRADIENT = 0,
    SIMPLICIAL_LDLT = 1,
    CHOLMOD = 2,
    CONJUGATE_GRADIENT_IC = 3
  };

  ///@{
  /**
   * Linear solver (default CONJUGATE_GRADIENT_IC: conjugate gradients with
   * an incomplete-Cholesky preconditioner; CONJUGATE_GRADIENT uses the
   * diagonal instead; both stop at the relative residual SolverTolerance,
   * default 1e-5: within 0.0015 degrees and 4e-4 in v of the exact solve,
   * dgATSolver.h). SIMPLICIAL_LDLT is Eigen's exact sparse factorisation;
   * CHOLMOD is used only when the module was built with it (otherwise
   * SIMPLICIAL_LDLT, with a warning). dgATSolver.h gives the measurements.
   */
  vtkSetClampMacro(LinearSolver, int, CONJUGATE_GRADIENT, CONJUGATE_GRADIENT_IC);
  vtkGetMacro(LinearSolver, int);
  vtkSetMacro(SolverTolerance, double);
  vtkGetMacro(SolverTolerance, double);
  ///@}

  ///@{
  /**
   * The conjugate-gradient solvers' tolerance on the epsilon levels before
   * the last, as a multiple F >= 1 of SolverTolerance: sqrt(F) looser per
   * level away from the last, at most F, while v still moves by more than
   * 10 x Tolerance (default 1: every level at SolverTolerance). The last
   * level, which gives the output, always solves to SolverTolerance. At 6,
   * AT takes about 15 % less time on large surfaces and stays within the
   * accuracy budget of the exact solve (1e-3 in v) on one process, but a
   * 3-rank ParaView run on a noisy cube was 1.3e-3 from it
   * (docs/at-speed.md), which is why it is not the default.
   */
  vtkSetMacro(SolverToleranceEarlyFactor, double);
  vtkGetMacro(SolverToleranceEarlyFactor, double);
  ///@}

  enum FieldScalings
  {
    FIELD_SCALING_NONE = 0,
    FIELD_SCALING_RANGE = 1
  };

  ///@{
  /**
   * How a field that is not a normal field is scaled for the solve (default
   * FIELD_SCALING_RANGE: by half its largest component range; see the class
   * description). Normal fields are never scaled.
   */
  vtkSetClampMacro(FieldScaling, int, FIELD_SCALING_NONE, FIELD_SCALING_RANGE);
  vtkGetMacro(FieldScaling, int);
  ///@}

  enum Metrics
  {
    METRIC_GRID = 0,
    METRIC_WORLD = 1
  };

  ///@{
  /**
   * The metric of the operators (default METRIC_GRID, the paper's: every
   * face, edge and vertex weighs 1, parameters in grid units). METRIC_WORLD:
   * weights from the points' coordinates, parameters in world units (see the
   * class description). A surface with a face of zero area or an edge of
   * zero length is an error under METRIC_WORLD.
   */
  vtkSetClampMacro(Metric, int, METRIC_GRID, METRIC_WORLD);
  vtkGetMacro(Metric, int);
  void SetMetricToGrid() { this->SetMetric(METRIC_GRID); }
  void SetMetricToWorld() { this->SetMetric(METRIC_WORLD); }
  ///@}

  /**
   * The factor the field was divided by in the last solve (1 for normal
   * fields and with FIELD_SCALING_NONE).
   */
  vtkGetMacro(FieldScale, double);

  /**
   * Number of (u-step, v-step) pairs made by the last solve.
   */
  vtkGetMacro(NumberOfIterations, int);

  /**
   * Conjugate-gradient iterations of the last solve, both systems (one
   * iteration of the u-system serves all its columns).
   */
  vtkGetMacro(NumberOfCGIterations, vtkIdType);

  ///@{
  /**
   * Distributed runs: the face and vertex values this process sent plus
   * received per halo update of one column in the last solve (0 in one
   * process). A CG iteration of the u-system moves HaloFaceValues * (field
   * components) doubles, one of the v-system HaloVertexValues.
   */
  vtkGetMacro(HaloFaceValues, vtkIdType);
  vtkGetMacro(HaloVertexValues, vtkIdType);
  ///@}

  /**
   * Number of solves this filter has made since it was created (executions
   * that only changed output parameters reuse the last solve).
   */
  vtkGetMacro(NumberOfSolves, int);

  /**
   * Includes the aborted state: after an aborted execution the filter is
   * out of date until it has run again.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkAmbrosioTortorelliFilter();
  ~vtkAmbrosioTortorelliFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // The distributed solve (vtkAmbrosioTortorelliFilterPieces.cxx).
  // ghostLevels: what downstream asked for; with one or more, port 0 also
  // holds the ring of ghost faces around the piece, with their owners' u.
  int RequestDataPieces(vtkMultiProcessController* controller, vtkPolyData* input,
    vtkPolyData* output, vtkPolyData* features, const dg::ATParameters& parameters,
    int ghostLevels);

  double Alpha = 0.1;
  double Lambda = 0.01;
  double EpsilonStart = 2.0;
  double EpsilonEnd = 0.25;
  double EpsilonRatio = 2.0;
  int MaximumIterations = 5;
  double Tolerance = 1e-4;
  double FeatureThreshold = 0.5;
  bool NormalizeVectorField = true;
  int LinearSolver = CONJUGATE_GRADIENT_IC;
  double SolverTolerance = 1e-5;
  double SolverToleranceEarlyFactor = 1.0;
  int FieldScaling = FIELD_SCALING_RANGE;
  int Metric = METRIC_GRID;
  double FieldScale = 1.0;
  int NumberOfIterations = 0;
  int NumberOfSolves = 0;
  vtkIdType NumberOfCGIterations = 0;
  vtkIdType HaloFaceValues = 0;
  vtkIdType HaloVertexValues = 0;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;

  vtkAmbrosioTortorelliFilter(const vtkAmbrosioTortorelliFilter&) = delete;
  void operator=(const vtkAmbrosioTortorelliFilter&) = delete;
};

#endif
