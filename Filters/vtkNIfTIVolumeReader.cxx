#include "vtkNIfTIVolumeReader.h"

#include "dgPieces.h"

#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkMatrix3x3.h>
#include <vtkMatrix4x4.h>
#include <vtkNIFTIImageHeader.h>
#include <vtkNIFTIImageReader.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkCellData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtk_zlib.h>
#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

vtkStandardNewMacro(vtkNIfTIVolumeReader);

vtkNIfTIVolumeReader::vtkNIfTIVolumeReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkNIfTIVolumeReader::~vtkNIfTIVolumeReader()
{
  this->SetFileName(nullptr);
}

int vtkNIfTIVolumeReader::CanReadFile(const char* fname)
{
  vtkNew<vtkNIFTIImageReader> r;
  return fname && r->CanReadFile(fname) ? 1 : 0;
}

namespace
{
// vtkNIFTIImageReader with its errors collected instead of printed.
struct Quiet : public vtkCommand
{
  static Quiet* New() { return new Quiet; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    if (this->Message.empty() && data)
      this->Message = static_cast<const char*>(data);
  }
  std::string Message;
};

// Empty, or the problem when the header of fileName (or of its .hdr for a
// .img) holds a datatype NIfTI does not define or a dim[0] outside 1..7 in
// both byte orders: VTK 9.2's vtkNIFTIImageReader crashes on such headers
// in RequestInformation (SIGSEGV seen for datatypes 2305, 2560, 4866, -5,
// and for dim[0] = 0: out-of-bounds reads), so they are refused before it
// gets there.
std::string HeaderProblem(const std::string& fileName)
{
  std::string header = fileName;
  const std::string lower = vtksys::SystemTools::LowerCase(fileName);
  for (const char* img : { ".img", ".img.gz" })
  {
    const std::size_t n = std::strlen(img);
    if (lower.size() > n && lower.compare(lower.size() - n, n, img) == 0)
    {
      const bool upper = header.compare(header.size() - n, 4, ".IMG") == 0;
      header.replace(header.size() - n, 4, upper ? ".HDR" : ".hdr");
    }
  }
  gzFile f = gzopen(header.c_str(), "rb");
  if (!f)
    return ""; // VTK's reader says why
  unsigned char h[348];
  const int got = gzread(f, h, sizeof h);
  gzclose(f);
  // The version as vtkNIFTIImageReader finds it: NIfTI-2's magic at 4,
  // NIfTI-1's at 344, else an Analyze header (sizeof_hdr 348, any order);
  // the byte order from dim[0] (1..7).
  auto magic = [&](int at, char v) {
    return got >= at + 4 && h[at] == 'n' && (h[at + 1] == '+' || h[at + 1] == 'i') &&
      h[at + 2] == v && h[at + 3] == 0;
  };
  int at = -1, dim0 = -1;
  if (magic(4, '2'))
    at = 12, dim0 = 16;
  else if (got == 348 && (magic(344, '1') || (h[0] == 92 && h[1] == 1 && !h[2] && !h[3]) ||
                          (!h[0] && !h[1] && h[2] == 1 && h[3] == 92)))
    at = 70, dim0 = 40;
  if (at < 0)
    return ""; // not a header: VTK's reader says so
  const int little = h[dim0] | h[dim0 + 1] << 8;
  const int big = h[dim0] << 8 | h[dim0 + 1];
  // (NIfTI-1 and Analyze: a 2-byte dim[0]; NIfTI-2's is 8 bytes, left to VTK.)
  if (dim0 == 40 && !(little >= 1 && little <= 7) && !(big >= 1 && big <= 7))
    return "dim[0] is " + std::to_string(little) + ", not a number of dimensions (1 to 7): a corrupt header?";
  const bool swap = !(little >= 1 && little <= 7);
  const short datatype = static_cast<short>(swap ? (h[at] << 8 | h[at + 1]) : (h[at] | h[at + 1] << 8));
  for (int known : { 0, 1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 768, 1024, 1280, 1536, 1792, 2048, 2304 })
    if (datatype == known)
      return "";
  return "unknown NIfTI datatype " + std::to_string(datatype) + " (a corrupt header?)";
}

// A header without voxels, or an uncompressed single file (.nii) shorter
// than its header's first volume: empty when it is long enough (or
// compressed, or a .hdr/.img pair), else the problem. vtkNIFTIImageReader
// allocates the volume the header declares before reading it, so a few
// bytes claiming 2^40 voxels would otherwise allocate that much.
std::string CheckDataSize(const char* fileName, vtkNIFTIImageReader* r)
{
  vtkNIFTIImageHeader* h = r->GetNIFTIHeader();
  vtkInformation* info = r->GetOutputInformation(0);
  int ext[6] = { 0, -1, 0, -1, 0, -1 };
  info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), ext);
  // No voxel at all (a dimension of 0): vtkNIFTIImageReader's RequestData
  // can spin for minutes on it.
  if (ext[1] < ext[0] || ext[3] < ext[2] || ext[5] < ext[4])
    return std::string(fileName) + ": a dimension of 0 in the header (no voxels)";
  const std::string name = fileName;
  if (!h || name.size() < 4 || vtksys::SystemTools::LowerCase(name.substr(name.size() - 4)) != ".nii")
    return ""; // .hdr/.img, .nii.gz: the voxels are elsewhere or compressed
  const std::string magic = h->GetMagic() ? h->GetMagic() : "";
  std::ifstream in(fileName, std::ios::binary);
  char head[2] = { 0, 0 };
  if (!in.read(head, 2) || (head[0] == '\x1f' && head[1] == '\x8b'))
    return ""; // gzip: its length says nothing
  in.seekg(0, std::ios::end);
  const double length = static_cast<double>(in.tellg());
  double needed = 1;
  for (int a = 0; a < 3; ++a)
    needed *= ext[2 * a + 1] - ext[2 * a] + 1;
  if (vtkInformation* scalar = vtkDataObject::GetActiveFieldInformation(
        info, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS))
  {
    const int type = scalar->Get(vtkDataObject::FIELD_ARRAY_TYPE());
    const int known[] = { VTK_CHAR, VTK_SIGNED_CHAR, VTK_UNSIGNED_CHAR, VTK_SHORT,
      VTK_UNSIGNED_SHORT, VTK_INT, VTK_UNSIGNED_INT, VTK_LONG, VTK_UNSIGNED_LONG, VTK_LONG_LONG,
      VTK_UNSIGNED_LONG_LONG, VTK_FLOAT, VTK_DOUBLE };
    const vtkIdType bytes =
      std::find(std::begin(known), std::end(known), type) != std::end(known)
      ? vtkDataArray::GetDataTypeSize(type)
      : 0;
    if (bytes <= 0)
      return std::string(fileName) + ": unsupported voxel data type (NIfTI datatype " +
        std::to_string(h->GetDataType()) + ")";
    needed *= scalar->Get(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS()) * static_cast<double>(bytes);
  }
  if (magic == "n+1" || magic == "n+2")
    needed += static_cast<double>(h->GetVoxOffset());
  if (length < needed)
  {
    std::ostringstream e;
    e << fileName << ": the file is shorter than its header says (" << length << " of " << needed
      << " bytes: truncated?)";
    return e.str();
  }
  return "";
}
}

