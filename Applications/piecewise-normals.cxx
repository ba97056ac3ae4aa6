// piecewise-normals: from a segmented volume to its digital surface,
// integral-invariant normals, Ambrosio-Tortorelli regularised normals, sharp
// features, and a picture. See --help.
#include "dgBuiltinShape.h"
#include "dgImageInput.h"
#include "dgRender.h"
#include "dgLabels.h"
#include "dgPipeline.h"
#include "dgProcesses.h"

#include <vtkAppendPolyData.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkInformation.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkOBJWriter.h>
#include <vtkOutputWindow.h>
#include <vtkStringOutputWindow.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLWriter.h>

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{
const char* Program = "piecewise-normals";

struct Options
{
  std::string Input;
  std::string OutputDir = ".";
  std::string Prefix;
  int BuiltinSize = 96;
  // Everything from the selection to the sharp features (dgPipeline.h).
  dg::PipelineSettings P;
  // Outputs.
  bool Png = true, Panels = false, Ply = false, Obj = false, Quiet = false;
  dg::ReadOptions Read; // LPS/RAS, DICOM series
  std::string Compression = "lz4";
  int Width = 1200, Height = 900;
  std::string Labels; // --labels: every label's surface in one run
  bool Interfaces = false; // --interfaces: the faces between labels, once
};

void Usage()
{
  std::cout <<
    R"(usage: piecewise-normals [options] [INPUT]

Reconstructs a piecewise-smooth normal field on the digital surface of a
segmented volume and delineates its sharp features (Coeurjolly, Foare, Gueth,
Lachaud, Pacific Graphics 2016): volume -> voxel-face surface -> integral-
invariant normals -> Ambrosio-Tortorelli regularisation -> files + picture.

INPUT   a DGtal .vol (Version 2 or 3), VTK .vti or .pvti, NIfTI .nii/.nii.gz (its
        sform or qform), MetaImage .mha/.mhd (Offset, TransformMatrix), NRRD
        .nrrd/.nhdr (space origin, space directions), a DICOM file (.dcm) or a
        directory holding a DICOM series (slices ordered along their normal).
        Patient-space inputs (NIfTI, MetaImage, NRRD, DICOM) give outputs in
        LPS patient coordinates (DICOM's and ITK's), or RAS with --ras.
        With no INPUT: a built-in shape (rotated cube + sphere - cylinder, 96^3).
  --ras                  outputs in RAS (x and y negated) instead of LPS
  --dicom-series UID     the series to read when the DICOM directory holds
                         several (otherwise an error lists them)

Inside voxels (default: value != 0)
  --label L              voxels whose value is L (label maps)
  --range LO HI          voxels whose value is in [LO, HI]
  --labels SPEC          every label of a label map in one run: "all", or labels
                         and ranges "1,4,10-12"; each label's pipeline runs on its
                         own box of the volume (plus the estimator's reach) and
                         the outputs hold all labels with a cell array Label
  --interfaces           with --labels: every face between two labels, or a label
                         and the background, once (cell arrays LabelInside >
                         LabelOutside; labels not selected count as background),
                         II normals out of LabelInside, and one AT on the whole
                         non-manifold complex: shared boundaries smoothed once,
                         the lines where 3 labels meet come out as features.
                         AT's own output (no islands, no sharp stage)
Noise (the paper's model: flip with probability k^(1 + distance to boundary))
  --noise K              noise level k in [0, 1] (default 0: none)
  --seed S               random seed (default 0)
Before the surface
  --min-component N      drop inside components and fill cavities smaller than
                         N voxels (default 8: the paper's noise leaves specks of
                         1-7 voxels; 0 keeps everything)
Input normals
  --estimator E          ii (default: integral invariant), vcm (Voronoi
                         covariance measure) or rht (randomized Hough transform);
                         AT regularises the chosen one
  --radius R             II ball radius in voxels (default 4)
  --curvatures           II: also output mean, Gaussian and principal curvatures
  --vcm-radii R r        VCM offset and convolution radii (default 10 4, the paper's)
  --rht-radius r         RHT neighbourhood radius (default 6, the paper's)
  --rht-trials N         RHT triplets per surfel (default 648, the paper's; --seed
                         seeds them)
Ambrosio-Tortorelli (lengths in voxels unless --at-metric world)
  --alpha A              data attachment weight (default 0.05, the paper's Fig. 5;
                         larger = closer to the input)
  --lambda L             length penalty of the features (default 0.005, half the
                         paper's 0.01: the sharp-features stage removes AT's extra
                         lines; larger = fewer features)
  --eps-start E          initial epsilon, width of the feature zone (default 2)
  --eps-end E            final epsilon (default 0.25)
  --eps-ratio R          epsilon divisor between levels, > 1 (default 2)
  --iterations N         maximum alternating iterations per level (default 5)
  --tolerance T          stop a level when max |v - v_prev| < T (default 1e-4)
  --feature-threshold T  an edge is a feature when v < T at both ends (default 0.5)
  --solver S             linear solver: ic (default; CG with incomplete Cholesky),
                         cg (CG with Jacobi), ldlt (exact, 5-7x slower), cholmod
  --at-metric M          grid (default, the paper's: eps in voxels, every face
                         weighs 1) or world (eps in world lengths, lambda per
                         world length, alpha per world area: the same result at
                         every resolution and spacing; docs/at-metric.md)
  --solver-tolerance T   CG's relative residual (default 1e-5; 1e-8 makes the
                         result independent of the preconditioner's blocks, e.g.
                         of the number of processes, at about twice AT's time)
Sharp features (after AT: one line per sharp edge, side normals up to it)
  --plain                the paper's own output instead: AT's normals and its
                         feature edges (a band of ladders along each edge)
  --second-pass          AT again on the side normals, then the sharp stage again:
                         normals closer to the truth near the edges, twice AT's time
Outputs (in --output-dir, named PREFIX_*; PREFIX defaults to the input's name)
  --output-dir DIR       default: current directory (created if missing)
  --prefix NAME          file name prefix
  --size N               grid size of the built-in shape (default 96)
  --no-png               no picture
  --panels               picture as a strip of four square panels, W x W/4,
                         instead of the default 2 x 2 grid at W x H
  --width W --height H   picture size in pixels (default 1200 x 900; with
                         --panels the height is W / 4 and H is not used)
  --compression C        .vtp compression: lz4 (default, fast), zlib (files about
                         1.35x smaller, 2-3x slower to write) or none
  --ply, --obj           also write the surface as PLY / OBJ
  --quiet                no progress bar
  -h, --help             this help

Writes PREFIX_surface.vtp (cell data: SharpNormals (active), FeatureRegion,
ATNormals, IINormals (VCMNormals, RHTNormals with --estimator), trivial Normals; point data: v = ATFeatureIndicator),
PREFIX_features.vtp (the feature lines, with FeatureAngle in degrees; with
--plain: AT's feature edges, with v) and PREFIX.png. Exit status 0 on success, 1 on bad input, 2 on bad options.

The picture has four panels, as the paper's Fig. 1, in one three-quarter view,
each framing the whole object: the digital surface (its quads, flat shaded) |
the input normals g (II) | the regularised normals u | the feature lines (red)
on the surface; normals are shown as colours RGB = (n + 1) / 2, one per quad.
Default layout 2 x 2 (1 2 / 3 4); with --panels 1 x 4 (1 2 3 4).

Several processes: mpirun -np N piecewise-normals ... runs rank r on piece r
of N (VTK's block split of the volume; AT solves one problem over all ranks)
and writes PREFIX_surface.pvtp and PREFIX_features.pvtp with one .vtp piece
per rank (PREFIX_surface_r.vtp), the summary and the picture from rank 0.
The sharp-features stage is not distributed: with N > 1 the output is AT's
plain one (as --plain), and --second-pass, --ply and --obj are not available.
The picture gathers the surface (points, quads, three normal fields) and the
lines on rank 0: about 125 bytes per surfel there (twice that while the pieces
arrive); --no-png avoids it. Each rank keeps its piece of the volume (.vol and
.nii read the whole file to cut it out); DICOM, the built-in shape and --noise
need the whole volume on every rank (noise is drawn on the whole volume, as
with one process).
)";
}

// Under mpirun every rank parses the same options: rank 0 alone says what
// is wrong with them (one message), every rank exits.
bool PrintsCommonMessages()
{
  return dg::Processes::LauncherRank() == 0;
}

[[noreturn]] void OptionError(const std::string& message)
{
  if (PrintsCommonMessages())
    std::cerr << Program << ": " << message << " (see --help)\n";
  std::exit(2);
}

double ParseNumber(const std::string& option, const std::string& text)
{
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || !end || *end != '\0' || !std::isfinite(v))
  {
    OptionError(option + " expects a number, got '" + text + "'");
  }
  return v;
}

Options ParseOptions(int argc, char* argv[])
{
  Options o;
  for (int a = 1; a < argc; ++a)
  {
    const std::string arg = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc)
      {
        OptionError(arg + " needs a value");
      }
      return argv[++a];
    };
    auto number = [&]() { return ParseNumber(arg, value()); };
    if (arg == "-h" || arg == "--help")
    {
      if (PrintsCommonMessages())
        Usage();
      std::exit(0);
    }
    else if (arg == "--output-dir")
      o.OutputDir = value();
    else if (arg == "--prefix")
      o.Prefix = value();
    else if (arg == "--size")
      o.BuiltinSize = static_cast<int>(number());
    else if (arg == "--label")
    {
      o.P.SelectionMode = vtkDigitalSurfaceFilter::LABEL;
      o.P.Label = number();
    }
    else if (arg == "--range")
    {
      o.P.SelectionMode = vtkDigitalSurfaceFilter::RANGE;
      o.P.Lower = number();
      o.P.Upper = number();
    }
    else if (arg == "--noise")
      o.P.Noise = number();
    else if (arg == "--seed")
    {
      const double s = number();
      if (s < 0 || s > 2147483647.0 || s != std::floor(s))
        OptionError("--seed expects an integer in [0, 2^31 - 1]");
      o.P.Seed = static_cast<int>(s);
    }
    else if (arg == "--min-component")
    {
      const double n = number();
      if (n < 0 || n > 2147483647.0 || n != std::floor(n))
        OptionError("--min-component expects an integer >= 0");
      o.P.MinimumComponentSize = static_cast<int>(n);
    }
    else if (arg == "--plain")
      o.P.Sharpen = false;
    else if (arg == "--second-pass")
      o.P.SecondPass = true;
    else if (arg == "--radius")
      o.P.Radius = number();
    else if (arg == "--estimator")
    {
      o.P.Estimator = value();
      if (o.P.Estimator != "ii" && o.P.Estimator != "vcm" && o.P.Estimator != "rht")
        OptionError("--estimator expects ii, vcm or rht");
    }
    else if (arg == "--vcm-radii")
    {
      o.P.VCMOffsetRadius = number();
      o.P.VCMConvolutionRadius = number();
    }
    else if (arg == "--rht-radius")
      o.P.RHTRadius = number();
    else if (arg == "--rht-trials")
    {
      const double n = number();
      if (n < 1 || n > 1e6 || n != std::floor(n))
        OptionError("--rht-trials expects an integer in [1, 1000000]");
      o.P.RHTTrials = static_cast<int>(n);
    }
    else if (arg == "--curvatures")
      o.P.Curvatures = true;
    else if (arg == "--alpha")
      o.P.Alpha = number();
    else if (arg == "--lambda")
      o.P.Lambda = number();
    else if (arg == "--eps-start")
      o.P.EpsStart = number();
    else if (arg == "--eps-end")
      o.P.EpsEnd = number();
    else if (arg == "--eps-ratio")
      o.P.EpsRatio = number();
    else if (arg == "--iterations")
      o.P.Iterations = static_cast<int>(number());
    else if (arg == "--tolerance")
      o.P.Tolerance = number();
    else if (arg == "--feature-threshold")
      o.P.FeatureThreshold = number();
    else if (arg == "--solver")
    {
      const std::string v = value();
      if (v == "ic")
        o.P.Solver = vtkAmbrosioTortorelliFilter::CONJUGATE_GRADIENT_IC;
      else if (v == "cg")
        o.P.Solver = vtkAmbrosioTortorelliFilter::CONJUGATE_GRADIENT;
      else if (v == "ldlt")
        o.P.Solver = vtkAmbrosioTortorelliFilter::SIMPLICIAL_LDLT;
      else if (v == "cholmod")
        o.P.Solver = vtkAmbrosioTortorelliFilter::CHOLMOD;
      else
        OptionError("--solver expects ic, cg, ldlt or cholmod (got '" + v + "')");
    }
    else if (arg == "--at-metric")
    {
      const std::string v = value();
      if (v == "grid")
        o.P.Metric = vtkAmbrosioTortorelliFilter::METRIC_GRID;
      else if (v == "world")
        o.P.Metric = vtkAmbrosioTortorelliFilter::METRIC_WORLD;
      else
        OptionError("--at-metric expects grid or world (got '" + v + "')");
    }
    else if (arg == "--solver-tolerance")
      o.P.SolverTolerance = number();
    else if (arg == "--labels")
      o.Labels = value();
    else if (arg == "--interfaces")
      o.Interfaces = true;
    else if (arg == "--ras")
      o.Read.Ras = true;
    else if (arg == "--dicom-series")
      o.Read.DicomSeries = value();
    else if (arg == "--compression")
    {
      o.Compression = value();
      if (o.Compression != "lz4" && o.Compression != "zlib" && o.Compression != "none")
        OptionError("--compression expects lz4, zlib or none (got '" + o.Compression + "')");
    }
    else if (arg == "--no-png")
      o.Png = false;
    else if (arg == "--panels")
      o.Panels = true;
    else if (arg == "--width")
      o.Width = static_cast<int>(number());
    else if (arg == "--height")
      o.Height = static_cast<int>(number());
    else if (arg == "--ply")
      o.Ply = true;
    else if (arg == "--obj")
      o.Obj = true;
    else if (arg == "--quiet")
      o.Quiet = true;
    else if (arg.size() > 1 && arg[0] == '-')
      OptionError("unknown option " + arg);
    else if (!o.Input.empty())
      OptionError("more than one input (" + o.Input + ", " + arg + ")");
    else
      o.Input = arg;
  }
  // Nonsensical parameters are refused here, with the option's name.
  if (o.BuiltinSize < 16 || o.BuiltinSize > 1024)
    OptionError("--size must be in [16, 1024]");
  if (o.P.SelectionMode == vtkDigitalSurfaceFilter::RANGE && !(o.P.Lower <= o.P.Upper))
    OptionError("--range needs LO <= HI");
  if (o.P.Noise < 0 || o.P.Noise > 1)
    OptionError("--noise must be in [0, 1]");
  if (!(o.P.Radius > 0))
    OptionError("--radius must be > 0");
  if (!(o.P.VCMConvolutionRadius > 0) || !(o.P.VCMOffsetRadius >= o.P.VCMConvolutionRadius) ||
    !std::isfinite(o.P.VCMOffsetRadius))
    OptionError("--vcm-radii R r needs 0 < r <= R");
  if (!(o.P.RHTRadius > 0) || !std::isfinite(o.P.RHTRadius))
    OptionError("--rht-radius must be > 0");
  if (!(o.P.Alpha > 0))
    OptionError("--alpha must be > 0");
  if (!(o.P.Lambda > 0))
    OptionError("--lambda must be > 0");
  if (!(o.P.EpsEnd > 0) || !(o.P.EpsStart >= o.P.EpsEnd))
    OptionError("epsilons need 0 < --eps-end <= --eps-start");
  if (!(o.P.EpsRatio > 1))
    OptionError("--eps-ratio must be > 1");
  if (o.P.Iterations < 1)
    OptionError("--iterations must be >= 1");
  if (!(o.P.Tolerance > 0))
    OptionError("--tolerance must be > 0");
  if (!(o.P.SolverTolerance > 0 && o.P.SolverTolerance < 1))
    OptionError("--solver-tolerance must be in (0, 1)");
  if (!(o.P.FeatureThreshold > 0 && o.P.FeatureThreshold < 1))
    OptionError("--feature-threshold must be in (0, 1)");
  if (o.Width < 64 || o.Height < 64 || o.Width > 8192 || o.Height > 8192)
    OptionError("--width and --height must be in [64, 8192]");
  if (!o.Labels.empty())
  {
    dg::LabelSpec spec;
    std::string error;
    if (!dg::ParseLabelSpec(o.Labels, spec, error))
      OptionError("--labels: " + error);
    if (o.P.SelectionMode != vtkDigitalSurfaceFilter::NON_ZERO)
      OptionError("--labels selects the voxels itself: drop --label and --range");
    // The noise is drawn from global voxel indices and the distance to the
    // whole boundary: per label box it would not be the whole volume's.
    if (o.P.Noise > 0)
      OptionError("--labels and --noise cannot be combined (add the noise to the label map first)");
    if (o.P.SecondPass)
      OptionError("--labels and --second-pass cannot be combined");
  }
  if (o.Interfaces)
  {
    if (o.Labels.empty())
      OptionError("--interfaces needs --labels (all, or the labels whose interfaces to build)");
    if (o.P.Estimator != "ii")
      OptionError("--interfaces estimates II normals only (drop --estimator)");
    // Removing a speck of one label would change its neighbours' interfaces;
    // the sharp stage reads a manifold surface.
    o.P.MinimumComponentSize = 0;
    o.P.Sharpen = false;
  }
  return o;
}

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
    std::fprintf(stderr, "\r%-22s [%s%s] %3d%%", this->Stage.c_str(),
      std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
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
    this->Temps.push_back(final + ".part");
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

// ---------------------------------------------------------------------------
// Several processes (mpirun -np N, N > 1): rank r runs the pipeline for piece
// r of N and writes its piece of each .pvtp.

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

// Owned cells of a piece (cells marked as ghosts by vtkGhostType excluded).
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

int RunPieces(Options opt, dg::Processes& procs)
{
  const int rank = procs.Rank(), size = procs.Size();
  const bool root = rank == 0;
  // A failure only this rank sees: say it with the rank, and exit non-zero
  // at once (mpirun then ends the ranks that wait for this one in a
  // collective step, within seconds).
  auto rankFail = [&](const std::string& message) {
    std::cerr << Program << ": rank " << rank << " of " << size << ": " << message << "\n";
    std::cerr.flush();
    return 1;
  };
  // A collective check: every rank learns whether all are fine; the lowest
  // failing rank alone prints its message (one message, not N).
  auto agreeOrFail = [&](bool ok, const std::string& message) {
    const long long first = -procs.Max(ok ? -static_cast<double>(size) : -static_cast<double>(rank));
    if (first >= size)
      return true;
    if (first == rank)
      std::cerr << Program << ": " << (size > 1 ? "rank " + std::to_string(rank) + " of " +
          std::to_string(size) + ": " : std::string()) << message << "\n";
    return false;
  };

  if (opt.Ply || opt.Obj)
  {
    if (root)
      std::cerr << Program << ": --ply and --obj are not available with " << size
                << " processes (convert the .pvtp afterwards)\n";
    return 2;
  }
  if (!opt.Labels.empty())
  {
    if (root)
      std::cerr << Program << ": --labels is not available with " << size
                << " processes (run one process per label, or one process)\n";
    return 2;
  }
  if (root)
  {
    std::cerr << Program << ": " << size << " processes: the sharp-features stage is not "
              << "distributed; writing Ambrosio-Tortorelli's plain output (as --plain"
              << (opt.P.SecondPass ? "; --second-pass ignored" : "") << ")\n";
  }
  opt.P.Sharpen = false;
  opt.P.SecondPass = false;

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  {
    std::error_code ec;
    std::filesystem::create_directories(opt.OutputDir, ec);
    const bool ok = !ec && std::filesystem::is_directory(opt.OutputDir);
    if (!agreeOrFail(ok, "cannot create the output directory '" + opt.OutputDir + "': " +
          (ec ? ec.message() : std::string("a file of that name exists"))))
      return 1;
  }

  vtkNew<ProgressBar> progress;
  progress->Enabled = root && !opt.Quiet && isatty(2);
  vtkNew<ErrorCatcher> errors;
  vtkNew<StageClock> clock;
  clock->Progress = progress;
  auto watch = [&](vtkAlgorithm* algo, const std::string& name, bool warningsFail) {
    algo->AddObserver(vtkCommand::ErrorEvent, errors);
    if (warningsFail)
      algo->AddObserver(vtkCommand::WarningEvent, errors);
    algo->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    algo->AddObserver(vtkCommand::ProgressEvent, progress);
    clock->Watch(algo, name);
  };

  // 1. Input: a reader that gives each piece its sub-extent, or (formats read
  // whole, the built-in shape, and noise, which is drawn on the whole volume
  // as with one process) the whole volume on every rank.
  vtkSmartPointer<vtkImageData> image;
  vtkSmartPointer<vtkAlgorithm> reader;
  std::string prefix = opt.Prefix;
  double readTime = 0;
  {
    const auto t0 = Clock::now();
    std::string error;
    if (opt.Input.empty())
    {
      image = dg::MakeBuiltinShape(opt.BuiltinSize);
      if (prefix.empty())
        prefix = "builtin";
    }
    else
    {
      if (opt.P.Noise <= 0)
        reader = dg::OpenImagePieces(opt.Input, error, opt.Read);
      if (!reader && error.empty())
        image = dg::ReadImage(opt.Input, error, opt.Read);
      if (prefix.empty())
        prefix = Stem(opt.Input);
    }
    // A bad header is every rank's failure: one message.
    if (!agreeOrFail(error.empty(), error))
      return 1;
    readTime = std::chrono::duration<double>(Clock::now() - t0).count();
  }

  // 2. The pipeline for this rank's piece, updated once from its last stage.
  dg::Pipeline pipeline;
  if (reader)
  {
    pipeline.Build(reader->GetOutputPort(), opt.P);
    watch(reader, "read", !reader->IsA("vtkDICOMImageReader"));
  }
  else
    pipeline.Build(image, opt.P);
  for (const auto& stage : pipeline.Stages)
    watch(stage.Algorithm, stage.Name, false);
  vtkAlgorithm* last = pipeline.Stages.back().Algorithm;
  // Objects inside the stages (a .pvti's piece readers) report to VTK's
  // output window, which no observer sees: collect it, so that a failure
  // says one line (naming the first error) and a success passes the
  // warnings on.
  vtkSmartPointer<vtkOutputWindow> previousWindow = vtkOutputWindow::GetInstance();
  vtkNew<vtkStringOutputWindow> collected;
  vtkOutputWindow::SetInstance(collected);
  const int updated = last->UpdatePiece(rank, size, 0);
  vtkOutputWindow::SetInstance(previousWindow);
  const std::string vtkText = collected->GetOutput();
  if (errors->Failed || !updated)
  {
    std::string message = errors->Failed ? errors->Message : "the pipeline failed on this piece";
    const std::string first = FirstVTKError(vtkText);
    if (!first.empty() && message.find(first) == std::string::npos)
      message += " (first error: " + first + ")";
    return rankFail(message);
  }
  if (!vtkText.empty())
    std::cerr << vtkText;
  if (reader)
  {
    std::string error;
    if (!dg::CheckImagePiece(reader, opt.Input, error))
      return rankFail(error);
  }
  vtkPolyData* result = pipeline.Result();
  vtkPolyData* features = pipeline.Features();
  // Every piece is done before any file is made: a rank that failed has
  // exited, and mpirun ends this one while it waits here, with nothing
  // written.
  procs.Barrier();

  // 3. Files: this rank's pieces and (rank 0) the summaries, in a folder of
  // their own until every rank has written, then moved into place.
  const std::filesystem::path outDir(opt.OutputDir);
  const std::filesystem::path partDir = outDir / ("." + prefix + ".parts");
  std::vector<std::string> mine; // file names this rank moves into place
  {
    std::error_code ec;
    std::filesystem::create_directories(partDir, ec);
    // The folder is shared: rank 0 may not remove it before all made it.
    if (!agreeOrFail(!ec, "cannot create '" + partDir.string() + "': " + ec.message()))
      return 1;
  }
  const auto writeStart = Clock::now();
  auto writePieces = [&](vtkPolyData* pd, const std::string& name) {
    vtkSmartPointer<vtkXMLWriter> w = procs.PieceWriter(pd, (partDir / (name + ".pvtp")).string());
    ConfigureXMLWriter(w, opt.Compression);
    w->AddObserver(vtkCommand::ErrorEvent, errors);
    w->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    mine.push_back(name + "_" + std::to_string(rank) + ".vtp");
    if (root)
      mine.push_back(name + ".pvtp");
    // Collective (rank 0 learns which pieces hold data): a rank whose piece
    // fails leaves the others waiting, so it exits at once (below) and
    // mpirun ends them; the final names never hold a partial file.
    return w->Write() == 1 && w->GetErrorCode() == vtkErrorCode::NoError && !errors->Failed;
  };
  auto writeFailure = [&](const std::string& name) {
    return rankFail("cannot write " + (outDir / (name + ".pvtp")).string() +
      (errors->Message.empty() ? "" : " (" + errors->Message + ")"));
  };
  if (!writePieces(result, prefix + "_surface"))
    return writeFailure(prefix + "_surface");
  if (!writePieces(features, prefix + "_features"))
    return writeFailure(prefix + "_features");
  const double writeTime = std::chrono::duration<double>(Clock::now() - writeStart).count();

  // 4. The picture, on rank 0, from the gathered pieces: points, quads and
  // the three normal fields travel (per surfel about one point, 24 bytes,
  // a quad, 40, and three normals, 12 + 24 + 24: 125 bytes on rank 0, twice
  // that while the received pieces are appended).
  double renderTime = 0;
  if (opt.Png)
  {
    const auto t0 = Clock::now();
    vtkSmartPointer<vtkPolyData> whole = procs.GatherToRoot(result, { "Normals", pipeline.InputNormalsName(), "ATNormals" });
    vtkSmartPointer<vtkPolyData> lines = procs.GatherToRoot(features, {});
    if (root)
    {
      dg::RenderOptions ro;
      ro.Width = opt.Width;
      ro.Height = opt.Height;
      ro.Panels = opt.Panels;
      std::string error;
      mine.push_back(prefix + ".png");
      if (!dg::RenderPicture(whole, pipeline.InputNormalsName(), lines, ro, (partDir / (prefix + ".png")).string(), error))
        return rankFail(error);
    }
    renderTime = std::chrono::duration<double>(Clock::now() - t0).count();
  }

  // 5. Every rank wrote: move the files into place.
  const bool allWritten = procs.All(true);
  bool moved = true;
  long long surfacePieces = 0, featurePieces = 0;
  for (const auto& name : mine)
  {
    const auto from = partDir / name;
    std::error_code ec;
    if (!std::filesystem::exists(from, ec))
      continue; // an empty piece the writer left out of the summary
    if (allWritten)
    {
      std::filesystem::rename(from, outDir / name, ec);
      moved = moved && !ec;
      if (name == prefix + "_surface_" + std::to_string(rank) + ".vtp")
        ++surfacePieces;
      if (name == prefix + "_features_" + std::to_string(rank) + ".vtp")
        ++featurePieces;
    }
    else
      std::filesystem::remove(from, ec);
  }
  surfacePieces = procs.Sum(surfacePieces);
  featurePieces = procs.Sum(featurePieces);
  const bool allMoved = agreeOrFail(moved || !allWritten,
    "cannot rename the output files in '" + opt.OutputDir + "'");
  if (root)
  {
    std::error_code ec;
    std::filesystem::remove_all(partDir, ec);
  }
  if (!allWritten || !allMoved)
    return 1;

  // 6. The summary, from rank 0, with the counts of all pieces.
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  if (vtkInformation* info = pipeline.Surface->GetInputInformation(0, 0))
    if (info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
      info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  const long long surfels = procs.Sum(OwnedCells(pipeline.Surface->GetOutput()));
  const long long edges = procs.Sum(static_cast<long long>(features->GetNumberOfLines()));
  const long long islands = procs.Sum(static_cast<long long>(
    opt.P.MinimumComponentSize > 1 ? pipeline.Islands->GetNumberOfRemovedIslands() : 0));
  const long long cavities = procs.Sum(static_cast<long long>(
    opt.P.MinimumComponentSize > 1 ? pipeline.Islands->GetNumberOfFilledCavities() : 0));
  const long long changed = procs.Sum(static_cast<long long>(
    opt.P.MinimumComponentSize > 1 ? pipeline.Islands->GetNumberOfChangedVoxels() : 0));
  const double memory = PeakMemoryMiB();
  const double memoryMax = procs.Max(memory), memorySum = procs.Sum(memory);
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  if (!root)
  {
    procs.Finalize();
    return 0;
  }
  std::vector<std::pair<std::string, double>> times;
  bool readSeen = false;
  for (const auto& t : clock->Times)
    readSeen = readSeen || t.first == "read";
  if (!readSeen)
    times.emplace_back("read", readTime);
  for (const auto& t : clock->Times)
    times.push_back(t);
  times.emplace_back("write", writeTime);
  if (opt.Png)
    times.emplace_back("gather + render", renderTime);
  std::ostringstream stages;
  stages << std::fixed;
  stages.precision(3);
  for (const auto& t : times)
    stages << (&t != &times.front() ? ", " : "") << t.first << " " << t.second << " s";
  std::cout << Program << ": " << (opt.Input.empty() ? "built-in shape" : opt.Input) << " "
            << whole[1] - whole[0] + 1 << "x" << whole[3] - whole[2] + 1 << "x"
            << whole[5] - whole[4] + 1 << ": " << surfels << " surfels, " << edges
            << " feature edges (Ambrosio-Tortorelli, " << size << " processes)\n";
  if (opt.P.MinimumComponentSize > 1)
    std::cout << "  removed " << islands << " inside components and filled " << cavities
              << " cavities smaller than " << opt.P.MinimumComponentSize << " voxels (" << changed
              << " voxels)\n";
  std::cout << std::fixed;
  std::cout.precision(3);
  std::cout << "  time (rank 0): " << stages.str() << " (total " << total << " s); peak memory "
            << static_cast<long>(memoryMax) << " MiB per rank at most (rank 0 "
            << static_cast<long>(memory) << " MiB, all ranks " << static_cast<long>(memorySum)
            << " MiB)\n";
  for (const auto& [name, pieces] : { std::make_pair(prefix + "_surface", surfacePieces),
         std::make_pair(prefix + "_features", featurePieces) })
    std::cout << "  wrote " << (outDir / (name + ".pvtp")).string() << " and " << pieces
              << " non-empty piece" << (pieces == 1 ? "" : "s") << " " << name << "_R.vtp (R = rank)\n";
  if (opt.Png)
    std::cout << "  wrote " << (outDir / (prefix + ".png")).string() << "\n";
  procs.Finalize();
  return 0;
}
} // namespace

int main(int argc, char* argv[])
{
  const Options opt = ParseOptions(argc, argv);
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread"); // Debian's ParaView VTK defaults to sequential
  }
  // Launched by mpirun with N > 1 processes: one piece per rank.
  dg::Processes procs;
  {
    std::string error;
    if (!procs.Initialize(&argc, &argv, error))
    {
      if (PrintsCommonMessages())
        std::cerr << Program << ": " << error << "\n";
      return 2;
    }
  }
  if (procs.Distributed())
  {
    return RunPieces(opt, procs);
  }
  using Clock = std::chrono::steady_clock;
  std::vector<std::pair<std::string, double>> times;
  auto t = Clock::now();
  auto lap = [&](const std::string& stage) {
    const auto now = Clock::now();
    times.emplace_back(stage, std::chrono::duration<double>(now - t).count());
    t = now;
  };

  // Before any work: a run that cannot write its results should not take
  // minutes to say so.
  {
    std::error_code ec;
    std::filesystem::create_directories(opt.OutputDir, ec);
    if (ec || !std::filesystem::is_directory(opt.OutputDir))
      return Fail("cannot create the output directory '" + opt.OutputDir +
        "': " + (ec ? ec.message() : std::string("a file of that name exists")));
  }

  vtkNew<ProgressBar> progress;
  progress->Enabled = !opt.Quiet && isatty(2);
  vtkNew<ErrorCatcher> errors;
  auto watch = [&](vtkAlgorithm* algo) {
    algo->AddObserver(vtkCommand::ErrorEvent, errors);
    algo->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    algo->AddObserver(vtkCommand::ProgressEvent, progress);
  };

  // 1. Input volume.
  vtkSmartPointer<vtkImageData> image;
  std::string prefix = opt.Prefix;
  if (opt.Input.empty())
  {
    image = dg::MakeBuiltinShape(opt.BuiltinSize);
    if (prefix.empty())
      prefix = "builtin";
  }
  else
  {
    std::string error;
    image = dg::ReadImage(opt.Input, error, opt.Read);
    if (!image)
      return Fail(error);
    if (prefix.empty())
      prefix = Stem(opt.Input);
  }
  lap("read");

  // 2. The pipeline, one stage at a time (progress bar, timings, errors):
  // once on the whole volume, or with --labels once per label on that
  // label's box of the volume grown by the stages' reach.
  struct Run
  {
    vtkSmartPointer<vtkImageData> Image;
    dg::PipelineSettings Settings;
    long long Label = 0;
  };
  std::vector<Run> runs;
  std::vector<dg::LabelBox> labelBoxes;
  if (opt.Labels.empty())
  {
    runs.push_back({ image, opt.P, 0 });
  }
  else
  {
    dg::LabelSpec spec;
    std::string error;
    if (!dg::ParseLabelSpec(opt.Labels, spec, error) ||
      !dg::FindLabels(image, spec, labelBoxes, error))
      return Fail("--labels: " + error);
    const int margin = dg::LabelMargin(opt.P);
    for (const dg::LabelBox& box : opt.Interfaces ? std::vector<dg::LabelBox>() : labelBoxes)
    {
      Run run{ dg::CropImage(image, box.Extent, margin), opt.P, box.Label };
      run.Settings.SelectionMode = vtkDigitalSurfaceFilter::LABEL;
      run.Settings.Label = static_cast<double>(box.Label);
      runs.push_back(run);
    }
    lap("labels");
  }
  vtkNew<vtkAppendPolyData> appendSurfaces, appendFeatures;
  std::unique_ptr<dg::Pipeline> pipelinePtr;
  long long surfels = 0, atLines = 0, removed = 0, filled = 0, changed = 0;
  std::vector<std::string> perLabel;
  std::map<std::string, double> stageTimes;
  std::vector<std::string> stageOrder;
  for (Run& run : runs)
  {
    pipelinePtr.reset(new dg::Pipeline);
    dg::Pipeline& pipeline = *pipelinePtr;
    pipeline.Build(run.Image, run.Settings);
    for (const auto& stage : pipeline.Stages)
    {
      watch(stage.Algorithm);
      progress->Stage = labelBoxes.empty() ? stage.Name
                                           : "label " + std::to_string(run.Label) + ": " + stage.Name;
      const auto t0 = Clock::now();
      stage.Algorithm->Update();
      if (errors->Failed)
        return Fail((labelBoxes.empty() ? "" : "label " + std::to_string(run.Label) + ": ") +
          errors->Message);
      if (!stageTimes.count(stage.Name))
        stageOrder.push_back(stage.Name);
      stageTimes[stage.Name] += std::chrono::duration<double>(Clock::now() - t0).count();
    }
    const long long n = pipeline.Surface->GetOutput()->GetNumberOfPolys();
    surfels += n;
    atLines += pipeline.AT->GetOutput(1)->GetNumberOfLines();
    if (run.Settings.MinimumComponentSize > 1)
    {
      removed += pipeline.Islands->GetNumberOfRemovedIslands();
      filled += pipeline.Islands->GetNumberOfFilledCavities();
      changed += pipeline.Islands->GetNumberOfChangedVoxels();
    }
    if (labelBoxes.empty())
      break;
    // Each label's outputs, tagged, into one surface and one set of lines.
    for (vtkPolyData* pd : { pipeline.Result(), pipeline.Features() })
    {
      vtkNew<vtkPolyData> tagged;
      tagged->ShallowCopy(pd);
      vtkNew<vtkIntArray> label;
      label->SetName("Label");
      label->SetNumberOfTuples(pd->GetNumberOfCells());
      label->FillValue(static_cast<int>(run.Label));
      tagged->GetCellData()->AddArray(label);
      (pd == pipeline.Result() ? appendSurfaces.Get() : appendFeatures.Get())->AddInputData(tagged);
    }
    std::ostringstream line;
    line << "  label " << run.Label << ": " << n << " surfels, "
         << pipeline.Features()->GetNumberOfLines() << " feature edges";
    perLabel.push_back(line.str());
    run.Image = nullptr; // the crop is no longer needed
  }
  // --interfaces: every interface face once, one AT on the whole complex.
  vtkNew<vtkAmbrosioTortorelliFilter> interfacesAT;
  if (opt.Interfaces)
  {
    auto runStage = [&](vtkAlgorithm* algorithm, const std::string& name) {
      watch(algorithm);
      progress->Stage = name;
      const auto t0 = Clock::now();
      algorithm->Update();
      const std::string key = name.substr(name.find(": ") == std::string::npos ? 0 : name.find(": ") + 2);
      if (!stageTimes.count(key))
        stageOrder.push_back(key);
      stageTimes[key] += std::chrono::duration<double>(Clock::now() - t0).count();
      return !errors->Failed;
    };
    std::string error;
    auto merged = dg::LabelInterfaces(image, labelBoxes, opt.P, runStage, error);
    if (!merged)
      return Fail(errors->Failed ? errors->Message : error);
    interfacesAT->SetInputData(merged);
    dg::ConfigureAT(interfacesAT, opt.P);
    if (!runStage(interfacesAT, "Ambrosio-Tortorelli"))
      return Fail(errors->Message);
    surfels = merged->GetNumberOfPolys();
    atLines = interfacesAT->GetOutput(1)->GetNumberOfLines();
  }
  for (const auto& name : stageOrder)
  {
    times.emplace_back(name, stageTimes[name]);
  }
  t = Clock::now();
  vtkPolyData* result = nullptr;
  vtkPolyData* features = nullptr;
  const char* inputNormalsName = "IINormals";
  if (opt.Interfaces)
  {
    result = interfacesAT->GetOutput(0);
    features = interfacesAT->GetOutput(1);
  }
  else if (labelBoxes.empty())
  {
    result = pipelinePtr->Result();
    features = pipelinePtr->Features();
    inputNormalsName = pipelinePtr->InputNormalsName();
  }
  else
  {
    appendSurfaces->Update();
    appendFeatures->Update();
    result = appendSurfaces->GetOutput();
    features = appendFeatures->GetOutput();
    inputNormalsName = pipelinePtr->InputNormalsName();
    // The picture shows the active normals: keep the pipeline's choice.
    result->GetCellData()->SetActiveNormals(pipelinePtr->NormalsName());
    lap("append");
  }

  // 5. Files.
  OutputFiles files;
  const std::string base = (std::filesystem::path(opt.OutputDir) / prefix).string();
  // The writers' errors go to the catcher too: one line instead of VTK's
  // multi-line report, and the reason (errno text) is in it.
  auto written = [&](auto* w) {
    w->AddObserver(vtkCommand::ErrorEvent, errors);
    w->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    // Write() can return 1 when the file did not open; the error code tells.
    return w->Write() == 1 && w->GetErrorCode() == vtkErrorCode::NoError && !errors->Failed;
  };
  auto writeFailure = [&](const std::string& path) {
    return Fail("cannot write " + path + (errors->Message.empty() ? "" : " (" + errors->Message + ")"));
  };
  auto writeVtp = [&](vtkPolyData* pd, const std::string& path) {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetInputData(pd);
    w->SetFileName(files.Temporary(path).c_str());
    w->SetDataModeToBinary(); // appended data trips Debian's expat + VTK 9.2 reader
    // LZ4 by default: on octa-flower 512^3 it writes in 1.1-1.4 s against
    // zlib's 2.8-3.4 s (a fifth of the whole program), for files 1.35x larger
    // (101 against 74 MB).
    if (opt.Compression == "zlib")
      w->SetCompressorTypeToZLib();
    else if (opt.Compression == "none")
      w->SetCompressorTypeToNone();
    else
      w->SetCompressorTypeToLZ4();
    return written(w.Get());
  };
  if (!writeVtp(result, base + "_surface.vtp"))
    return writeFailure(base + "_surface.vtp");
  if (!writeVtp(features, base + "_features.vtp"))
    return writeFailure(base + "_features.vtp");
  if (opt.Ply)
  {
    vtkNew<vtkPLYWriter> w;
    w->SetInputData(result);
    w->SetFileName(files.Temporary(base + "_surface.ply").c_str());
    if (!written(w.Get()))
      return writeFailure(base + "_surface.ply");
  }
  if (opt.Obj)
  {
    vtkNew<vtkOBJWriter> w;
    w->SetInputData(result);
    w->SetFileName(files.Temporary(base + "_surface.obj").c_str());
    if (!written(w.Get()))
      return writeFailure(base + "_surface.obj");
  }
  lap("write");
  if (opt.Png)
  {
    dg::RenderOptions ro;
    ro.Width = opt.Width;
    ro.Height = opt.Height;
    ro.Panels = opt.Panels;
    std::string error;
    const std::string png = files.Temporary(base + ".png");
    if (!dg::RenderPicture(result, inputNormalsName, features, ro, png, error))
      return Fail(error);
    lap("render");
  }
  if (!files.Commit())
    return Fail("cannot rename the output files in '" + opt.OutputDir + "'");

  int dims[3];
  image->GetDimensions(dims);
  std::ostringstream stages;
  double total = 0;
  for (const auto& s : times)
  {
    stages << (total > 0 || &s != &times.front() ? ", " : "") << s.first << " " << std::fixed;
    stages.precision(3);
    stages << s.second << " s";
    total += s.second;
  }
  std::cout << Program << ": " << (opt.Input.empty() ? "built-in shape" : opt.Input) << " "
            << dims[0] << "x" << dims[1] << "x" << dims[2] << ": "
            << surfels << " surfels, " << features->GetNumberOfLines() << " feature edges";
  if (opt.Interfaces)
    std::cout << " (label interfaces, Ambrosio-Tortorelli's own output)";
  else if (opt.P.Sharpen && opt.P.SecondPass)
    std::cout << " (one line per edge, second pass; the first Ambrosio-Tortorelli alone: "
              << atLines << ")";
  else if (opt.P.Sharpen)
    std::cout << " (one line per edge; Ambrosio-Tortorelli alone: " << atLines << ")";
  if (!labelBoxes.empty())
    std::cout << ", " << labelBoxes.size() << " label" << (labelBoxes.size() == 1 ? "" : "s");
  std::cout << "\n";
  for (const auto& line : perLabel)
    std::cout << line << "\n";
  if (opt.P.MinimumComponentSize > 1)
    std::cout << "  removed " << removed << " inside components and filled " << filled
              << " cavities smaller than " << opt.P.MinimumComponentSize << " voxels (" << changed
              << " voxels)\n";
  std::cout
            << "  time: " << stages.str() << " (total " << total << " s); peak memory "
            << static_cast<long>(PeakMemoryMiB()) << " MiB\n";
  for (const auto& f : files.Finals)
    std::cout << "  wrote " << f << "\n";
  return 0;
}
