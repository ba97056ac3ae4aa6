#include "dgVolFormat.h"

#include <vtk_zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace dg
{
namespace
{
// Real headers are a dozen short lines; a bound keeps a binary file that
// lacks the "." line from being scanned as text for ever.
constexpr std::size_t MaxHeaderBytes = 64 * 1024;
// 2^36 voxels (4096^3) is far beyond what fits in memory here; anything
// larger is a corrupt header rather than a real volume.
constexpr std::uint64_t MaxVoxels = std::uint64_t(1) << 36;

std::string Trim(const std::string& s)
{
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos)
  {
    return std::string();
  }
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

bool ParseInt(const std::string& text, long long& value)
{
  if (text.empty())
  {
    return false;
  }
  char* end = nullptr;
  errno = 0;
  value = std::strtoll(text.c_str(), &end, 10);
  return errno == 0 && end && *end == '\0';
}

bool ParseDouble(const std::string& text, double& value)
{
  if (text.empty())
  {
    return false;
  }
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  return errno == 0 && end && *end == '\0';
}
} // namespace

bool ParseVol(const std::uint8_t* bytes, std::size_t size, VolHeader& header,
  std::vector<std::uint8_t>* voxels, std::string& error, const std::function<bool(double)>& progress)
{
  header = VolHeader();
  std::size_t pos = 0;
  bool sawDot = false;
  while (pos < size && pos < MaxHeaderBytes)
  {
    std::size_t eol = pos;
    while (eol < size && bytes[eol] != '\n')
    {
      ++eol;
    }
    if (eol == size)
    {
      error = "header is not terminated by a line holding a single '.'";
      return false;
    }
    const std::string line(reinterpret_cast<const char*>(bytes + pos), eol - pos);
    pos = eol + 1;
    const std::string t = Trim(line);
    if (t == ".")
    {
      sawDot = true;
      break;
    }
    if (t.empty())
    {
      continue;
    }
    const auto colon = t.find(':');
    if (colon == std::string::npos)
    {
      error = "bad header line '" + t.substr(0, 60) + "' (expected 'Key: value')";
      return false;
    }
    for (char c : t)
    {
      if (static_cast<unsigned char>(c) < 32 && c != '\t')
      {
        error = "header holds binary bytes";
        return false;
      }
    }
    header.Fields[Trim(t.substr(0, colon))] = Trim(t.substr(colon + 1));
  }
  if (!sawDot)
  {
    error = size == 0 ? "file is empty" : "header is not terminated by a line holding a single '.'";
    return false;
  }

  const char* keys[3] = { "X", "Y", "Z" };
  std::uint64_t count = 1;
  for (int a = 0; a < 3; ++a)
  {
    auto it = header.Fields.find(keys[a]);
    long long v = 0;
    if (it == header.Fields.end())
    {
      error = std::string("header lacks the dimension '") + keys[a] + "'";
      return false;
    }
    if (!ParseInt(it->second, v) || v <= 0 || v > std::numeric_limits<int>::max())
    {
      error = std::string("bad dimension ") + keys[a] + ": '" + it->second + "'";
      return false;
    }
    header.Dims[a] = static_cast<int>(v);
    count *= static_cast<std::uint64_t>(v);
    if (count > MaxVoxels)
    {
      error = "dimensions too large (more than 2^36 voxels)";
      return false;
    }
  }
  auto vit = header.Fields.find("Version");
  long long version = 0;
  if (vit == header.Fields.end() || !ParseInt(vit->second, version) ||
    (version != 2 && version != 3))
  {
    error = "unsupported or missing Version (2 or 3 expected)";
    return false;
  }
  header.Version = static_cast<int>(version);
  auto sit = header.Fields.find("Voxel-Size");
  if (sit != header.Fields.end())
  {
    double s = 0;
    if (!ParseDouble(sit->second, s) || !(s > 0) || s > 1e30)
    {
      error = "bad Voxel-Size '" + sit->second + "'";
      return false;
    }
    header.VoxelSize = s;
  }
  if (!voxels)
  {
    return true;
  }

  const std::uint8_t* data = bytes + pos;
  const std::size_t available = size - pos;
  if (header.Version == 2)
  {
    if (available != count)
    {
      std::ostringstream msg;
      msg << "voxel data holds " << available << " bytes, the header's dimensions need " << count;
      error = msg.str();
      return false;
    }
    voxels->assign(data, data + count);
    return true;
  }

  // Version 3: exactly one zlib stream that inflates to exactly count bytes.
  // Deflate cannot expand data more than 1032:1, so a header promising more
  // than that is refused before anything is allocated: a 100-byte file must
  // not make the reader allocate gigabytes (found by fuzzing).
  if (count > static_cast<std::uint64_t>(available) * 1032 + 1024)
  {
    std::ostringstream msg;
    msg << "zlib stream of " << available << " bytes cannot hold the " << count
        << " voxels of the header's dimensions (truncated file?)";
    error = msg.str();
    return false;
  }
  // zlib counts in uInt, so input and output are handed over in chunks.
  voxels->assign(static_cast<std::size_t>(count), 0);
  z_stream zs;
  std::memset(&zs, 0, sizeof(zs));
  if (inflateInit(&zs) != Z_OK)
  {
    error = "cannot initialise zlib";
    return false;
  }
  // Output in about 64 pieces when someone watches progress (at least 1 MiB
  // each); zlib counts in uInt, so never more than 1 GiB at a time.
  const std::size_t chunk = progress
    ? std::max<std::size_t>(std::size_t(1) << 20, static_cast<std::size_t>(count) / 64)
    : std::size_t(1) << 30;
  const std::size_t inChunk = std::size_t(1) << 30;
  std::uint8_t probe = 0; // one byte past the end: detects a stream that is too long
  bool probing = false;
  int status = Z_OK;
  const char* failure = nullptr;
  for (;;)
  {
    if (zs.avail_in == 0)
    {
      const std::size_t done = zs.total_in;
      zs.next_in = const_cast<Bytef*>(data + done);
      zs.avail_in = static_cast<uInt>(std::min(available - done, inChunk));
    }
    if (zs.avail_out == 0)
    {
      const std::size_t done = zs.total_out;
      if (done < count)
      {
        if (progress && done > 0 && !progress(static_cast<double>(done) / count))
        {
          failure = "aborted";
          break;
        }
        zs.next_out = voxels->data() + done;
        zs.avail_out = static_cast<uInt>(std::min(static_cast<std::size_t>(count) - done, chunk));
      }
      else if (!probing)
      {
        probing = true;
        zs.next_out = &probe;
        zs.avail_out = 1;
      }
      else
      {
        failure = "zlib stream holds more voxels than the header's dimensions";
        break;
      }
    }
    status = inflate(&zs, Z_NO_FLUSH);
    if (status == Z_STREAM_END)
    {
      break;
    }
    if (status == Z_BUF_ERROR && zs.avail_out != 0 && zs.total_in == available)
    {
      failure = "zlib stream is truncated";
      break;
    }
    if (status != Z_OK && status != Z_BUF_ERROR)
    {
      failure = "zlib stream is corrupt";
      break;
    }
  }
  const std::size_t produced = zs.total_out;
  const std::size_t consumed = zs.total_in;
  inflateEnd(&zs);
  if (failure)
  {
    error = failure;
    return false;
  }
  if (produced != count)
  {
    std::ostringstream msg;
    msg << "zlib stream holds " << produced << " voxels, the header's dimensions need " << count;
    error = msg.str();
    return false;
  }
  if (consumed != available)
  {
    error = "unexpected bytes after the zlib stream";
    return false;
  }
  return true;
}

bool ReadVolFile(const std::string& path, VolHeader& header, std::vector<std::uint8_t>* voxels,
  std::string& error, const std::function<bool(double)>& progress)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
  {
    error = "cannot open '" + path + "': " + std::strerror(errno);
    return false;
  }
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
  {
    error = "cannot read '" + path + "'";
    return false;
  }
  if (!ParseVol(bytes.data(), bytes.size(), header, voxels, error, progress))
  {
    error = path + ": " + error;
    return false;
  }
  return true;
}