bool vtkNIfTIVolumeReader::Open(vtkNIFTIImageReader* r, bool withData, std::string& error)
{
  if (!this->FileName || !*this->FileName)
  {
    error = "no FileName set";
    return false;
  }
  if (const std::string problem = HeaderProblem(this->FileName); !problem.empty())
  {
    error = std::string(this->FileName) + ": " + problem;
    return false;
  }
  // The reader's error and its executive's (which follows it), collected.
  vtkNew<Quiet> quiet;
  const unsigned long tag = r->AddObserver(vtkCommand::ErrorEvent, quiet);
  const unsigned long etag = r->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, quiet);
  r->SetFileName(this->FileName);
  if (withData)
  {
    r->Update();
  }
  else
  {
    r->UpdateInformation();
  }
  r->RemoveObserver(tag);
  r->GetExecutive()->RemoveObserver(etag);
  if (quiet->Message.empty())
  {
    return true;
  }
  // CanReadFile reads the header once more, on this failure path only.
  vtkNew<vtkNIFTIImageReader> probe;
  if (!probe->CanReadFile(this->FileName))
  {
    error = std::string(this->FileName) + ": not a NIfTI file (or it cannot be opened)";
  }
  else
  {
    error = std::string(this->FileName) + ": " + quiet->Message;
  }
  return false;
}

