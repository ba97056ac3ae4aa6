#include "vtkDigitalNoiseFilter.h"

#include "dgPipelineAbort.h"
#include "dgNoise.h"
#include "dgVoxelSelection.h"

#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <cstring>

vtkStandardNewMacro(vtkDigitalNoiseFilter);

vtkDigitalNoiseFilter::~vtkDigitalNoiseFilter() = default;

vtkDigitalNoiseFilter::vtkDigitalNoiseFilter()
{
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkDigitalNoiseFilter::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkDataObject::SetPointDataActiveScalarInfo(
    outputVector->GetInformationObject(0), VTK_UNSIGNED_CHAR, 1);
  return 1;
}

int vtkDigitalNoiseFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // The noise of a voxel depends on its index in the whole image and on its
  // distance to the boundary anywhere in it: always the whole extent, so
  // that a piece sees the noise of a one-process run (its output is the
  // whole image; downstream stages take their piece from it).
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
    inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  return 1;
}

vtkMTimeType vtkDigitalNoiseFilter::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkDigitalNoiseFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  this->NumberOfFlippedVoxels = 0;
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
  int ext[6];
  input->GetExtent(ext);
  const int dims[3] = { ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1 };
  if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
  {
    vtkErrorMacro("Input image is empty.");
    return 0;
  }
  const dg::VoxelSelection select{ this->SelectionMode, this->LowerThreshold,
    this->UpperThreshold, this->Label, this->SelectedComponent };
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  std::int64_t count = 0;
  std::string error;
  if (!dg::SelectVoxels(dg::SelectionArray(this->GetInputArrayToProcess(0, inputVector),
    this->GetInputArrayInformation(0), input), dims, select, inside.data(),
        dims[0], 0, count, error))
  {
    vtkErrorMacro("Cannot select voxels: " << error << ".");
    return 0;
  }
  this->UpdateProgress(0.2);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }
  const std::int64_t flipped = dg::ApplyNoise(inside, dims, this->NoiseLevel,
    static_cast<std::uint64_t>(this->Seed), [this](double f) {
      this->UpdateProgress(0.2 + 0.7 * f);
      return !this->GetAbortExecute();
    });
  if (flipped < 0)
  {
    return this->Abort->Abort(outputVector);
  }
  this->NumberOfFlippedVoxels = flipped;
  this->UpdateProgress(0.9);

  output->CopyStructure(input);
  vtkNew<vtkUnsignedCharArray> values;
  values->SetName("Inside");
  values->SetNumberOfValues(static_cast<vtkIdType>(inside.size()));
  std::memcpy(values->GetPointer(0), inside.data(), inside.size());
  output->GetPointData()->SetScalars(values);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkDigitalNoiseFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NoiseLevel: " << this->NoiseLevel << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "SelectionMode: " << this->SelectionMode << "\n";
  os << indent << "LowerThreshold: " << this->LowerThreshold << "\n";
  os << indent << "UpperThreshold: " << this->UpperThreshold << "\n";
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "SelectedComponent: " << this->SelectedComponent << "\n";
}
