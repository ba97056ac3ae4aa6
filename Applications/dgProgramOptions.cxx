#include "dgProgramOptions.h"

#include "dgLabels.h"
#include "dgProcesses.h"

#include <vtkVersion.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>

namespace dgapp
{
// Under mpirun every rank parses the same options: rank 0 alone says what
// is wrong with them (one message), every rank exits.
bool PrintsCommonMessages()
{
  return dg::Processes::LauncherRank() == 0;
}

namespace
{
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

Inside voxels (default: value != 0, for unsigned masks and label maps; a
float or signed volume needs --range, --label or --labels)
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
  --solver-tolerance-early F  that tolerance times F >= 1 on the epsilon levels
                         before the last (sqrt(F) per level, at most F; default
                         1): 6 takes about 15 % off AT's time on large surfaces,
                         within the budget of the exact solve (docs/at-speed.md)
Sharp features (after AT: one line per sharp edge, side normals up to it)
  --plain                the paper's own output instead: AT's normals and its
                         feature edges (a band of ladders along each edge)
  --second-pass          AT again on the side normals, then the sharp stage again:
                         normals closer to the truth near the edges, twice AT's time
Curvature (corrected curvature measures of the final normals, docs/curvature-measures.md)
  --curvature            mean, Gaussian and principal curvatures per face, each
                         side of a crease measured on its own, the creases'
                         angles, whole-surface figures (area, specific surface
                         area, integral of H, Euler characteristic); writes
                         PREFIX_creases.vtp and the picture PREFIX_curvature.png
  --curvature-radius R   their ball radius in voxels (default 6: the first pass's,
                         and the scale of each face's own, 2/3 to 3 times it,
                         chosen from the noise and the variation of the
                         curvature around the face; implies --curvature)
  --curvature-fixed-radius  one ball radius for every face, R (implies --curvature)
Mesh (vertices moved to follow the final normals, sharp edges kept, docs/mesh.md)
  --mesh                 the piecewise-smooth mesh: each vertex moved within its
                         voxel corner's cell so that the faces follow the normals
                         and the feature lines stay creases; writes
                         PREFIX_mesh.vtp (point normals split along the creases),
                         PREFIX_mesh_creases.vtp and the picture PREFIX_mesh.png
  --mesh-triangles       the mesh in triangles (each quad split along the diagonal
                         that follows its normal best); implies --mesh
  --mesh-format LIST     also write the mesh as stl, ply and/or obj ("stl,ply"),
                         with normals (STL: per facet; implies --mesh-triangles)
  --mesh-tolerance T     the mesh solve's relative residual per iteration (default
                         1e-3; several processes give one process's positions
                         to about T voxel: 1e-10 within 1e-8)
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
  --version              the program's version (and VTK's), then exit

Writes PREFIX_surface.vtp (cell data: SharpNormals (active), FeatureRegion,
CreaseSides (per face, bit i: its side i is a feature edge), ATNormals,
IINormals (VCMNormals, RHTNormals with --estimator), trivial Normals; point
data: v = ATFeatureIndicator),
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
The output is the one-process default output: the sharp-features stage
gathers the surface on rank 0; --ply, --obj and --mesh-format gather what they
write there. The picture gathers the surface (points, quads, three normal
fields) and the lines on rank 0: about 125 bytes per surfel there (twice that
while the pieces arrive); --no-png avoids it. Each rank reads only its piece of
the volume and the layers around it that the stages need (--noise: 25
layers at k = 0.3, 43 at 0.5 for a 256^3 volume: the noise is one process's);
DICOM and the built-in shape are held whole on every rank.

Memory pages: the program runs itself again at start-up with glibc's
huge-page malloc (GLIBC_TUNABLES=glibc.malloc.hugetlb=1; 2 MiB pages, far
fewer page faults: on a 512^3 volume the whole run took 6.9 s instead of
8.6 s), with the same results; not under mpirun. DG_HUGEPAGES=0 in the
environment turns that and the module's own huge-page advice off.
)";
}

[[noreturn]] void OptionError(const std::string& message)
{
  if (PrintsCommonMessages())
  {
    std::cerr << Program << ": " << message << " (see --help)\n";
    std::exit(2);
  }
  // Under mpirun every rank finds the same error before MPI starts. The
  // other ranks leave quietly with 0: had they exited with 2, mpirun could
  // end rank 0 before it printed why (seen as an empty message under load).
  // The job's status is rank 0's 2.
  std::exit(0);
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

} // namespace

Options ParseOptions(int argc, char* argv[])
{
  Options o;
  for (int a = 1; a < argc; ++a)
  {
    const std::string arg = argv[a];
    auto value = [&]() -> std::string
    {
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
    else if (arg == "--version")
    {
      if (PrintsCommonMessages())
        std::cout << Program << " " << DG_VERSION << " (VTK " << vtkVersion::GetVTKVersion()
                  << ")\n";
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
    else if (arg == "--curvature")
      o.P.Curvature = true;
    else if (arg == "--curvature-fixed-radius")
    {
      o.P.Curvature = true;
      o.P.CurvatureFixedRadius = true;
    }
    else if (arg == "--curvature-radius")
    {
      o.P.Curvature = true;
      o.P.CurvatureRadius = number();
      if (!(o.P.CurvatureRadius > 0))
        OptionError("--curvature-radius must be > 0 (voxels)");
    }
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
    else if (arg == "--solver-tolerance-early")
      o.P.SolverToleranceEarlyFactor = number();
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
    else if (arg == "--mesh")
      o.Mesh = true;
    else if (arg == "--mesh-triangles")
      o.Mesh = o.MeshTriangles = true;
    else if (arg == "--mesh-tolerance")
    {
      o.Mesh = true;
      o.MeshTolerance = number();
      if (!(o.MeshTolerance > 0 && o.MeshTolerance < 1))
        OptionError("--mesh-tolerance must be in (0, 1)");
    }
    else if (arg == "--mesh-format")
    {
      o.Mesh = true;
      std::string list = value(), item;
      std::stringstream items(list);
      int n = 0;
      while (std::getline(items, item, ','))
      {
        ++n;
        if (item == "stl")
          o.MeshStl = o.MeshTriangles = true;
        else if (item == "ply")
          o.MeshPly = true;
        else if (item == "obj")
          o.MeshObj = true;
        else
          OptionError("--mesh-format expects stl, ply and/or obj, separated by commas (got '" +
            item + "')");
      }
      if (n == 0)
        OptionError("--mesh-format expects stl, ply and/or obj, separated by commas");
    }
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
  if (!(o.P.SolverToleranceEarlyFactor >= 1 && std::isfinite(o.P.SolverToleranceEarlyFactor)))
    OptionError("--solver-tolerance-early must be a finite number >= 1");
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
  if (o.P.Curvature && !o.Labels.empty())
    OptionError("--curvature measures one surface: drop --labels (or --label L for one label)");
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
} // namespace dgapp
