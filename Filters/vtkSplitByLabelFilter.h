/**
 * @class   vtkSplitByLabelFilter
 * @brief   One block per label of a surface's "Label" cell array.
 *
 * Input: a vtkPolyData with a one-component cell array "Label" (the name
 * can be changed with LabelArrayName), as vtkDigitalSurfaceFilter and
 * vtkIINormalEstimator in EachLabel mode, the AT filter and the sharp
 * features filter after them write it. Output: a
 * vtkPartitionedDataSetCollection with one vtkPartitionedDataSet (of one
 * polydata) per distinct label, in increasing label order, named "Label
 * <value>" (block metadata vtkCompositeDataSet::NAME(), what ParaView's
 * Multiblock Inspector and block selection show). Each block holds the cells
 * of its label with their cell data, the points they use with their point
 * data, and the input's field data. A missing or multi-component label
 * array is an error and gives an empty collection.
 */
#ifndef vtkSplitByLabelFilter_h
#define vtkSplitByLabelFilter_h

#include "vtkDigitalGeometryModule.h"
#include "vtkPartitionedDataSetCollectionAlgorithm.h"

class vtkDataObject;
class vtkPolyData;

class VTKDIGITALGEOMETRY_EXPORT vtkSplitByLabelFilter : public vtkPartitionedDataSetCollectionAlgorithm
{
public:
  static vtkSplitByLabelFilter* New();
  vtkTypeMacro(vtkSplitByLabelFilter, vtkPartitionedDataSetCollectionAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The surface to split (as vtkPolyDataAlgorithm::SetInputData).
   */
  void SetInputData(vtkDataObject* input) { this->SetInputDataObject(0, input); }

  ///@{
  /**
   * The cell array holding the labels (default "Label").
   */
  vtkSetStringMacro(LabelArrayName);
  vtkGetStringMacro(LabelArrayName);
  ///@}

protected:
  vtkSplitByLabelFilter();
  ~vtkSplitByLabelFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* LabelArrayName = nullptr;

private:
  vtkSplitByLabelFilter(const vtkSplitByLabelFilter&) = delete;
  void operator=(const vtkSplitByLabelFilter&) = delete;
};

#endif
