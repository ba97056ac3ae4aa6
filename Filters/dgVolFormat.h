// DGtal's VOL volume format: an ASCII header of "Key: value" lines, a line
// holding a single ".", then X*Y*Z bytes with x fastest; raw for Version 2,
// one zlib stream for Version 3. Plain C++ (no VTK pipeline) so that the
// decoder can be unit-tested and fuzzed on its own.
#ifndef dgVolFormat_h
#define dgVolFormat_h

#include <cstdint>
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

/// Encodes a volume as a .vol file (version 2: raw, version 3: zlib).
bool EncodeVol(const int dims[3], const std::uint8_t* voxels, int version,
  std::vector<std::uint8_t>& out, std::string& error);

bool WriteVolFile(const std::string& path, const int dims[3], const std::uint8_t* voxels,
  int version, std::string& error);

} // namespace dg

#endif
