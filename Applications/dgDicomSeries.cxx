#include "dgDicomSeries.h"
#include "dgDicomGeometry.h"
#include "dgImageHeader.h"
#include "dgImageInput.h"

#ifdef DG_HAVE_GDCM
#include <gdcmDirectory.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmPixelFormat.h>
#include <gdcmScanner.h>
#include <gdcmTag.h>
#include <gdcmTrace.h>
#endif

#include <vtkDataArray.h>
#include <vtkPointData.h>

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>
#include <vector>

namespace dg
{
#ifndef DG_HAVE_GDCM
bool HaveDicom()
{
  return false;
}

vtkSmartPointer<vtkImageData> ReadDicom(const std::string& path, const std::string&, std::string& error)
{
  error = "cannot read '" + path + "': this build of the program has no DICOM reader (GDCM was not "
    "found at configure time: install libgdcm-dev and configure again)";
  return nullptr;
}
#else
namespace
{
using Vec = std::array<double, 3>;

Vec Cross(const Vec& a, const Vec& b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

// A DICOM multi-valued decimal string ("1.5\\-2\\3") as numbers; nullptr or
// anything that does not parse gives fewer numbers than expected.
std::vector<double> Numbers(const char* text)
{
  return text ? ParseNumbers(text) : std::vector<double>();
}

std::string Trim(const char* text)
{
  std::string t = text ? text : "";
  while (!t.empty() && (t.back() == ' ' || t.back() == '\0'))
    t.pop_back();
  while (!t.empty() && t.front() == ' ')
    t.erase(t.begin());
  return t;
}

const gdcm::Tag TagSeriesUID(0x0020, 0x000e);
const gdcm::Tag TagPosition(0x0020, 0x0032);
const gdcm::Tag TagOrientation(0x0020, 0x0037);
const gdcm::Tag TagPixelSpacing(0x0028, 0x0030);
const gdcm::Tag TagSliceThickness(0x0018, 0x0050);
const gdcm::Tag TagSpacingBetweenSlices(0x0018, 0x0088);
const gdcm::Tag TagPixelData(0x7fe0, 0x0010);

struct Slice
{
  std::string File;
  Vec Position;
  double Along = 0; // position along the slice normal
};

int VTKType(gdcm::PixelFormat::ScalarType t)
{
  switch (t)
  {
    case gdcm::PixelFormat::UINT8: return VTK_UNSIGNED_CHAR;
    case gdcm::PixelFormat::INT8: return VTK_SIGNED_CHAR;
    case gdcm::PixelFormat::UINT12:
    case gdcm::PixelFormat::UINT16: return VTK_UNSIGNED_SHORT;
    case gdcm::PixelFormat::INT12:
    case gdcm::PixelFormat::INT16: return VTK_SHORT;
    case gdcm::PixelFormat::UINT32: return VTK_UNSIGNED_INT;
    case gdcm::PixelFormat::INT32: return VTK_INT;
    case gdcm::PixelFormat::FLOAT32: return VTK_FLOAT;
    case gdcm::PixelFormat::FLOAT64: return VTK_DOUBLE;
    default: return -1;
  }
}

// Rescaled values (RescaleSlope/Intercept other than 1/0): float voxels.
template <typename T>
void Rescale(const char* raw, std::size_t n, double slope, double intercept, float* out)
{
  const T* v = reinterpret_cast<const T*>(raw);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = static_cast<float>(slope * static_cast<double>(v[i]) + intercept);
}

bool RescaleSlice(int vtkType, const char* raw, std::size_t n, double slope, double intercept, float* out)
{
  switch (vtkType)
  {
    case VTK_UNSIGNED_CHAR: Rescale<unsigned char>(raw, n, slope, intercept, out); return true;
    case VTK_SIGNED_CHAR: Rescale<signed char>(raw, n, slope, intercept, out); return true;
    case VTK_UNSIGNED_SHORT: Rescale<unsigned short>(raw, n, slope, intercept, out); return true;
    case VTK_SHORT: Rescale<short>(raw, n, slope, intercept, out); return true;
    case VTK_UNSIGNED_INT: Rescale<unsigned int>(raw, n, slope, intercept, out); return true;
    case VTK_INT: Rescale<int>(raw, n, slope, intercept, out); return true;
    case VTK_FLOAT: Rescale<float>(raw, n, slope, intercept, out); return true;
    case VTK_DOUBLE: Rescale<double>(raw, n, slope, intercept, out); return true;
    default: return false;
  }
}

bool IsDirectory(const std::string& path)
{
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}
} // namespace

bool HaveDicom()
{
  return true;
}

vtkSmartPointer<vtkImageData> ReadDicom(const std::string& path, const std::string& seriesUID, std::string& error)
{
  gdcm::Trace::WarningOff();
  gdcm::Trace::ErrorOff();
  gdcm::Trace::DebugOff();
  const bool directory = IsDirectory(path);
  const std::string what = directory ? "DICOM series in '" + path + "'" : "'" + path + "'";
  auto fail = [&](const std::string& why) -> vtkSmartPointer<vtkImageData> {
    error = "cannot read " + what + ": " + why;
    return nullptr;
  };

  // 1. The files, their series and their geometry tags (headers only).
  gdcm::Directory::FilenamesType files;
  if (directory)
  {
    gdcm::Directory dir;
    dir.Load(path, false);
    files = dir.GetFilenames();
    std::sort(files.begin(), files.end());
  }
  else
  {
    files.push_back(path);
  }
  gdcm::Scanner scanner;
  for (const auto& t : { TagSeriesUID, TagPosition, TagOrientation, TagPixelSpacing, TagSliceThickness,
         TagSpacingBetweenSlices })
    scanner.AddTag(t);
  scanner.Scan(files);
  std::map<std::string, std::vector<std::string>> series; // UID -> files
  for (const auto& f : files)
  {
    if (!scanner.IsKey(f.c_str()))
      continue; // not DICOM
    series[Trim(scanner.GetValue(f.c_str(), TagSeriesUID))].push_back(f);
  }
  if (series.empty())
    return fail(directory ? "no DICOM file in the directory" : "not a DICOM file");
  auto list = [&]() {
    std::string s;
    for (const auto& [uid, fs] : series)
      s += (s.empty() ? "" : ", ") + (uid.empty() ? std::string("(no SeriesInstanceUID)") : uid) + " (" +
        std::to_string(fs.size()) + " files)";
    return s;
  };
  std::vector<std::string> chosen;
  if (!seriesUID.empty())
  {
    const auto it = series.find(seriesUID);
    if (it == series.end())
      return fail("no series " + seriesUID + " (found " + list() + ")");
    chosen = it->second;
  }
  else if (series.size() > 1)
  {
    return fail("it holds " + std::to_string(series.size()) + " series: " + list() +
      "; choose one with --dicom-series UID");
  }
  else
  {
    chosen = series.begin()->second;
  }

  // 2. Geometry: one orientation, positions along the slice normal
  // (dgDicomGeometry.h).
  std::vector<DicomSliceTags> tags;
  for (const std::string& f : chosen)
  {
    auto value = [&](const gdcm::Tag& t) {
      const char* v = scanner.GetValue(f.c_str(), t);
      return std::string(v ? v : "");
    };
    tags.push_back({ f, value(TagPosition), value(TagOrientation), value(TagPixelSpacing) });
  }
  DicomStack stack;
  std::string why;
  if (!OrderDicomSlices(tags, stack, why))
    return fail(why);
  const Vec row = stack.Row, col = stack.Column, normal = stack.Normal;
  const double* pixelSpacing = stack.PixelSpacing;
  std::vector<Slice> slices;
  for (std::size_t s = 0; s < stack.Files.size(); ++s)
    slices.push_back({ stack.Files[s], stack.Positions[s], stack.Along[s] });

  // 3. The voxels, slice by slice in that order.
  const std::size_t nSlices = slices.size();
  unsigned int dims[3] = { 0, 0, 0 };
  int type = -1;
  std::vector<std::vector<char>> buffers(nSlices);
  std::vector<std::pair<double, double>> rescale(nSlices);
  double frameGeometry[15] = {}; // a single multi-frame file: GDCM's origin, cosines, spacing
  for (std::size_t s = 0; s < nSlices; ++s)
  {
    gdcm::ImageReader reader;
    reader.SetFileName(slices[s].File.c_str());
    if (!reader.Read())
      return fail("'" + DicomFileName(slices[s].File) + "' has no image GDCM can read");
    const gdcm::Image& image = reader.GetImage();
    const unsigned int* d = image.GetDimensions();
    const unsigned int depth = image.GetNumberOfDimensions() > 2 ? d[2] : 1;
    if (depth != 1 && nSlices > 1)
      return fail("'" + DicomFileName(slices[s].File) + "' is a multi-frame image inside a series of single slices");
    const gdcm::PixelFormat pf = image.GetPixelFormat();
    if (pf.GetSamplesPerPixel() != 1)
      return fail("'" + DicomFileName(slices[s].File) + "' has " + std::to_string(pf.GetSamplesPerPixel()) +
        " samples per pixel (colour): a segmented volume needs one");
    const int t = VTKType(pf.GetScalarType());
    if (t < 0)
      return fail("'" + DicomFileName(slices[s].File) + "' has an unsupported pixel format (BitsAllocated " +
        std::to_string(pf.GetBitsAllocated()) + ")");
    if (s == 0)
    {
      dims[0] = d[0];
      dims[1] = d[1];
      dims[2] = depth;
      type = t;
      if (depth > 1)
      {
        std::copy(image.GetOrigin(), image.GetOrigin() + 3, frameGeometry);
        std::copy(image.GetDirectionCosines(), image.GetDirectionCosines() + 6, frameGeometry + 3);
        std::copy(image.GetSpacing(), image.GetSpacing() + 3, frameGeometry + 9);
      }
    }
    else if (d[0] != dims[0] || d[1] != dims[1])
      return fail("'" + DicomFileName(slices[s].File) + "' has " + std::to_string(d[0]) + " x " + std::to_string(d[1]) +
        " pixels, '" + DicomFileName(slices[0].File) + "' " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]));
    else if (t != type)
      return fail("'" + DicomFileName(slices[s].File) + "' has another pixel type than '" + DicomFileName(slices[0].File) + "'");
    const std::size_t bytes = static_cast<std::size_t>(d[0]) * d[1] * depth * pf.GetPixelSize();
    if (image.GetBufferLength() != bytes)
      return fail("'" + DicomFileName(slices[s].File) + "' has " + std::to_string(image.GetBufferLength()) +
        " bytes of pixel data, " + std::to_string(bytes) + " expected");
    buffers[s].resize(bytes);
    if (!image.GetBuffer(buffers[s].data()))
      return fail("'" + DicomFileName(slices[s].File) + "': its pixel data cannot be decoded");
    rescale[s] = { image.GetSlope(), image.GetIntercept() };
  }

