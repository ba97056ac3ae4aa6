// libFuzzer target: the .vol decoder must reject or decode any byte string
// without crashing, and a decoded volume must have exactly X*Y*Z voxels.
#include "dgVolFormat.h"

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  dg::VolHeader header;
  std::vector<std::uint8_t> voxels;
  std::string error;
  if (dg::ParseVol(data, size, header, &voxels, error))
  {
    const std::size_t expected =
      std::size_t(header.Dims[0]) * std::size_t(header.Dims[1]) * std::size_t(header.Dims[2]);
    if (voxels.size() != expected || header.Dims[0] <= 0 || !error.empty())
    {
      std::abort();
    }
    // A decoded volume re-encodes and decodes to itself.
    std::vector<std::uint8_t> again, back;
    dg::VolHeader h2;
    if (!dg::EncodeVol(header.Dims, voxels.data(), header.Version, again, error) ||
      !dg::ParseVol(again.data(), again.size(), h2, &back, error) || back != voxels)
    {
      std::abort();
    }
  }
  else if (error.empty())
  {
    std::abort(); // a failure must say why
  }
  return 0;
}
