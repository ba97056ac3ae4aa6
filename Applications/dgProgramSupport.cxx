#include "dgProgramSupport.h"

#include "dgHugePages.h"

#include <vtkDataArray.h>
#include <vtkDigitalSurfaceFilter.h>
#include <vtkPolyData.h>
#include <vtkSetGet.h>
#include <vtkType.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLWriter.h>

#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

#include <iostream>
#include <sstream>

namespace dgapp
{
std::string DefaultSelectionRefusal(const Options& opt, int scalarType, const std::string& input)
{
  if (opt.P.SelectionMode != vtkDigitalSurfaceFilter::NON_ZERO || !opt.Labels.empty())
    return std::string();
  const char* what = nullptr;
  switch (scalarType)
  {
    case VTK_FLOAT:
    case VTK_DOUBLE:
      what = "floating-point";
      break;
    case VTK_SIGNED_CHAR:
    case VTK_SHORT:
    case VTK_INT:
    case VTK_LONG:
    case VTK_LONG_LONG:
    case VTK_ID_TYPE:
      what = "signed";
      break;
    case VTK_CHAR: // signed or not, as the platform's char
      if (static_cast<char>(-1) < 0)
        what = "signed";
      break;
    default:
      break;
  }
  if (!what)
    return std::string();
  return "'" + input + "' holds " + what + " values: choose the inside voxels with --range LO HI " +
    "or --label L (--labels for every label of a label map); the default, value != 0, is for " +
    "unsigned masks";
}

namespace
{
template <typename T, typename Pass>
bool AnyVoxelPasses(const T* values, vtkIdType count, int stride, Pass pass)
{
  for (vtkIdType i = 0; i < count; ++i)
    if (pass(static_cast<double>(values[i * stride])))
      return true;
  return false;
}
}

std::string EmptySelectionMessage(const Options& opt, vtkDataArray* scalars)
{
  if (!scalars || !opt.Labels.empty() || scalars->GetNumberOfTuples() == 0)
    return std::string();
  const int mode = opt.P.SelectionMode;
  const double label = opt.P.Label, lo = opt.P.Lower, hi = opt.P.Upper;
  auto pass = [&](double v)
  {
    if (mode == vtkDigitalSurfaceFilter::LABEL)
      return v == label;
    if (mode == vtkDigitalSurfaceFilter::RANGE)
      return lo <= v && v <= hi;
    return v != 0;
  };
  bool found = true;
  const vtkIdType n = scalars->GetNumberOfTuples();
  const int stride = scalars->GetNumberOfComponents();
  if (scalars->HasStandardMemoryLayout())
  {
    switch (scalars->GetDataType())
    {
      vtkTemplateMacro(
        found = AnyVoxelPasses(static_cast<const VTK_TT*>(scalars->GetVoidPointer(0)), n, stride, pass));
      default:
        return std::string();
    }
  }
  else
  {
    found = false;
    for (vtkIdType i = 0; i < n && !found; ++i)
      found = pass(scalars->GetComponent(i, 0));
  }
  if (found)
    return std::string();
  std::ostringstream s;
  if (mode == vtkDigitalSurfaceFilter::LABEL)
    s << "no voxel has the label " << label << " (--label)";
  else if (mode == vtkDigitalSurfaceFilter::RANGE)
    s << "no voxel value is in the range [" << lo << ", " << hi << "] (--range)";
  else
    s << "no voxel is non-zero";
  double range[2];
  scalars->GetRange(range, 0);
  s << ": the values are " << range[0] << " to " << range[1];
  return s.str();
}

std::string Stem(const std::string& path)
{
  std::string s = path;
  while (!s.empty() && s.back() == '/')
    s.pop_back();
  const auto slash = s.find_last_of('/');
  if (slash != std::string::npos)
    s = s.substr(slash + 1);
  // "scan.nii.gz" -> "scan": a compressed file's two extensions go.
  for (const char* two : { ".nii.gz", ".vol.gz" })
  {
    const std::string t = two;
    if (s.size() > t.size() && s.compare(s.size() - t.size(), t.size(), t) == 0)
      return s.substr(0, s.size() - t.size());
  }
  const auto dot = s.find_last_of('.');
  if (dot != std::string::npos && dot > 0)
    s = s.substr(0, dot);
  return s.empty() ? "result" : s;
}

double PeakMemoryMiB()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

int Fail(const std::string& message)
{
  std::cerr << Program << ": " << message << "\n";
  return 1;
}

void ConfigureXMLWriter(vtkXMLWriter* w, const std::string& compression)
{
  w->SetDataModeToBinary(); // appended data trips Debian's expat + VTK 9.2 reader
  if (compression == "zlib")
    w->SetCompressorTypeToZLib();
  else if (compression == "none")
    w->SetCompressorTypeToNone();
  else
    w->SetCompressorTypeToLZ4();
}

// The first error in text collected from VTK's output window ("ERROR: In
// file, line N" then the message), as one line without the object's address.
std::string FirstVTKError(const std::string& text)
{
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind("ERROR: In ", 0) != 0 || !std::getline(in, line))
      continue;
    const auto open = line.find(" (0x");
    const auto close = line.find("): ", open == std::string::npos ? 0 : open);
    if (open != std::string::npos && close != std::string::npos)
      line = line.substr(0, open) + line.substr(close + 1);
    return line;
  }
  return "";
}

long long OwnedCells(vtkPolyData* pd)
{
  vtkUnsignedCharArray* ghosts = pd->GetCellGhostArray();
  if (!ghosts)
    return pd->GetNumberOfCells();
  long long n = 0;
  for (vtkIdType c = 0; c < ghosts->GetNumberOfTuples(); ++c)
    n += ghosts->GetValue(c) == 0 ? 1 : 0;
  return n;
}
bool HugePageMalloc()
{
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  return tunables && std::strstr(tunables, "glibc.malloc.hugetlb=1");
}

void ReexecWithHugePages(char* argv[])
{
#if defined(__linux__)
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (dg::HugePagesDisabled() || (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")))
  {
    return;
  }
  // Not under an MPI launcher: it set the process up (pipes, PMIx
  // environment) around the program it started, and a full test run once
  // failed a 2-rank run we could not reproduce; an exec there is not worth
  // the doubt. The ranks run with the module's own huge-page advice only.
  for (const char* launcher : { "OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE" })
  {
    if (std::getenv(launcher))
    {
      return;
    }
  }
  std::string value = "glibc.malloc.hugetlb=1";
  if (tunables && *tunables)
  {
    value = std::string(tunables) + ":" + value;
  }
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0)
  {
    return;
  }
  execv("/proc/self/exe", argv);
  // Still here: the exec failed; go on as we are (the variable is harmless).
#else
  (void)argv;
#endif
}

} // namespace dgapp

// Last in the file: Xlib's macros (None, Bool, Status, ...) must not reach
// the VTK headers above.
#include <vtkRenderingOpenGLConfigure.h> // VTK_USE_X
#if defined(DG_HAVE_X11) && defined(VTK_USE_X)
#include <X11/Xlib.h>
#endif

std::string dgapp::PictureUnavailable()
{
#if defined(DG_HAVE_X11) && defined(VTK_USE_X)
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
  {
    return "no X display for the picture (DISPLAY is not set): run under xvfb-run, or pass --no-png";
  }
  ::Display* x = XOpenDisplay(nullptr);
  if (!x)
  {
    return std::string("cannot open the X display '") + display +
      "' for the picture: run under xvfb-run, or pass --no-png";
  }
  XCloseDisplay(x);
#endif
  return std::string();
}
