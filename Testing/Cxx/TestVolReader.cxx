// The .vol decoder and vtkDGtalVolReader: round trips through files written
// here (both versions), sub-extents and pieces (with ghost layers) equal to
// the box of the whole read, a real VolGallery file when ../shared is
// present, and every corrupt variant failing cleanly.
#include "dgTestShapes.h"
#include "dgVolFormat.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkExtentTranslator.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkDataSetAttributes.h>

#include <gtest/gtest.h>
#include "dgTestTemp.h"

#include <cstdio>
#include <fstream>
#include <random>
#include <array>
#include <algorithm>
#include "dgPieces.h"

#include <vtk_zlib.h>

namespace
{
using dgtest::TempPath;

std::vector<std::uint8_t> RandomVolume(const int dims[3], unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> v(std::size_t(dims[0]) * dims[1] * dims[2]);
  for (auto& x : v)
  {
    // Mostly zeros with runs, like a segmentation, plus arbitrary labels.
    x = (rng() % 4 == 0) ? static_cast<std::uint8_t>(rng() % 256) : 0;
  }
  return v;
}

void WriteBytes(const std::string& path, const std::vector<std::uint8_t>& bytes)
{
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// Reads through the VTK class, expecting failure: an error and no voxels.
// With a box, only that box is asked for: a piece must fail wherever the
// damage lies, as the whole read does (the stream is inflated to its end).
void ExpectReaderFails(const std::string& path, const char* what, const int* box = nullptr)
{
  vtkNew<vtkDGtalVolReader> reader;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(reader);
  obs->Observe(reader->GetExecutive());
  reader->SetFileName(path.c_str());
  if (box)
  {
    reader->UpdateInformation();
    reader->UpdateExtent(const_cast<int*>(box));
  }
  else
  {
    reader->Update();
  }
  EXPECT_GE(obs->Errors, 1) << what;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints() > 0 &&
      reader->GetOutput()->GetPointData()->GetScalars() != nullptr,
    false)
    << what;
  EXPECT_STRNE(reader->GetErrorMessage(), "") << what;
}

std::vector<int> Extent(vtkImageData* image)
{
  int e[6];
  image->GetExtent(e);
  return std::vector<int>(e, e + 6);
}

// Every voxel of `part` equals the same voxel of `whole` (by structured
// index), and part's geometry is whole's.
void ExpectBoxOfWhole(vtkImageData* whole, vtkImageData* part, const std::string& what)
{
  int e[6];
  part->GetExtent(e);
  for (int a = 0; a < 3; ++a)
  {
    EXPECT_EQ(part->GetOrigin()[a], whole->GetOrigin()[a]) << what;
    EXPECT_EQ(part->GetSpacing()[a], whole->GetSpacing()[a]) << what;
  }
  auto* s = vtkUnsignedCharArray::SafeDownCast(part->GetPointData()->GetScalars());
  ASSERT_NE(s, nullptr) << what;
  EXPECT_STREQ(s->GetName(), "Value") << what;
  ASSERT_EQ(s->GetNumberOfValues(), part->GetNumberOfPoints()) << what;
  for (int k = e[4]; k <= e[5]; ++k)
    for (int j = e[2]; j <= e[3]; ++j)
      for (int i = e[0]; i <= e[1]; ++i)
        ASSERT_EQ(part->GetScalarComponentAsDouble(i, j, k, 0),
          whole->GetScalarComponentAsDouble(i, j, k, 0))
          << what << " at " << i << " " << j << " " << k;
}
} // namespace

TEST(VolReader, RoundTripBothVersions)
{
  const int dims[3] = { 7, 5, 9 };
  const auto voxels = RandomVolume(dims, 3);
  for (int version : { 2, 3 })
  {
    const std::string path = TempPath("roundtrip" + std::to_string(version) + ".vol");
    std::string error;
    ASSERT_TRUE(dg::WriteVolFile(path, dims, voxels.data(), version, error)) << error;
    vtkNew<vtkDGtalVolReader> reader;
    ASSERT_EQ(reader->CanReadFile(path.c_str()), 1);
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkImageData* image = reader->GetOutput();
    int d[3];
    image->GetDimensions(d);
    EXPECT_EQ(d[0], 7);
    EXPECT_EQ(d[1], 5);
    EXPECT_EQ(d[2], 9);
    auto* s = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
    ASSERT_NE(s, nullptr);
    ASSERT_EQ(s->GetNumberOfValues(), static_cast<vtkIdType>(voxels.size()));
    // x fastest, as in VTK's point order.
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i)
        {
          const std::size_t idx = (std::size_t(k) * dims[1] + j) * dims[0] + i;
          ASSERT_EQ(image->GetScalarComponentAsDouble(i, j, k, 0), voxels[idx]);
        }
  }
}