bool EncodeVol(const int dims[3], const std::uint8_t* voxels, int version,
  std::vector<std::uint8_t>& out, std::string& error)
{
  if (dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0 || (version != 2 && version != 3))
  {
    error = "bad dimensions or version";
    return false;
  }
  const std::size_t count = std::size_t(dims[0]) * dims[1] * dims[2];
  std::ostringstream h;
  h << "Center-X: " << dims[0] / 2 << "\nCenter-Y: " << dims[1] / 2 << "\nCenter-Z: " << dims[2] / 2
    << "\nX: " << dims[0] << "\nY: " << dims[1] << "\nZ: " << dims[2]
    << "\nVoxel-Size: 1\nAlpha-Color: 0\nVoxel-Endian: 0\nInt-Endian: 0123\nVersion: " << version
    << "\n.\n";
  const std::string head = h.str();
  out.assign(head.begin(), head.end());
  if (version == 2)
  {
    out.insert(out.end(), voxels, voxels + count);
    return true;
  }
  uLongf bound = compressBound(static_cast<uLong>(count));
  std::vector<std::uint8_t> z(bound);
  if (compress2(z.data(), &bound, voxels, static_cast<uLong>(count), Z_DEFAULT_COMPRESSION) != Z_OK)
  {
    error = "zlib compression failed";
    return false;
  }
  out.insert(out.end(), z.begin(), z.begin() + bound);
  return true;
}

bool WriteVolFile(const std::string& path, const int dims[3], const std::uint8_t* voxels,
  int version, std::string& error)
{
  std::vector<std::uint8_t> bytes;
  if (!EncodeVol(dims, voxels, version, bytes, error))
  {
    return false;
  }
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out)
  {
    error = "cannot write '" + path + "'";
    return false;
  }
  return true;
}

} // namespace dg
