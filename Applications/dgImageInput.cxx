#include "dgImageInput.h"
#include "dgDicomSeries.h"
#include "dgImageHeader.h"

#include "vtkDGtalVolReader.h"
#include "vtkNIfTIVolumeReader.h"
#include "vtkOrientedImageReader.h"

#include <vtkCallbackCommand.h>
#include <vtkMatrix3x3.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkStringOutputWindow.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPImageDataReader.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

namespace dg
{
namespace
{
struct ErrorSink
{
  bool Failed = false;
  std::string Message;
  static void Callback(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* self = static_cast<ErrorSink*>(clientData);
    self->Failed = true;
    if (callData && self->Message.empty())
    {
      std::string m = static_cast<const char*>(callData);
      // VTK's messages carry a "file, line" prefix and a trailing newline:
      // keep the last line of text, which says what went wrong.
      while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
      {
        m.pop_back();
      }
      const auto nl = m.find_last_of('\n');
      self->Message = nl == std::string::npos ? m : m.substr(nl + 1);
    }
  }
};

bool IsDirectory(const std::string& path)
{
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool IsFile(const std::string& path)
{
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

} // namespace

std::string Extension(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
  {
    return "";
  }
  std::string e = path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

namespace
{
// The reader for path, configured but not run; nullptr with error set when
// the file cannot be one of ours.
vtkSmartPointer<vtkAlgorithm> MakeReader(const std::string& path, std::string& error, const ReadOptions& options)
{
  vtkSmartPointer<vtkAlgorithm> reader;
  const std::string ext = Extension(path);
  if (!IsFile(path))
  {
    error = "cannot open '" + path + "': no such file";
    return nullptr;
  }
  else if (ext == "vol")
  {
    auto r = vtkSmartPointer<vtkDGtalVolReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == "nii" || (ext == "gz" && path.size() > 7 &&
             Extension(path.substr(0, path.size() - 3)) == "nii"))
  {
    auto r = vtkSmartPointer<vtkNIfTIVolumeReader>::New();
    if (!r->CanReadFile(path.c_str()))
    {
      error = "'" + path + "' is not a readable NIfTI file";
      return nullptr;
    }
    r->SetFileName(path.c_str());
    r->SetCoordinateSystem(options.Ras ? vtkNIfTIVolumeReader::RAS : vtkNIfTIVolumeReader::LPS);
    reader = r;
  }
  else if (ext == "vti")
  {
    auto r = vtkSmartPointer<vtkXMLImageDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == "pvti")
  {
    // A parallel image: its pieces are read where the request needs them.
    auto r = vtkSmartPointer<vtkXMLPImageDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == "mha" || ext == "mhd" || ext == "nrrd" || ext == "nhdr")
  {
    // The module's reader: VTK's MetaImage or NRRD reader with the header's
    // orientation put on the image. The header is checked here first so
    // that the program's message names the file once.
    const bool nrrd = ext == "nrrd" || ext == "nhdr";
    auto r = vtkSmartPointer<vtkOrientedImageReader>::New();
    if (!r->CanReadFile(path.c_str()))
    {
      error = "'" + path + "' is not a readable " + (nrrd ? "NRRD" : "MetaImage") + " file";
      return nullptr;
    }
    HeaderGeometry g;
    if (const std::string why = ReadHeaderGeometry(path, nrrd, options.Ras, g); !why.empty())
    {
      error = "cannot read '" + path + "': " + why;
      return nullptr;
    }
    r->SetFileName(path.c_str());
    r->SetCoordinateSystem(options.Ras ? vtkOrientedImageReader::RAS : vtkOrientedImageReader::LPS);
    reader = r;
  }
  else
  {
    error = "unknown input format '" + (ext.empty() ? path : "." + ext) +
      "' (expected .vol, .vti, .pvti, .nii, .nii.gz, .mha, .mhd, .nrrd, .nhdr, .dcm or a DICOM directory)";
    return nullptr;
  }
  return reader;
}

// The last line of VTK's report (it carries a "file, line" prefix and a
// trailing newline): what went wrong.
std::string LastLine(std::string m)
{
  while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
  {
    m.pop_back();
  }
  const auto nl = m.find_last_of('\n');
  return nl == std::string::npos ? m : m.substr(nl + 1);
}
} // namespace

vtkSmartPointer<vtkImageData> ReadImage(const std::string& path, std::string& error, const ReadOptions& options)
{
  if (IsDirectory(path) || Extension(path) == "dcm")
  {
    // DICOM: GDCM, the whole series at once.
    vtkSmartPointer<vtkImageData> image = ReadDicom(path, options.DicomSeries, error);
    if (image && options.Ras)
    {
      double o[3];
      image->GetOrigin(o);
      const double* d = image->GetDirectionMatrix()->GetData();
      const double f[9] = { -d[0], -d[1], -d[2], -d[3], -d[4], -d[5], d[6], d[7], d[8] };
      image->SetOrigin(-o[0], -o[1], o[2]);
      image->SetDirectionMatrix(f);
    }
    return image;
  }
  ErrorSink sink;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(&ErrorSink::Callback);
  cb->SetClientData(&sink);
  vtkSmartPointer<vtkAlgorithm> reader = MakeReader(path, error, options);
  if (!reader)
  {
    return nullptr;
  }
  reader->AddObserver(vtkCommand::ErrorEvent, cb);
  // vtkImageReader2 subclasses (NRRD, MetaImage raw) only *warn* when the
  // data is shorter than the header says, and return the partial volume.
  const bool warningsFail = true;
  if (warningsFail)
  {
    reader->AddObserver(vtkCommand::WarningEvent, cb);
  }
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, cb);
  // Some readers report short reads with vtkGenericWarningMacro, which no
  // observer sees: collect the output window's text during the read.
  vtkSmartPointer<vtkOutputWindow> previous = vtkOutputWindow::GetInstance();
  vtkNew<vtkStringOutputWindow> collected;
  vtkOutputWindow::SetInstance(collected);
  reader->Update();
  vtkOutputWindow::SetInstance(previous);
  if (warningsFail && !collected->GetOutput().empty())
  {
    sink.Failed = true;
    if (sink.Message.empty())
    {
      std::string m = collected->GetOutput();
      while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
      {
        m.pop_back();
      }
      const auto nl = m.find_last_of('\n');
      sink.Message = nl == std::string::npos ? m : m.substr(nl + 1);
      if (m.find("File operation failed") != std::string::npos)
      {
        sink.Message = "file is shorter than its header says (truncated)";
      }
    }
  }
  if (auto* vol = vtkDGtalVolReader::SafeDownCast(reader))
  {
    if (sink.Failed)
    {
      error = vol->GetErrorMessage();
      return nullptr;
    }
  }
  vtkImageData* image = vtkImageData::SafeDownCast(reader->GetOutputDataObject(0));
  if (sink.Failed)
  {
    error = "cannot read '" + path + "': " + (sink.Message.empty() ? "reader error" : sink.Message);
    return nullptr;
  }
  if (!image)
  {
    error = "cannot read '" + path + "': not an image";
    return nullptr;
  }
  int dims[3];
  image->GetDimensions(dims);
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  const long long n = static_cast<long long>(dims[0]) * dims[1] * dims[2];
  if (n <= 0 || !scalars || scalars->GetNumberOfTuples() != n)
  {
    error = "cannot read '" + path + "': no voxel data (truncated or corrupt file?)";
    return nullptr;
  }
  auto result = vtkSmartPointer<vtkImageData>::New();
  result->ShallowCopy(image);
  return result;
}

vtkSmartPointer<vtkAlgorithm> OpenImagePieces(const std::string& path, std::string& error, const ReadOptions& options)
{
  error.clear();
  if (IsDirectory(path))
  {
    return nullptr; // DICOM series: read whole
  }
  if (Extension(path) == "dcm")
  {
    return nullptr; // DICOM file: read whole
  }
  vtkSmartPointer<vtkAlgorithm> reader = MakeReader(path, error, options);
  if (!reader)
  {
    return nullptr;
  }
  // The header alone: geometry, whole extent, and whether the reader can
  // give a sub-extent (vtkDGtalVolReader may not, in older builds).
  ErrorSink sink;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(&ErrorSink::Callback);
  cb->SetClientData(&sink);
  reader->AddObserver(vtkCommand::ErrorEvent, cb);
  reader->AddObserver(vtkCommand::WarningEvent, cb);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, cb);
  vtkSmartPointer<vtkOutputWindow> previous = vtkOutputWindow::GetInstance();
  vtkNew<vtkStringOutputWindow> collected;
  vtkOutputWindow::SetInstance(collected);
  reader->UpdateInformation();
  vtkOutputWindow::SetInstance(previous);
  reader->RemoveObserver(cb);
  reader->GetExecutive()->RemoveObserver(cb);
  if (auto* vol = vtkDGtalVolReader::SafeDownCast(reader))
  {
    if (sink.Failed)
    {
      error = vol->GetErrorMessage();
      return nullptr;
    }
  }
  if (sink.Failed || !collected->GetOutput().empty())
  {
    const std::string m = sink.Message.empty() ? LastLine(collected->GetOutput()) : sink.Message;
    error = "cannot read '" + path + "': " + (m.empty() ? "reader error" : m);
    return nullptr;
  }
  vtkInformation* info = reader->GetOutputInformation(0);
  if (!info || !info->Get(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT()) ||
    !info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    return nullptr; // this reader gives the whole volume only
  }
  return reader;
}

bool CheckImagePiece(vtkAlgorithm* reader, const std::string& path, std::string& error)
{
  vtkImageData* image = vtkImageData::SafeDownCast(reader->GetOutputDataObject(0));
  if (!image)
  {
    error = "cannot read '" + path + "': not an image";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  const long long n = static_cast<long long>(dims[0]) * dims[1] * dims[2];
  if (n <= 0)
  {
    return true; // nothing was asked of this reader
  }
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  if (!scalars || scalars->GetNumberOfTuples() != n)
  {
    error = "cannot read '" + path + "': no voxel data (truncated or corrupt file?)";
    return false;
  }
  return true;
}

} // namespace dg
