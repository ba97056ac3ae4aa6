#include "dgImageInput.h"
#include "dgDicomSeries.h"

#include "vtkDGtalVolReader.h"
#include "vtkNIfTIVolumeReader.h"

#include <vtkCallbackCommand.h>
#include <vtkMatrix3x3.h>
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


// The geometry of a MetaImage or NRRD header, which VTK's readers drop
// (TransformMatrix, space directions, space): world = Origin + Direction ·
// diag(Spacing) · index, in LPS (RAS when asked).
struct HeaderGeometry
{
  bool Has = false; // false: keep what VTK's reader gives (axis-aligned)
  double Origin[3] = { 0, 0, 0 };
  double Spacing[3] = { 1, 1, 1 };
  double Direction[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }; // row-major
};

std::string Lower(std::string v)
{
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  return v;
}

std::string Fmt(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// Direction and spacing from three axis vectors (columns): normalised
// columns, their lengths; refused when one is zero or two are not at right
// angles (a shear, which origin + direction + spacing cannot carry).
std::string FromColumns(const double columns[3][3], const char* name, HeaderGeometry& g)
{
  double unit[3][3];
  for (int a = 0; a < 3; ++a)
  {
    const double len = std::sqrt(columns[a][0] * columns[a][0] + columns[a][1] * columns[a][1] +
      columns[a][2] * columns[a][2]);
    if (!(len > 0) || !std::isfinite(len))
      return std::string("its ") + name + " give axis " + std::to_string(a) + " no length";
    for (int r = 0; r < 3; ++r)
      unit[a][r] = columns[a][r] / len;
    g.Spacing[a] *= len;
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
    {
      const double c = unit[a][0] * unit[b][0] + unit[a][1] * unit[b][1] + unit[a][2] * unit[b][2];
      if (std::abs(c) > 1e-4)
        return std::string("its ") + name + " are sheared: axes " + std::to_string(a) + " and " +
          std::to_string(b) + " at " + Fmt(std::acos(std::max(-1.0, std::min(1.0, c))) * 180 / M_PI) +
          " degrees, not 90 (origin, spacing and direction cannot carry a shear)";
    }
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a)
      g.Direction[3 * r + a] = unit[a][r];
  g.Has = true;
  return "";
}

// Empty on success, else the problem (one line, without the file's name).
std::string ReadHeaderGeometry(const std::string& path, bool nrrd, bool ras, HeaderGeometry& g)
{
  const auto fields = HeaderFields(path, nrrd ? ':' : '=');
  auto field = [&](std::initializer_list<const char*> keys) -> const std::string* {
    for (const char* k : keys)
      for (const auto& f : fields)
        if (f.first == k)
          return &f.second;
    return nullptr;
  };
  // The patient space the header is written in, as a flip of LPS.
  double flip[3] = { 1, 1, 1 };
  double columns[3][3];
  if (!nrrd)
  {
    const std::string* ndims = field({ "ndims" });
    if (!ndims || ParseNumbers(*ndims) != std::vector<double>{ 3 })
      return ""; // 2-D or 4-D: VTK's reader, as before
    if (const std::string* o = field({ "offset", "origin", "position" }))
    {
      const auto v = ParseNumbers(*o);
      if (v.size() != 3)
        return "its Offset (" + *o + ") is not three numbers";
      std::copy(v.begin(), v.end(), g.Origin);
    }
    if (const std::string* sp = field({ "elementspacing", "elementsize" }))
    {
      const auto v = ParseNumbers(*sp);
      if (v.size() != 3)
        return "its ElementSpacing (" + *sp + ") is not three numbers";
      std::copy(v.begin(), v.end(), g.Spacing);
    }
    double m[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    if (const std::string* t = field({ "transformmatrix", "rotation", "orientation" }))
    {
      const auto v = ParseNumbers(*t);
      if (v.size() != 9)
        return "its TransformMatrix (" + *t + ") is not nine numbers";
      std::copy(v.begin(), v.end(), m);
    }
    // ITK's MetaImageIO: the i-th triple is the direction of axis i.
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r)
        columns[a][r] = m[3 * a + r];
    if (std::string why = FromColumns(columns, "TransformMatrix columns", g); !why.empty())
      return why;
  }
  else
  {
    if (const std::string* space = field({ "space" }))
    {
      const std::string v = Lower(*space);
      if (v == "left-posterior-superior" || v == "lps")
        ;
      else if (v == "right-anterior-superior" || v == "ras")
        flip[0] = flip[1] = -1;
      else if (v == "left-anterior-superior" || v == "las")
        flip[1] = -1;
      else
        return "its space '" + *space + "' is not a patient space this reader converts to LPS "
          "(left-posterior-superior, right-anterior-superior, left-anterior-superior)";
    }
    const std::string* dirs = field({ "space directions" });
    if (!dirs)
      return ""; // axis-aligned (spacings): VTK's reader, as before
    std::vector<std::vector<double>> vectors;
    for (std::size_t at = dirs->find('('); at != std::string::npos; at = dirs->find('(', at + 1))
    {
      const auto close = dirs->find(')', at);
      if (close == std::string::npos)
        return "its space directions (" + *dirs + ") are not 3-vectors in parentheses";
      vectors.push_back(ParseNumbers(dirs->substr(at + 1, close - at - 1)));
    }
    if (vectors.size() != 3 || std::any_of(vectors.begin(), vectors.end(), [](const auto& v) { return v.size() != 3; }))
      return "its space directions (" + *dirs + ") are not three 3-vectors";
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r)
        columns[a][r] = flip[r] * vectors[a][r];
    if (const std::string* o = field({ "space origin" }))
    {
      const auto v = ParseNumbers(*o);
      if (v.size() != 3)
        return "its space origin (" + *o + ") is not a 3-vector";
      for (int r = 0; r < 3; ++r)
        g.Origin[r] = flip[r] * v[r];
    }
    if (std::string why = FromColumns(columns, "space directions", g); !why.empty())
      return why;
  }
  if (ras)
  {
    for (int r = 0; r < 2; ++r)
    {
      g.Origin[r] = -g.Origin[r];
      for (int a = 0; a < 3; ++a)
        g.Direction[3 * r + a] = -g.Direction[3 * r + a];
    }
  }
  return "";
}

