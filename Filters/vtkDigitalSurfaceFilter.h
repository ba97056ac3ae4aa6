/**
 * @class   vtkDigitalSurfaceFilter
 * @brief   Extract the digital surface (voxel-face quads) of a set of voxels.
 *
 * The input is a vtkImageData whose point scalars (one value per voxel) select
 * the "inside" voxels; the output is the boundary of that voxel set as a 2D
 * cubical complex (docs/method.md section 1): one quad per surfel, i.e. per voxel
 * face that separates an inside voxel from an outside 6-neighbour. Voxels
 * beyond the image extent are outside, so the surface is always closed.
 *
 * Output (vtkPolyData):
 * - points: the surfels' corners, each stored once, at voxel corners in world
 *   coordinates: origin + direction * (spacing * (index - 1/2));
 * - polys: one quad per surfel, counter-clockwise seen from outside (its
 *   right-hand normal points from the inside voxel to the outside one);
 * - cell data "Normals" (float, active normals): the trivial outward normal;
 *   "InsideVoxel" (int, 3 components): structured index (i, j, k) of the
 *   surfel's inside voxel in the image's index space; "SurfelDirection"
 *   (unsigned char): 0..5 for -x, +x, -y, +y, -z, +z (axis = d / 2);
 * - with pieces, or with GenerateGlobalIds on (off by default: ParaView's
 *   array menus of later filters on the same image would otherwise offer
 *   "GlobalIds" as their default array), cell data "GlobalIds" (vtkIdType,
 *   the cell data's global ids):
 *   ((k * Ny + j) * Nx + i) * 6 + d, with (i, j, k) the inside voxel counted
 *   from the lower corner of the whole extent, (Nx, Ny, Nz) the whole
 *   extent's dimensions and d the direction; point data "GlobalIds" (the
 *   point data's global ids): (ck * (Ny + 1) + cj) * (Nx + 1) + ci, the
 *   pointel's corner index (0..N along each axis) in the whole extent. Both
 *   come from the grid alone, so every partition into pieces gives the same
 *   ids and results can be compared cell by cell with a one-process run;
 * - field data "ImageExtent" (int[6], the whole extent), "ImageOrigin" and
 *   "ImageSpacing" (double[3]): the image the surface came from, so that
 *   later stages (vtkIINormalEstimator) can check they look at the same
 *   volume.
 *
 * Pieces: asked for piece p of N (UPDATE_PIECE_NUMBER and
 * UPDATE_NUMBER_OF_PIECES, as ParaView's parallel pipeline does on every
 * rank), the filter owns the voxels of dg::PieceExtent (VTK's block split
 * of the whole extent, by points) and emits the surfels whose inside voxel
 * it owns: over all pieces, every surfel exactly once. It asks its input
 * for that extent grown by G + 1 voxels (G the requested ghost levels, plus
 * IMAGE_GHOST_LEVELS() when a downstream stage set it), so the input's
 * reader must produce sub-extents (CAN_PRODUCE_SUB_EXTENT; VTK's XML, NRRD
 * and MetaImage readers and the module's readers do). With G > 0 ghost
 * levels, the surfels whose inside voxel lies within G voxels of the own
 * extent are added as ghost cells (vtkGhostType DUPLICATECELL): for G = 1
 * they hold every surfel that shares a point with an owned one. A piece
 * with no surfel is normal: an empty output, no error.
 *
 * Non-manifold configurations (two voxels touching along an edge only) are
 * kept as they are: that edge has four incident quads.
 *
 * Selection of inside voxels, from the array chosen with
 * SetInputArrayToProcess (default: the active point scalars), any numeric
 * type: SelectionMode NonZero (default: value != 0), Range (LowerThreshold
 * <= value <= UpperThreshold), Label (value == Label) or EachLabel (below).
 * For a multi-component array, SelectedComponent must name the component.
 *
 * EachLabel (label maps, docs/labels.md): every non-zero value the string
 * Labels selects ("all", default, or "1,4,10-12") is one label; each
 * label's surface is extracted on a copy of its voxel box grown by one
 * voxel (dg::CropImage), which gives exactly the Label mode's surface of
 * that value on the whole image (same quads, points and order), and the
 * labels' surfaces are appended in increasing label order, with the cell
 * data "Label" (int). Points are not shared between labels: a face between
 * two labels is in both surfaces, with each label's outward orientation, and
 * every label stays its own connected components for the later stages
 * (vtkIINormalEstimator in EachLabel mode, the AT filter,
 * vtkSplitByLabelFilter). The values must be integers (fitting an int); a
 * spec that selects no label present is an error that lists the labels
 * there. One piece only (a distributed request is refused), no GlobalIds.
 *
 * Interfaces (label maps' shared boundaries, docs/labels.md): every face
 * between two different selected labels, or between a selected label and
 * anything else (background, unselected labels, the image's outside), once,
 * oriented out of the larger label, with the cell data "LabelInside" (the
 * larger label; also written as "Label", so that vtkIINormalEstimator in
 * EachLabel mode estimates each face with its inside label's voxels) and
 * "LabelOutside" (0 for background). Points are merged by voxel corner, so
 * the output is one complex, non-manifold where three or more labels meet
 * (3 or 4 faces on an edge): the AT filter smooths each shared boundary
 * once and keeps those lines as features. Same Labels, pieces and GlobalIds
 * rules as EachLabel.
 *
 * The extraction runs in parallel with vtkSMPTools and its output does not
 * depend on the number of threads. Memory: one byte per voxel for the
 * selection mask, plus the output.
 */
