#include "vtkDGtalVolReader.h"

#include "dgPieces.h"
#include "dgPipelineAbort.h"
#include "dgVolFormat.h"

#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cstring>
#include <fstream>

vtkStandardNewMacro(vtkDGtalVolReader);

namespace
{
// The header is read from the first bytes only (RequestInformation must not
// decode the whole volume).
bool ReadHeader(const char* fname, dg::VolHeader& header, std::string& error)
{
  if (!fname || !*fname)
  {
    error = "no FileName set";
    return false;
  }
  std::ifstream in(fname, std::ios::binary);
  if (!in)
  {
    error = std::string("cannot open '") + fname + "'";
    return false;
  }
  std::vector<std::uint8_t> head(64 * 1024);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (!dg::ParseVol(head.data(), head.size(), header, nullptr, error))
  {
    error = std::string(fname) + ": " + error;
    return false;
  }
  return true;
}
} // namespace

vtkDGtalVolReader::vtkDGtalVolReader()
{
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetNumberOfInputPorts(0);
}

vtkDGtalVolReader::~vtkDGtalVolReader()
{
  this->SetFileName(nullptr);
}

int vtkDGtalVolReader::CanReadFile(const char* fname)
{
  dg::VolHeader header;
  std::string error;
  return ReadHeader(fname, header, error) ? 1 : 0;
}

int vtkDGtalVolReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  dg::VolHeader header;
  this->LastError.clear();
  if (!ReadHeader(this->FileName, header, this->LastError))
  {
    vtkErrorMacro("Cannot read VOL file: " << this->LastError);
    return 0;
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  int ext[6] = { 0, header.Dims[0] - 1, 0, header.Dims[1] - 1, 0, header.Dims[2] - 1 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), ext, 6);
  const double s = header.VoxelSize;
  double spacing[3] = { s, s, s };
  double origin[3] = { 0, 0, 0 };
  outInfo->Set(vtkDataObject::SPACING(), spacing, 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(outInfo, VTK_UNSIGNED_CHAR, 1);
  // Any sub-extent (a piece, with or without ghost layers): RequestData
  // reads only the box's voxels into the output (dg::VolStream).
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

vtkMTimeType vtkDGtalVolReader::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkDGtalVolReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const auto abortGuard = this->Abort->Begin(this, outputVector);
  this->LastError.clear();
  const auto fail = [&](const std::string& why) {
    this->LastError = why;
    vtkErrorMacro("Cannot read VOL file: " << this->LastError);
    output->Initialize();
    return 0;
  };
  if (!this->FileName)
  {
    return fail("no FileName set");
  }
  // The header first (RequestInformation read it too, but the file may have
  // changed since): it fixes the whole extent and refuses a data size that
  // cannot match before anything is allocated.
  dg::VolStream vol;
  std::string error;
  if (!vol.Open(this->FileName, error))
  {
    return fail(std::string(this->FileName) + ": " + error);
  }
  const dg::VolHeader& header = vol.Header();
  // The requested box (the whole volume unless a piece or a sub-extent was
  // asked for); the executive keeps it inside the whole extent.
  const int whole[6] = { 0, header.Dims[0] - 1, 0, header.Dims[1] - 1, 0, header.Dims[2] - 1 };
  int ext[6];
  std::copy(whole, whole + 6, ext);
  if (outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
  }
  if (!dg::ExtentEmpty(ext) && !dg::ExtentContains(whole, ext))
  {
    return fail("requested extent outside the file's extent (the file changed?)");
  }
  // Only the box is allocated; the voxels are read straight into it (a
  // Version 3 stream through a bounded window): a piece holds its own
  // voxels, never the whole volume, and a whole read holds one copy.
  vtkNew<vtkUnsignedCharArray> values;
  values->SetName("Value");
  values->SetNumberOfValues(dg::ExtentEmpty(ext)
      ? 0
      : static_cast<vtkIdType>(ext[1] - ext[0] + 1) * (ext[3] - ext[2] + 1) * (ext[5] - ext[4] + 1));
  const auto progress = [this](double f) {
    this->UpdateProgress(0.05 + 0.9 * f);
    return !this->GetAbortExecute();
  };
  if (!vol.ReadBox(ext, values->GetPointer(0), error, progress))
  {
    if (this->GetAbortExecute())
    {
      return this->Abort->Abort(outputVector);
    }
    return fail(std::string(this->FileName) + ": " + error);
  }
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }
  const double s = header.VoxelSize;
  output->SetExtent(ext);
  output->SetSpacing(s, s, s);
  output->SetOrigin(0, 0, 0);
  output->GetPointData()->SetScalars(values);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkDGtalVolReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}
