/**
 * @class   vtkIINormalEstimator
 * @brief   Integral-invariant normals and curvatures of a digital surface.
 *
 * Inputs: port 0 the digital surface made by vtkDigitalSurfaceFilter (it
 * needs its cell arrays "InsideVoxel" and "SurfelDirection" and its field
 * data "ImageExtent", "ImageOrigin", "ImageSpacing"); port 1 the vtkImageData
 * it came from, given with SetSourceConnection / SetSourceData (as for
 * vtkProbeFilter). The image's whole extent, origin and spacing must equal
 * the ones recorded in the surface.
 *
 * Inside voxels: the image is read with the same selection rules as
 * vtkDigitalSurfaceFilter (SelectionMode NonZero (default), Range or Label,
 * on the array chosen with SetInputArrayToProcess, default the active point
 * scalars); set the same parameters on both filters. The defaults of both
 * match. A surfel whose inside voxel is not selected here means the two
 * selections differ: that is an error.
 *
 * EachLabel (label maps, docs/labels.md): the surface made by
 * vtkDigitalSurfaceFilter in EachLabel mode carries the cell data "Label";
 * the cells of each label are estimated with that label's voxels only
 * (value == label), on a copy of the image around the label's surfels (its
 * voxel box) grown by the ball's reach ceil(r) + 1 (dg::CropImage): each
 * ball sees the voxels it sees in the whole image, so the normals and
 * curvatures are bitwise those of a Label-mode run on the whole image, for
 * the cost of the label's box rather than a full-volume pass per label.
 * A missing "Label" array is an error; one piece only.
 *
 * Method (docs/method.md section 6): for every surfel with centre c (inside voxel +
 * half a voxel along its direction, grid units) the covariance matrix C of
 * the inside voxel centres in the ball |p - c| <= r. The normal is the
 * eigenvector of the smallest eigenvalue of C, oriented from the barycentre
 * of those voxels towards c (not by the surfel's trivial normal, which is
 * unreliable on noisy data); the trivial normal decides only when the
 * barycentre offset is zero or perpendicular to the eigenvector.
 *
 * Output: the input surface plus cell data "IINormals" (double, 3
 * components, unit length, set as the active normals), in world orientation:
 * the grid-space normal n goes through the inverse transpose of the image's
 * index-to-world matrix (direction * diag(spacing)), so a non-identity
 * direction matrix (det -1 too) is handled. The trivial "Normals" array
 * stays as an ordinary array.
 *
 * With ComputeCurvatures on (off by default): "IIMeanCurvature",
 * "IIGaussianCurvature", "IIK1", "IIK2" (k1 >= k2, 1 / world length; convex
 * is positive) and "IIK1Direction", "IIK2Direction" (the tangent directions
 * of k1 and k2: unit, world, sign arbitrary; k1's is the eigenvector of the
 * smaller tangent eigenvalue of the covariance, as docs/method.md section 6
 * says; earlier notes paired them the other way: see dgIntegralInvariant.cxx).
 *
 * Radius: in voxels (RadiusUnits VOXELS, default, Radius 3) or in world
 * units (WORLD). The ball is a ball of world space: with an isotropic
 * spacing, the digital ball of that radius in voxels; with an anisotropic
 * one (CT at 0.7 x 0.7 x 2.5 mm), an ellipsoid of index space whose world
 * radius is Radius in world units, or Radius times the smallest spacing in
 * voxels. The sums stay exact (rows of that ellipsoid, prefix sums) and the
 * covariance is formed in world lengths, so normals and curvatures are
 * those of the world shape at any spacing (docs/curvatures.md,
 * "Anisotropic spacing"). The radius must be positive and, in voxels, not
 * larger than the image's largest dimension.
 *
 * Cost: the image is stored as runs of inside voxels along x (memory about
 * 32 bytes per run plus 8 bytes per x-row; a 1-byte mask of the image exists
 * only while the runs are built); each surfel costs one look-up per x-row of
 * the ball (about pi r^2), not one per voxel (4/3 pi r^3). Parallel over
 * surfels with vtkSMPTools; the result does not depend on the thread count.
 * Octa-flower 512^3 (671 270 surfels), r = 8, 2 cores: about 2 s for the
 * normals (Benchmarks/BenchII).
 *
 * Pieces: asked for piece p of N with G ghost levels, the estimator asks
 * the image's source for the piece's own extent (dg::PieceExtent, as
 * vtkDigitalSurfaceFilter) grown by G + ceil(r) + 1 voxels, and tells the
 * surface filter the same reach (IMAGE_GHOST_LEVELS), so that both get one
 * extent from a shared source. Each ball then sees exactly the voxels it
 * sees in one process: normals and curvatures are bitwise those of a
 * one-process run (the ball sums are integers). When the image given does
 * not cover every surfel's ball (grown by ceil(r) + 1 and clipped to the
 * whole extent), that is an error, not a silently cropped ball. Ghost cells
 * of the surface get their estimate like the others.
 */
#ifndef vtkIINormalEstimator_h
#define vtkIINormalEstimator_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>

namespace dg
{
class PipelineAbort;
}

class vtkAlgorithmOutput;
class vtkDataArray;
class vtkDataObject;
class vtkImageData;

