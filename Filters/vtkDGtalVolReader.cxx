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
  // Any sub-extent (a piece, with or without ghost layers): the whole file
  // is decoded and the box copied out (RequestData).
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
  dg::VolHeader header;
  std::vector<std::uint8_t> voxels;
  const auto progress = [this](double f) {
    this->UpdateProgress(0.05 + 0.75 * f);
    return !this->GetAbortExecute();
  };
  if (!this->FileName ||
    !dg::ReadVolFile(this->FileName, header, &voxels, this->LastError, progress))
  {
    if (this->GetAbortExecute())
    {
      this->LastError.clear();
      return this->Abort->Abort(outputVector);
    }
    if (!this->FileName)
    {
      this->LastError = "no FileName set";
    }
    vtkErrorMacro("Cannot read VOL file: " << this->LastError);
    output->Initialize();
    return 0;
  }
  this->UpdateProgress(0.8);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }
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
    this->LastError = "requested extent outside the file's extent (the file changed?)";
    vtkErrorMacro("Cannot read VOL file: " << this->LastError);
    output->Initialize();
    return 0;
  }
  const double s = header.VoxelSize;
  output->SetExtent(ext);
  output->SetSpacing(s, s, s);
  output->SetOrigin(0, 0, 0);
  vtkNew<vtkUnsignedCharArray> values;
  values->SetName("Value");
  if (dg::ExtentEmpty(ext))
  {
    values->SetNumberOfValues(0);
  }
  else if (std::equal(ext, ext + 6, whole))
  {
    values->SetNumberOfValues(static_cast<vtkIdType>(voxels.size()));
    std::memcpy(values->GetPointer(0), voxels.data(), voxels.size());
  }
  else
  {
    values->SetNumberOfValues(static_cast<vtkIdType>(ext[1] - ext[0] + 1) *
      (ext[3] - ext[2] + 1) * (ext[5] - ext[4] + 1));
    dg::CopyExtent(voxels.data(), whole, ext, 1, values->GetPointer(0));
  }
  output->GetPointData()->SetScalars(values);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkDGtalVolReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}
