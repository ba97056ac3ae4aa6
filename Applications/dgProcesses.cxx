#include "dgProcesses.h"

#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkXMLWriter.h>

#ifdef DG_HAVE_MPI
#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkCommunicator.h>
#include <vtkLogger.h>
#include <vtkMPIController.h>
#include <vtkMultiProcessController.h>
#include <vtkXMLPPolyDataWriter.h>
#endif

#include <cstdlib>
#include <string>

namespace dg
{
namespace
{
int EnvironmentInteger(const char* const* names, int fallback)
{
  for (const char* const* n = names; *n; ++n)
  {
    if (const char* v = std::getenv(*n))
    {
      char* end = nullptr;
      const long x = std::strtol(v, &end, 10);
      if (end != v && *end == '\0' && x >= 0 && x < (1L << 30))
        return static_cast<int>(x);
    }
  }
  return fallback;
}
} // namespace

int Processes::LauncherRank()
{
  static const char* const names[] = { "OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK", nullptr };
  return EnvironmentInteger(names, 0);
}

int Processes::LauncherSize()
{
  static const char* const names[] = { "OMPI_COMM_WORLD_SIZE", "PMI_SIZE", nullptr };
  return EnvironmentInteger(names, 1);
}

bool Processes::Available()
{
#ifdef DG_HAVE_MPI
  return true;
#else
  return false;
#endif
}

bool Processes::Initialize(int* argc, char*** argv, std::string& error)
{
  if (LauncherSize() <= 1)
    return true; // one process: no MPI at all, as before
#ifdef DG_HAVE_MPI
  auto mpi = vtkSmartPointer<vtkMPIController>::New();
  mpi->Initialize(argc, argv);
  // VTK's MPI start-up turns its logger on, which prints every VTK error
  // to stderr by itself (colour codes, stack of requests) besides the
  // output window that the program reads them from: messages go through
  // the output window alone, as with one process.
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  this->Started = true;
  this->MPI = mpi;
  vtkMultiProcessController::SetGlobalController(mpi);
  this->LocalRank = mpi->GetLocalProcessId();
  this->NumberOfProcesses = mpi->GetNumberOfProcesses();
  return true;
#else
  (void)argc;
  (void)argv;
  error = "launched as " + std::to_string(LauncherSize()) +
    " processes, but this build has no MPI (its VTK lacks ParallelMPI): run it as one process";
  return false;
#endif
}

void Processes::Finalize()
{
#ifdef DG_HAVE_MPI
  if (this->Started)
  {
    vtkMultiProcessController::SetGlobalController(nullptr);
    this->MPI->Finalize();
    this->MPI = nullptr;
    this->Started = false;
  }
#endif
}

Processes::~Processes()
{
  // A failed run exits without MPI_Finalize on purpose: mpirun then ends
  // the other ranks, which may wait in a collective operation.
}

vtkMultiProcessController* Processes::Controller() const
{
#ifdef DG_HAVE_MPI
  return this->MPI;
#else
  return nullptr;
#endif
}

#ifdef DG_HAVE_MPI
namespace
{
template <typename T>
T Reduced(vtkMultiProcessController* mpi, T value, int operation)
{
  if (!mpi)
    return value;
  T out{};
  mpi->AllReduce(&value, &out, 1, operation);
  return out;
}
} // namespace
#endif

long long Processes::Sum(long long value) const
{
#ifdef DG_HAVE_MPI
  return Reduced(this->MPI.Get(), value, vtkCommunicator::SUM_OP);
#else
  return value;
#endif
}

double Processes::Sum(double value) const
{
#ifdef DG_HAVE_MPI
  return Reduced(this->MPI.Get(), value, vtkCommunicator::SUM_OP);
#else
  return value;
#endif
}

double Processes::Max(double value) const
{
#ifdef DG_HAVE_MPI
  return Reduced(this->MPI.Get(), value, vtkCommunicator::MAX_OP);
#else
  return value;
#endif
}

bool Processes::All(bool ok) const
{
#ifdef DG_HAVE_MPI
  return Reduced(this->MPI.Get(), ok ? 1 : 0, vtkCommunicator::MIN_OP) == 1;
#else
  return ok;
#endif
}

void Processes::Barrier() const
{
#ifdef DG_HAVE_MPI
  if (this->MPI)
    this->MPI->Barrier();
#endif
}

vtkSmartPointer<vtkPolyData> Processes::GatherToRoot(vtkPolyData* piece,
  const std::vector<std::string>& cellArrays, const std::vector<std::string>& pointArrays) const
{
#ifdef DG_HAVE_MPI
  if (this->MPI)
  {
    // Only what the picture needs travels: points, cells and the listed
    // cell arrays.
    vtkNew<vtkPolyData> slim;
    slim->SetPoints(piece->GetPoints());
    slim->SetVerts(piece->GetVerts());
    slim->SetLines(piece->GetLines());
    slim->SetPolys(piece->GetPolys());
    slim->SetStrips(piece->GetStrips());
    vtkCellData* cd = piece->GetCellData();
    for (const auto& name : cellArrays)
    {
      if (vtkDataArray* a = cd->GetArray(name.c_str()))
      {
        slim->GetCellData()->AddArray(a);
        if (a == cd->GetNormals())
          slim->GetCellData()->SetNormals(a);
      }
    }
    vtkPointData* pd = piece->GetPointData();
    for (const auto& name : pointArrays)
    {
      if (vtkDataArray* a = pd->GetArray(name.c_str()))
      {
        slim->GetPointData()->AddArray(a);
        if (a == pd->GetNormals())
          slim->GetPointData()->SetNormals(a);
      }
    }
    std::vector<vtkSmartPointer<vtkDataObject>> received;
    this->MPI->Gather(slim, received, 0);
    if (this->LocalRank != 0)
      return nullptr;
    vtkNew<vtkAppendPolyData> append;
    int inputs = 0;
    for (auto& d : received)
    {
      // Empty pieces may lack the arrays, which would drop them from the
      // appended result: leave them out.
      auto* pd = vtkPolyData::SafeDownCast(d);
      if (pd && pd->GetNumberOfCells() > 0)
      {
        append->AddInputData(pd);
        ++inputs;
      }
    }
    auto out = vtkSmartPointer<vtkPolyData>::New();
    if (inputs == 0)
    {
      out->DeepCopy(slim);
      return out;
    }
    append->Update();
    out->ShallowCopy(append->GetOutput());
    return out;
  }
#endif
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(piece);
  return out;
}

vtkSmartPointer<vtkXMLWriter> Processes::PieceWriter(vtkPolyData* piece, const std::string& pvtpPath) const
{
#ifdef DG_HAVE_MPI
  auto w = vtkSmartPointer<vtkXMLPPolyDataWriter>::New();
  w->SetInputData(piece);
  w->SetFileName(pvtpPath.c_str());
  w->SetNumberOfPieces(this->NumberOfProcesses);
  w->SetStartPiece(this->LocalRank);
  w->SetEndPiece(this->LocalRank);
  w->SetGhostLevel(0);
  w->SetController(this->MPI);
  // On every rank: the summary step is collective (rank 0 learns which
  // pieces hold data, and alone writes the .pvtp).
  w->SetWriteSummaryFile(1);
  return w;
#else
  (void)piece;
  (void)pvtpPath;
  return nullptr;
#endif
}
} // namespace dg