TEST(VolReader, SubExtentsAreBoxesOfTheWholeRead)
{
  const int dims[3] = { 23, 17, 11 };
  const auto voxels = RandomVolume(dims, 5);
  for (int version : { 2, 3 })
  {
    const std::string path = TempPath("sub" + std::to_string(version) + ".vol");
    std::string error;
    ASSERT_TRUE(dg::WriteVolFile(path, dims, voxels.data(), version, error)) << error;
    vtkNew<vtkDGtalVolReader> whole;
    whole->SetFileName(path.c_str());
    whole->Update();
    ASSERT_EQ(whole->GetOutput()->GetNumberOfPoints(), 23 * 17 * 11);
    EXPECT_EQ(whole->GetOutput()->GetPointData()->GetArray(vtkDataSetAttributes::GhostArrayName()),
      nullptr);
    // Inside, on every border, one voxel thick along each axis, a single
    // voxel, a corner, the whole extent.
    const std::vector<std::vector<int>> boxes = { { 3, 15, 2, 9, 4, 7 }, { 0, 22, 0, 16, 0, 4 },
      { 0, 5, 10, 16, 6, 10 }, { 17, 22, 0, 16, 0, 10 }, { 7, 7, 0, 16, 0, 10 },
      { 0, 22, 16, 16, 0, 10 }, { 2, 20, 3, 13, 10, 10 }, { 22, 22, 16, 16, 10, 10 },
      { 0, 0, 0, 0, 0, 0 }, { 0, 22, 0, 16, 0, 10 } };
    for (const auto& box : boxes)
    {
      const std::string what = "version " + std::to_string(version) + " box " +
        std::to_string(box[0]) + ".." + std::to_string(box[1]) + " " + std::to_string(box[2]) +
        ".." + std::to_string(box[3]) + " " + std::to_string(box[4]) + ".." +
        std::to_string(box[5]);
      vtkNew<vtkDGtalVolReader> reader;
      reader->SetFileName(path.c_str());
      reader->UpdateInformation();
      ASSERT_EQ(reader->GetOutputInformation(0)->Get(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT()), 1);
      ASSERT_TRUE(reader->UpdateExtent(box.data())) << what;
      EXPECT_EQ(Extent(reader->GetOutput()), box) << what;
      ExpectBoxOfWhole(whole->GetOutput(), reader->GetOutput(), what);
      EXPECT_EQ(
        reader->GetOutput()->GetPointData()->GetArray(vtkDataSetAttributes::GhostArrayName()),
        nullptr)
        << what;
    }
    // Pieces as the executive makes them (vtkExtentTranslator, block mode,
    // by cells: neighbours share a layer of voxels), with ghost layers
    // marked in vtkGhostType by the executive.
    const int wholeExtent[6] = { 0, 22, 0, 16, 0, 10 };
    for (int n : { 2, 3, 4, 7 })
      for (int ghosts : { 0, 1, 2 })
        for (int p = 0; p < n; ++p)
        {
          const std::string what = "version " + std::to_string(version) + " piece " +
            std::to_string(p) + " of " + std::to_string(n) + " ghosts " + std::to_string(ghosts);
          int expected[6], own[6], we[6];
          std::copy(wholeExtent, wholeExtent + 6, we);
          vtkNew<vtkExtentTranslator> t;
          t->PieceToExtentThreadSafe(p, n, ghosts, we, expected, vtkExtentTranslator::BLOCK_MODE, 0);
          t->PieceToExtentThreadSafe(p, n, 0, we, own, vtkExtentTranslator::BLOCK_MODE, 0);
          vtkNew<vtkDGtalVolReader> reader;
          reader->SetFileName(path.c_str());
          ASSERT_TRUE(reader->UpdatePiece(p, n, ghosts)) << what;
          vtkImageData* out = reader->GetOutput();
          EXPECT_EQ(Extent(out), std::vector<int>(expected, expected + 6)) << what;
          ExpectBoxOfWhole(whole->GetOutput(), out, what);
          vtkDataArray* ghost =
            out->GetPointData()->GetArray(vtkDataSetAttributes::GhostArrayName());
          if (ghosts == 0)
          {
            EXPECT_EQ(ghost, nullptr) << what;
            continue;
          }
          ASSERT_NE(ghost, nullptr) << what;
          // A voxel is a ghost exactly when it lies outside the piece's own box.
          for (int k = expected[4]; k <= expected[5]; ++k)
            for (int j = expected[2]; j <= expected[3]; ++j)
              for (int i = expected[0]; i <= expected[1]; ++i)
              {
                int ijk[3] = { i, j, k };
                const bool inOwn = i >= own[0] && i <= own[1] && j >= own[2] && j <= own[3] &&
                  k >= own[4] && k <= own[5];
                ASSERT_EQ(ghost->GetTuple1(out->ComputePointId(ijk)) != 0, !inOwn)
                  << what << " at " << i << " " << j << " " << k;
              }
        }
  }
}

