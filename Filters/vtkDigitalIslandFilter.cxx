#include "vtkDigitalIslandFilter.h"

#include "dgIslands.h"
#include "dgPieces.h"
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

namespace
{
// f(first voxel, count) for each x row of the local box b (i0, i1, j0, j1,
// k0, k1) in an array of dims, x fastest, in order.
template <typename F>
void ForRows(const int dims[3], const int b[6], F f)
{
  for (int k = b[4]; k <= b[5]; ++k)
  {
    for (int j = b[2]; j <= b[3]; ++j)
    {
      f((static_cast<std::int64_t>(k) * dims[1] + j) * dims[0] + b[0], b[1] - b[0] + 1);
    }
  }
}
} // namespace

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
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_UNSIGNED_CHAR, 1);
  // Any sub-extent, exactly: a piece request is split by the executive
  // (with its ghost levels, and their vtkGhostType) as for a reader.
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

int vtkDigitalIslandFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // The requested box grown by the reach of a small component
  // (dg::ComponentReach): what is beyond cannot change the result inside.
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  int whole[6], requested[6], grown[6];
  if (!dg::RequestedImageBox(inInfo, outputVector->GetInformationObject(0), whole, requested))
  {
    return 1;
  }
  dg::GrowExtent(requested, this->Reach(), whole, grown);
  dg::RequestImageBox(inInfo, grown);
  return 1;
}

int vtkDigitalIslandFilter::Reach() const
{
  return dg::ComponentReach(this->MinimumSize, this->RemoveIslands != 0, this->FillCavities != 0);
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
  // The input's box (the window labelled) and the requested one (the
  // output's): the whole image both, unless a piece or a sub-extent was
  // asked for.
  int ext[6], whole[6], out[6];
  input->GetExtent(ext);
  std::copy(ext, ext + 6, whole);
  std::copy(ext, ext + 6, out);
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  }
  if (outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), out);
  }
  if (dg::ExtentEmpty(out) && !dg::ExtentEmpty(whole))
  {
    // An empty piece (more pieces than voxels): nothing to do, no error.
    output->CopyStructure(input);
    output->SetExtent(out);
    return 1;
  }
  const int dims[3] = { ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1 };
  if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
  {
    vtkErrorMacro("Input image is empty (extent " << ext[0] << ".." << ext[1] << ", " << ext[2]
                                                  << ".." << ext[3] << ", " << ext[4] << ".."
                                                  << ext[5] << ").");
    return 0;
  }
  // Every voxel within the reach of the requested box must be there.
  int needed[6];
  dg::GrowExtent(out, this->Reach(), whole, needed);
  if (!dg::ExtentContains(ext, needed))
  {
    vtkErrorMacro("The input (extent " << ext[0] << ".." << ext[1] << ", " << ext[2] << ".."
                                       << ext[3] << ", " << ext[4] << ".." << ext[5]
                                       << ") does not hold the requested extent grown by "
                                       << this->Reach() << " voxels (" << needed[0] << ".."
                                       << needed[1] << ", " << needed[2] << ".." << needed[3]
                                       << ", " << needed[4] << ".." << needed[5] << ").");
    return 0;
  }
  // The input's faces inside the whole extent are open: the volume goes on
  // beyond them. Counts are of the requested box within CountedExtent;
  // outBox is the requested box in the window's indices.
  dg::ComponentWindow window;
  int outBox[6];
  bool countAll = true;
  for (int a = 0; a < 3; ++a)
  {
    // Ifs, not (c ? 1u : 0u) << n: GCC 12 at -O2 with the sanitizers lost
    // such bits in dg::ApplyNoise.
    if (ext[2 * a] > whole[2 * a])
      window.OpenFaces |= 1u << (2 * a);
    if (ext[2 * a + 1] < whole[2 * a + 1])
      window.OpenFaces |= 2u << (2 * a);
    outBox[2 * a] = out[2 * a] - ext[2 * a];
    outBox[2 * a + 1] = out[2 * a + 1] - ext[2 * a];
    window.Counted[2 * a] = std::max(out[2 * a], this->CountedExtent[2 * a]) - ext[2 * a];
    window.Counted[2 * a + 1] =
      std::min(out[2 * a + 1], this->CountedExtent[2 * a + 1]) - ext[2 * a];
    countAll = countAll && window.Counted[2 * a] == 0 && window.Counted[2 * a + 1] == dims[a] - 1;
  }
  if (dg::ExtentEmpty(window.Counted))
  {
    const int none[6] = { 0, -1, 0, -1, 0, -1 };
    std::copy(none, none + 6, window.Counted);
  }
  const bool sameBox = std::equal(out, out + 6, ext);
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
  if (!countAll)
  {
    insideCount = 0;
    ForRows(dims, window.Counted, [&](std::int64_t first, std::int64_t n) {
      insideCount += std::count(inside + first, inside + first + n, std::uint8_t(1));
    });
  }
  this->UpdateProgress(0.2);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }

  dg::IslandCounts counts;
  const bool done = dg::RemoveSmallComponents(inside, dims, this->MinimumSize,
    this->RemoveIslands != 0, this->FillCavities != 0, counts,
    [this](double f) {
      this->UpdateProgress(0.2 + 0.75 * f);
      return !this->GetAbortExecute();
    },
    &window);
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
  if (!sameBox)
  {
    // The requested box, row by row, out of the window.
    vtkNew<vtkUnsignedCharArray> box;
    box->SetName("Inside");
    box->SetNumberOfValues(static_cast<vtkIdType>(out[1] - out[0] + 1) * (out[3] - out[2] + 1) *
      (out[5] - out[4] + 1));
    std::uint8_t* dst = box->GetPointer(0);
    ForRows(dims, outBox, [&](std::int64_t first, std::int64_t n) {
      dst = std::copy(inside + first, inside + first + n, dst);
    });
    output->SetExtent(out);
    output->GetPointData()->SetScalars(box);
  }
  else
  {
    output->GetPointData()->SetScalars(values);
  }
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
  os << indent << "CountedExtent: " << this->CountedExtent[0] << " " << this->CountedExtent[1]
     << " " << this->CountedExtent[2] << " " << this->CountedExtent[3] << " "
     << this->CountedExtent[4] << " " << this->CountedExtent[5] << "\n";
  os << indent << "NumberOfRemovedIslands: " << this->NumberOfRemovedIslands << "\n";
  os << indent << "NumberOfFilledCavities: " << this->NumberOfFilledCavities << "\n";
  os << indent << "NumberOfChangedVoxels: " << this->NumberOfChangedVoxels << "\n";
}
