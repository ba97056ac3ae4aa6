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
 * Pieces: the noise of a voxel depends on its index in the whole image and
 * on its distance to the boundary anywhere in it, so the filter always
 * reads and writes the whole extent, whatever piece is asked for: every
 * piece then sees the one-process noise (memory: the whole volume on every
 * process; a piece-local variant would need the distance transform's
 * ghost exchange).
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

  /**
   * Number of voxels flipped by the last execution.
   */
  vtkGetMacro(NumberOfFlippedVoxels, vtkIdType);

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
  vtkIdType NumberOfFlippedVoxels = 0;

private:
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkDigitalNoiseFilter(const vtkDigitalNoiseFilter&) = delete;
  void operator=(const vtkDigitalNoiseFilter&) = delete;
};

#endif
