// The program's command line: its options, their parsing and --help.
#ifndef dgProgramOptions_h
#define dgProgramOptions_h

#include "dgImageInput.h"
#include "dgPipeline.h"

#include <string>

namespace dgapp
{
constexpr const char* Program = "piecewise-normals";

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
  std::string Labels;      // --labels: every label's surface in one run
  bool Interfaces = false; // --interfaces: the faces between labels, once
  // --mesh: the piecewise-smooth mesh (vtkPiecewiseSmoothMeshFilter) of the
  // final normals, in triangles on request, also as STL / PLY / OBJ.
  bool Mesh = false, MeshTriangles = false;
  bool MeshStl = false, MeshPly = false, MeshObj = false;
  double MeshTolerance = 1e-3; // vtkPiecewiseSmoothMeshFilter's SolverTolerance
};

/// Under mpirun every rank parses the same options: rank 0 alone prints
/// what is common to all ranks.
bool PrintsCommonMessages();

/// The options of argv; prints --help and exits 0, or prints one error and
/// exits 2 (rank 0 only under mpirun).
Options ParseOptions(int argc, char* argv[]);
} // namespace dgapp

#endif
