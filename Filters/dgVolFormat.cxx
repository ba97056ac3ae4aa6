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

namespace
{
// The header part of ParseVol: on success, pos is the first byte after the
// "." line and count the number of voxels.
bool ParseVolHeader(const std::uint8_t* bytes, std::size_t size, VolHeader& header,
  std::size_t& pos, std::uint64_t& count, std::string& error)
{
  header = VolHeader();
  pos = 0;
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
  count = 1;
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
  return true;
}

// Deflate cannot expand data more than 1032:1, so a header promising more
// than that is refused before anything is allocated: a 100-byte file must
// not make the reader allocate gigabytes (found by fuzzing).
bool StreamCanHold(std::uint64_t available, std::uint64_t count, std::string& error)
{
  if (count > available * 1032 + 1024)
  {
    std::ostringstream msg;
    msg << "zlib stream of " << available << " bytes cannot hold the " << count
        << " voxels of the header's dimensions (truncated file?)";
    error = msg.str();
    return false;
  }
  return true;
}

bool RawSizeMatches(std::uint64_t available, std::uint64_t count, std::string& error)
{
  if (available != count)
  {
    std::ostringstream msg;
    msg << "voxel data holds " << available << " bytes, the header's dimensions need " << count;
    error = msg.str();
    return false;
  }
  return true;
}
} // namespace

