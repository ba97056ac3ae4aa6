#include "vtkNIfTIVolumeReader.h"

#include "dgPieces.h"

#include <vtkByteSwap.h>
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
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
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

// The file vtkNIFTIImageReader takes the header from, found as it finds it:
// a .img's .hdr, and when the name does not exist, the same name with
// ".gz" added or removed. Empty when there is none (VTK's reader says so).
std::string HeaderFile(const std::string& fileName)
{
  const auto ends = [](const std::string& s, std::size_t end, const char* ext) {
    return end >= 4 && s[end - 4] == '.' &&
      vtksys::SystemTools::LowerCase(s.substr(end - 3, 3)) == ext + 1;
  };
  std::string name = fileName;
  const std::size_t n = name.size();
  const bool gz = n >= 3 && name[n - 3] == '.' &&
    vtksys::SystemTools::LowerCase(name.substr(n - 2)) == "gz";
  const std::size_t m = gz ? n - 3 : n;
  const bool upper = m >= 3 && std::isupper(static_cast<unsigned char>(name[m - 3]));
  if (ends(name, m, ".img"))
    name.replace(m - 3, 3, upper ? "HDR" : "hdr");
  if (vtksys::SystemTools::FileExists(name))
    return name;
  name = gz ? name.substr(0, m) : name + (upper ? ".GZ" : ".gz");
  return vtksys::SystemTools::FileExists(name) ? name : std::string();
}

// A signed integer field of a header as VTK's reader decodes it: `bytes`
// bytes at `at`, little-endian unless swapped.
std::int64_t Field(const unsigned char* h, int at, int bytes, bool swap)
{
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i)
    v |= static_cast<std::uint64_t>(h[swap ? at + bytes - 1 - i : at + i]) << (8 * i);
  if (bytes < 8 && (v >> (8 * bytes - 1)) != 0)
    return static_cast<std::int64_t>(v) - (std::int64_t(1) << (8 * bytes));
  return static_cast<std::int64_t>(v);
}

