#include "vtkSplitByLabelFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkSplitByLabelFilter);

vtkSplitByLabelFilter::vtkSplitByLabelFilter()
{
  this->SetLabelArrayName("Label");
}

vtkSplitByLabelFilter::~vtkSplitByLabelFilter()
{
  this->SetLabelArrayName(nullptr);
}

int vtkSplitByLabelFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

namespace
{
// vtkPolyData numbers its cells verts, lines, polys, strips: a block's
// cells are inserted in that order so that its cell data lines up.
int Category(int type)
{
  switch (type)
  {
    case VTK_VERTEX:
    case VTK_POLY_VERTEX:
      return 0;
    case VTK_LINE:
    case VTK_POLY_LINE:
      return 1;
    case VTK_TRIANGLE_STRIP:
      return 3;
    default:
      return 2;
  }
}

std::string BlockName(double label)
{
  std::ostringstream s;
  if (label == std::floor(label) && std::abs(label) < 9.0e15)
  {
    s << "Label " << static_cast<long long>(label);
  }
  else
  {
    s << "Label " << label;
  }
  return s.str();
}
} // namespace

int vtkSplitByLabelFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  auto* output = vtkPartitionedDataSetCollection::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro("Missing input polydata or output.");
    return 0;
  }
  const char* name = this->LabelArrayName ? this->LabelArrayName : "";
  vtkDataArray* labels = input->GetCellData()->GetArray(name);
  if (!labels || labels->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro("The input has no one-component cell array '"
      << name << "' to split by (vtkDigitalSurfaceFilter writes 'Label' in EachLabel mode).");
    return 0;
  }
  const vtkIdType nCells = input->GetNumberOfCells();
  std::map<double, std::vector<vtkIdType>> cellsOf;
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    cellsOf[labels->GetTuple1(c)].push_back(c);
  }
  output->SetNumberOfPartitionedDataSets(static_cast<unsigned int>(cellsOf.size()));
  unsigned int block = 0;
  vtkNew<vtkIdList> ids;
  for (auto& entry : cellsOf)
  {
    std::vector<vtkIdType>& cells = entry.second;
    std::stable_sort(cells.begin(), cells.end(), [input](vtkIdType a, vtkIdType b) {
      return Category(input->GetCellType(a)) < Category(input->GetCellType(b));
    });
    vtkNew<vtkPolyData> part;
    vtkNew<vtkPoints> points;
    points->SetDataType(input->GetPoints() ? input->GetPoints()->GetDataType() : VTK_DOUBLE);
    part->SetPoints(points);
    part->AllocateEstimate(static_cast<vtkIdType>(cells.size()), 4);
    part->GetPointData()->CopyAllocate(input->GetPointData());
    part->GetCellData()->CopyAllocate(input->GetCellData(), static_cast<vtkIdType>(cells.size()));
    std::vector<vtkIdType> pointMap(input->GetNumberOfPoints(), -1);
    std::vector<vtkIdType> cellPoints;
    for (vtkIdType c : cells)
    {
      input->GetCellPoints(c, ids);
      cellPoints.resize(ids->GetNumberOfIds());
      for (vtkIdType q = 0; q < ids->GetNumberOfIds(); ++q)
      {
        vtkIdType& m = pointMap[ids->GetId(q)];
        if (m < 0)
        {
          m = points->InsertNextPoint(input->GetPoint(ids->GetId(q)));
          part->GetPointData()->CopyData(input->GetPointData(), ids->GetId(q), m);
        }
        cellPoints[q] = m;
      }
      const vtkIdType newId = part->InsertNextCell(
        input->GetCellType(c), static_cast<vtkIdType>(cellPoints.size()), cellPoints.data());
      part->GetCellData()->CopyData(input->GetCellData(), c, newId);
    }
    part->GetFieldData()->ShallowCopy(input->GetFieldData());
    output->SetPartition(block, 0, part);
    output->GetMetaData(block)->Set(vtkCompositeDataSet::NAME(), BlockName(entry.first).c_str());
    ++block;
    this->UpdateProgress(static_cast<double>(block) / cellsOf.size());
  }
  return 1;
}

void vtkSplitByLabelFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "LabelArrayName: " << (this->LabelArrayName ? this->LabelArrayName : "(none)")
     << "\n";
}
