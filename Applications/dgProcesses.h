// The program's processes: one (the default) or the ranks of an MPI job when
// it is launched by mpirun with more than one process. Everything MPI-specific
// of the program lives here, so that a VTK without its MPI layer still builds
// the one-process program (DG_HAVE_MPI off).
//
// Under N > 1 ranks, rank r runs the pipeline for piece r of N (the filters
// find the controller through vtkMultiProcessController's global controller)
// and the helpers below reduce figures and gather what rank 0 alone needs.
#ifndef dgProcesses_h
#define dgProcesses_h

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <string>
#include <vector>

class vtkMultiProcessController;
class vtkXMLWriter;

namespace dg
{
class Processes
{
public:
  /// Rank and size as the launcher announces them in the environment
  /// (OpenMPI's OMPI_COMM_WORLD_*, MPICH/Hydra's PMI_*, PMIx's PMIX_RANK
  /// with OMPI size); 0 and 1 when not launched by mpirun. Known before MPI
  /// is initialised, so that option errors print once.
  static int LauncherRank();
  static int LauncherSize();
  /// True when this build can run as several processes.
  static bool Available();

  /// Starts MPI when the launcher announced more than one process (and
  /// makes its controller VTK's global one). False with error set when it
  /// cannot (no MPI in this build, MPI_Init failed).
  bool Initialize(int* argc, char*** argv, std::string& error);
  /// MPI_Finalize when Initialize started it; the last call of a successful run.
  void Finalize();
  ~Processes();

  int Rank() const { return this->LocalRank; }
  int Size() const { return this->NumberOfProcesses; }
  bool Distributed() const { return this->NumberOfProcesses > 1; }
  vtkMultiProcessController* Controller() const;

  /// Collective reductions over all ranks (the value itself with one process).
  long long Sum(long long value) const;
  double Max(double value) const;
  double Sum(double value) const;
  /// True on every rank when `ok` is true on every rank.
  bool All(bool ok) const;
  void Barrier() const;

  /// Rank 0 receives every rank's `piece` (only the listed cell and point
  /// arrays are sent; the active normals keep their role) and returns them
  /// appended; other ranks return nullptr. The appended surface keeps the
  /// pieces' copies of shared border points (the pictures and the mesh
  /// files do not need them merged). Collective.
  vtkSmartPointer<vtkPolyData> GatherToRoot(vtkPolyData* piece,
    const std::vector<std::string>& cellArrays,
    const std::vector<std::string>& pointArrays = {}) const;

  /// An XML writer of one piece of a parallel .pvtp (pieces PREFIX_r.vtp
  /// next to it, the summary written by rank 0; an empty piece is neither
  /// written nor listed); nullptr without MPI. Its Write() is collective.
  vtkSmartPointer<vtkXMLWriter> PieceWriter(vtkPolyData* piece, const std::string& pvtpPath) const;

private:
  int LocalRank = 0;
  int NumberOfProcesses = 1;
  bool Started = false;
  vtkSmartPointer<vtkMultiProcessController> MPI;
};
} // namespace dg

#endif
