#include "vtkOrientedImageReader.h"

#include "dgImageHeader.h"
#include "dgPieces.h"

#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMetaImageReader.h>
#include <vtkNew.h>
#include <vtkNrrdReader.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringOutputWindow.h>

#include <algorithm>
#include <cctype>

vtkStandardNewMacro(vtkOrientedImageReader);

namespace
{
enum class Format
{
  None,
  MetaImage,
  Nrrd
};

Format FormatOf(const char* fname)
{
  const std::string path = fname ? fname : "";
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return Format::None;
  std::string e = path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  if (e == "mha" || e == "mhd")
    return Format::MetaImage;
  if (e == "nrrd" || e == "nhdr")
    return Format::Nrrd;
  return Format::None;
}

vtkSmartPointer<vtkImageReader2> ReaderFor(Format f)
{
  if (f == Format::MetaImage)
    return vtkSmartPointer<vtkMetaImageReader>::New();
  if (f == Format::Nrrd)
    return vtkSmartPointer<vtkNrrdReader>::New();
  return nullptr;
}

// The last non-empty line of a VTK report: what went wrong, without the
// "file, line" prefix.
std::string LastLine(std::string m)
{
  while (!m.empty() && (m.back() == '\n' || m.back() == ' '))
    m.pop_back();
  const auto nl = m.find_last_of('\n');
  return nl == std::string::npos ? m : m.substr(nl + 1);
}

// Everything VTK's reader says while it runs: its errors and warnings
// through observers, and the warnings vtkImageReader2 sends to the global
// output window only (a short read is one), through a string window put in
// place for the duration and restored after.
class ReportCapture : public vtkCommand
{
public:
  static ReportCapture* New() { return new ReportCapture; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (this->Message.empty() && data)
      this->Message = LastLine(static_cast<const char*>(data));
    if (this->Message.empty())
      this->Message = "reader error";
  }
  void Start(vtkAlgorithm* reader)
  {
    this->Reader = reader;
    this->Tags[0] = reader->AddObserver(vtkCommand::ErrorEvent, this);
    this->Tags[1] = reader->AddObserver(vtkCommand::WarningEvent, this);
    this->Tags[2] = reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, this);
    this->Previous = vtkOutputWindow::GetInstance();
    vtkOutputWindow::SetInstance(this->Window);
  }
  // The one-line problem, or empty when the read went through.
  std::string Stop()
  {
    vtkOutputWindow::SetInstance(this->Previous);
    this->Reader->RemoveObserver(this->Tags[0]);
    this->Reader->RemoveObserver(this->Tags[1]);
    this->Reader->GetExecutive()->RemoveObserver(this->Tags[2]);
    const std::string text = this->Window->GetOutput();
    if (text.find("File operation failed") != std::string::npos)
      return "the file is shorter than its header says (truncated)";
    if (this->Message.empty() && !text.empty())
      return LastLine(text);
    return this->Message;
  }

private:
  std::string Message;
  vtkAlgorithm* Reader = nullptr;
  unsigned long Tags[3] = { 0, 0, 0 };
  vtkSmartPointer<vtkOutputWindow> Previous;
  vtkNew<vtkStringOutputWindow> Window;
};
} // namespace

vtkOrientedImageReader::vtkOrientedImageReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkOrientedImageReader::~vtkOrientedImageReader()
{
  this->SetFileName(nullptr);
}

int vtkOrientedImageReader::CanReadFile(const char* fname)
{
  vtkSmartPointer<vtkImageReader2> r = ReaderFor(FormatOf(fname));
  return r && r->CanReadFile(fname) ? 1 : 0;
}

int vtkOrientedImageReader::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  this->Inner = nullptr;
  this->Oriented = false;
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro(<< "no FileName set");
    return 0;
  }
  const Format format = FormatOf(this->FileName);
  vtkSmartPointer<vtkImageReader2> inner = ReaderFor(format);
  if (!inner)
  {
    vtkErrorMacro(<< this->FileName
                  << ": not a MetaImage (.mha, .mhd) or NRRD (.nrrd, .nhdr) file name");
    return 0;
  }
  const char* what = format == Format::Nrrd ? "NRRD" : "MetaImage";
  if (!inner->CanReadFile(this->FileName))
  {
    vtkErrorMacro(<< this->FileName << ": not a readable " << what
                  << " file (or it cannot be opened)");
    return 0;
  }
  dg::HeaderGeometry g;
  const std::string why = dg::ReadHeaderGeometry(
    this->FileName, format == Format::Nrrd, this->CoordinateSystem == RAS, g);
  if (!why.empty())
  {
    vtkErrorMacro(<< this->FileName << ": " << why);
    return 0;
  }
  if (format == Format::MetaImage)
  {
    const std::string shortData = dg::CheckMetaImageDataSize(this->FileName);
    if (!shortData.empty())
    {
      vtkErrorMacro(<< this->FileName << ": " << shortData);
      return 0;
    }
  }
  inner->SetFileName(this->FileName);
  vtkNew<ReportCapture> capture;
  capture->Start(inner);
  inner->UpdateInformation();
  const std::string problem = capture->Stop();
  if (!problem.empty())
  {
    vtkErrorMacro(<< this->FileName << ": " << problem);
    return 0;
  }
  vtkInformation* in = inner->GetOutputInformation(0);
  vtkInformation* out = outputVector->GetInformationObject(0);
  int whole[6];
  in->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  int components = 1;
  if (vtkInformation* scalar = vtkDataObject::GetActiveFieldInformation(
        in, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS))
  {
    components = scalar->Get(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS());
  }
  int sizes[3];
  this->FirstAxisAsComponents = format == Format::Nrrd &&
                                dg::NrrdHasThreeSpatialAxes(this->FileName, sizes) &&
                                components == sizes[0] && whole[1] - whole[0] + 1 == sizes[1] &&
                                whole[3] - whole[2] + 1 == sizes[2] && whole[5] == whole[4];
  if (this->FirstAxisAsComponents)
  {
    const int grid[6] = { 0, sizes[0] - 1, 0, sizes[1] - 1, 0, sizes[2] - 1 };
    std::copy(grid, grid + 6, whole);
    components = 1;
    if (!g.Has)
    {
      // VTK's reader put the first axis's spacing on the second, and so on.
      double o[3] = { 0, 0, 0 }, s[3] = { 1, 1, 1 };
      in->Get(vtkDataObject::ORIGIN(), o);
      in->Get(vtkDataObject::SPACING(), s);
      vtkErrorMacro(<< this->FileName
                    << ": a 3-D NRRD whose first axis is shorter than 10 voxels needs space "
                       "directions (VTK's reader loses its spacing otherwise)");
      return 0;
    }
  }
  std::copy(whole, whole + 6, this->Whole);
  if (g.Has)
  {
    std::copy(g.Origin, g.Origin + 3, this->Origin);
    std::copy(g.Spacing, g.Spacing + 3, this->Spacing);
    std::copy(g.Direction, g.Direction + 9, this->Direction);
    this->Oriented = true;
  }
  else
  {
    in->Get(vtkDataObject::ORIGIN(), this->Origin);
    in->Get(vtkDataObject::SPACING(), this->Spacing);
    const double identity[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    std::copy(identity, identity + 9, this->Direction);
  }
  out->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole, 6);
  out->Set(vtkDataObject::ORIGIN(), this->Origin, 3);
  out->Set(vtkDataObject::SPACING(), this->Spacing, 3);
  out->Set(vtkDataObject::DIRECTION(), this->Direction, 9);
  out->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  if (vtkInformation* scalar = vtkDataObject::GetActiveFieldInformation(
        in, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS))
  {
    vtkDataObject::SetPointDataActiveScalarInfo(
      out, scalar->Get(vtkDataObject::FIELD_ARRAY_TYPE()), components);
  }
  this->Inner = inner;
  return 1;
}

