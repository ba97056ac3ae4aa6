// libFuzzer target: vtkNIfTIVolumeReader (Filters/vtkNIfTIVolumeReader.cxx,
// the qform / sform geometry on top of VTK's vtkNIFTIImageReader) on
// arbitrary bytes written as a .nii file in a per-process temporary
// directory, read once in LPS and once in RAS (gzip input is skipped, see
// below).
//
// VTK 9.2's reader crashes on some corrupt headers (an unbounded datatype
// lookup, a division by dim[5], ...); the reader's header pre-check
// (HeaderProblem in vtkNIfTIVolumeReader.cxx) decodes the header as VTK
// does and refuses those first. A crash inside vtkNIFTIImageReader here is
// a class that check misses: refuse it there, and add the minimised input
// to corpus_nifti as regression_<what> (a read past VTK's datatype table
// crashes or not with the memory layout of the run: -minimize_crash may
// need a hand-made reproducer).
//
// Fails on any crash or sanitizer report, and when a promise of the
// reader's header breaks:
// - an error is reported with a non-empty message and leaves an empty
//   output;
// - without an error: a non-empty image whose scalars cover its points,
//   finite origin, spacing > 0, a direction of unit columns at right angles
//   within the shear tolerance the reader accepts (|cos| <= 1e-4);
// - RAS is LPS with x and y negated (same outcome, same spacing);
// - pieces 0 and 1 of 2 and the first slice (read from the file by the
//   reader's own part read, not VTK's whole read) succeed when the whole
//   read does and hold its voxels, byte for byte, with its geometry.
#include "vtkNIfTIVolumeReader.h"
#include "dgFuzzSupport.h"

#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkObject.h>
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
std::string Dir, Path;

class Collect : public vtkCommand
{
public:
  static Collect* New() { return new Collect; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    if (event == vtkCommand::ErrorEvent)
    {
      ++this->Errors;
      if (!data || !*static_cast<const char*>(data))
        std::abort(); // an error without a message
    }
  }
  int Errors = 0;
};

void Cleanup()
{
  if (!Dir.empty())
  {
    std::remove(Path.c_str());
    rmdir(Dir.c_str());
  }
}

struct Result
{
  bool Ok = false;
  int Dims[3] = { 0, 0, 0 };
  double Origin[3], Spacing[3], Direction[9];
};

Result Read(int system)
{
  vtkNew<Collect> collect;
  vtkNew<vtkNIfTIVolumeReader> reader;
  reader->AddObserver(vtkCommand::ErrorEvent, collect);
  reader->AddObserver(vtkCommand::WarningEvent, collect);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, collect);
  reader->SetFileName(Path.c_str());
  reader->SetCoordinateSystem(system);
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  Result r;
  if (collect->Errors)
  {
    if (image->GetNumberOfPoints() != 0)
      std::abort(); // an error leaves an empty output
    return r;
  }
  r.Ok = true;
  const vtkIdType n = image->GetNumberOfPoints();
  vtkDataArray* s = image->GetPointData()->GetScalars();
  if (n <= 0 || !s || s->GetNumberOfTuples() != n)
    std::abort();
  image->GetDimensions(r.Dims);
  image->GetOrigin(r.Origin);
  image->GetSpacing(r.Spacing);
  for (int i = 0; i < 9; ++i)
    r.Direction[i] = image->GetDirectionMatrix()->GetData()[i];
  dgfuzz::CheckGridGeometry(r.Origin, r.Spacing, r.Direction);
  return r;
}
// The part reads against the whole read (issue 38's ReadBox).
void ComparePieces()
{
  vtkNew<vtkNIfTIVolumeReader> whole;
  whole->SetFileName(Path.c_str());
  whole->Update();
  vtkImageData* w = whole->GetOutput();
  vtkDataArray* ws = w->GetPointData()->GetScalars();
  int we[6];
  w->GetExtent(we);
  const int slice[6] = { we[0], we[1], we[2], we[3], we[4], we[4] };
  for (int request = 0; request < 3; ++request)
  {
    vtkNew<Collect> collect;
    vtkNew<vtkNIfTIVolumeReader> reader;
    reader->AddObserver(vtkCommand::ErrorEvent, collect);
    reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, collect);
    reader->SetFileName(Path.c_str());
    if (request < 2)
      reader->UpdatePiece(request, 2, 0);
    else
    {
      reader->UpdateInformation();
      reader->UpdateExtent(const_cast<int*>(slice));
    }
    vtkImageData* p = reader->GetOutput();
    vtkDataArray* ps = p->GetPointData()->GetScalars();
    if (collect->Errors || !ps || ps->GetDataType() != ws->GetDataType() ||
      ps->GetNumberOfComponents() != ws->GetNumberOfComponents())
      std::abort(); // the whole read succeeded: so must its parts
    int e[6];
    p->GetExtent(e);
    const int bytes = ws->GetDataTypeSize() * ws->GetNumberOfComponents();
    for (int k = e[4]; k <= e[5]; ++k)
      for (int j = e[2]; j <= e[3]; ++j)
        for (int i = e[0]; i <= e[1]; ++i)
        {
          int ijk[3] = { i, j, k };
          const auto* a = static_cast<const unsigned char*>(ws->GetVoidPointer(0)) +
            w->ComputePointId(ijk) * bytes;
          const auto* b = static_cast<const unsigned char*>(ps->GetVoidPointer(0)) +
            p->ComputePointId(ijk) * bytes;
          if (std::memcmp(a, b, bytes) != 0)
            std::abort();
        }
    for (int a = 0; a < 3; ++a)
      if (p->GetOrigin()[a] != w->GetOrigin()[a] || p->GetSpacing()[a] != w->GetSpacing()[a])
        std::abort();
  }
}
} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
  // Quiet without GlobalWarningDisplayOff, which would silence the error
  // events the reader and this target rely on.
  vtkOutputWindow::GetInstance()->SetDisplayModeToNever();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (Dir.empty())
  {
    Dir = dgfuzz::MakeScratchDirectory("nifti");
    Path = Dir + "/v.nii";
    std::atexit(Cleanup);
  }
  // gzip streams are skipped: vtkNIFTIImageReader allocates the volume
  // their header declares before inflating, and their length bounds nothing
  // (VTK's code, not this module's; an uncompressed file is checked).
  if (size >= 2 && data[0] == 0x1f && data[1] == 0x8b)
    return 0;
  std::FILE* f = std::fopen(Path.c_str(), "wb");
  if (!f || (size && std::fwrite(data, 1, size, f) != size))
    std::abort();
  std::fclose(f);

  const Result lps = Read(vtkNIfTIVolumeReader::LPS);
  const Result ras = Read(vtkNIfTIVolumeReader::RAS);
  if (lps.Ok != ras.Ok)
    std::abort();
  if (lps.Ok)
  {
    for (int r = 0; r < 3; ++r)
    {
      const double sign = r < 2 ? -1 : 1;
      if (lps.Dims[r] != ras.Dims[r] || ras.Spacing[r] != lps.Spacing[r] ||
        ras.Origin[r] != sign * lps.Origin[r])
        std::abort();
      for (int a = 0; a < 3; ++a)
        if (ras.Direction[3 * r + a] != sign * lps.Direction[3 * r + a])
          std::abort();
    }
    ComparePieces();
  }
  return 0;
}
