#include "vtkDigitalIslandFilter.h"

#include "dgIslands.h"
#include "dgPipelineAbort.h"
#include "dgVoxelSelection.h"

#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>

vtkStandardNewMacro(vtkDigitalIslandFilter);

vtkDigitalIslandFilter::~vtkDigitalIslandFilter() = default;

vtkDigitalIslandFilter::vtkDigitalIslandFilter()
{
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkDigitalIslandFilter::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkDataObject::SetPointDataActiveScalarInfo(
    outputVector->GetInformationObject(0), VTK_UNSIGNED_CHAR, 1);
  return 1;
}

int vtkDigitalIslandFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // A component can reach anywhere in the image: ask for all of it, so that
  // a smaller extent requested downstream never cuts a shape into islands.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  }
  return 1;
}

vtkMTimeType vtkDigitalIslandFilter::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkDigitalIslandFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  this->NumberOfRemovedIslands = 0;
  this->NumberOfFilledCavities = 0;
  this->NumberOfChangedVoxels = 0;
  if (!input || !output)
  {
    vtkErrorMacro("Missing input image.");
    return 0;
  }
  const auto abortGuard = this->Abort->Begin(this, outputVector);
  if (dg::PipelineAbort::InputAborted(inputVector, this->GetNumberOfInputPorts()))
  {
    return this->Abort->Abort(outputVector);
  }
  // An image output keeps its arrays from the last run unless told: after
  // an error it must be empty, not the previous result.
  output->GetPointData()->Initialize();
  output->GetFieldData()->Initialize();
  if (this->MinimumSize < 1)
  {
    vtkErrorMacro("MinimumSize must be at least 1 voxel (it is " << this->MinimumSize
                                                                << "; 1 changes nothing).");
    return 0;
  }
  int ext[6];
  input->GetExtent(ext);
  const int dims[3] = { ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1 };
  if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
  {
    vtkErrorMacro("Input image is empty (extent " << ext[0] << ".." << ext[1] << ", " << ext[2]
                                                  << ".." << ext[3] << ", " << ext[4] << ".."
                                                  << ext[5] << ").");
    return 0;
  }
  const dg::VoxelSelection select{ this->SelectionMode, this->LowerThreshold,
    this->UpperThreshold, this->Label, this->SelectedComponent };
  // The selection is made and cleaned in the output array itself.
  vtkNew<vtkUnsignedCharArray> values;
  values->SetName("Inside");
  values->SetNumberOfValues(static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2]);
  std::uint8_t* inside = values->GetPointer(0);
  std::int64_t insideCount = 0;
  std::string error;
  if (!dg::SelectVoxels(dg::SelectionArray(this->GetInputArrayToProcess(0, inputVector),
                          this->GetInputArrayInformation(0), input),
        dims, select, inside, dims[0], 0, insideCount, error))
  {
    vtkErrorMacro("Cannot select voxels: " << error << ".");
    return 0;
  }
  this->UpdateProgress(0.2);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }

  dg::IslandCounts counts;
  const bool done = dg::RemoveSmallComponents(inside, dims, this->MinimumSize,
    this->RemoveIslands != 0, this->FillCavities != 0, counts, [this](double f) {
      this->UpdateProgress(0.2 + 0.75 * f);
      return !this->GetAbortExecute();
    });
  if (!done)
  {
    return this->Abort->Abort(outputVector);
  }
  this->NumberOfRemovedIslands = counts.RemovedIslands;
  this->NumberOfFilledCavities = counts.FilledCavities;
  this->NumberOfChangedVoxels = counts.ChangedVoxels;
  if (insideCount > 0 && counts.ChangedVoxels == insideCount && counts.FilledCavities == 0)
  {
    vtkWarningMacro("Every inside voxel was in an island smaller than MinimumSize ("
      << this->MinimumSize << " voxels): the output has no inside voxel.");
  }

  output->CopyStructure(input);
  output->GetPointData()->SetScalars(values);
  const auto addCount = [output](const char* name, vtkIdType n) {
    vtkNew<vtkIntArray> a;
    a->SetName(name);
    a->SetNumberOfValues(1);
    a->SetValue(0, static_cast<int>(std::min<vtkIdType>(n, VTK_INT_MAX)));
    output->GetFieldData()->AddArray(a);
  };
  addCount("RemovedIslands", this->NumberOfRemovedIslands);
  addCount("FilledCavities", this->NumberOfFilledCavities);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkDigitalIslandFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* modes[] = { "NonZero", "Range", "Label" };
  os << indent << "MinimumSize: " << this->MinimumSize << "\n";
  os << indent << "RemoveIslands: " << (this->RemoveIslands ? "On" : "Off") << "\n";
  os << indent << "FillCavities: " << (this->FillCavities ? "On" : "Off") << "\n";
  os << indent << "SelectionMode: " << modes[this->SelectionMode] << "\n";
  os << indent << "LowerThreshold: " << this->LowerThreshold << "\n";
  os << indent << "UpperThreshold: " << this->UpperThreshold << "\n";
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "SelectedComponent: " << this->SelectedComponent << "\n";
  os << indent << "NumberOfRemovedIslands: " << this->NumberOfRemovedIslands << "\n";
  os << indent << "NumberOfFilledCavities: " << this->NumberOfFilledCavities << "\n";
  os << indent << "NumberOfChangedVoxels: " << this->NumberOfChangedVoxels << "\n";
}