// Empty, or the problem when the header holds what VTK 9.2's
// vtkNIFTIImageReader cannot survive:
// - a datatype outside the 14 it maps to a VTK type: its lookup loop has no
//   bound (only datatype 0 meets its end marker), so it reads past its
//   table until some word happens to equal the datatype, and crashes in
//   RequestInformation when none does first (SIGSEGV/SIGBUS seen for 1536,
//   2048, 2305, 2560, 4866, -5): NIfTI's 1, 1536 and 2048 are among them;
// - with dim[0] >= 5, a dim[5] of 0 (its RequestData divides by it: SIGFPE)
//   or one whose product with the type's values per voxel overflows its int
//   component count (its row copy then writes past the volume: SIGSEGV);
// - a dim[0] outside 1..7 as it decodes it (NIfTI's own range; VTK lets 0
//   through);
// - a vox_offset below 0, not finite or beyond 64 bits.
// The header is decoded exactly as VTK decodes it, or the check would look
// at other bytes than VTK does: NIfTI-2 when the magic at 4 says version 2
// to 9 (then the datatype is at 12 and dim[] holds 8-byte integers), else
// NIfTI-1 by the magic at 344 or Analyze 7.5 by sizeof_hdr; byte-swapped
// when dim[0], read little-endian, is below 0 or above 7 (all 8 bytes of
// NIfTI-2's; a NIfTI-1 dim[0] of 0 is not swapped).
std::string HeaderProblem(const std::string& fileName)
{
  const std::string header = HeaderFile(fileName);
  gzFile f = header.empty() ? nullptr : gzopen(header.c_str(), "rb");
  if (!f)
    return ""; // VTK's reader says why
  unsigned char h[348];
  const int got = gzread(f, h, sizeof h);
  gzclose(f);
  if (got != static_cast<int>(sizeof h))
    return ""; // shorter than any header: VTK's reader refuses it
  const auto magic = [&](int at, bool version2) {
    return h[at] == 'n' && (h[at + 1] == '+' || h[at + 1] == 'i') &&
      (version2 ? h[at + 2] >= '2' && h[at + 2] <= '9' : h[at + 2] == '1') && h[at + 3] == 0;
  };
  const bool nifti2 = magic(4, true);
  if (nifti2 && std::memcmp(h + 8, "\r\n\032\n", 4) != 0)
    return ""; // a NIfTI-2 signature broken by newline conversion: VTK's reader refuses it
  if (!nifti2 && !magic(344, false) && !(h[0] == 92 && h[1] == 1 && !h[2] && !h[3]) &&
    !(!h[0] && !h[1] && h[2] == 1 && h[3] == 92))
    return ""; // not a header: VTK's reader says so
  const int dimAt = nifti2 ? 16 : 40, dimBytes = nifti2 ? 8 : 2;
  const std::int64_t rawDim0 = Field(h, dimAt, dimBytes, false);
  const bool swap = rawDim0 < 0 || rawDim0 > 7;
  // VTK keeps the low 32 bits of NIfTI-2's dim[0] (an int).
  const auto ndim = static_cast<std::int32_t>(
    static_cast<std::uint32_t>(Field(h, dimAt, dimBytes, swap) & 0xffffffff));
  if (ndim < 1 || ndim > 7)
    return "dim[0] is " + std::to_string(ndim) +
      ", not a number of dimensions (1 to 7): a corrupt header?";

  const auto datatype = static_cast<int>(Field(h, nifti2 ? 12 : 70, 2, swap));
  struct Type
  {
    int Code, Values;
  };
  // NIfTI's datatypes with a VTK scalar type, and the values per voxel.
  static const Type types[] = { { 2, 1 }, { 4, 1 }, { 8, 1 }, { 16, 1 }, { 32, 2 }, { 64, 1 },
    { 128, 3 }, { 256, 1 }, { 512, 1 }, { 768, 1 }, { 1024, 1 }, { 1280, 1 }, { 1792, 2 },
    { 2304, 4 } };
  const Type* type = std::find_if(
    std::begin(types), std::end(types), [&](const Type& t) { return t.Code == datatype; });
  if (type == std::end(types))
  {
    switch (datatype)
    {
      case 0:
        return "NIfTI datatype 0 (DT_UNKNOWN): the header gives no voxel type";
      case 1:
        return "NIfTI datatype 1 (1-bit binary) is not supported";
      case 1536:
        return "NIfTI datatype 1536 (128-bit float) is not supported";
      case 2048:
        return "NIfTI datatype 2048 (256-bit complex) is not supported";
      default:
        return "unknown NIfTI datatype " + std::to_string(datatype) + " (a corrupt header?)";
    }
  }
  // VTK's reader allocates the volume before it seeks to vox_offset, and
  // the length check (CheckDataSize) counts on an offset >= 0: a negative
  // one (or NIfTI-1's float beyond int64, which VTK's conversion turns
  // negative) would pass any size.
  double offset = 0;
  if (nifti2)
    offset = static_cast<double>(Field(h, 168, 8, swap));
  else
  {
    const auto bits = static_cast<std::uint32_t>(Field(h, 108, 4, swap) & 0xffffffff);
    float value;
    std::memcpy(&value, &bits, sizeof value);
    offset = value;
  }
  if (!(offset >= 0 && offset < 9.2e18))
  {
    std::ostringstream e;
    e << "vox_offset is " << offset << ", not a byte offset into the file (a corrupt header?)";
    return e.str();
  }
  if (ndim >= 5)
  {
    const std::int64_t vectors = Field(h, dimAt + 5 * dimBytes, dimBytes, swap);
    if (vectors == 0)
      return "dim[5] is 0 in a " + std::to_string(ndim) +
        "-D header (no vector components): a corrupt header?";
    // (A negative dim[5] or one beyond int32 VTK's reader refuses itself.)
    if (vectors > 0 && vectors <= 0x7fffffff &&
      vectors * type->Values > std::numeric_limits<int>::max())
      return "dim[5] is " + std::to_string(vectors) + ": " +
        std::to_string(vectors * type->Values) +
        " values per voxel, more than VTK's reader can count (a corrupt header?)";
  }
  return "";
}

// A header without voxels, a single file (.nii) shorter than its header's
// first volume, or a compressed one (.nii.gz) too small to inflate to it:
// empty when the file can hold the volume (or it is a .hdr/.img pair), else
// the problem. vtkNIFTIImageReader allocates the volume the header declares
// before reading it, so a few bytes claiming 2^40 voxels would otherwise
// allocate that much. Deflate cannot expand data more than 1032 times (its
// longest match, 258 bytes, costs at least 2 bits), in one gzip member or
// several, so a compressed file is refused only when no valid stream of its
// length could hold the volume.
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
  const std::string lower = vtksys::SystemTools::LowerCase(fileName);
  const auto endsWith = [&](const char* ext) {
    const std::size_t n = std::strlen(ext);
    return lower.size() >= n && lower.compare(lower.size() - n, n, ext) == 0;
  };
  if (!h || !(endsWith(".nii") || endsWith(".nii.gz")))
    return ""; // .hdr/.img: the voxels are elsewhere
  const std::string magic = h->GetMagic() ? h->GetMagic() : "";
  std::ifstream in(fileName, std::ios::binary);
  char head[2] = { 0, 0 };
  if (!in.read(head, 2))
    return "";
  const bool gzip = head[0] == '\x1f' && head[1] == '\x8b';
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
  if (gzip && needed > 1032.0 * length + 1024.0)
  {
    std::ostringstream e;
    e << fileName << ": the compressed file (" << length << " bytes) cannot hold the " << needed
      << " bytes its header declares (a corrupt header?)";
    return e.str();
  }
  if (!gzip && length < needed)
  {
    std::ostringstream e;
    e << fileName << ": the file is shorter than its header says (" << length << " of " << needed
      << " bytes: truncated?)";
    return e.str();
  }
  return "";
}

