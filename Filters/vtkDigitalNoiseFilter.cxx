#include "vtkDigitalNoiseFilter.h"

#include "dgNoise.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"
#include "dgVoxelSelection.h"

#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

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
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_UNSIGNED_CHAR, 1);
  // Any sub-extent (within UncertaintyBound): a piece request is split by
  // the executive, with its ghost levels, as for a reader.
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

namespace
{
using SDDP = vtkStreamingDemandDrivenPipeline;

void WholeSize(const int whole[6], double& voxels, int& largestAxis)
{
  voxels = 1;
  largestAxis = 0;
  for (int a = 0; a < 3; ++a)
  {
    const int n = std::max(0, whole[2 * a + 1] - whole[2 * a] + 1);
    voxels *= n;
    largestAxis = std::max(largestAxis, n);
  }
}

std::string ExtentText(const int e[6])
{
  std::ostringstream s;
  s << e[0] << ".." << e[1] << ", " << e[2] << ".." << e[3] << ", " << e[4] << ".." << e[5];
  return s.str();
}
} // namespace

int vtkDigitalNoiseFilter::ComputeReach(double wholeVoxels, int largestAxis) const
{
  return dg::NoiseReach(this->NoiseLevel, wholeVoxels, this->UncertaintyBound, largestAxis);
}

int vtkDigitalNoiseFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The requested box grown by the reach of the noise's dependence on the
  // boundary (dg::NoiseReach): what lies beyond changes a voxel's decision
  // with a probability below UncertaintyBound over the whole volume.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  int whole[6], requested[6], grown[6];
  if (!dg::RequestedImageBox(inInfo, outputVector->GetInformationObject(0), whole, requested))
  {
    return 1;
  }
  double voxels;
  int largest;
  WholeSize(whole, voxels, largest);
  this->Reach = this->ComputeReach(voxels, largest);
  dg::GrowExtent(requested, this->Reach, whole, grown);
  dg::RequestImageBox(inInfo, grown);
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
  this->NumberOfUncertainVoxels = 0;
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
  // The input's box and the requested one (the output's): the whole image
  // both, unless a piece or a sub-extent was asked for.
  dg::NoiseBox box;
  input->GetExtent(box.Box);
  std::copy(box.Box, box.Box + 6, box.Whole);
  std::copy(box.Box, box.Box + 6, box.Out);
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (inInfo && inInfo->Has(SDDP::WHOLE_EXTENT()))
  {
    inInfo->Get(SDDP::WHOLE_EXTENT(), box.Whole);
  }
  if (outInfo && outInfo->Has(SDDP::UPDATE_EXTENT()))
  {
    outInfo->Get(SDDP::UPDATE_EXTENT(), box.Out);
  }
  if (dg::ExtentEmpty(box.Out) && !dg::ExtentEmpty(box.Whole))
  {
    // An empty piece (more pieces than voxels): nothing to do, no error.
    output->CopyStructure(input);
    output->SetExtent(box.Out);
    return 1;
  }
  const int dims[3] = { box.Box[1] - box.Box[0] + 1, box.Box[3] - box.Box[2] + 1,
    box.Box[5] - box.Box[4] + 1 };
  if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
  {
    vtkErrorMacro("Input image is empty (extent " << ExtentText(box.Box) << ").");
    return 0;
  }
  // Every voxel within the reach of the requested box must be there (and
  // the box itself inside the image).
  double voxels;
  int largest;
  WholeSize(box.Whole, voxels, largest);
  this->Reach = this->ComputeReach(voxels, largest);
  int needed[6];
  dg::GrowExtent(box.Out, this->Reach, box.Whole, needed);
  if (!dg::ExtentContains(box.Whole, box.Out) || !dg::ExtentContains(box.Box, needed) ||
    !dg::ExtentContains(box.Whole, box.Box))
  {
    vtkErrorMacro("The input (extent " << ExtentText(box.Box)
                                       << ") does not hold the requested extent ("
                                       << ExtentText(box.Out) << ") grown by " << this->Reach
                                       << " voxels within the whole extent ("
                                       << ExtentText(box.Whole) << ").");
    return 0;
  }
  std::copy(this->CountedExtent, this->CountedExtent + 6, box.Counted);
  const bool sameBox = std::equal(box.Out, box.Out + 6, box.Box);
  const dg::VoxelSelection select{ this->SelectionMode, this->LowerThreshold,
    this->UpperThreshold, this->Label, this->SelectedComponent };
  const std::size_t outVoxels = static_cast<std::size_t>(box.Out[1] - box.Out[0] + 1) *
    (box.Out[3] - box.Out[2] + 1) * (box.Out[5] - box.Out[4] + 1);
  vtkNew<vtkUnsignedCharArray> values;
  values->SetName("Inside");
  values->SetNumberOfValues(static_cast<vtkIdType>(outVoxels));
  // On the requested box itself the selection is made and noised in the
  // output array; a larger box is selected apart and only Out written out.
  std::vector<std::uint8_t> window;
  if (!sameBox)
  {
    window.resize(static_cast<std::size_t>(dims[0]) * dims[1] * dims[2]);
  }
  std::uint8_t* inside = sameBox ? values->GetPointer(0) : window.data();
  std::int64_t count = 0;
  std::string error;
  if (!dg::SelectVoxels(dg::SelectionArray(this->GetInputArrayToProcess(0, inputVector),
                          this->GetInputArrayInformation(0), input),
        dims, select, inside, dims[0], 0, count, error))
  {
    vtkErrorMacro("Cannot select voxels: " << error << ".");
    return 0;
  }
  this->UpdateProgress(0.2);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }
  dg::NoiseCounts counts;
  if (!dg::ApplyNoise(inside, box, this->NoiseLevel, static_cast<std::uint64_t>(this->Seed),
        values->GetPointer(0), counts, [this](double f) {
          this->UpdateProgress(0.2 + 0.7 * f);
          return !this->GetAbortExecute();
        }))
  {
    return this->Abort->Abort(outputVector);
  }
  std::vector<std::uint8_t>().swap(window);
  this->NumberOfFlippedVoxels = counts.Flipped;
  this->NumberOfUncertainVoxels = counts.Uncertain;
  if (counts.Uncertain > 0)
  {
    vtkWarningMacro(<< counts.Uncertain << " voxel(s) of the extent " << ExtentText(box.Out)
                    << " may differ from the whole-volume noise: their distance to the "
                       "boundary lies beyond the "
                    << this->Reach
                    << " layers read around it (set a smaller UncertaintyBound, or 0 for "
                       "the whole volume).");
  }
  this->UpdateProgress(0.9);

  output->CopyStructure(input);
  output->SetExtent(box.Out);
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
  os << indent << "UncertaintyBound: " << this->UncertaintyBound << "\n";
  os << indent << "Reach: " << this->Reach << "\n";
  os << indent << "CountedExtent: " << this->CountedExtent[0] << " " << this->CountedExtent[1]
     << " " << this->CountedExtent[2] << " " << this->CountedExtent[3] << " "
     << this->CountedExtent[4] << " " << this->CountedExtent[5] << "\n";
  os << indent << "NumberOfFlippedVoxels: " << this->NumberOfFlippedVoxels << "\n";
  os << indent << "NumberOfUncertainVoxels: " << this->NumberOfUncertainVoxels << "\n";
}