TEST(VolReader, HandWrittenVersionTwoFile)
{
  // A single voxel of value 128 at the centre of a 3^3 volume, as DGtal writes it.
  std::string text = "Center-X: 1\nCenter-Y: 1\nCenter-Z: 1\nX: 3\nY: 3\nZ: 3\nVoxel-Size: 2\n"
                     "Alpha-Color: 0\nVoxel-Endian: 0\nInt-Endian: 0123\nVersion: 2\n.\n";
  std::vector<std::uint8_t> bytes(text.begin(), text.end());
  for (int a = 0; a < 27; ++a)
  {
    bytes.push_back(a == 13 ? 128 : 0);
  }
  const std::string path = TempPath("onevoxel.vol");
  WriteBytes(path, bytes);
  vtkNew<vtkDGtalVolReader> reader;
  reader->SetFileName(path.c_str());
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputConnection(reader->GetOutputPort());
  surface->Update();
  EXPECT_EQ(surface->GetOutput()->GetNumberOfPolys(), 6);
  EXPECT_EQ(reader->GetOutput()->GetSpacing()[0], 2.0);
  double b[6];
  surface->GetOutput()->GetBounds(b);
  EXPECT_DOUBLE_EQ(b[0], 1.0); // voxel 1 at x = 2, half a voxel is 1
  EXPECT_DOUBLE_EQ(b[1], 3.0);
}

