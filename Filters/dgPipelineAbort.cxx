#include "dgPipelineAbort.h"

#include <vtkAlgorithm.h>
#include <vtkDataObject.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationIntegerKey.h>
#include <vtkInformationVector.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <algorithm>

namespace dg
{

vtkInformationIntegerKey* PipelineAbort::ABORTED()
{
  // Never deleted: keys live as long as the process (as VTK's own do).
  static vtkInformationIntegerKey* key =
    new vtkInformationIntegerKey("DG_ABORTED", "vtkDigitalGeometry");
  return key;
}

namespace
{
template<typename F>
void ForEachOutput(vtkInformationVector* outputs, F f)
{
  for (int i = 0; outputs && i < outputs->GetNumberOfInformationObjects(); ++i)
  {
    vtkInformation* info = outputs->GetInformationObject(i);
    if (vtkDataObject* data = info ? info->Get(vtkDataObject::DATA_OBJECT()) : nullptr)
    {
      f(info, data);
    }
  }
}
} // namespace

PipelineAbort::Guard::~Guard()
{
  if (this->Algorithm)
  {
    this->Algorithm->SetAbortExecute(0);
  }
}

PipelineAbort::Guard PipelineAbort::Begin(vtkAlgorithm* algorithm, vtkInformationVector* outputs)
{
  this->Aborted = false;
  ForEachOutput(outputs, [](vtkInformation*, vtkDataObject* d) {
    d->GetInformation()->Remove(ABORTED());
  });
  return Guard(algorithm);
}

int PipelineAbort::Abort(vtkInformationVector* outputs)
{
  this->Aborted = true;
  ForEachOutput(outputs, [](vtkInformation* info, vtkDataObject* d) {
    d->Initialize();
    vtkImageData* image = vtkImageData::SafeDownCast(d);
    if (image && info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
    {
      image->SetExtent(info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()));
    }
    d->GetInformation()->Set(ABORTED(), 1);
  });
  return 1;
}

bool PipelineAbort::InputAborted(vtkInformationVector** inputs, int numberOfPorts)
{
  for (int p = 0; inputs && p < numberOfPorts; ++p)
  {
    for (int c = 0; inputs[p] && c < inputs[p]->GetNumberOfInformationObjects(); ++c)
    {
      vtkInformation* info = inputs[p]->GetInformationObject(c);
      vtkDataObject* data = info ? info->Get(vtkDataObject::DATA_OBJECT()) : nullptr;
      if (data && data->GetInformation()->Has(ABORTED()))
      {
        return true;
      }
    }
  }
  return false;
}

vtkMTimeType PipelineAbort::MTime(vtkMTimeType base) const
{
  if (!this->Aborted)
  {
    return base;
  }
  this->Stamp.Modified();
  return std::max(base, this->Stamp.GetMTime());
}

} // namespace dg
