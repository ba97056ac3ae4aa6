/**
 * @class   vtkVCMNormalEstimator
 * @brief   Voronoi Covariance Measure normals and feature score of a digital surface.
 *
 * Inputs as vtkIINormalEstimator: port 0 the digital surface made by
 * vtkDigitalSurfaceFilter (cell arrays "InsideVoxel", "SurfelDirection",
 * field data "ImageExtent", "ImageOrigin", "ImageSpacing"); port 1 the
 * vtkImageData it came from (SetSourceConnection / SetSourceData), with the
 * same whole extent, origin and spacing, and the same selection of inside
 * voxels (SelectionMode, thresholds, Label, the array of
 * SetInputArrayToProcess; the defaults of both filters match).
 *
 * Method (docs/method.md section 9; Merigot, Ovsjanikov, Guibas 2011, and Cuel,
 * Lachaud, Thibert 2014 for digital surfaces): K is the set of surfel
 * centres of the image (grid units). Every lattice point x of Z^3 (voxel
 * centres, inside or outside, also beyond the image) with d(x, K) <= R
 * (OffsetRadius) belongs to the Voronoi cell of its nearest surfel centre
 * p(x) (ties: the surfel with the smallest GlobalId). VCM(p) = sum of
 * (x - p)(x - p)^T over p's cell; for the surfel with centre c, V = sum of
 * VCM(p) over the surfel centres p with |p - c| <= r (ConvolutionRadius).
 * The normal is the eigenvector of V's largest eigenvalue, oriented from
 * the barycentre of the inside voxels within r of c towards c (as II;
 * the trivial normal decides only when that offset is zero or
 * perpendicular). All sums are exact integers (doubled coordinates): the
 * result does not depend on the thread count or on the pieces.
 *
 * Output: the input surface plus cell data "VCMNormals" (double, 3
 * components, unit, the active normals), in world orientation (through the
 * inverse transpose of direction * diag(spacing), as II). With
 * ComputeFeatureScore on (off by default): "VCMFeatureScore" = l1 / (l0 +
 * l1 + l2) and "VCMEigenvalues" (l0 >= l1 >= l2, 3 components, grid units:
 * voxel^2 summed over the lattice points). The score is about 0 on smooth
 * parts (Voronoi cells are needles along the normal) and grows where the
 * cells fan out over a crease; the paper thresholds it (T about 0.1..0.3).
 *
 * Radii: OffsetRadius R (default 10) and ConvolutionRadius r (default 4),
 * the paper's Fig. 5 values, in voxels (RadiusUnits VOXELS) or world units
 * (WORLD: divided by the spacing, which must then be isotropic). Both must
 * be positive, r <= R, and not larger than the image's largest dimension.
 *
 * Cost (dgVCM.h): an exact separable Euclidean distance transform with a
 * nearest-site map over the lattice box of the surfels grown by R, in slabs:
 * memory (4 R + 2 T + 3) planes of nx * ny * 8 bytes (T = 16), the sites (16
 * bytes and 48 bytes of measure each) and the image as runs (as II). Time
 * linear in the box's volume plus the offset's. Octa-flower 512^3, R = 10,
 * r = 4, 2 cores: see docs/vcm.md (Benchmarks/BenchVCM).
 *
 * Pieces: asked for piece p of N with G ghost levels, the estimator asks
 * the image's source for the piece's own extent (dg::PieceExtent) grown by
 * G + ceil(2 R + r) + 1 voxels and tells the surface filter the same reach
 * (IMAGE_GHOST_LEVELS). The sites are the surfels of that image box, not
 * the piece's cells (a Voronoi cell near the piece's border needs the
 * neighbouring pieces' sites): V(s) reads the sites within r of c, whose
 * cells are decided by the sites within R of their lattice points, so every
 * site within 2 R + r of c must be known, and its two voxels lie within
 * 2 R + r + 1 of the surfel's inside voxel. The result is then bitwise that
 * of a one-process run. An image that does not hold that reach is an error.
 */
