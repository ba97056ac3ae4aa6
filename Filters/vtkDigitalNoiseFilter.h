/**
 * @class   vtkDigitalNoiseFilter
 * @brief   The paper's noise model on a segmented volume (docs/method.md section 7).
 *
 * Selects the inside voxels of the input image (same selection as
 * vtkDigitalSurfaceFilter: non-zero by default, a closed range or one label)
 * and flips each voxel p (inside <-> outside) with probability
 * NoiseLevel^(1 + d(p)), where d(p) is the Euclidean distance in voxels from p
 * to the boundary voxels of the original shape (voxels with a 6-neighbour of
 * the other state, on both sides). The output has the input's geometry and
 * one unsigned char point array "Inside" (1 inside, 0 outside), active.
 *
 * The draws come from a hash of (Seed, voxel index): the same seed gives the
 * same volume, whatever the number of threads. NoiseLevel 0 returns the
 * selection unchanged; the paper uses 0.1 ... 0.5.
 *
 * Pieces and sub-extents: the output is the requested extent
 * (CAN_PRODUCE_SUB_EXTENT; a piece request is split by VTK's executive, as
 * for vtkDigitalIslandFilter, ghost levels included), and the filter asks
 * its input for that box grown by Reach voxels (clipped to the whole
 * extent), as one piece. The draws are indexed in the whole extent, so a
 * voxel's draw is the same in every box; only its distance to the boundary
 * can differ, and only where the boundary lies beyond the box. Every voxel
 * whose distance to the whole volume's boundary is below Reach gets
 * exactly the whole-volume decision; a voxel farther out flips with
 * probability at most k^(1 + Reach). Reach is the smallest number of
 * layers for which that probability times the whole volume's voxel count
 * is at most UncertaintyBound (1e-6 by default: over all pieces together,
 * the expected number of voxels that differ from one process's result is
 * at most 1e-6), capped at the whole extent's largest axis (then
 * the box is the whole volume and the result exact). For a 256^3 volume
 * that is 25 layers at k = 0.3 and 43 at k = 0.5; k = 0 reads only the box.
 * Nothing is left to chance silently: a voxel of the box whose decision
 * could differ (its distance within the box is larger than its distance
 * to a face of the box inside the image, and its draw would flip it at
 * that distance) is counted, GetNumberOfUncertainVoxels, and a non-zero
 * count gives a warning. On the whole extent nothing of this applies: the
 * output is bitwise the one of a single run, as before pieces.
 */
#ifndef vtkDigitalNoiseFilter_h
#define vtkDigitalNoiseFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkImageAlgorithm.h"

#include <memory>

namespace dg
{
class PipelineAbort;
}

class VTKDIGITALGEOMETRY_EXPORT vtkDigitalNoiseFilter : public vtkImageAlgorithm
{
public:
  static vtkDigitalNoiseFilter* New();
  vtkTypeMacro(vtkDigitalNoiseFilter, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Noise level k in [0, 1] (default 0.3): boundary voxels flip with
   * probability k, voxels at distance d with k^(1+d).
   */
  vtkSetClampMacro(NoiseLevel, double, 0.0, 1.0);
  vtkGetMacro(NoiseLevel, double);
  ///@}

  ///@{
  /**
   * Seed of the random draws, >= 0 (default 0).
   */
  vtkSetClampMacro(Seed, int, 0, VTK_INT_MAX);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /**
   * Selection of the inside voxels, as in vtkDigitalSurfaceFilter
   * (0 non-zero, 1 range [LowerThreshold, UpperThreshold], 2 Label).
   */
  vtkSetClampMacro(SelectionMode, int, 0, 2);
  vtkGetMacro(SelectionMode, int);
  vtkSetMacro(LowerThreshold, double);
  vtkGetMacro(LowerThreshold, double);
  vtkSetMacro(UpperThreshold, double);
  vtkGetMacro(UpperThreshold, double);
  vtkSetMacro(Label, double);
  vtkGetMacro(Label, double);
  vtkSetMacro(SelectedComponent, int);
  vtkGetMacro(SelectedComponent, int);
  ///@}

  ///@{
  /**
   * Bound on the expected number of voxels of the whole volume whose noise
   * may differ from a one-process run when the filter produces a piece or
   * a sub-extent (default 1e-6); it sets Reach. 0 reads the whole extent
   * whatever the request (exact, the memory of the whole volume).
   */
  vtkSetClampMacro(UncertaintyBound, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(UncertaintyBound, double);
  ///@}

  /**
   * Voxel layers asked beyond the requested extent for a whole extent of
   * `wholeVoxels` voxels whose largest axis has `largestAxis` voxels, with
   * the current NoiseLevel and UncertaintyBound (dg::NoiseReach).
   */
  int ComputeReach(double wholeVoxels, int largestAxis) const;

  /**
   * Voxel layers the last update asked beyond its requested extent.
   */
  vtkGetMacro(Reach, int);

  ///@{
  /**
   * The voxels whose flips NumberOfFlippedVoxels counts: those of the
   * output extent inside CountedExtent (by default everything, i.e. the
   * output extent). A piece whose output overlaps its neighbours' (the
   * extent a downstream filter asks for, with its ghost layers) sets its
   * own voxels (dg::PieceExtent) here, so that the pieces' counts add up
   * to the whole volume's.
   */
  vtkSetVector6Macro(CountedExtent, int);
  vtkGetVector6Macro(CountedExtent, int);
  ///@}

  /**
   * Number of voxels flipped by the last execution, in its output extent
   * and CountedExtent (a piece's own count: per piece, not the whole
   * volume's).
   */
  vtkGetMacro(NumberOfFlippedVoxels, vtkIdType);

  /**
   * Voxels of the last output whose decision may differ from the
   * whole-volume run (see the class description; the whole output
   * extent, whatever CountedExtent); 0 on the whole extent.
   */
  vtkGetMacro(NumberOfUncertainVoxels, vtkIdType);

  /**
   * Includes the aborted state: after an aborted execution (SetAbortExecute
   * from a progress observer: empty outputs, no error) the filter is out of
   * date until it has run again.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkDigitalNoiseFilter();
  ~vtkDigitalNoiseFilter() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double NoiseLevel = 0.3;
  int Seed = 0;
  int SelectionMode = 0;
  double LowerThreshold = 1.0;
  double UpperThreshold = VTK_DOUBLE_MAX;
  double Label = 1.0;
  int SelectedComponent = -1;
  double UncertaintyBound = 1e-6;
  int Reach = 0;
  int CountedExtent[6] = { VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN,
    VTK_INT_MAX };
  vtkIdType NumberOfFlippedVoxels = 0;
  vtkIdType NumberOfUncertainVoxels = 0;

private:
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkDigitalNoiseFilter(const vtkDigitalNoiseFilter&) = delete;
  void operator=(const vtkDigitalNoiseFilter&) = delete;
};

#endif
