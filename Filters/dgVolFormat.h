// DGtal's VOL volume format: an ASCII header of "Key: value" lines, a line
// holding a single ".", then X*Y*Z bytes with x fastest; raw for Version 2,
// one zlib stream for Version 3. Plain C++ (no VTK pipeline) so that the
// decoder can be unit-tested and fuzzed on its own.
#ifndef dgVolFormat_h
#define dgVolFormat_h

#include <cstdint>
#include <fstream>
#include <map>
#include <functional>
#include <string>
#include <vector>

namespace dg
{

struct VolHeader
{
  int Dims[3] = { 0, 0, 0 };
  int Version = 0;
  double VoxelSize = 1.0;
  std::map<std::string, std::string> Fields; // every header line, as written
};

/// Parses a whole .vol file held in memory. On failure returns false and
/// sets error to a one-line reason; header and voxels are then unspecified.
/// With headerOnly, the voxel data is neither decoded nor checked.
/// progress (optional) is called with the decoded fraction in [0, 1] about
/// 64 times while a zlib stream inflates; when it returns false, decoding
/// stops and error is "aborted".
bool ParseVol(const std::uint8_t* bytes, std::size_t size, VolHeader& header,
  std::vector<std::uint8_t>* voxels, std::string& error,
  const std::function<bool(double)>& progress = std::function<bool(double)>());

/// Reads and parses a file from disk (same contract as ParseVol).
bool ReadVolFile(const std::string& path, VolHeader& header, std::vector<std::uint8_t>* voxels,
  std::string& error, const std::function<bool(double)>& progress = std::function<bool(double)>());

/// A .vol file read in part: Open reads the header only (its first 64 KiB,
/// as vtkDGtalVolReader's RequestInformation does), ReadBox then reads the
/// voxels of a box straight into the caller's buffer. Version 2 (raw) seeks
/// to each row of the box; Version 3 inflates the one zlib stream through a
/// bounded window (256 KiB of input, 1 MiB of output) and keeps only the
/// bytes of the box, so that a piece of a large volume never holds the whole
/// volume. The stream is inflated to its end whatever the box, so that every
/// box of a file fails exactly when the whole read fails (truncated, corrupt,
/// too many or too few voxels, trailing bytes): the pieces of one file agree
/// on whether it is readable.
class VolStream
{
public:
  /// Reads and checks the header and where the voxels start; false with a
  /// one-line reason (without the file's name) on failure.
  bool Open(const std::string& path, std::string& error);
  const VolHeader& Header() const { return this->Head; }
  /// Writes the voxels of box (an inclusive extent inside [0, Dims - 1]; an
  /// empty one reads nothing but still checks the data) into out, x fastest,
  /// (box[1] - box[0] + 1) * (box[3] - box[2] + 1) * (box[5] - box[4] + 1)
  /// bytes. Same errors and progress contract as ParseVol.
  bool ReadBox(const int box[6], std::uint8_t* out, std::string& error,
    const std::function<bool(double)>& progress = std::function<bool(double)>());

private:
  bool ReadRaw(const int box[6], std::uint8_t* out, std::string& error,
    const std::function<bool(double)>& progress);
  bool Inflate(const int box[6], std::uint8_t* out, std::string& error,
    const std::function<bool(double)>& progress);

  std::ifstream In;
  VolHeader Head;
  std::uint64_t DataOffset = 0; // the first voxel byte
  std::uint64_t DataSize = 0;   // the bytes after the header
};

/// Copies into out (the box, x fastest) the bytes of box found in span, the
/// decoded bytes [start, start + n) of a volume of dims (x fastest).
void CopySpanToBox(const std::uint8_t* span, std::uint64_t start, std::uint64_t n,
  const int dims[3], const int box[6], std::uint8_t* out);

/// Encodes a volume as a .vol file (version 2: raw, version 3: zlib).
bool EncodeVol(const int dims[3], const std::uint8_t* voxels, int version,
  std::vector<std::uint8_t>& out, std::string& error);

bool WriteVolFile(const std::string& path, const int dims[3], const std::uint8_t* voxels,
  int version, std::string& error);

} // namespace dg

#endif