int vtkOrientedImageReader::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  output->Initialize();
  if (!this->Inner)
  {
    vtkErrorMacro(<< (this->FileName ? this->FileName : "(no file)")
                  << ": the header could not be read");
    return 0;
  }
  int ext[6];
  outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
  if (ext[0] > ext[1] || ext[2] > ext[3] || ext[4] > ext[5])
  {
    return 1; // an empty piece: nothing to read
  }
  // vtkNrrdReader reads a sub-extent; vtkMetaImageReader does not (it
  // writes the whole volume into a buffer of the requested extent's size:
  // heap corruption), so it reads the whole volume and the box is copied out.
  // vtkNrrdReader reads a sub-extent; vtkMetaImageReader does not (it
  // writes the whole volume into a buffer of the requested extent's size:
  // heap corruption), so it reads the whole volume and the box is copied
  // out; so does a NRRD whose first axis VTK reads as components.
  int innerWhole[6], read[6];
  this->Inner->GetOutputInformation(0)->Get(
    vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), innerWhole);
  const bool subExtents =
    !this->FirstAxisAsComponents &&
    this->Inner->GetOutputInformation(0)->Get(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT()) == 1;
  std::copy(subExtents ? ext : innerWhole, (subExtents ? ext : innerWhole) + 6, read);
  if (!dg::ExtentContains(this->Whole, ext))
  {
    vtkErrorMacro(<< this->FileName
                  << ": requested extent outside the file's extent (the file changed?)");
    return 0;
  }
  vtkNew<ReportCapture> capture;
  capture->Start(this->Inner);
  this->Inner->UpdateExtent(read);
  const std::string problem = capture->Stop();
  vtkSmartPointer<vtkImageData> image = this->Inner->GetOutput();
  if (!problem.empty())
  {
    vtkErrorMacro(<< this->FileName << ": " << problem);
    return 0;
  }
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (this->FirstAxisAsComponents && scalars &&
      static_cast<vtkIdType>(scalars->GetNumberOfComponents()) == this->Whole[1] + 1)
  {
    // Components fastest, then the 2-D image's x and y: the 3-D grid's
    // voxel order. The same array, one component.
    vtkSmartPointer<vtkDataArray> folded = vtk::TakeSmartPointer(scalars->NewInstance());
    folded->ShallowCopy(scalars);
    folded->SetNumberOfComponents(1);
    folded->SetNumberOfTuples(scalars->GetNumberOfValues());
    auto grid = vtkSmartPointer<vtkImageData>::New();
    grid->SetExtent(this->Whole);
    grid->GetPointData()->SetScalars(folded);
    image = grid;
    scalars = folded;
  }
  int got[6] = { 0, -1, 0, -1, 0, -1 };
  if (image)
    image->GetExtent(got);
  if (!scalars || !dg::ExtentContains(got, ext) ||
      scalars->GetNumberOfTuples() != image->GetNumberOfPoints())
  {
    vtkErrorMacro(<< this->FileName << ": no voxel data (truncated or corrupt file?)");
    return 0;
  }
  dg::CropImageToExtent(image, ext, output);
  if (!subExtents)
  {
    // The whole volume is not kept between executions.
    this->Inner->GetOutput()->ReleaseData();
  }
  output->SetOrigin(this->Origin);
  output->SetSpacing(this->Spacing);
  output->SetDirectionMatrix(this->Direction);
  return 1;
}

void vtkOrientedImageReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "CoordinateSystem: " << (this->CoordinateSystem == LPS ? "LPS" : "RAS") << "\n";
  os << indent << "Oriented: " << (this->Oriented ? "yes" : "no") << "\n";
}