TEST(VolReader, RealVolGalleryFileWhenPresent)
{
  const std::string path = std::string(DG_SHARED_DATA_DIR) + "/fandisk-64.vol";
  std::ifstream probe(path);
  if (!probe)
  {
    GTEST_SKIP() << "../shared/data/volgallery is absent";
  }
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> bytes(
    (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  dg::VolHeader header;
  std::vector<std::uint8_t> direct;
  std::string error;
  ASSERT_TRUE(dg::ParseVol(bytes.data(), bytes.size(), header, &direct, error)) << error;
  EXPECT_EQ(header.Version, 3);
  vtkNew<vtkDGtalVolReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  auto* s = vtkUnsignedCharArray::SafeDownCast(reader->GetOutput()->GetPointData()->GetScalars());
  ASSERT_NE(s, nullptr);
  ASSERT_EQ(s->GetNumberOfValues(), 64 * 64 * 64);
  long inside = 0;
  for (vtkIdType p = 0; p < s->GetNumberOfValues(); ++p)
  {
    ASSERT_EQ(s->GetValue(p), direct[p]);
    inside += s->GetValue(p) != 0;
  }
  EXPECT_GT(inside, 1000);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputConnection(reader->GetOutputPort());
  surface->Update();
  EXPECT_GT(surface->GetOutput()->GetNumberOfPolys(), 1000);
}

TEST(VolReader, CorruptFilesFailCleanly)
{
  const int dims[3] = { 6, 6, 6 };
  const auto voxels = RandomVolume(dims, 11);
  std::vector<std::uint8_t> v2, v3;
  std::string error;
  ASSERT_TRUE(dg::EncodeVol(dims, voxels.data(), 2, v2, error));
  ASSERT_TRUE(dg::EncodeVol(dims, voxels.data(), 3, v3, error));
  const std::string text(v2.begin(), v2.end());
  const std::size_t headerEnd = text.find("\n.\n") + 3;

  // Truncated at several points: inside the header, right after it, mid-data.
  for (const auto* file : { &v2, &v3 })
  {
    for (std::size_t cut : { std::size_t(0), std::size_t(5), headerEnd - 2, headerEnd,
           headerEnd + 3, file->size() - 1 })
    {
      std::vector<std::uint8_t> t(file->begin(), file->begin() + cut);
      const std::string path = TempPath("trunc.vol");
      WriteBytes(path, t);
      ExpectReaderFails(path, ("truncated at " + std::to_string(cut)).c_str());
      // The first slice only: its bytes come first in the file.
      const int firstSlice[6] = { 0, 5, 0, 5, 0, 0 };
      ExpectReaderFails(path, ("truncated at " + std::to_string(cut) + ", first slice").c_str(), firstSlice);
    }
  }
  // Bad header lines.
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string s(v2.begin(), v2.end());
    s.replace(s.find(from), from.size(), to);
    return std::vector<std::uint8_t>(s.begin(), s.end());
  };
  const std::pair<const char*, std::vector<std::uint8_t>> bad[] = {
    { "no colon", replace("X: 6", "X 6") },
    { "negative dimension", replace("X: 6", "X: -6") },
    { "non-numeric dimension", replace("Y: 6", "Y: six") },
    { "huge dimension", replace("Z: 6", "Z: 99999999999") },
    { "unknown version", replace("Version: 2", "Version: 7") },
    { "dimensions larger than data", replace("X: 6", "X: 7") },
    { "dimensions smaller than data", replace("X: 6", "X: 5") },
    { "bad voxel size", replace("Voxel-Size: 1", "Voxel-Size: -1") },
  };
  for (const auto& b : bad)
  {
    const std::string path = TempPath("bad.vol");
    WriteBytes(path, b.second);
    ExpectReaderFails(path, b.first);
  }
  // Flipped bytes in the zlib stream: every flip must fail or decode to
  // exactly the right size (zlib's Adler-32 catches almost all).
  const std::string t3(v3.begin(), v3.end());
  const std::size_t z0 = t3.find("\n.\n") + 3;
  int failures = 0;
  for (std::size_t pos = z0; pos < v3.size(); pos += 3)
  {
    std::vector<std::uint8_t> c = v3;
    c[pos] ^= 0x5A;
    dg::VolHeader h;
    std::vector<std::uint8_t> out;
    std::string err;
    if (!dg::ParseVol(c.data(), c.size(), h, &out, err))
    {
      ++failures;
      EXPECT_FALSE(err.empty());
    }
    else
    {
      EXPECT_EQ(out.size(), voxels.size());
    }
  }
  EXPECT_GT(failures, 0);
  // A flipped byte in the stream through the reader class.
  std::vector<std::uint8_t> c = v3;
  c[z0 + 1] ^= 0xFF;
  const std::string path = TempPath("flip.vol");
  WriteBytes(path, c);
  ExpectReaderFails(path, "flipped zlib header byte");
  // Bytes after the stream, and a stream one voxel too long: found only
  // past the last slice, so the first slice's piece must still see them.
  const int firstSlice[6] = { 0, 5, 0, 5, 0, 0 };
  std::vector<std::uint8_t> trailing = v3;
  trailing.push_back(0);
  WriteBytes(path, trailing);
  ExpectReaderFails(path, "a byte after the zlib stream, whole read");
  ExpectReaderFails(path, "a byte after the zlib stream, first slice", firstSlice);
  {
    std::vector<std::uint8_t> extra(voxels);
    extra.push_back(7);
    uLongf bound = compressBound(static_cast<uLong>(extra.size()));
    std::vector<std::uint8_t> z(bound);
    ASSERT_EQ(compress2(z.data(), &bound, extra.data(), static_cast<uLong>(extra.size()), 6), Z_OK);
    const std::string head = "X: 6\nY: 6\nZ: 6\nVersion: 3\n.\n";
    std::vector<std::uint8_t> longer(head.begin(), head.end());
    longer.insert(longer.end(), z.begin(), z.begin() + bound);
    WriteBytes(path, longer);
    ExpectReaderFails(path, "a stream one voxel too long, whole read");
    ExpectReaderFails(path, "a stream one voxel too long, first slice", firstSlice);
  }
  // Every byte-flipped stream that the whole decode refuses, the first
  // slice refuses too.
  for (std::size_t pos = z0; pos < v3.size(); pos += 7)
  {
    std::vector<std::uint8_t> flipped = v3;
    flipped[pos] ^= 0x5A;
    dg::VolHeader h;
    std::vector<std::uint8_t> out;
    std::string err;
    if (!dg::ParseVol(flipped.data(), flipped.size(), h, &out, err))
    {
      WriteBytes(path, flipped);
      ExpectReaderFails(path, ("flipped byte " + std::to_string(pos) + ", first slice").c_str(),
        firstSlice);
    }
  }
  ExpectReaderFails(TempPath("does-not-exist.vol"), "missing file");

  // Found by fuzzing: a tiny zlib stream under a header promising billions
  // of voxels must be refused before any allocation.
  std::string huge = "X: 4\nY: 2\nZ: 888888888\nVersion: 3\n.\n";
  std::vector<std::uint8_t> hugeBytes(huge.begin(), huge.end());
  hugeBytes.insert(hugeBytes.end(), v3.begin() + z0, v3.end());
  dg::VolHeader h;
  std::vector<std::uint8_t> out;
  std::string err;
  EXPECT_FALSE(dg::ParseVol(hugeBytes.data(), hugeBytes.size(), h, &out, err));
  EXPECT_NE(err.find("cannot hold"), std::string::npos) << err;
  EXPECT_LT(out.capacity(), std::size_t(1) << 20);
}

// dg::VolStream against the whole decode: every box of a volume larger than
// the 1 MiB inflate window (rows cut by the window's ends), of both
// versions, and of narrow shapes (one-voxel rows, one-row slices), equals
// the box cut from ParseVol's volume; the row copy itself on random splits
// of the stream.
TEST(VolReader, StreamedBoxesEqualTheWholeDecode)
{
  const std::vector<std::array<int, 3>> shapes = { { 131, 97, 101 }, { 1, 7, 300 }, { 300, 1, 5 },
    { 1, 1, 1 } };
  for (const auto& shape : shapes)
  {
    const int dims[3] = { shape[0], shape[1], shape[2] };
    const auto voxels = RandomVolume(dims, 17);
    const int X = dims[0] - 1, Y = dims[1] - 1, Z = dims[2] - 1;
    const std::vector<std::array<int, 6>> boxes = { { 0, X, 0, Y, 0, Z }, { 0, X, 0, Y, Z / 2, Z },
      { X / 3, X, Y / 4, Y / 2, Z / 3, std::min(Z, Z / 3 + 2) }, { X, X, Y, Y, Z, Z }, { 0, 0, 0, 0, 0, 0 },
      { 0, X, Y / 2, Y / 2, 0, Z }, { X / 2, X / 2, 0, Y, 0, Z } };
    for (int version : { 2, 3 })
    {
      const std::string path = TempPath("stream" + std::to_string(version) + ".vol");
      std::string error;
      ASSERT_TRUE(dg::WriteVolFile(path, dims, voxels.data(), version, error)) << error;
      for (const auto& b : boxes)
      {
        const std::string what = std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" +
          std::to_string(dims[2]) + " version " + std::to_string(version) + " box " +
          std::to_string(b[0]) + ".." + std::to_string(b[1]) + " " + std::to_string(b[2]) + ".." +
          std::to_string(b[3]) + " " + std::to_string(b[4]) + ".." + std::to_string(b[5]);
        const int whole[6] = { 0, X, 0, Y, 0, Z };
        std::vector<std::uint8_t> expected(
          std::size_t(b[1] - b[0] + 1) * (b[3] - b[2] + 1) * (b[5] - b[4] + 1));
        dg::CopyExtent(voxels.data(), whole, b.data(), 1, expected.data());
        dg::VolStream vol;
        ASSERT_TRUE(vol.Open(path, error)) << what << ": " << error;
        std::vector<std::uint8_t> got(expected.size(), 0xEE);
        ASSERT_TRUE(vol.ReadBox(b.data(), got.data(), error)) << what << ": " << error;
        EXPECT_EQ(got, expected) << what;
        // The same box, the stream handed over in random spans.
        std::mt19937 rng(b[0] + 31 * b[5]);
        std::vector<std::uint8_t> spans(expected.size(), 0xEE);
        for (std::size_t at = 0; at < voxels.size();)
        {
          const std::size_t n = std::min<std::size_t>(voxels.size() - at, 1 + rng() % 5000);
          dg::CopySpanToBox(voxels.data() + at, at, n, dims, b.data(), spans.data());
          at += n;
        }
        EXPECT_EQ(spans, expected) << what << " (random spans)";
      }
    }
  }
}