// VTK's MetaImage or NRRD reader with the header's geometry put on its
// output, in the pipeline information too, so that sub-extents (pieces)
// keep it.
template <class Base>
class OrientedReader : public Base
{
public:
  static OrientedReader* New()
  {
    auto* r = new OrientedReader;
    r->InitializeObjectBase();
    return r;
  }
  HeaderGeometry Geometry;

protected:
  int RequestInformation(vtkInformation* request, vtkInformationVector** in, vtkInformationVector* out) override
  {
    const int ok = Base::RequestInformation(request, in, out);
    if (ok && this->Geometry.Has)
    {
      vtkInformation* info = out->GetInformationObject(0);
      info->Set(vtkDataObject::ORIGIN(), this->Geometry.Origin, 3);
      info->Set(vtkDataObject::SPACING(), this->Geometry.Spacing, 3);
      info->Set(vtkDataObject::DIRECTION(), this->Geometry.Direction, 9);
    }
    return ok;
  }
  int RequestData(vtkInformation* request, vtkInformationVector** in, vtkInformationVector* out) override
  {
    const int ok = Base::RequestData(request, in, out);
    if (this->Geometry.Has)
    {
      if (auto* image = vtkImageData::GetData(out))
      {
        image->SetOrigin(this->Geometry.Origin);
        image->SetSpacing(this->Geometry.Spacing);
        image->SetDirectionMatrix(this->Geometry.Direction);
      }
    }
    return ok;
  }
};
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
  else if (ext == "mha" || ext == "mhd")
  {
    auto r = vtkSmartPointer<OrientedReader<vtkMetaImageReader>>::New();
    if (!r->CanReadFile(path.c_str()))
    {
      error = "'" + path + "' is not a readable MetaImage file";
      return nullptr;
    }
    if (const std::string why = ReadHeaderGeometry(path, false, options.Ras, r->Geometry); !why.empty())
    {
      error = "cannot read '" + path + "': " + why;
      return nullptr;
    }
    r->SetFileName(path.c_str());
    reader = r;
  }
  else if (ext == "nrrd" || ext == "nhdr")
  {
    auto r = vtkSmartPointer<OrientedReader<vtkNrrdReader>>::New();
    if (!r->CanReadFile(path.c_str()))
    {
      error = "'" + path + "' is not a readable NRRD file";
      return nullptr;
    }
    if (const std::string why = ReadHeaderGeometry(path, true, options.Ras, r->Geometry); !why.empty())
    {
      error = "cannot read '" + path + "': " + why;
      return nullptr;
    }
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

std::vector<double> ParseNumbers(const std::string& text)
{
  std::vector<double> out;
  std::string t = text;
  for (char& c : t)
    if (c == '(' || c == ')' || c == ',' || c == '\\')
      c = ' ';
  std::istringstream ss(t);
  double v;
  while (ss >> v)
    out.push_back(v);
  return out;
}

} // namespace dg