#ifndef vtkDigitalSurfaceFilter_h
#define vtkDigitalSurfaceFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPolyDataAlgorithm.h"

class vtkDataArray;
class vtkImageData;
class vtkInformationIntegerKey;

#include <memory>

namespace dg
{
class PipelineAbort;
}

class VTKDIGITALGEOMETRY_EXPORT vtkDigitalSurfaceFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkDigitalSurfaceFilter* New();
  vtkTypeMacro(vtkDigitalSurfaceFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum SelectionModes
  {
    NON_ZERO = 0,
    RANGE = 1,
    LABEL = 2,
    EACH_LABEL = 3,
    INTERFACES = 4
  };

  ///@{
  /**
   * How inside voxels are selected (default NON_ZERO).
   */
  vtkSetClampMacro(SelectionMode, int, NON_ZERO, INTERFACES);
  vtkGetMacro(SelectionMode, int);
  void SetSelectionModeToNonZero() { this->SetSelectionMode(NON_ZERO); }
  void SetSelectionModeToRange() { this->SetSelectionMode(RANGE); }
  void SetSelectionModeToLabel() { this->SetSelectionMode(LABEL); }
  void SetSelectionModeToEachLabel() { this->SetSelectionMode(EACH_LABEL); }
  void SetSelectionModeToInterfaces() { this->SetSelectionMode(INTERFACES); }
  ///@}

  ///@{
  /**
   * The labels EACH_LABEL and INTERFACES modes extract (default "all": every non-zero
   * value): labels and inclusive ranges separated by commas, "1,4,10-12",
   * as the program's --labels.
   */
  vtkSetStringMacro(Labels);
  vtkGetStringMacro(Labels);
  ///@}

  ///@{
  /**
   * Closed range [LowerThreshold, UpperThreshold] used in RANGE mode
   * (defaults 1 and VTK_DOUBLE_MAX).
   */
  vtkSetMacro(LowerThreshold, double);
  vtkGetMacro(LowerThreshold, double);
  vtkSetMacro(UpperThreshold, double);
  vtkGetMacro(UpperThreshold, double);
  ///@}

  ///@{
  /**
   * The label value selected in LABEL mode (default 1).
   */
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

  /**
   * Includes the aborted state: after an aborted execution (SetAbortExecute
   * from a progress observer: empty outputs, no error) the filter is out of
   * date until it has run again.
   */
  vtkMTimeType GetMTime() override;

  /**
   * Request key (an integer, set by a downstream stage on this filter's
   * output information during REQUEST_UPDATE_EXTENT): how many voxel layers
   * beyond the piece's own extent that stage reads from the same image.
   * vtkIINormalEstimator sets it to ceil(radius) + 1 + its ghost levels, so
   * that this filter and the estimator ask the image's source for the same
   * extent: two different requests on one output would leave one of them
   * with the other's extent. It is a request key (like the piece keys): the
   * executive carries it upstream through filters in between, such as
   * ParaView's vtkPVPostFilter.
   */
  static vtkInformationIntegerKey* IMAGE_GHOST_LEVELS();

  ///@{
  /**
   * Adds the cell and point "GlobalIds" in a one-piece run too (they are
   * always there when the output is one of several pieces), e.g. to compare
   * a one-process result with a distributed one. Default off.
   */
  vtkSetMacro(GenerateGlobalIds, bool);
  vtkGetMacro(GenerateGlobalIds, bool);
  vtkBooleanMacro(GenerateGlobalIds, bool);
  ///@}

protected:
  vtkDigitalSurfaceFilter();
  ~vtkDigitalSurfaceFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  // RequestData of this piece alone (RequestData adds the pieces' agreement).
  int ExecutePiece(vtkInformation*, vtkInformationVector**, vtkInformationVector*);

  int SelectionMode = NON_ZERO;
  double LowerThreshold = 1.0;
  double UpperThreshold = VTK_DOUBLE_MAX;
  double Label = 1.0;
  int SelectedComponent = -1;
  bool GenerateGlobalIds = false;
  char* Labels = nullptr;

  // EACH_LABEL: every selected label's surface on its own box, appended;
  // INTERFACES: the faces between labels once, on shared points.
  int ExecuteEachLabel(vtkImageData* input,
    vtkDataArray* scalars,
    const int whole[6],
    vtkPolyData* output,
    vtkInformationVector* outputVector);
  // The whole image's record every mode writes (field data ImageExtent,
  // ImageOrigin, ImageSpacing): the estimators check a surface against it.
  static void AddImageRecord(
    vtkPolyData* output, const int whole[6], const double origin[3], const double spacing[3]);

private:
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkDigitalSurfaceFilter(const vtkDigitalSurfaceFilter&) = delete;
  void operator=(const vtkDigitalSurfaceFilter&) = delete;
};

#endif
