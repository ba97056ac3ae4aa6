/**
 * @class   vtkAmbrosioTortorelliFilter
 * @brief   Piecewise-smooth regularisation of a cell field on a polygonal
 *          surface, with its discontinuity set (Ambrosio-Tortorelli).
 *
 * The method of Coeurjolly, Foare, Gueth and Lachaud, "Piecewise smooth
 * reconstruction of normal vector field on digital data" (Pacific Graphics
 * 2016), as specified in MATH.md sections 2-5: the input field g (one value
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
 * Units: the metric is the identity (as in the paper), so Alpha, Lambda and
 * the epsilons are in "grid units": edge lengths and face areas count as 1
 * whatever the point coordinates are. On a digital surface a voxel side is 1
 * (spacing does not matter); on a triangle mesh, one edge is one unit.
 *
 * Input: a vtkPolyData with polygons (quads of a digital surface, triangles,
 * any polygons; non-manifold and boundary edges are allowed). The field is
 * the cell array chosen with SetInputArrayToProcess (default: the active
 * cell normals), any number of components. Only the polygon cells take part;
 * other cells (verts, lines, strips) keep their input value.
 *
 * Output port 0: the input surface (shallow copy) plus
 * - cell data "ATNormals" (double) for a 3-component field, set as the active
 *   normals; for any other field "<input name>_AT". With
 *   NormalizeVectorField on (default) 3-component results are unit vectors.
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
 * values, zero vectors in a field to normalise) give an error and empty
 * outputs. A failed linear solve gives a warning; that step keeps its
 * previous values.
 *
 * The linear systems keep their sparsity pattern over the whole run; the
 * default solver is warm-started Jacobi-preconditioned conjugate gradients
 * (parallel with vtkSMPTools, deterministic whatever the thread count); see
 * dgATSolver.h for the alternatives.
 */
#ifndef vtkAmbrosioTortorelliFilter_h
#define vtkAmbrosioTortorelliFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

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
   * (in (0, 1), default 0.5).
   */
  vtkSetMacro(FeatureThreshold, double);
  vtkGetMacro(FeatureThreshold, double);
  ///@}

  ///@{
  /**
   * Normalise the result to unit length when the field has 3 components
   * (default on). Ignored for other fields.
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
   * default 1e-8). SIMPLICIAL_LDLT is Eigen's exact sparse factorisation;
   * CHOLMOD is used only when the module was built with it (otherwise
   * SIMPLICIAL_LDLT, with a warning). dgATSolver.h gives the measurements.
   */
  vtkSetClampMacro(LinearSolver, int, CONJUGATE_GRADIENT, CONJUGATE_GRADIENT_IC);
  vtkGetMacro(LinearSolver, int);
  vtkSetMacro(SolverTolerance, double);
  vtkGetMacro(SolverTolerance, double);
  ///@}

  /**
   * Number of (u-step, v-step) pairs made by the last execution.
   */
  vtkGetMacro(NumberOfIterations, int);

protected:
  vtkAmbrosioTortorelliFilter();
  ~vtkAmbrosioTortorelliFilter() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

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
  double SolverTolerance = 1e-8;
  int NumberOfIterations = 0;

private:
  vtkAmbrosioTortorelliFilter(const vtkAmbrosioTortorelliFilter&) = delete;
  void operator=(const vtkAmbrosioTortorelliFilter&) = delete;
};

#endif