#ifndef vtkVCMNormalEstimator_h
#define vtkVCMNormalEstimator_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>

namespace dg
{
class PipelineAbort;
}

class vtkAlgorithmOutput;
class vtkDataObject;

class VTKDIGITALGEOMETRY_EXPORT vtkVCMNormalEstimator : public vtkPolyDataAlgorithm
{
public:
  static vtkVCMNormalEstimator* New();
  vtkTypeMacro(vtkVCMNormalEstimator, vtkPolyDataAlgorithm);
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
   * Offset radius R (default 10), in RadiusUnits: the lattice points within
   * R of the surface make the Voronoi cells.
   */
  vtkSetMacro(OffsetRadius, double);
  vtkGetMacro(OffsetRadius, double);
  ///@}

  ///@{
  /**
   * Convolution radius r (default 4), in RadiusUnits: the cells of the
   * surfels within r of a surfel are summed. Must not exceed OffsetRadius.
   */
  vtkSetMacro(ConvolutionRadius, double);
  vtkGetMacro(ConvolutionRadius, double);
  ///@}

  ///@{
  /**
   * Units of both radii: VOXELS (default) or WORLD (isotropic spacing required).
   */
  vtkSetClampMacro(RadiusUnits, int, VOXELS, WORLD);
  vtkGetMacro(RadiusUnits, int);
  void SetRadiusUnitsToVoxels() { this->SetRadiusUnits(VOXELS); }
  void SetRadiusUnitsToWorld() { this->SetRadiusUnits(WORLD); }
  ///@}

  ///@{
  /**
   * Also output "VCMFeatureScore" and "VCMEigenvalues" (default off).
   */
  vtkSetMacro(ComputeFeatureScore, vtkTypeBool);
  vtkGetMacro(ComputeFeatureScore, vtkTypeBool);
  vtkBooleanMacro(ComputeFeatureScore, vtkTypeBool);
  ///@}

  enum SelectionModes
  {
    NON_ZERO = 0,
    RANGE = 1,
    LABEL = 2
  };

  ///@{
  /**
   * Selection of the inside voxels: set it as on vtkDigitalSurfaceFilter.
   */
  vtkSetClampMacro(SelectionMode, int, NON_ZERO, LABEL);
  vtkGetMacro(SelectionMode, int);
  void SetSelectionModeToNonZero() { this->SetSelectionMode(NON_ZERO); }
  void SetSelectionModeToRange() { this->SetSelectionMode(RANGE); }
  void SetSelectionModeToLabel() { this->SetSelectionMode(LABEL); }
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
   * normal (barycentre offset zero or perpendicular, or a zero measure).
   */
  vtkGetMacro(NumberOfTrivialFallbacks, vtkIdType);

  /**
   * Includes the aborted state: after an aborted execution (SetAbortExecute
   * from a progress observer: empty outputs, no error) the filter is out of
   * date until it has run again.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkVCMNormalEstimator();
  ~vtkVCMNormalEstimator() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // Voxel layers beyond a surfel's inside voxel that its estimate reads:
  // ceil(2 R + r) + 1 (see the class documentation).
  int Reach(vtkInformation* sourceInfo) const;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // RequestData of this piece alone (RequestData adds the pieces' agreement).
  int ExecutePiece(vtkInformation*, vtkInformationVector**, vtkInformationVector*);

  double OffsetRadius = 10.0;
  double ConvolutionRadius = 4.0;
  int RadiusUnits = VOXELS;
  vtkTypeBool ComputeFeatureScore = false;
  int SelectionMode = NON_ZERO;
  double LowerThreshold = 1.0;
  double UpperThreshold = VTK_DOUBLE_MAX;
  double Label = 1.0;
  int SelectedComponent = -1;
  vtkIdType NumberOfTrivialFallbacks = 0;

private:
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkVCMNormalEstimator(const vtkVCMNormalEstimator&) = delete;
  void operator=(const vtkVCMNormalEstimator&) = delete;
};

#endif
