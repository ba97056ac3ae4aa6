// The bad-input matrix (issue 5), readers' half: .vol, NIfTI, MetaImage and
// NRRD files damaged one field at a time; geometry a reader cannot carry is
// refused, never straightened, and short data is an error. The program's
// rows (DICOM included) are in test_program.py and test_dicom_mha_nrrd.py.
#include "dgBadInput.h"
#include "dgTestShapes.h"
#include "dgVolFormat.h"
#include "vtkDGtalVolReader.h"
#include "vtkNIfTIVolumeReader.h"
#include "vtkOrientedImageReader.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>
#include "dgTestTemp.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>

namespace
{
using dgtest::Expect;
using dgtest::Outcome;
using dgtest::Row;
using dgtest::Run;

Outcome ReadVolBytes(const std::string& name,
  const std::function<void(std::vector<std::uint8_t>&)>& damage)
{
  const int dims[3] = { 5, 6, 7 };
  std::vector<std::uint8_t> voxels(5 * 6 * 7);
  for (std::size_t v = 0; v < voxels.size(); ++v)
  {
    voxels[v] = static_cast<std::uint8_t>((v * 37) % 3);
  }
  std::vector<std::uint8_t> bytes;
  std::string error;
  dg::EncodeVol(dims, voxels.data(), 3, bytes, error);
  damage(bytes);
  const std::string path = dgtest::TempPath("matrix_" + name + ".vol");
  std::ofstream(path, std::ios::binary)
    .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  vtkNew<vtkDGtalVolReader> reader;
  reader->SetFileName(path.c_str());
  return Run(reader);
}

std::size_t DataStart(const std::vector<std::uint8_t>& b)
{
  const std::string s(b.begin(), b.end());
  return s.find("\n.\n") + 3;
}

// A NIfTI-1 file (.nii, uint8 voxels 5 x 6 x 7) written byte by byte, so that
// each row can damage exactly one field of a header that is valid otherwise.
struct NIfTIHeader
{
  std::vector<std::uint8_t> Bytes = std::vector<std::uint8_t>(352, 0);
  template<typename T>
  void Put(std::size_t offset, T value)
  {
    std::memcpy(this->Bytes.data() + offset, &value, sizeof(T));
  }
  void SForm(const double rows[3][4])
  {
    this->Put<short>(254, 1);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        this->Put<float>(280 + 16 * r + 4 * c, static_cast<float>(rows[r][c]));
  }
};

NIfTIHeader GoodNIfTI()
{
  NIfTIHeader h;
  h.Put<int>(0, 348);
  const short dim[8] = { 3, 5, 6, 7, 1, 1, 1, 1 };
  for (int d = 0; d < 8; ++d)
    h.Put<short>(40 + 2 * d, dim[d]);
  h.Put<short>(70, 2); // DT_UINT8
  h.Put<short>(72, 8);
  const float pixdim[8] = { 1, 0.7f, 0.7f, 2.5f, 1, 1, 1, 1 };
  for (int d = 0; d < 8; ++d)
    h.Put<float>(76 + 4 * d, pixdim[d]);
  h.Put<float>(108, 352.0f);
  h.Put<float>(112, 1.0f);
  h.Bytes[123] = 2; // millimetres
  const double rows[3][4] = { { 0.7, 0, 0, -10 }, { 0, 0.7, 0, 20 }, { 0, 0, 2.5, 5 } };
  h.SForm(rows);
  std::memcpy(h.Bytes.data() + 344, "n+1", 4);
  return h;
}

Outcome ReadNIfTIBytes(const std::string& name,
  const NIfTIHeader& header,
  std::size_t voxels = 5 * 6 * 7)
{
  std::vector<std::uint8_t> bytes = header.Bytes;
  for (std::size_t v = 0; v < voxels; ++v)
    bytes.push_back(static_cast<std::uint8_t>(v % 3));
  const std::string path = dgtest::TempPath("matrix_" + name + ".nii");
  std::ofstream(path, std::ios::binary)
    .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  vtkNew<vtkNIfTIVolumeReader> reader;
  reader->SetFileName(path.c_str());
  return Run(reader);
}

// The same bytes as a .nii.gz: one gzip member holding one stored
// (uncompressed) deflate block, so that no compressor is needed here.
Outcome ReadNIfTIGzip(const std::string& name, const NIfTIHeader& header,
  std::size_t voxels = 5 * 6 * 7)
{
  std::vector<std::uint8_t> raw = header.Bytes;
  for (std::size_t v = 0; v < voxels; ++v)
    raw.push_back(static_cast<std::uint8_t>(v % 3));
  std::uint32_t crc = 0xffffffffu;
  for (std::uint8_t b : raw)
  {
    crc ^= b;
    for (int k = 0; k < 8; ++k)
      crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  crc ^= 0xffffffffu;
  const auto n = static_cast<std::uint16_t>(raw.size());
  std::vector<std::uint8_t> gz = { 0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 255, 1,
    static_cast<std::uint8_t>(n & 0xff), static_cast<std::uint8_t>(n >> 8),
    static_cast<std::uint8_t>(~n & 0xff), static_cast<std::uint8_t>((~n >> 8) & 0xff) };
  gz.insert(gz.end(), raw.begin(), raw.end());
  const std::uint32_t size = static_cast<std::uint32_t>(raw.size());
  for (std::uint32_t v : { crc, size })
    for (int k = 0; k < 4; ++k)
      gz.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  const std::string path = dgtest::TempPath("matrix_" + name + ".nii.gz");
  std::ofstream(path, std::ios::binary)
    .write(reinterpret_cast<const char*>(gz.data()), static_cast<std::streamsize>(gz.size()));
  vtkNew<vtkNIfTIVolumeReader> reader;
  reader->SetFileName(path.c_str());
  return Run(reader);
}

NIfTIHeader WithSForm(const double rows[3][4])
{
  NIfTIHeader h = GoodNIfTI();
  h.SForm(rows);
  return h;
}

// A MetaImage or NRRD file (uint8, 5 x 6 x 7) with the given header text
// and `voxels` bytes of data, read by vtkOrientedImageReader.
Outcome ReadOrientedBytes(const std::string& name,
  const std::string& header,
  std::size_t voxels = 5 * 6 * 7)
{
  const std::string path = dgtest::TempPath("matrix_" + name);
  std::ofstream f(path, std::ios::binary);
  f << header;
  for (std::size_t v = 0; v < voxels; ++v)
    f.put(static_cast<char>(v % 3));
  f.close();
  vtkNew<vtkOrientedImageReader> reader;
  reader->SetFileName(path.c_str());
  return Run(reader);
}

std::string MetaImageHeader(const std::string& transform)
{
  return "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
         "TransformMatrix = " +
         transform +
         "\nOffset = 1 2 3\nElementSpacing = 0.7 0.7 2.5\nDimSize = 5 6 7\nElementType = "
         "MET_UCHAR\nElementDataFile = LOCAL\n";
}

std::string NrrdHeader(const std::string& space, const std::string& directions)
{
  return "NRRD0004\ntype: uint8\ndimension: 3\nspace: " + space +
         "\nsizes: 5 6 7\nspace directions: " + directions +
         "\nendian: little\nencoding: raw\nspace origin: (1,2,3)\n\n";
}

const Row Rows[] = {
  // vtkDGtalVolReader (the full corruption sweep is in TestVolReader)
  { "VolTruncatedData",
    Expect::Error,
    "",
    []
    {
      return ReadVolBytes(
        "truncated", [](std::vector<std::uint8_t>& b) { b.resize(b.size() - 4); });
    } },
  { "VolTruncatedHeader",
    Expect::Error,
    "",
    []
    {
      return ReadVolBytes(
        "header", [](std::vector<std::uint8_t>& b) { b.resize(DataStart(b) - 4); });
    } },
  { "VolCorruptStream",
    Expect::Error,
    "",
    []
    {
      return ReadVolBytes("corrupt",
        [](std::vector<std::uint8_t>& b)
        {
          for (std::size_t p = DataStart(b) + 2; p < b.size(); p += 2)
          {
            b[p] ^= 0xA5;
          }
        });
    } },
  // vtkNIfTIVolumeReader: geometry it cannot carry is refused, never
  // straightened (issue 18); the program's rows are in test_program.py.
  { "NIfTINotANIfTIFile",
    Expect::Error,
    "not a NIfTI file",
    []
    {
      NIfTIHeader h = GoodNIfTI();
      h.Put<int>(0, 1234);
      std::memcpy(h.Bytes.data() + 344, "xyz", 4);
      return ReadNIfTIBytes("notnifti", h);
    } },
  { "NIfTIShearedSForm",
    Expect::Error,
    "sheared",
    []
    {
      const double rows[3][4] = { { 0.7, 0.3, 0, 0 }, { 0, 0.7, 0, 0 }, { 0, 0, 2.5, 0 } };
      return ReadNIfTIBytes("sheared", WithSForm(rows));
    } },
  { "NIfTIDegenerateSForm",
    Expect::Error,
    "degenerate voxel axis 1",
    []
    {
      const double rows[3][4] = { { 0.7, 0, 0, 0 }, { 0, 0, 0, 0 }, { 0, 0, 2.5, 0 } };
      return ReadNIfTIBytes("degenerate", WithSForm(rows));
    } },
  { "NIfTITruncatedVoxels",
    Expect::Error,
    "",
    [] { return ReadNIfTIBytes("truncated", GoodNIfTI(), 5 * 6 * 7 / 2); } },
  // A few hundred compressed bytes claiming 10^9 voxels: refused before VTK
  // 9.2's reader allocates them (deflate expands at most 1032 times).
  { "NIfTIGzipClaimsGigabytes",
    Expect::Error,
    "cannot hold",
    []
    {
      NIfTIHeader h = GoodNIfTI();
      for (int d = 1; d <= 3; ++d)
        h.Put<short>(40 + 2 * d, 1000);
      return ReadNIfTIGzip("gzip_claims", h);
    } },
  { "NIfTIGzipGood",
    Expect::Result,
    "",
    []
    {
      Outcome o = ReadNIfTIGzip("gzip_good", GoodNIfTI());
      o.ExpectedCells = 5 * 6 * 7;
      return o;
    } },
  { "NIfTINoQFormNoSForm",
    Expect::Warning,
    "no qform or sform",
    []
    {
      NIfTIHeader h = GoodNIfTI();
      h.Put<short>(252, 0);
      h.Put<short>(254, 0);
      Outcome o = ReadNIfTIBytes("noform", h);
      o.ExpectedCells = 5 * 6 * 7;
      return o;
    } },
  { "NIfTIGood",
    Expect::Result,
    "",
    []
    {
      Outcome o = ReadNIfTIBytes("good", GoodNIfTI());
      o.ExpectedCells = 5 * 6 * 7;
      return o;
    } },
  // vtkOrientedImageReader (MetaImage, NRRD): geometry it cannot carry is
  // refused, never straightened; short data is an error, not a warning.
  { "OrientedShearedTransformMatrix",
    Expect::Error,
    "sheared",
    [] { return ReadOrientedBytes("sheared.mha", MetaImageHeader("1 0 0 0.5 1 0 0 0 1")); } },
  { "OrientedTransformMatrixNotNineNumbers",
    Expect::Error,
    "not nine numbers",
    [] { return ReadOrientedBytes("eight.mha", MetaImageHeader("1 0 0 0 1 0 0 0")); } },
  { "OrientedNrrdUnknownSpace",
    Expect::Error,
    "not a patient space",
    [] {
      return ReadOrientedBytes("space.nrrd", NrrdHeader("scanner-xyz", "(1,0,0) (0,1,0) (0,0,1)"));
    } },
  { "OrientedNrrdDegenerateDirection",
    Expect::Error,
    "no length",
    []
    {
      return ReadOrientedBytes(
        "zero.nrrd", NrrdHeader("left-posterior-superior", "(1,0,0) (0,0,0) (0,0,1)"));
    } },
  { "OrientedNrrdTruncatedData",
    Expect::Error,
    "",
    []
    {
      return ReadOrientedBytes(
        "short.nrrd", NrrdHeader("left-posterior-superior", "(1,0,0) (0,1,0) (0,0,1)"), 100);
    } },
  { "OrientedMetaImageTruncatedData",
    Expect::Error,
    "",
    [] { return ReadOrientedBytes("short.mha", MetaImageHeader("1 0 0 0 1 0 0 0 1"), 100); } },
  { "OrientedNotAnImageName",
    Expect::Error,
    "not a MetaImage",
    [] { return ReadOrientedBytes("image.raw", MetaImageHeader("1 0 0 0 1 0 0 0 1")); } },
  { "OrientedGoodMetaImage",
    Expect::Result,
    "",
    []
    {
      Outcome o = ReadOrientedBytes("good.mha", MetaImageHeader("0 1 0 -1 0 0 0 0 1"));
      o.ExpectedCells = 5 * 6 * 7;
      return o;
    } },
  { "OrientedGoodNrrd",
    Expect::Result,
    "",
    []
    {
      Outcome o = ReadOrientedBytes(
        "good.nrrd", NrrdHeader("right-anterior-superior", "(0,0.7,0) (-0.7,0,0) (0,0,2.5)"));
      o.ExpectedCells = 5 * 6 * 7;
      return o;
    } },
  { "VolGood",
    Expect::Result,
    "",
    []
    {
      Outcome o = ReadVolBytes("good", [](std::vector<std::uint8_t>&) {});
      o.ExpectedCells = 5 * 6 * 7;
      return o;
    } },
};

DG_BAD_INPUT_MATRIX(Rows);
} // namespace
