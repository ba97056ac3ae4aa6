/**
 * @class   vtkDigitalIslandFilter
 * @brief   Remove small islands and fill small cavities of a segmented volume.
 *
 * Noise in a segmentation (the paper's noise model, vtkDigitalNoiseFilter,
 * or a real segmenter's) leaves floating specks outside the shape and tiny
 * holes inside it. Each becomes a small closed piece of digital surface
 * whose surfels have normals pointing every way, and the integral-invariant
 * normals and Ambrosio-Tortorelli features around it report false features.
 * This filter cleans the voxel set before vtkDigitalSurfaceFilter:
 *
 * - islands: every connected component of inside voxels with fewer than
 *   MinimumSize voxels becomes outside (RemoveIslands); a component may
 *   touch the image border;
 * - cavities: every connected component of outside voxels with fewer than
 *   MinimumSize voxels that has no voxel on the image border becomes inside
 *   (FillCavities). Voxels beyond the extent are outside (as for the
 *   digital surface), so an outside component on the border is part of the
 *   exterior and is never filled, however small.
 *
 * Connectivity is 6 (voxels sharing a face) for both, the adjacency of the
 * digital surface: a speck touching the shape along an edge or at a corner
 * only is an island (its surface is a separate closed piece), and so is
 * each voxel of a diagonal chain. This is also VTK's vtkImageConnectivityFilter
 * (6-connectivity in 3D), which this filter does not use: it lives in
 * VTK::ImagingMorphological, which ParaView 5.11's VTK (the one this module
 * is built against by default) does not have. The labelling is run-length
 * union-find (dgIslands.h): a few words of memory per run of voxels along x.
 *
 * A one-voxel-thick image is accepted: its components are 4-connected in
 * the slice, and it has no cavity, every voxel being on the border.
 *
 * Islands are removed first and cavities are found in the result, so that a
 * speck inside a small cavity does not leave a hole once the cavity is
 * filled. The output has no island and no cavity smaller than MinimumSize:
 * running the filter again changes nothing.
 *
 * Inside voxels are selected as in vtkDigitalSurfaceFilter (SelectionMode
 * NON_ZERO by default, RANGE [LowerThreshold, UpperThreshold] or LABEL, on
 * the array chosen with SetInputArrayToProcess, SelectedComponent of a
 * multi-component array). The output has the input's extent, origin,
 * spacing and direction matrix and one unsigned char point array "Inside"
 * (1 inside, 0 outside), active, as vtkDigitalNoiseFilter's; its field data
 * has int arrays "RemovedIslands" and "FilledCavities" (one value each).
 * The result does not depend on the number of threads.
 *
 * Pieces and sub-extents: on any requested extent the output is exactly
 * the whole-image result on that box (CAN_PRODUCE_SUB_EXTENT). The filter
 * asks its input for the box grown by R = (MinimumSize - 1) voxels per pass
 * on (2 (MinimumSize - 1) with both, 14 by default; clipped to the whole
 * extent), as one piece, and labels that window: a component that touches
 * a face of the window inside the image may continue beyond it and is
 * kept, island or cavity, as large ones are. A small component meeting the
 * box lies within MinimumSize - 2 voxels of it; a cavity's walls depend on
 * the islands removed up to MinimumSize - 1 voxels out, and those islands
 * on the next MinimumSize - 1 layers: hence twice the reach with both
 * passes (dg::ComponentReach; TestIslandFilter shows a case that growing by
 * MinimumSize alone gets wrong). A piece of an n-voxel cube costs the
 * labelling of (n + 2R)^3 voxels instead of n^3, and an input with less
 * than the grown box is an error. A piece request (UpdatePiece(p, n, g), a
 * ParaView rank) is split by VTK's executive (vtkExtentTranslator, block
 * mode, by cells: neighbouring pieces share a layer of voxels), g ghost
 * layers included; the executive marks them in vtkGhostType (point and cell
 * arrays), and the filter asks its input for that box grown by R, so ghost
 * voxels are exact too. The counts (Get methods and field data) are those
 * of the requested box (within CountedExtent): components whose first
 * voxel (x fastest) lies in it, changed voxels in it; over disjoint boxes
 * (dg::PieceExtent) they add up to the whole image's. An empty requested extent gives an empty image,
 * no error. On the whole extent nothing of this applies: the output is
 * the one of a single run.
 */