class VTKDIGITALGEOMETRY_EXPORT vtkIINormalEstimator : public vtkPolyDataAlgorithm
{
public:
  static vtkIINormalEstimator* New();
  vtkTypeMacro(vtkIINormalEstimator, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The image the surface was extracted from (input port 1).
   */
  void SetSourceConnection(vtkAlgorithmOutput* algOutput);
  void SetSourceData(vtkDataObject* source);
  vtkDataObject* GetSource();
  ///@}

  enum RadiusUnitsTypes
  {
    VOXELS = 0,
    WORLD = 1
  };

  ///@{
  /**
   * Ball radius (default 3), in RadiusUnits.
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  ///@}

  ///@{
  /**
   * Units of Radius: VOXELS (default; of the smallest spacing) or WORLD.
   */
  vtkSetClampMacro(RadiusUnits, int, VOXELS, WORLD);
  vtkGetMacro(RadiusUnits, int);
  void SetRadiusUnitsToVoxels() { this->SetRadiusUnits(VOXELS); }
  void SetRadiusUnitsToWorld() { this->SetRadiusUnits(WORLD); }
  ///@}

  ///@{
  /**
   * Also output mean, Gaussian and principal curvatures and the principal
   * directions (default off).
   */
  vtkSetMacro(ComputeCurvatures, vtkTypeBool);
  vtkGetMacro(ComputeCurvatures, vtkTypeBool);
  vtkBooleanMacro(ComputeCurvatures, vtkTypeBool);
  ///@}

  enum CurvatureReferences
  {
    CONTINUOUS = 0,
    DIGITAL_BALL = 1,
    DIGITAL_TANGENT_PLANE = 2
  };

  ///@{
  /**
   * Zero-curvature reference of the curvature formulas (default
   * DIGITAL_TANGENT_PLANE). The formulas of docs/method.md section 6 compare the
   * ball's inside volume and covariance with those of a half ball:
   * CONTINUOUS uses the Euclidean half ball (2 pi r^3 / 3, 2 pi r^5 / 15), as
   * written there; DIGITAL_BALL half of the digital ball (exact for
   * axis-aligned planes); DIGITAL_TANGENT_PLANE the digital ball's voxels on
   * the inner side of the estimated tangent plane (exact for planes of every
   * orientation, one more O(r^2) sum per surfel). The lattice error of the
   * Euclidean constants is of order 1 / r^2 per voxel and dominates at
   * small radii (about 0.01 / voxel at r = 6); all three agree as r grows.
   * Normals do not depend on this setting.
   */
  vtkSetClampMacro(CurvatureReference, int, CONTINUOUS, DIGITAL_TANGENT_PLANE);
  vtkGetMacro(CurvatureReference, int);
  ///@}

  enum SelectionModes
  {
    NON_ZERO = 0,
    RANGE = 1,
    LABEL = 2,
    EACH_LABEL = 3
  };

  ///@{
  /**
   * Selection of the inside voxels: set it as on vtkDigitalSurfaceFilter.
   * EACH_LABEL reads the surface's "Label" cell array (see the class
   * description); the labels are the surface's, there is no Labels list.
   */
  vtkSetClampMacro(SelectionMode, int, NON_ZERO, EACH_LABEL);
  vtkGetMacro(SelectionMode, int);
  void SetSelectionModeToNonZero() { this->SetSelectionMode(NON_ZERO); }
  void SetSelectionModeToRange() { this->SetSelectionMode(RANGE); }
  void SetSelectionModeToLabel() { this->SetSelectionMode(LABEL); }
  void SetSelectionModeToEachLabel() { this->SetSelectionMode(EACH_LABEL); }
  vtkSetMacro(LowerThreshold, double);
  vtkGetMacro(LowerThreshold, double);
  vtkSetMacro(UpperThreshold, double);
  vtkGetMacro(UpperThreshold, double);
  vtkSetMacro(Label, double);
  vtkGetMacro(Label, double);
  vtkSetMacro(SelectedComponent, int);
  vtkGetMacro(SelectedComponent, int);
  ///@}

  /**
   * Surfels of the last execution whose orientation came from the trivial
   * normal (barycentre offset zero or perpendicular, or a degenerate ball).
   */
  vtkGetMacro(NumberOfTrivialFallbacks, vtkIdType);

  /**
   * Includes the aborted state: after an aborted execution (SetAbortExecute
   * from a progress observer: empty outputs, no error) the filter is out of
   * date until it has run again.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkIINormalEstimator();
  ~vtkIINormalEstimator() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // RequestData of this piece alone (RequestData adds the pieces' agreement).
  int ExecutePiece(vtkInformation*, vtkInformationVector**, vtkInformationVector*);
  // EACH_LABEL: every label's cells with that label's voxels, on its box.
  int ExecuteEachLabel(vtkPolyData* surface, vtkImageData* image, vtkDataArray* scalars,
    const int* surfelVoxels, int reach, vtkPolyData* output, vtkInformationVector* outputVector);

  double Radius = 3.0;
  int RadiusUnits = VOXELS;
  vtkTypeBool ComputeCurvatures = false;
  int CurvatureReference = DIGITAL_TANGENT_PLANE;
  int SelectionMode = NON_ZERO;
  double LowerThreshold = 1.0;
  double UpperThreshold = VTK_DOUBLE_MAX;
  double Label = 1.0;
  int SelectedComponent = -1;
  vtkIdType NumberOfTrivialFallbacks = 0;

private:
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkIINormalEstimator(const vtkIINormalEstimator&) = delete;
  void operator=(const vtkIINormalEstimator&) = delete;
};

#endif