  // 4. Slice spacing: uniform, along the normal, or refused.
  double spacing[3] = { pixelSpacing[1], pixelSpacing[0], 1.0 };
  Vec origin = slices[0].Position;
  double direction[9];
  for (int a = 0; a < 3; ++a)
  {
    direction[3 * a + 0] = row[a];
    direction[3 * a + 1] = col[a];
    direction[3 * a + 2] = normal[a];
  }
  if (dims[2] > 1)
  {
    // One multi-frame file: GDCM's geometry (its frames' positions).
    const double* g = frameGeometry;
    origin = { g[0], g[1], g[2] };
    Vec r{ g[3], g[4], g[5] }, c{ g[6], g[7], g[8] };
    Vec n = Cross(r, c);
    for (int a = 0; a < 3; ++a)
    {
      direction[3 * a + 0] = r[a];
      direction[3 * a + 1] = c[a];
      direction[3 * a + 2] = n[a];
    }
    spacing[0] = g[9];
    spacing[1] = g[10];
    spacing[2] = g[11];
  }
  else if (nSlices > 1)
  {
    double step = 1;
    if (!UniformDicomStep(stack, step, why))
      return fail(why);
    spacing[2] = step;
  }
  else
  {
    // One slice: its thickness, if any.
    const auto between = Numbers(scanner.GetValue(slices[0].File.c_str(), TagSpacingBetweenSlices));
    const auto thick = Numbers(scanner.GetValue(slices[0].File.c_str(), TagSliceThickness));
    if (between.size() == 1 && between[0] > 0)
      spacing[2] = between[0];
    else if (thick.size() == 1 && thick[0] > 0)
      spacing[2] = thick[0];
  }