bool vtkNIfTIVolumeReader::Geometry(vtkNIFTIImageReader* r, bool warn, double origin[3],
  double spacing[3], double direction[9], std::string& error)
{
  vtkNIFTIImageHeader* h = r->GetNIFTIHeader();
  vtkMatrix4x4* m = nullptr;
  this->GeometrySource = NONE;
  if (h && h->GetSFormCode() > 0 && r->GetSFormMatrix())
  {
    m = r->GetSFormMatrix();
    this->GeometrySource = SFORM;
  }
  else if (h && h->GetQFormCode() > 0 && r->GetQFormMatrix())
  {
    m = r->GetQFormMatrix();
    this->GeometrySource = QFORM;
  }
  vtkInformation* info = r->GetOutputInformation(0);
  double s[3] = { 1, 1, 1 }, o[3] = { 0, 0, 0 };
  if (info->Has(vtkDataObject::SPACING()))
    info->Get(vtkDataObject::SPACING(), s);
  if (info->Has(vtkDataObject::ORIGIN()))
    info->Get(vtkDataObject::ORIGIN(), o);
  // world = R (o + s * index) + t, with R = m's 3x3 and t its offset.
  double R[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }, t[3] = { 0, 0, 0 };
  if (m)
  {
    for (int a = 0; a < 3; ++a)
    {
      for (int b = 0; b < 3; ++b)
        R[3 * a + b] = m->GetElement(a, b);
      t[a] = m->GetElement(a, 3);
    }
  }
  else if (warn)
  {
    vtkWarningMacro(<< this->FileName
                    << ": no qform or sform in the header: voxel size only, no orientation");
  }
  for (int c = 0; c < 3; ++c)
  {
    const double len = std::sqrt(R[c] * R[c] + R[3 + c] * R[3 + c] + R[6 + c] * R[6 + c]);
    if (!(len > 0) || !std::isfinite(len) || !(s[c] > 0) || !std::isfinite(s[c] * len))
    {
      error = std::string(this->FileName) + ": degenerate voxel axis " + std::to_string(c) +
        " in the header transform";
      return false;
    }
    spacing[c] = s[c] * len;
    for (int a = 0; a < 3; ++a)
      direction[3 * a + c] = R[3 * a + c] / len;
  }
  // The columns must be orthogonal: a shear cannot be carried by origin,
  // spacing and direction, and applying it approximately would put the
  // surface in the wrong place.
  for (int c = 0; c < 3; ++c)
    for (int d = c + 1; d < 3; ++d)
    {
      double dot = 0;
      for (int a = 0; a < 3; ++a)
        dot += direction[3 * a + c] * direction[3 * a + d];
      if (std::abs(dot) > 1e-4)
      {
        std::ostringstream e;
        e << this->FileName << ": the " << (this->GeometrySource == SFORM ? "sform" : "qform")
          << " is sheared (voxel axes " << c << " and " << d << " at "
          << std::acos(std::max(-1.0, std::min(1.0, dot))) * 180.0 / M_PI
          << " degrees, not 90): resample the volume onto an orthogonal grid first";
        error = e.str();
        return false;
      }
    }
  for (int a = 0; a < 3; ++a)
  {
    origin[a] = t[a] + R[3 * a] * o[0] + R[3 * a + 1] * o[1] + R[3 * a + 2] * o[2];
    if (!std::isfinite(origin[a]))
    {
      error = std::string(this->FileName) + ": the header transform's offset is not finite";
      return false;
    }
  }
  if (this->CoordinateSystem == LPS)
  {
    // LPS = diag(-1, -1, 1) RAS.
    for (int a = 0; a < 2; ++a)
    {
      origin[a] = -origin[a];
      for (int c = 0; c < 3; ++c)
        direction[3 * a + c] = -direction[3 * a + c];
    }
  }
  return true;
}

int vtkNIfTIVolumeReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // One header read: vtkNIFTIImageReader's own RequestInformation, on a
  // reader kept for RequestData, which then reads the voxels only.
  this->Inner = vtkSmartPointer<vtkNIFTIImageReader>::New();
  vtkNIFTIImageReader* r = this->Inner;
  double origin[3], spacing[3], direction[9];
  std::string error;
  if (!this->Open(r, false, error) || !this->Geometry(r, true, origin, spacing, direction, error) ||
    !(error = CheckDataSize(this->FileName, r)).empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  vtkInformation* in = r->GetOutputInformation(0);
  vtkInformation* out = outputVector->GetInformationObject(0);
  int ext[6];
  in->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), ext);
  out->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), ext, 6);
  out->Set(vtkDataObject::SPACING(), spacing, 3);
  out->Set(vtkDataObject::ORIGIN(), origin, 3);
  out->Set(vtkDataObject::DIRECTION(), direction, 9);
  // Any sub-extent: the whole volume is read and the box cropped out
  // (RequestData).
  out->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  if (vtkInformation* scalar = vtkDataObject::GetActiveFieldInformation(
        in, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS))
  {
    vtkDataObject::SetPointDataActiveScalarInfo(out,
      scalar->Get(vtkDataObject::FIELD_ARRAY_TYPE()),
      scalar->Get(vtkDataObject::FIELD_NUMBER_OF_COMPONENTS()));
  }
  return 1;
}

int vtkNIfTIVolumeReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  // The voxels, by the reader of RequestInformation (its header is
  // current: any change of FileName or a Modified() runs
  // RequestInformation again, with a new reader).
  if (!this->Inner)
  {
    this->Inner = vtkSmartPointer<vtkNIFTIImageReader>::New();
  }
  vtkNIFTIImageReader* r = this->Inner;
  // Whatever happens below, the inner reader does not keep the whole
  // volume after this execution.
  struct Release
  {
    vtkNIFTIImageReader* R;
    ~Release()
    {
      if (vtkDataObject* d = this->R->GetOutputDataObject(0))
      {
        d->ReleaseData();
      }
    }
  } release{ r };
  double origin[3], spacing[3], direction[9];
  std::string error;
  if (!this->Open(r, true, error) || !this->Geometry(r, false, origin, spacing, direction, error))
  {
    vtkErrorMacro(<< error);
    output->Initialize();
    return 0;
  }
  vtkImageData* image = r->GetOutput();
  const vtkIdType n = image ? image->GetNumberOfPoints() : 0;
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (n == 0 || !scalars || scalars->GetNumberOfTuples() != n)
  {
    vtkErrorMacro(<< this->FileName << ": no voxel data (truncated or corrupt file?)");
    output->Initialize();
    return 0;
  }
  int whole[6], ext[6];
  image->GetExtent(whole);
  std::copy(whole, whole + 6, ext);
  if (outInfo && outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
  }
  if (!dg::ExtentEmpty(ext) && !dg::ExtentContains(whole, ext))
  {
    vtkErrorMacro(<< this->FileName
                  << ": requested extent outside the file's extent (the file changed?)");
    output->Initialize();
    return 0;
  }
  dg::CropImageToExtent(image, ext, output);
  output->SetOrigin(origin);
  output->SetSpacing(spacing);
  output->SetDirectionMatrix(direction);
  return 1;
}

void vtkNIfTIVolumeReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* sources[] = { "none", "qform", "sform" };
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "CoordinateSystem: " << (this->CoordinateSystem == LPS ? "LPS" : "RAS") << "\n";
  os << indent << "GeometrySource: " << sources[this->GeometrySource] << "\n";
}
