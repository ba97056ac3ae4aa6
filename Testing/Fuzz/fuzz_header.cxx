// libFuzzer target: the hand-written MetaImage / NRRD header parsers of
// Filters/dgImageHeader.{h,cxx} (ReadHeaderGeometry, CheckMetaImageDataSize,
// NrrdHasThreeSpatialAxes, ParseNumbers) on arbitrary header text.
//
// With bit 1 of byte 0 set, the text is instead a DICOM series' geometry
// tags (Applications/dgDicomGeometry.h: OrderDicomSlices, UniformDicomStep),
// one slice per line, "position|orientation|pixel spacing" as the tags'
// strings; on success the cosines are unit and at right angles, the slices
// sorted along the normal, and the step positive and finite.
//
// Input: byte 0 = flags (bit 0: NRRD, else MetaImage), byte 1 = size of a
// companion data file "d.raw" in 16-byte units, then the header text, which
// is written to a per-process temporary directory (every '/' turned into
// '_', so an ElementDataFile cannot name a file outside it).
//
// Fails on any crash or sanitizer report, and when a promise of the header
// breaks:
// - an error is one non-empty line;
// - on success with g.Has: origin, spacing and direction finite, spacing
//   > 0, direction columns of unit length and at right angles within the
//   shear tolerance the parser accepts (|cos| <= 1e-4);
// - RAS is LPS with x and y negated (same error, same spacing);
// - ParseNumbers gives finite numbers only.
#include "dgDicomGeometry.h"
#include "dgImageHeader.h"
#include "dgFuzzSupport.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>
#include <unistd.h>

namespace
{
std::string Dir;

void Cleanup()
{
  if (!Dir.empty())
  {
    std::remove((Dir + "/h.mha").c_str());
    std::remove((Dir + "/d.raw").c_str());
    rmdir(Dir.c_str());
  }
}

void Write(const std::string& path, const char* data, std::size_t size)
{
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f)
    std::abort();
  if (size && std::fwrite(data, 1, size, f) != size)
    std::abort();
  std::fclose(f);
}

void CheckError(const std::string& why)
{
  if (why.empty() || why.find('\n') != std::string::npos)
    std::abort();
}

void CheckGeometry(const dg::HeaderGeometry& g)
{
  dgfuzz::CheckGridGeometry(g.Origin, g.Spacing, g.Direction);
}
void CheckUnit(const dg::DicomVec& v)
{
  const double n = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  if (!(std::fabs(n - 1) <= 1e-9))
    std::abort();
}

void FuzzDicomGeometry(const std::string& text)
{
  std::vector<dg::DicomSliceTags> slices;
  for (std::size_t at = 0; at < text.size() && slices.size() < 64;)
  {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos)
      end = text.size();
    const std::string line = text.substr(at, end - at);
    dg::DicomSliceTags t;
    t.File = "slice" + std::to_string(slices.size()) + ".dcm";
    const std::size_t a = line.find('|'), b = a == std::string::npos ? a : line.find('|', a + 1);
    t.Position = line.substr(0, a);
    if (a != std::string::npos)
      t.Orientation = line.substr(a + 1, b == std::string::npos ? b : b - a - 1);
    if (b != std::string::npos)
      t.PixelSpacing = line.substr(b + 1);
    slices.push_back(t);
    at = end + 1;
  }
  dg::DicomStack stack;
  std::string why;
  if (!dg::OrderDicomSlices(slices, stack, why))
  {
    CheckError(why);
    return;
  }
  CheckUnit(stack.Row);
  CheckUnit(stack.Column);
  CheckUnit(stack.Normal);
  const double cosRC = stack.Row[0] * stack.Column[0] + stack.Row[1] * stack.Column[1] + stack.Row[2] * stack.Column[2];
  if (!(std::fabs(cosRC) <= 1e-3 + 1e-9) || stack.Files.size() != slices.size() ||
    stack.Positions.size() != slices.size() || stack.Along.size() != slices.size())
    std::abort();
  for (std::size_t s = 1; s < stack.Along.size(); ++s)
    if (!(stack.Along[s - 1] <= stack.Along[s]))
      std::abort();
  if (stack.Along.size() >= 2)
  {
    double step = 0;
    if (dg::UniformDicomStep(stack, step, why))
    {
      if (!(step > 0) || !std::isfinite(step))
        std::abort();
    }
    else
    {
      CheckError(why);
    }
  }
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (size < 2)
    return 0;
  if (Dir.empty())
  {
    Dir = dgfuzz::MakeScratchDirectory("header");
    std::atexit(Cleanup);
  }
  const bool nrrd = data[0] & 1;
  std::string text(reinterpret_cast<const char*>(data) + 2, size - 2);
  if (data[0] & 2)
  {
    FuzzDicomGeometry(text);
    return 0;
  }
  for (char& c : text)
    if (c == '/')
      c = '_';
  const std::string path = Dir + "/h.mha", companion = Dir + "/d.raw";
  Write(path, text.data(), text.size());
  const std::string zeros(16 * std::size_t(data[1]), '\0');
  Write(companion, zeros.data(), zeros.size());

  dg::HeaderGeometry lps, ras;
  const std::string whyLps = dg::ReadHeaderGeometry(path, nrrd, false, lps);
  const std::string whyRas = dg::ReadHeaderGeometry(path, nrrd, true, ras);
  if (whyLps != whyRas || lps.Has != ras.Has)
    std::abort();
  if (!whyLps.empty())
  {
    CheckError(whyLps);
  }
  else if (lps.Has)
  {
    CheckGeometry(lps);
    CheckGeometry(ras);
    for (int r = 0; r < 3; ++r)
    {
      const double sign = r < 2 ? -1 : 1;
      if (ras.Origin[r] != sign * lps.Origin[r] || ras.Spacing[r] != lps.Spacing[r])
        std::abort();
      for (int a = 0; a < 3; ++a)
        if (ras.Direction[3 * r + a] != sign * lps.Direction[3 * r + a])
          std::abort();
    }
  }

  if (const std::string why = dg::CheckMetaImageDataSize(path); !why.empty())
    CheckError(why);
  int sizes[3] = { 0, 0, 0 };
  dg::NrrdHasThreeSpatialAxes(path, sizes);

  // ParseNumbers on each line of the text.
  for (std::size_t at = 0; at <= text.size();)
  {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos)
      end = text.size();
    for (double v : dg::ParseNumbers(text.substr(at, end - at)))
      if (!std::isfinite(v))
        std::abort();
    at = end + 1;
  }
  return 0;
}