// Why a piece request cannot be read in part, or empty when it can. The
// part read covers the single-file NIfTI layouts (magic n+1 / n+2 in a
// .nii or .nii.gz): voxels packed x fastest from vox_offset, one volume
// after another. The rest falls back to vtkNIFTIImageReader's whole read
// and a cropped copy, as before: an Analyze or .hdr/.img pair (the voxels
// in another file, found by VTK's own name rules) and a dim[5] > 1 (vector
// components stored as whole volumes one after the other: a .nii.gz would
// have to be inflated once per component or held whole).
std::string WholeReadReason(const char* fileName, vtkNIFTIImageReader* r)
{
  vtkNIFTIImageHeader* h = r->GetNIFTIHeader();
  const std::string magic = h && h->GetMagic() ? h->GetMagic() : "";
  const std::string lower = vtksys::SystemTools::LowerCase(fileName);
  const auto endsWith = [&](const char* ext) {
    const std::size_t n = std::strlen(ext);
    return lower.size() >= n && lower.compare(lower.size() - n, n, ext) == 0;
  };
  if (magic.size() != 3 || magic[0] != 'n' || magic[1] != '+' ||
    !(endsWith(".nii") || endsWith(".nii.gz")))
    return "not a single-file NIfTI";
  if (h->GetDim(0) >= 5 && h->GetDim(5) != 1)
    return "vector components stored as separate volumes";
  return "";
}