  // 5. The image: raw values, or rescaled to float when a slice has a
  // RescaleSlope/Intercept other than 1/0.
  bool rescaled = false;
  for (const auto& r : rescale)
    rescaled = rescaled || r.first != 1 || r.second != 0;
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->SetDimensions(static_cast<int>(dims[0]), static_cast<int>(dims[1]),
    static_cast<int>(dims[2] > 1 ? dims[2] : nSlices));
  out->SetOrigin(origin[0], origin[1], origin[2]);
  out->SetSpacing(spacing);
  out->SetDirectionMatrix(direction);
  out->AllocateScalars(rescaled ? VTK_FLOAT : type, 1);
  vtkDataArray* scalars = out->GetPointData()->GetScalars();
  scalars->SetName("DICOM");
  char* dst = static_cast<char*>(scalars->GetVoidPointer(0));
  std::size_t offset = 0;
  for (std::size_t s = 0; s < nSlices; ++s)
  {
    const std::size_t bytes = buffers[s].size();
    if (rescaled)
    {
      const std::size_t n = bytes / static_cast<std::size_t>(vtkDataArray::GetDataTypeSize(type));
      RescaleSlice(type, buffers[s].data(), n, rescale[s].first, rescale[s].second,
        reinterpret_cast<float*>(dst) + offset);
      offset += n;
    }
    else
    {
      std::memcpy(dst + offset, buffers[s].data(), bytes);
      offset += bytes;
    }
    std::vector<char>().swap(buffers[s]);
  }
  return out;
}
#endif
} // namespace dg
