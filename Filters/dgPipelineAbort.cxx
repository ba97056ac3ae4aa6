#include "dgPipelineAbort.h"

#include <vtkDataObject.h>
#include <vtkInformation.h>
#include <vtkInformationIntegerKey.h>
#include <vtkInformationVector.h>

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
      f(data);
    }
  }
}
} // namespace

void PipelineAbort::Begin(vtkInformationVector* outputs)
{
  this->Aborted = false;
  ForEachOutput(outputs, [](vtkDataObject* d) { d->GetInformation()->Remove(ABORTED()); });
}

int PipelineAbort::Abort(vtkInformationVector* outputs)
{
  this->Aborted = true;
  ForEachOutput(outputs,
    [](vtkDataObject* d)
    {
      d->Initialize();
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
