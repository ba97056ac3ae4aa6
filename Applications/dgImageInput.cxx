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
#include <vtkXMLPImageDataReader.h>
#include <vtkInformation.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
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

// The header lines of a MetaImage or NRRD file (text up to the data; at most
// 64 KiB), lower-cased keys: what VTK's readers would silently drop.
std::vector<std::pair<std::string, std::string>> HeaderFields(const std::string& path, char separator)
{
  std::vector<std::pair<std::string, std::string>> fields;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t read = 0;
  while (read < 65536 && std::getline(in, line))
  {
    read += line.size() + 1;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    if (line.empty())
      break; // NRRD: the blank line before the data
    const auto at = line.find(separator);
    if (at == std::string::npos)
      continue;
    std::string key = line.substr(0, at), value = line.substr(at + 1);
    auto trim = [](std::string& t) {
      while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front())))
        t.erase(t.begin());
      while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back())))
        t.pop_back();
    };
    trim(key);
    trim(value);
    std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return std::tolower(c); });
    fields.emplace_back(key, value);
    if (key == "elementdatafile")
      break; // MetaImage: the data follow
  }
  return fields;
}

std::vector<double> Numbers(const std::string& text)
{
  std::vector<double> out;
  std::string t = text;
  for (char& c : t)
    if (c == '(' || c == ')' || c == ',')
      c = ' ';
  std::istringstream ss(t);
  double v;
  while (ss >> v)
    out.push_back(v);
  return out;
}

// Geometry that VTK's MetaImage and NRRD readers ignore: refused with a
// message rather than silently straightened (world coordinates would be
// wrong). Empty when the file's geometry is what the reader produces.
std::string UnsupportedGeometry(const std::string& path, bool nrrd)
{
  for (const auto& f : HeaderFields(path, nrrd ? ':' : '='))
  {
    if (!nrrd && (f.first == "transformmatrix" || f.first == "rotation" || f.first == "orientation"))
    {
      const auto m = Numbers(f.second);
      bool identity = m.size() == 9;
      for (std::size_t i = 0; identity && i < 9; ++i)
        identity = std::abs(m[i] - ((i % 4) == 0 ? 1.0 : 0.0)) < 1e-6;
      if (!identity)
        return "its " + f.first + " (" + f.second + ") turns or flips the voxel axes, which this reader "
          "would drop: convert the volume to NIfTI (.nii.gz) or .vti with its direction";
    }
    if (nrrd && f.first == "space directions")
    {
      const auto m = Numbers(f.second);
      bool diagonal = m.size() == 9;
      for (std::size_t i = 0; diagonal && i < 9; ++i)
        diagonal = (i % 4) == 0 ? m[i] > 0 : std::abs(m[i]) < 1e-9;
      if (!diagonal)
        return "its space directions (" + f.second + ") turn or flip the voxel axes, which this reader "
          "would drop: convert the volume to NIfTI (.nii.gz) or .vti with its direction";
    }
    if (nrrd && f.first == "space")
    {
      std::string v = f.second;
      std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
      if (v != "left-posterior-superior" && v != "lps")
        return "its space '" + f.second + "' is not LPS, the patient coordinates every other input "
          "is read in: convert the volume to NIfTI (.nii.gz) or .vti";
    }
  }
  return "";
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
vtkSmartPointer<vtkAlgorithm> MakeReader(const std::string& path, std::string& error, bool ras)
{
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
  else if (ext == "pvti")
  {
    // A parallel image: its pieces are read where the request needs them.
    auto r = vtkSmartPointer<vtkXMLPImageDataReader>::New();
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
    if (const std::string why = UnsupportedGeometry(path, false); !why.empty())
    {
      error = "cannot read '" + path + "': " + why;
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
    if (const std::string why = UnsupportedGeometry(path, true); !why.empty())
    {
      error = "cannot read '" + path + "': " + why;
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

vtkSmartPointer<vtkImageData> ReadImage(const std::string& path, std::string& error, bool ras)
{
  ErrorSink sink;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetCallback(&ErrorSink::Callback);
  cb->SetClientData(&sink);
  vtkSmartPointer<vtkAlgorithm> reader = MakeReader(path, error, ras);
  if (!reader)
  {
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

vtkSmartPointer<vtkAlgorithm> OpenImagePieces(const std::string& path, std::string& error, bool ras)
{
  error.clear();
  if (IsDirectory(path))
  {
    return nullptr; // DICOM series: read whole
  }
  if (Extension(path) == "dcm")
  {
    return nullptr; // VTK's DICOM reader gives the whole volume only
  }
  vtkSmartPointer<vtkAlgorithm> reader = MakeReader(path, error, ras);
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
