// What the program's two drivers (one process, and one piece per rank under
// mpirun) share: progress, error capture, all-or-nothing output files, stage
// clocks and small helpers.
#ifndef dgProgramSupport_h
#define dgProgramSupport_h

#include "dgProgramOptions.h"

#include <vtkAlgorithm.h>
#include <vtkCommand.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

class vtkDataArray;
class vtkPolyData;
class vtkXMLWriter;

namespace dg
{
class Processes;
}

namespace dgapp
{
// Progress bar on the terminal, fed by the filters' ProgressEvent; silent
// when stderr is not a terminal (logs, CI).
class ProgressBar : public vtkCommand
{
public:
  static ProgressBar* New() { return new ProgressBar; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (!this->Enabled || !data)
    {
      return;
    }
    const double f = *static_cast<double*>(data);
    const int width = 30;
    const int filled = static_cast<int>(f * width + 0.5);
    std::fprintf(stderr,
      "\r%-22s [%s%s] %3d%%",
      this->Stage.c_str(),
      std::string(filled, '#').c_str(),
      std::string(width - filled, '.').c_str(),
      static_cast<int>(100 * f + 0.5));
    if (f >= 1.0)
    {
      std::fprintf(stderr, "\n");
    }
    std::fflush(stderr);
  }
  bool Enabled = false;
  std::string Stage;
};

// Collects the first VTK error of any stage as one line.
class ErrorCatcher : public vtkCommand
{
public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    this->Failed = true;
    if (data && this->Message.empty())
    {
      std::string m = static_cast<const char*>(data);
      while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
        m.pop_back();
      const auto nl = m.find_last_of('\n');
      m = nl == std::string::npos ? m : m.substr(nl + 1);
      // "vtkClass (0x55...): message" -> "vtkClass: message"
      const auto open = m.find(" (0x");
      const auto close = m.find("): ", open == std::string::npos ? 0 : open);
      if (open != std::string::npos && close != std::string::npos)
      {
        m = m.substr(0, open) + m.substr(close + 1);
      }
      this->Message = m;
    }
  }
  bool Failed = false;
  std::string Message;
};

// Files are written under temporary names and renamed only when every one
// of them succeeded, so that a failure leaves no partial output behind.
class OutputFiles
{
public:
  std::string Temporary(const std::string& final)
  {
    this->Finals.push_back(final);
    // ".part" before the extension: the PLY writer appends ".ply" to any
    // name that does not end with it.
    const std::size_t slash = final.find_last_of('/');
    const std::size_t dot = final.find_last_of('.');
    const bool hasExtension = dot != std::string::npos && (slash == std::string::npos || dot > slash);
    this->Temps.push_back(hasExtension ? final.substr(0, dot) + ".part" + final.substr(dot)
                                       : final + ".part");
    return this->Temps.back();
  }
  bool Commit()
  {
    for (std::size_t i = 0; i < this->Finals.size(); ++i)
    {
      if (std::rename(this->Temps[i].c_str(), this->Finals[i].c_str()) != 0)
      {
        return false;
      }
    }
    this->Temps.clear();
    return true;
  }
  ~OutputFiles()
  {
    for (const auto& t : this->Temps)
      std::remove(t.c_str());
  }
  std::vector<std::string> Finals, Temps;
};

// Per-stage times from the algorithms' own start and end: under pieces the
// last stage is updated once (updating stage by stage would make the image
// stages run twice: the II stage asks for more ghost voxels than the surface
// alone), so the times are taken as each stage runs.
class StageClock : public vtkCommand
{
public:
  static StageClock* New() { return new StageClock; }
  void Watch(vtkAlgorithm* algo, const std::string& name)
  {
    this->Names[algo] = name;
    algo->AddObserver(vtkCommand::StartEvent, this);
    algo->AddObserver(vtkCommand::EndEvent, this);
  }
  void Execute(vtkObject* caller, unsigned long event, void*) override
  {
    const auto it = this->Names.find(caller);
    if (it == this->Names.end())
      return;
    const auto now = std::chrono::steady_clock::now();
    if (event == vtkCommand::StartEvent)
    {
      this->Started[caller] = now;
      if (this->Progress)
        this->Progress->Stage = it->second;
      return;
    }
    const double dt = std::chrono::duration<double>(now - this->Started[caller]).count();
    for (auto& t : this->Times)
    {
      if (t.first == it->second)
      {
        t.second += dt;
        return;
      }
    }
    this->Times.emplace_back(it->second, dt);
  }
  std::map<vtkObject*, std::string> Names;
  std::map<vtkObject*, std::chrono::steady_clock::time_point> Started;
  std::vector<std::pair<std::string, double>> Times;
  ProgressBar* Progress = nullptr;
};

/// The output prefix of an input path: its name without the directory and
/// the extension ("scan.nii.gz" -> "scan").
std::string Stem(const std::string& path);

/// The process's peak resident memory.
double PeakMemoryMiB();

/// Runs the program again in place (exec: same process id, arguments and
/// environment) with glibc's transparent-huge-page malloc switched on
/// (GLIBC_TUNABLES glibc.malloc.hugetlb=1), unless it already is or
/// DG_HUGEPAGES=0, or under an MPI launcher (mpirun). glibc reads that
/// switch only at start-up. On octa-flower
/// 512^3 it took the whole program from 8.9 to 6.6 s (read, surface and II
/// 2-3x faster, AT 5.6 -> 5.0 s), the results bit for bit the same; the
/// exec costs about 0.05 s (docs/at-speed.md). Returns only when it does
/// not exec (or the exec fails).
void ReexecWithHugePages(char* argv[]);
/// True when glibc's huge-page malloc is on in this process.
bool HugePageMalloc();

/// Empty when the picture can be rendered here, else a one-line reason.
/// VTK's X render window aborts the process when it cannot open its display
/// (no DISPLAY on a server, or a dead one), so the program asks first,
/// before any work, and fails with this message instead.
std::string PictureUnavailable();

/// Prints "piecewise-normals: message" and returns the exit status 1.
int Fail(const std::string& message);

/// The default selection (value != 0) is meant for masks and label maps of
/// unsigned integers. On float or signed values (a scalar field, CT in
/// Hounsfield units) it takes nearly every voxel and gives a box: without an
/// explicit --range, --label or --labels such an input is refused. Returns
/// the one-line refusal for a VTK scalar type, or "" when the run may go on.
std::string DefaultSelectionRefusal(const Options& opt, int scalarType, const std::string& input);

/// Without --labels: "" when some voxel of the scalars (component 0) passes
/// the selection, else one line naming what was asked (the label, the range)
/// and the values the volume holds. Before any stage runs: later stages see
/// only the island filter's 0/1 volume.
std::string EmptySelectionMessage(const Options& opt, vtkDataArray* scalars);

/// Binary data, compressed as --compression says.
void ConfigureXMLWriter(vtkXMLWriter* w, const std::string& compression);

/// The first error in text collected from VTK's output window, one line.
std::string FirstVTKError(const std::string& text);

/// Owned cells of a piece (cells marked as ghosts by vtkGhostType excluded).
long long OwnedCells(vtkPolyData* pd);

/// Several processes (mpirun -np N, N > 1): rank r runs the pipeline for
/// piece r of N and writes its piece of each .pvtp (dgRunPieces.cxx).
int RunPieces(Options opt, dg::Processes& procs);
} // namespace dgapp

#endif
