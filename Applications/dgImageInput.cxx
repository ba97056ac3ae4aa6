#include "dgImageInput.h"

#include "vtkDGtalVolReader.h"
#include "vtkNIfTIVolumeReader.h"

#include <vtkCallbackCommand.h>
#include <vtkDICOMImageReader.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkMetaImageReader.h>
#include <vtkNew.h>
#include <vtkNrrdReader.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkStringOutputWindow.h>
#include <vtkXMLImageDataReader.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>

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

vtkSmartPointer<vtkImageData> ReadImage(const std::string& path, std::string& error, bool ras)
{
  ErrorSink sink;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(&ErrorSink::Callback);
  cb->SetClientData(&sink);
  vtkSmartPointer<vtkAlgorithm> reader;
  const std::string ext = Extension(path);
  if (IsDirectory(path))
  {
    auto dicom = vtkSmartPointer<vtkDICOMImageReader>::New();
    dicom->SetDirectoryName(path.c_str());
    reader = dicom;
  }
  else if (!IsFile(path))
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
    r->SetCoordinateSystem(ras ? vtkNIfTIVolumeReader::RAS : vtkNIfTIVolumeReader::LPS);
    reader = r;
  }
  else if (ext == "vti")
  {
    auto r = vtkSmartPointer<vtkXMLImageDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == "mha" || ext == "mhd")
  {
    auto r = vtkSmartPointer<vtkMetaImageReader>::New();
    if (!r->CanReadFile(path.c_str()))
    {
      error = "'" + path + "' is not a readable MetaImage file";
      return nullptr;
    }
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == "nrrd" || ext == "nhdr")
  {
    auto r = vtkSmartPointer<vtkNrrdReader>::New();
    if (!r->CanReadFile(path.c_str()))
    {
      error = "'" + path + "' is not a readable NRRD file";
      return nullptr;
    }
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == "dcm")
  {
    auto r = vtkSmartPointer<vtkDICOMImageReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  else
  {
    error = "unknown input format '" + (ext.empty() ? path : "." + ext) +
      "' (expected .vol, .vti, .nii, .nii.gz, .mha, .mhd, .nrrd, .nhdr, .dcm or a DICOM directory)";
    return nullptr;
  }
  reader->AddObserver(vtkCommand::ErrorEvent, cb);
  // vtkImageReader2 subclasses (NRRD, MetaImage raw) only *warn* when the
  // data is shorter than the header says, and return the partial volume.
  const bool warningsFail = !reader->IsA("vtkDICOMImageReader");
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
} // namespace dg
