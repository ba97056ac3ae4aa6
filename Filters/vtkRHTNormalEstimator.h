/**
 * @class   vtkRHTNormalEstimator
 * @brief   Randomized Hough Transform normals of a digital surface.
 *
 * Boulch and Marlet, "Fast and robust normal estimation for point clouds with
 * sharp features", SGP 2012, on the surfel centres of a digital surface
 * (docs/method.md section 10; docs/rht.md). Near a crease the triplets that span one
 * face outvote those that straddle it, so RHT keeps edges sharper than a
 * covariance estimator such as vtkIINormalEstimator.
 *
 * Inputs, as for vtkIINormalEstimator: port 0 the digital surface made by
 * vtkDigitalSurfaceFilter (cell arrays "InsideVoxel", "SurfelDirection",
 * field data "ImageExtent", "ImageOrigin", "ImageSpacing"); port 1 the
 * vtkImageData it came from (SetSourceConnection / SetSourceData). The image
 * is needed twice: the candidate points of a surfel (the surfel centres
 * within Radius) are computed from its inside voxels, so that a piece sees
 * the surfels of its neighbours too, and the reference orientation is
 * docs/method.md section 6's (from the barycentre of the inside voxels within
 * Radius towards the surfel centre). Set the same selection (SelectionMode,
 * thresholds, Label, array) as on vtkDigitalSurfaceFilter.
 *
 * Method, per surfel with centre c: N = the surfel centres within Radius of
 * c, in grid order. NumberOfTrials triplets of distinct points of N are drawn
 * uniformly (collinear triplets are redrawn, at most 10 x NumberOfTrials
 * draws); each gives its plane's unit normal in the hemisphere of the
 * reference. NumberOfAccumulators hemisphere accumulators, each turned by a
 * random rotation (A distinct ones of a pool of 32 drawn from Seed alone and
 * shared by all surfels, picked per surfel), count the normals in about 2 k^2 bins of nearly equal
 * area (k = AccumulatorResolution latitude bands); each accumulator's
 * estimate is the mean normal of its winning bin; the result is the
 * normalised mean of the estimates, oriented outward. Fewer than three
 * points, or no valid triplet: the reference direction (counted in
 * NumberOfFallbacks).
 *
 * Randomness: the pool of rotations from Seed alone; one generator per
 * surfel, seeded from (Seed, the surfel's inside voxel in image indices, its
 * direction), picks its rotations and draws its triplets: the output does
 * not depend on the number of threads, the surfel order or the pieces.
 *
 * Output: the input surface plus cell data "RHTNormals" (double, 3
 * components, unit, the active normals), in world orientation (the grid
 * normal through the inverse transpose of direction * diag(spacing)).
 *
 * Radius: in voxels (RadiusUnits VOXELS, default 6) or world units (WORLD,
 * isotropic spacing). The defaults are the paper's (Coeurjolly et al. 2016,
 * Fig. 5: r = 6, 648 trials) and Boulch and Marlet's 5 accumulators.
 *
 * Pieces: as vtkIINormalEstimator, the estimator asks the image's source for
 * the piece's own extent grown by the ghost levels and ceil(r) + 1 voxels
 * (the reach of every candidate surfel's inside and outside voxels and of
 * the orientation ball) and tells the surface filter the same reach
 * (IMAGE_GHOST_LEVELS). A piece's normals are bitwise those of a one-process
 * run; an image that does not hold the reach is an error.
 *
 * Cost: about NumberOfTrials x (1 + NumberOfAccumulators) small steps per
 * surfel, parallel over surfels (vtkSMPTools); octa-flower 512^3 in
 * docs/rht.md (Benchmarks/BenchRHT).
 */
#ifndef vtkRHTNormalEstimator_h
#define vtkRHTNormalEstimator_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

#include <memory>

namespace dg
{
class PipelineAbort;
}

class vtkAlgorithmOutput;
class vtkDataObject;

class VTKDIGITALGEOMETRY_EXPORT vtkRHTNormalEstimator : public vtkPolyDataAlgorithm
{
public:
  static vtkRHTNormalEstimator* New();
  vtkTypeMacro(vtkRHTNormalEstimator, vtkPolyDataAlgorithm);
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
   * Radius of the neighbourhood (default 6), in RadiusUnits.
   */
  vtkSetMacro(Radius, double);
  vtkGetMacro(Radius, double);
  vtkSetClampMacro(RadiusUnits, int, VOXELS, WORLD);
  vtkGetMacro(RadiusUnits, int);
  void SetRadiusUnitsToVoxels() { this->SetRadiusUnits(VOXELS); }
  void SetRadiusUnitsToWorld() { this->SetRadiusUnits(WORLD); }
  ///@}

  ///@{
  /**
   * Valid (non-collinear) triplets drawn per surfel (default 648).
   */
  vtkSetMacro(NumberOfTrials, int);
  vtkGetMacro(NumberOfTrials, int);
  ///@}

  ///@{
  /**
   * Accumulators, each turned by its own random rotation (default 5).
   */
  vtkSetMacro(NumberOfAccumulators, int);
  vtkGetMacro(NumberOfAccumulators, int);
  ///@}

  ///@{
  /**
   * Latitude bands k of each hemisphere accumulator, about 2 k^2 bins
   * (default 10: bins of about 9 degrees; 1..100).
   */
  vtkSetMacro(AccumulatorResolution, int);
  vtkGetMacro(AccumulatorResolution, int);
  ///@}

  ///@{
  /**
   * Seed of the rotation pool and of the per-surfel generators, >= 0 (default 0).
   */
  vtkSetClampMacro(Seed, int, 0, VTK_INT_MAX);
  vtkGetMacro(Seed, int);
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
   * Surfels of the last execution whose normal is the reference direction
   * (fewer than 3 candidate points or no valid triplet), and those whose
   * reference came from the trivial normal (barycentre offset zero).
   */
  vtkGetMacro(NumberOfFallbacks, vtkIdType);
  vtkGetMacro(NumberOfTrivialFallbacks, vtkIdType);

  /**
   * Includes the aborted state (as vtkIINormalEstimator).
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkRHTNormalEstimator();
  ~vtkRHTNormalEstimator() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int ExecutePiece(vtkInformation*, vtkInformationVector**, vtkInformationVector*);

  double Radius = 6.0;
  int RadiusUnits = VOXELS;
  int NumberOfTrials = 648;
  int NumberOfAccumulators = 5;
  int AccumulatorResolution = 10;
  int Seed = 0;
  int SelectionMode = NON_ZERO;
  double LowerThreshold = 1.0;
  double UpperThreshold = VTK_DOUBLE_MAX;
  double Label = 1.0;
  int SelectedComponent = -1;
  vtkIdType NumberOfFallbacks = 0;
  vtkIdType NumberOfTrivialFallbacks = 0;

private:
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkRHTNormalEstimator(const vtkRHTNormalEstimator&) = delete;
  void operator=(const vtkRHTNormalEstimator&) = delete;
};

#endif