#ifndef vtkDigitalIslandFilter_h
#define vtkDigitalIslandFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkImageAlgorithm.h"

#include <memory>

namespace dg
{
class PipelineAbort;
}

class VTKDIGITALGEOMETRY_EXPORT vtkDigitalIslandFilter : public vtkImageAlgorithm
{
public:
  static vtkDigitalIslandFilter* New();
  vtkTypeMacro(vtkDigitalIslandFilter, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum SelectionModes
  {
    NON_ZERO = 0,
    RANGE = 1,
    LABEL = 2
  };

  ///@{
  /**
   * Components (islands and cavities) with fewer voxels than this are
   * removed or filled; larger ones are kept. Default 8; 1 changes nothing;
   * below 1 is an error.
   */
  vtkSetMacro(MinimumSize, int);
  vtkGetMacro(MinimumSize, int);
  ///@}

  ///@{
  /**
   * Remove small inside components (default on).
   */
  vtkSetMacro(RemoveIslands, vtkTypeBool);
  vtkGetMacro(RemoveIslands, vtkTypeBool);
  vtkBooleanMacro(RemoveIslands, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Fill small outside components that do not touch the image border
   * (default on).
   */
  vtkSetMacro(FillCavities, vtkTypeBool);
  vtkGetMacro(FillCavities, vtkTypeBool);
  vtkBooleanMacro(FillCavities, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Selection of the inside voxels, as in vtkDigitalSurfaceFilter
   * (default NON_ZERO; RANGE: LowerThreshold <= value <= UpperThreshold,
   * defaults 1 and VTK_DOUBLE_MAX; LABEL: value == Label, default 1).
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
  ///@}

  ///@{
  /**
   * Component of a multi-component scalar array to select on (default -1:
   * the array must have a single component).
   */
  vtkSetMacro(SelectedComponent, int);
  vtkGetMacro(SelectedComponent, int);
  ///@}

  ///@{
  /**
   * The box whose components and voxels the counts below count: the
   * requested extent inside CountedExtent (by default everything, i.e. the
   * requested extent). A piece whose requested extent overlaps its
   * neighbours' (a downstream filter's ghost layers) sets its own voxels
   * (dg::PieceExtent) here, so that the pieces' counts add up to the whole
   * image's.
   */
  vtkSetVector6Macro(CountedExtent, int);
  vtkGetVector6Macro(CountedExtent, int);
  ///@}

  ///@{
  /**
   * What the last execution did: islands removed, cavities filled, and the
   * voxels whose value differs from the input's selection (an island voxel
   * inside a filled cavity ends up inside again and does not count), in
   * the requested extent and CountedExtent.
   */
  vtkGetMacro(NumberOfRemovedIslands, vtkIdType);
  vtkGetMacro(NumberOfFilledCavities, vtkIdType);
  vtkGetMacro(NumberOfChangedVoxels, vtkIdType);
  ///@}

  /**
   * Includes the aborted state: after an aborted execution (SetAbortExecute
   * from a progress observer: empty outputs, no error) the filter is out of
   * date until it has run again.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkDigitalIslandFilter();
  ~vtkDigitalIslandFilter() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int MinimumSize = 8;
  vtkTypeBool RemoveIslands = true;
  vtkTypeBool FillCavities = true;
  int SelectionMode = NON_ZERO;
  double LowerThreshold = 1.0;
  double UpperThreshold = VTK_DOUBLE_MAX;
  double Label = 1.0;
  int SelectedComponent = -1;
  int CountedExtent[6] = { VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN,
    VTK_INT_MAX };
  vtkIdType NumberOfRemovedIslands = 0;
  vtkIdType NumberOfFilledCavities = 0;
  vtkIdType NumberOfChangedVoxels = 0;

private:
  // Voxel layers asked beyond the requested extent (dg::ComponentReach).
  int Reach() const;
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkDigitalIslandFilter(const vtkDigitalIslandFilter&) = delete;
  void operator=(const vtkDigitalIslandFilter&) = delete;
};

#endif
