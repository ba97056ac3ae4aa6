// libFuzzer target: the program's DICOM series reader
// (Applications/dgDicomSeries.cxx, dg::ReadDicom): GDCM parses the files,
// the module's own code orders the slices along their normal, checks one
// orientation, PixelSpacing and uniform spacing, and builds origin,
// spacing and direction from ImagePositionPatient / ImageOrientationPatient
// (ParseNumbers on backslash-separated decimal strings).
//
// Input: up to 4 files separated by the 8 bytes "DGSLICE!", written to a
// per-process temporary directory that ReadDicom reads as one series.
//
// Not in scripts/fuzz.sh's default run (DG_FUZZ_DICOM=1 adds it): GDCM
// 3.0.21 (Debian, assertions on) aborts on corrupt file meta headers
// (assert in gdcm::ReadExplicitDataElement from FileMetaInformation::Read,
// under gdcm::Scanner::Scan) within seconds, and some inputs take GDCM
// ~10 s; neither is this module's code, and ReadDicom cannot guard it
// short of parsing DICOM itself.
//
// Fails on any crash or sanitizer report, and when a promise breaks:
// - nullptr comes with a non-empty one-line error;
// - an image has voxels whose scalars cover its points, a finite origin,
//   spacing > 0 and finite, and a direction of unit columns at right angles
//   within the orientation tolerance the reader accepts (|cos| <= 1e-3).
#include "dgDicomSeries.h"
#include "dgFuzzSupport.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unistd.h>

namespace
{
std::string Dir;
constexpr int MaxFiles = 4;

std::string FileName(int i)
{
  return Dir + "/s" + std::to_string(i) + ".dcm";
}

void Cleanup()
{
  if (!Dir.empty())
  {
    for (int i = 0; i < MaxFiles; ++i)
      std::remove(FileName(i).c_str());
    rmdir(Dir.c_str());
  }
}
} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (Dir.empty())
  {
    Dir = dgfuzz::MakeScratchDirectory("dicom");
    std::atexit(Cleanup);
  }
  for (int i = 0; i < MaxFiles; ++i)
    std::remove(FileName(i).c_str());
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  static const std::string marker = "DGSLICE!";
  std::size_t at = 0;
  for (int i = 0; i < MaxFiles && at <= bytes.size(); ++i)
  {
    std::size_t end = bytes.find(marker, at);
    if (end == std::string::npos || i == MaxFiles - 1)
      end = bytes.size();
    std::FILE* f = std::fopen(FileName(i).c_str(), "wb");
    if (!f || (end > at && std::fwrite(bytes.data() + at, 1, end - at, f) != end - at))
      std::abort();
    std::fclose(f);
    at = end + marker.size();
  }

  std::string error;
  vtkSmartPointer<vtkImageData> image = dg::ReadDicom(Dir, "", error);
  if (std::getenv("DG_FUZZ_VERBOSE")) // what a seed gives
    std::fprintf(stderr, "%s\n", image ? "an image" : error.c_str());
  if (!image)
  {
    if (error.empty() || error.find('\n') != std::string::npos)
      std::abort();
    return 0;
  }
  const vtkIdType n = image->GetNumberOfPoints();
  vtkDataArray* s = image->GetPointData()->GetScalars();
  if (n <= 0 || !s || s->GetNumberOfTuples() != n)
    std::abort();
  double origin[3], spacing[3];
  image->GetOrigin(origin);
  image->GetSpacing(spacing);
  const double* d = image->GetDirectionMatrix()->GetData();
  dgfuzz::CheckGridGeometry(origin, spacing, d, 1e-6, 1e-3);
  return 0;
}