bool ParseVol(const std::uint8_t* bytes, std::size_t size, VolHeader& header,
  std::vector<std::uint8_t>* voxels, std::string& error, const std::function<bool(double)>& progress)
{
  std::size_t pos = 0;
  std::uint64_t count = 0;
  if (!ParseVolHeader(bytes, size, header, pos, count, error))
  {
    return false;
  }
  if (!voxels)
  {
    return true;
  }

  const std::uint8_t* data = bytes + pos;
  const std::size_t available = size - pos;
  if (header.Version == 2)
  {
    if (!RawSizeMatches(available, count, error))
    {
      return false;
    }
    voxels->assign(data, data + count);
    return true;
  }

  // Version 3: exactly one zlib stream that inflates to exactly count bytes.
  if (!StreamCanHold(available, count, error))
  {
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

void CopySpanToBox(const std::uint8_t* span, std::uint64_t start, std::uint64_t n,
  const int dims[3], const int box[6], std::uint8_t* out)
{
  if (box[1] < box[0] || box[3] < box[2] || box[5] < box[4])
  {
    return;
  }
  const std::uint64_t nx = static_cast<std::uint64_t>(dims[0]);
  const std::uint64_t ny = static_cast<std::uint64_t>(dims[1]);
  const std::uint64_t bx = static_cast<std::uint64_t>(box[1] - box[0] + 1);
  const std::uint64_t by = static_cast<std::uint64_t>(box[3] - box[2] + 1);
  const std::uint64_t end = start + n;
  std::uint64_t p = start;
  // One step per row of the box met in the span; rows outside the box are
  // jumped over (a whole slab at once before the box's first slice), so the
  // cost follows the box, not the span.
  while (p < end)
  {
    const std::uint64_t row = p / nx;
    const std::uint64_t y = row % ny;
    const std::uint64_t z = row / ny;
    if (z > static_cast<std::uint64_t>(box[5]))
    {
      return;
    }
    if (z < static_cast<std::uint64_t>(box[4]))
    {
      p = (static_cast<std::uint64_t>(box[4]) * ny + box[2]) * nx;
      continue;
    }
    if (y < static_cast<std::uint64_t>(box[2]))
    {
      p = (z * ny + box[2]) * nx;
      continue;
    }
    if (y > static_cast<std::uint64_t>(box[3]))
    {
      p = ((z + 1) * ny + box[2]) * nx;
      continue;
    }
    const std::uint64_t rowStart = row * nx;
    const std::uint64_t lo = std::max<std::uint64_t>(p, rowStart + box[0]);
    const std::uint64_t hi = std::min<std::uint64_t>(end, rowStart + box[1] + 1);
    if (lo < hi)
    {
      std::memcpy(out + ((z - box[4]) * by + (y - box[2])) * bx + (lo - rowStart - box[0]),
        span + (lo - start), static_cast<std::size_t>(hi - lo));
    }
    p = rowStart + nx;
  }
}

bool VolStream::Open(const std::string& path, std::string& error)
{
  this->In.close();
  this->In.clear();
  this->In.open(path, std::ios::binary);
  if (!this->In)
  {
    error = "cannot open '" + path + "': " + std::strerror(errno);
    return false;
  }
  // The header from the first bytes only, as RequestInformation reads it.
  std::vector<std::uint8_t> head(MaxHeaderBytes);
  this->In.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(this->In.gcount()));
  this->In.clear();
  std::size_t pos = 0;
  std::uint64_t count = 0;
  if (!ParseVolHeader(head.data(), head.size(), this->Head, pos, count, error))
  {
    return false;
  }
  this->In.seekg(0, std::ios::end);
  const std::streamoff length = this->In.tellg();
  if (length < 0 || static_cast<std::uint64_t>(length) < pos)
  {
    error = "cannot read '" + path + "'";
    return false;
  }
  this->DataOffset = pos;
  this->DataSize = static_cast<std::uint64_t>(length) - pos;
  // The size checks of ParseVol, before the caller allocates anything.
  return this->Head.Version == 2 ? RawSizeMatches(this->DataSize, count, error)
                                 : StreamCanHold(this->DataSize, count, error);
}

bool VolStream::ReadBox(const int box[6], std::uint8_t* out, std::string& error,
  const std::function<bool(double)>& progress)
{
  for (int a = 0; a < 3; ++a)
  {
    if (box[2 * a] <= box[2 * a + 1] &&
      (box[2 * a] < 0 || box[2 * a + 1] >= this->Head.Dims[a]))
    {
      error = "requested box outside the volume";
      return false;
    }
  }
  // One report before any byte: a small volume decodes in one window, and
  // a caller must still be able to abort (and see progress) while it reads.
  if (progress && !progress(0.0))
  {
    error = "aborted";
    return false;
  }
  return this->Head.Version == 2 ? this->ReadRaw(box, out, error, progress)
                                 : this->Inflate(box, out, error, progress);
}

bool VolStream::ReadRaw(const int box[6], std::uint8_t* out, std::string& error,
  const std::function<bool(double)>& progress)
{
  if (box[1] < box[0] || box[3] < box[2] || box[5] < box[4])
  {
    return true; // the size was checked by Open: nothing else can fail
  }
  const std::uint64_t nx = static_cast<std::uint64_t>(this->Head.Dims[0]);
  const std::uint64_t ny = static_cast<std::uint64_t>(this->Head.Dims[1]);
  const std::uint64_t bx = static_cast<std::uint64_t>(box[1] - box[0] + 1);
  const std::uint64_t by = static_cast<std::uint64_t>(box[3] - box[2] + 1);
  const std::uint64_t bz = static_cast<std::uint64_t>(box[5] - box[4] + 1);
  // Contiguous runs: whole slabs when the box spans x and y, whole rows of
  // a slice when it spans x, else one row of the box at a time.
  const bool fullX = bx == nx, fullY = fullX && by == ny;
  const std::uint64_t run = fullY ? bx * by * bz : fullX ? bx * by : bx;
  const std::uint64_t runs = bx * by * bz / run;
  const std::uint64_t report = std::max<std::uint64_t>(1, runs / 64);
  for (std::uint64_t r = 0; r < runs; ++r)
  {
    // The run's first voxel: row r of the box (or slice r, or the slab).
    const std::uint64_t rowsPerRun = fullY ? by * bz : fullX ? by : 1;
    const std::uint64_t row = r * rowsPerRun;
    const std::uint64_t z = box[4] + row / by, y = box[2] + row % by;
    const std::uint64_t at = this->DataOffset + (z * ny + y) * nx + box[0];
    this->In.seekg(static_cast<std::streamoff>(at));
    this->In.read(reinterpret_cast<char*>(out + r * run), static_cast<std::streamsize>(run));
    if (!this->In || static_cast<std::uint64_t>(this->In.gcount()) != run)
    {
      error = "cannot read the voxel data (the file changed while read?)";
      return false;
    }
    if (progress && (r + 1) % report == 0 && !progress(static_cast<double>(r + 1) / runs))
    {
      error = "aborted";
      return false;
    }
  }
  return true;
}

bool VolStream::Inflate(const int box[6], std::uint8_t* out, std::string& error,
  const std::function<bool(double)>& progress)
{
  const std::uint64_t count = static_cast<std::uint64_t>(this->Head.Dims[0]) *
    static_cast<std::uint64_t>(this->Head.Dims[1]) * static_cast<std::uint64_t>(this->Head.Dims[2]);
  // Bounded buffers: the compressed input in 256 KiB reads, the decoded
  // bytes in a 1 MiB window of which the box's bytes are copied out.
  std::vector<std::uint8_t> input(std::size_t(256) << 10);
  std::vector<std::uint8_t> window(
    static_cast<std::size_t>(std::min<std::uint64_t>(count, std::uint64_t(1) << 20)));
  this->In.clear();
  this->In.seekg(static_cast<std::streamoff>(this->DataOffset));
  std::uint64_t unread = this->DataSize;
  z_stream zs;
  std::memset(&zs, 0, sizeof(zs));
  if (inflateInit(&zs) != Z_OK)
  {
    error = "cannot initialise zlib";
    return false;
  }
  const std::uint64_t step =
    std::max<std::uint64_t>(std::uint64_t(1) << 20, count / 64); // progress about 64 times
  std::uint64_t produced = 0, nextReport = step;
  std::uint8_t probe = 0; // one byte past the end: detects a stream that is too long
  const char* failure = nullptr;
  for (;;)
  {
    if (zs.avail_in == 0 && unread > 0)
    {
      const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(unread, input.size()));
      this->In.read(reinterpret_cast<char*>(input.data()), static_cast<std::streamsize>(want));
      if (static_cast<std::size_t>(this->In.gcount()) != want)
      {
        failure = "cannot read the zlib stream (the file changed while read?)";
        break;
      }
      unread -= want;
      zs.next_in = input.data();
      zs.avail_in = static_cast<uInt>(want);
    }
    const bool probing = produced == count;
    zs.next_out = probing ? &probe : window.data();
    zs.avail_out =
      probing ? 1 : static_cast<uInt>(std::min<std::uint64_t>(window.size(), count - produced));
    const int status = inflate(&zs, Z_NO_FLUSH);
    const std::uint64_t got = probing ? 1 - zs.avail_out : static_cast<std::uint64_t>(
      std::min<std::uint64_t>(window.size(), count - produced) - zs.avail_out);
    if (probing && got > 0)
    {
      failure = "zlib stream holds more voxels than the header's dimensions";
      break;
    }
    if (!probing && got > 0)
    {
      CopySpanToBox(window.data(), produced, got, this->Head.Dims, box, out);
      produced += got;
      if (progress && produced >= nextReport && produced < count)
      {
        nextReport += step;
        if (!progress(static_cast<double>(produced) / count))
        {
          failure = "aborted";
          break;
        }
      }
    }
    if (status == Z_STREAM_END)
    {
      break;
    }
    if (status == Z_BUF_ERROR && zs.avail_in == 0 && unread == 0)
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
  const bool trailing = zs.avail_in > 0 || unread > 0;
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
  if (trailing)
  {
    error = "unexpected bytes after the zlib stream";
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