// Reads the box ext of the first volume of a single-file NIfTI into a new
// array, exactly as vtkNIFTIImageReader's RequestData would for the whole
// extent followed by a crop (VTK 9.2, IO/Image/vtkNIFTIImageReader.cxx):
// - the file through zlib's gzFile, as VTK opens it: a .nii.gz inflates
//   as it is read, a plain file (or a .nii.gz that is not compressed) is
//   read directly and gzseek seeks;
// - the voxels at HeaderSize (vox_offset) + ((k Y + j) X + i) times the
//   voxel's bytes (all its components, packed), the first time point only;
// - bytes swapped per scalar when the header is of the other byte order
//   (GetSwapBytes);
// - no scl_slope / scl_inter: VTK's reader passes them on
//   (GetRescaleSlope) and leaves the values as stored;
// - qfac < 0 (GetQFac): VTK reverses the slices, output slice K is file
//   slice Z - 1 - K.
// The file is read in increasing offsets (a gzip stream cannot go back),
// row by row of the box straight into the output; in a .nii.gz the bytes
// before, between and after the rows are inflated and dropped through
// zlib's buffer. A .nii.gz is inflated to the end of the first volume
// whatever the box, as the whole read does, so that all pieces of a file
// fail or succeed together. Empty on success, else the problem.
std::string ReadBox(const std::string& fileName, vtkNIFTIImageReader* r, const int whole[6],
  const int ext[6], vtkSmartPointer<vtkDataArray>& array,
  const std::function<bool(double)>& progress)
{
  const int scalarType = r->GetDataScalarType();
  const int components = r->GetNumberOfScalarComponents();
  array = vtk::TakeSmartPointer(vtkDataArray::CreateDataArray(scalarType));
  if (!array || components < 1)
    return "unsupported voxel data type";
  array->SetName("NIFTI");
  array->SetNumberOfComponents(components);
  const bool empty = dg::ExtentEmpty(ext);
  const vtkIdType bx = empty ? 0 : ext[1] - ext[0] + 1, by = empty ? 0 : ext[3] - ext[2] + 1,
                  bz = empty ? 0 : ext[5] - ext[4] + 1;
  array->SetNumberOfTuples(bx * by * bz);
  const int scalarSize = array->GetDataTypeSize();
  const std::int64_t voxel = static_cast<std::int64_t>(scalarSize) * components;
  const std::int64_t nx = whole[1] - whole[0] + 1, ny = whole[3] - whole[2] + 1,
                     nz = whole[5] - whole[4] + 1;
  const std::int64_t row = voxel * nx, slice = row * ny;
  const std::int64_t start = static_cast<std::int64_t>(r->GetHeaderSize());
  const std::size_t boxRow = static_cast<std::size_t>(voxel * bx);
  const bool swap = r->GetSwapBytes() && scalarSize > 1;
  const bool reversed = r->GetQFac() < 0;
  // The file's slices of the box, in file order.
  const int first = empty ? 0 : reversed ? static_cast<int>(nz - 1 - ext[5]) : ext[4];
  const int last = empty ? -1 : reversed ? static_cast<int>(nz - 1 - ext[4]) : ext[5];

  gzFile f = gzopen(fileName.c_str(), "rb");
  if (!f)
    return "cannot open the file";
  // Larger than zlib's 8 KiB default: fewer reads and inflate calls
  // (zlib then holds 256 KiB of input and 512 KiB of output).
  gzbuffer(f, 256 * 1024);
  const auto problem = [&f](const char* what) -> std::string {
    int code = Z_OK;
    const char* message = gzerror(f, &code);
    std::string text = gzeof(f) ? "NIFTI file is truncated, some data is missing."
                                : std::string(what) + (code != Z_OK && message ? std::string(": ") + message : "");
    gzclose(f);
    return text;
  };
  auto* out = static_cast<unsigned char*>(array->GetVoidPointer(0));
  for (int k = first; k <= last; ++k)
  {
    const int outK = reversed ? static_cast<int>(nz - 1 - k) : k;
    unsigned char* dst = out + static_cast<std::size_t>(outK - ext[4]) * by * boxRow;
    for (int j = ext[2]; j <= ext[3]; ++j, dst += boxRow)
    {
      const std::int64_t at = start + k * slice + j * row + ext[0] * voxel;
      if (gzseek(f, static_cast<z_off_t>(at), SEEK_SET) != static_cast<z_off_t>(at))
        return problem("cannot seek in the file");
      if (gzread(f, dst, static_cast<unsigned>(boxRow)) != static_cast<int>(boxRow))
        return problem("cannot read the voxels");
      if (swap)
        vtkByteSwap::SwapVoidRange(dst, static_cast<vtkIdType>(bx) * components, scalarSize);
    }
    if (progress && !progress(static_cast<double>(k - first + 1) / (last - first + 1)))
    {
      gzclose(f);
      return "aborted";
    }
  }
  // The last byte of the first volume, when compressed: the rest of the
  // stream up to it inflates (and is checked) as in the whole read.
  if (!gzdirect(f))
  {
    const std::int64_t end = start + nz * slice - 1;
    unsigned char byte;
    if (gzseek(f, static_cast<z_off_t>(end), SEEK_SET) != static_cast<z_off_t>(end) ||
      gzread(f, &byte, 1) != 1)
      return problem("cannot read the voxels");
  }
  gzclose(f);
  return "";
}
} // namespace

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
  // Any sub-extent: RequestData reads only the box's voxels (ReadBox), or
  // for the layouts it does not cover the whole volume, cropped.
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
  // The requested box against the whole extent of RequestInformation's
  // header (the same reader: its information is current).
  int whole[6] = { 0, -1, 0, -1, 0, -1 }, ext[6];
  r->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
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
  if (!std::equal(ext, ext + 6, whole) && WholeReadReason(this->FileName, r).empty())
  {
    // A piece: the header's checks again (HeaderProblem, VTK's own; the
    // header is not re-read when nothing changed), then only the box's
    // voxels, read from the file into the output.
    if (!this->Open(r, false, error) ||
      !this->Geometry(r, false, origin, spacing, direction, error))
    {
      vtkErrorMacro(<< error);
      output->Initialize();
      return 0;
    }
    r->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
    if (!dg::ExtentContains(whole, ext))
    {
      vtkErrorMacro(<< this->FileName
                    << ": requested extent outside the file's extent (the file changed?)");
      output->Initialize();
      return 0;
    }
    vtkSmartPointer<vtkDataArray> values;
    const auto progress = [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    };
    const std::string problem =
      ReadBox(HeaderFile(this->FileName), r, whole, ext, values, progress);
    if (!problem.empty())
    {
      output->Initialize();
      if (problem != "aborted")
      {
        vtkErrorMacro(<< this->FileName << ": " << problem);
      }
      return 0;
    }
    output->SetExtent(ext);
    output->GetPointData()->SetScalars(values);
    output->SetOrigin(origin);
    output->SetSpacing(spacing);
    output->SetDirectionMatrix(direction);
    return 1;
  }
  // The whole extent (one copy: the output shares VTK's array), or a part
  // that cannot be read alone (WholeReadReason): VTK's whole read, then the
  // box copied out.
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
  image->GetExtent(whole);
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
