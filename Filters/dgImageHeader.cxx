#include "dgImageHeader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <utility>

namespace dg
{
namespace
{
// The header lines of a MetaImage or NRRD file (text up to the data; at most
// 64 KiB), lower-cased keys: what VTK's readers would silently drop.
std::vector<std::pair<std::string, std::string>> HeaderFields(const std::string& path,
  char separator)
{
  std::vector<std::pair<std::string, std::string>> fields;
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t read = 0;
  while (read < 65536 && std::getline(in, line))
  {
    read += line.size() + 1;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    if (line.empty())
      break; // NRRD: the blank line before the data
    const auto at = line.find(separator);
    if (at == std::string::npos)
      continue;
    std::string key = line.substr(0, at), value = line.substr(at + 1);
    auto trim = [](std::string& t)
    {
      while (!t.empty() && std::isspace(static_cast<unsigned char>(t.front())))
        t.erase(t.begin());
      while (!t.empty() && std::isspace(static_cast<unsigned char>(t.back())))
        t.pop_back();
    };
    trim(key);
    trim(value);
    std::transform(
      key.begin(), key.end(), key.begin(), [](unsigned char c) { return std::tolower(c); });
    fields.emplace_back(key, value);
    if (key == "elementdatafile")
      break; // MetaImage: the data follow
  }
  return fields;
}

std::string Lower(std::string v)
{
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  return v;
}

std::string Fmt(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// Direction and spacing from three axis vectors (columns): normalised
// columns, their lengths; refused when one is zero or two are not at right
// angles (a shear, which origin + direction + spacing cannot carry).
std::string FromColumns(const double columns[3][3], const char* name, HeaderGeometry& g)
{
  double unit[3][3];
  for (int a = 0; a < 3; ++a)
  {
    const double len = std::sqrt(columns[a][0] * columns[a][0] + columns[a][1] * columns[a][1] +
                                 columns[a][2] * columns[a][2]);
    if (!(len > 0) || !std::isfinite(len))
      return std::string("its ") + name + " give axis " + std::to_string(a) + " no length";
    for (int r = 0; r < 3; ++r)
      unit[a][r] = columns[a][r] / len;
    g.Spacing[a] *= len;
    if (!(g.Spacing[a] > 0) || !std::isfinite(g.Spacing[a]))
      return "its spacing along axis " + std::to_string(a) + " (" + Fmt(g.Spacing[a]) +
             ") is not a positive size";
  }
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b)
    {
      const double c = unit[a][0] * unit[b][0] + unit[a][1] * unit[b][1] + unit[a][2] * unit[b][2];
      if (std::abs(c) > 1e-4)
        return std::string("its ") + name + " are sheared: axes " + std::to_string(a) + " and " +
               std::to_string(b) + " at " +
               Fmt(std::acos(std::max(-1.0, std::min(1.0, c))) * 180 / M_PI) +
               " degrees, not 90 (origin, spacing and direction cannot carry a shear)";
    }
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a)
      g.Direction[3 * r + a] = unit[a][r];
  g.Has = true;
  return "";
}

// Empty on success, else the problem (one line, without the file's name).
} // namespace

std::string ReadHeaderGeometry(const std::string& path, bool nrrd, bool ras, HeaderGeometry& g)
{
  const auto fields = HeaderFields(path, nrrd ? ':' : '=');
  auto field = [&](std::initializer_list<const char*> keys) -> const std::string*
  {
    for (const char* k : keys)
      for (const auto& f : fields)
        if (f.first == k)
          return &f.second;
    return nullptr;
  };
  // The patient space the header is written in, as a flip of LPS.
  double flip[3] = { 1, 1, 1 };
  double columns[3][3];
  if (!nrrd)
  {
    const std::string* ndims = field({ "ndims" });
    if (!ndims || ParseNumbers(*ndims) != std::vector<double>{ 3 })
      return ""; // 2-D or 4-D: VTK's reader, as before
    if (const std::string* o = field({ "offset", "origin", "position" }))
    {
      const auto v = ParseNumbers(*o);
      if (v.size() != 3)
        return "its Offset (" + *o + ") is not three numbers";
      std::copy(v.begin(), v.end(), g.Origin);
    }
    if (const std::string* sp = field({ "elementspacing", "elementsize" }))
    {
      const auto v = ParseNumbers(*sp);
      if (v.size() != 3)
        return "its ElementSpacing (" + *sp + ") is not three numbers";
      std::copy(v.begin(), v.end(), g.Spacing);
    }
    double m[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    if (const std::string* t = field({ "transformmatrix", "rotation", "orientation" }))
    {
      const auto v = ParseNumbers(*t);
      if (v.size() != 9)
        return "its TransformMatrix (" + *t + ") is not nine numbers";
      std::copy(v.begin(), v.end(), m);
    }
    // ITK's MetaImageIO: the i-th triple is the direction of axis i.
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r)
        columns[a][r] = m[3 * a + r];
    if (std::string why = FromColumns(columns, "TransformMatrix columns", g); !why.empty())
      return why;
  }
  else
  {
    if (const std::string* space = field({ "space" }))
    {
      const std::string v = Lower(*space);
      if (v == "left-posterior-superior" || v == "lps")
        ;
      else if (v == "right-anterior-superior" || v == "ras")
        flip[0] = flip[1] = -1;
      else if (v == "left-anterior-superior" || v == "las")
        flip[1] = -1;
      else
        return "its space '" + *space +
               "' is not a patient space this reader converts to LPS "
               "(left-posterior-superior, right-anterior-superior, left-anterior-superior)";
    }
    const std::string* dirs = field({ "space directions" });
    if (!dirs)
      return ""; // axis-aligned (spacings): VTK's reader, as before
    std::vector<std::vector<double>> vectors;
    for (std::size_t at = dirs->find('('); at != std::string::npos; at = dirs->find('(', at + 1))
    {
      const auto close = dirs->find(')', at);
      if (close == std::string::npos)
        return "its space directions (" + *dirs + ") are not 3-vectors in parentheses";
      vectors.push_back(ParseNumbers(dirs->substr(at + 1, close - at - 1)));
    }
    if (vectors.size() != 3 ||
        std::any_of(vectors.begin(), vectors.end(), [](const auto& v) { return v.size() != 3; }))
      return "its space directions (" + *dirs + ") are not three 3-vectors";
    for (int a = 0; a < 3; ++a)
      for (int r = 0; r < 3; ++r)
        columns[a][r] = flip[r] * vectors[a][r];
    if (const std::string* o = field({ "space origin" }))
    {
      const auto v = ParseNumbers(*o);
      if (v.size() != 3)
        return "its space origin (" + *o + ") is not a 3-vector";
      for (int r = 0; r < 3; ++r)
        g.Origin[r] = flip[r] * v[r];
    }
    if (std::string why = FromColumns(columns, "space directions", g); !why.empty())
      return why;
  }
  if (ras)
  {
    for (int r = 0; r < 2; ++r)
    {
      g.Origin[r] = -g.Origin[r];
      for (int a = 0; a < 3; ++a)
        g.Direction[3 * r + a] = -g.Direction[3 * r + a];
    }
  }
  return "";
}

std::string CheckMetaImageDataSize(const std::string& path)
{
  const auto fields = HeaderFields(path, '=');
  auto field = [&](const char* key) -> std::string
  {
    for (const auto& f : fields)
      if (f.first == key)
        return f.second;
    return "";
  };
  if (Lower(field("compresseddata")) == "true")
    return "";
  const auto dims = ParseNumbers(field("dimsize"));
  if (dims.empty())
    return "";
  const std::string type = Lower(field("elementtype"));
  static const std::pair<const char*, int> sizes[] = { { "met_uchar", 1 },
    { "met_char", 1 },
    { "met_ushort", 2 },
    { "met_short", 2 },
    { "met_uint", 4 },
    { "met_int", 4 },
    { "met_float", 4 },
    { "met_double", 8 },
    { "met_ulong", 8 },
    { "met_long", 8 },
    { "met_ulong_long", 8 },
    { "met_long_long", 8 } };
  int bytes = 0;
  for (const auto& s : sizes)
    if (type == s.first)
      bytes = s.second;
  if (bytes == 0)
    return ""; // a type VTK's reader will judge
  double expected = bytes;
  for (double d : dims)
    expected *= d;
  const auto channels = ParseNumbers(field("elementnumberofchannels"));
  if (!channels.empty())
    expected *= channels[0];
  const std::string data = field("elementdatafile");
  std::uintmax_t available = 0;
  if (Lower(data) == "local")
  {
    // The data follow the ElementDataFile line.
    std::ifstream in(path, std::ios::binary);
    std::string line;
    while (std::getline(in, line))
    {
      std::string key = line.substr(0, line.find('='));
      key.erase(
        std::remove_if(key.begin(), key.end(), [](unsigned char ch) { return std::isspace(ch); }),
        key.end());
      if (Lower(key) == "elementdatafile")
        break;
    }
    const std::streamoff start = in.tellg();
    in.seekg(0, std::ios::end);
    const std::streamoff end = in.tellg();
    available = start >= 0 && end >= start ? static_cast<std::uintmax_t>(end - start) : 0;
  }
  else if (!data.empty() && data.find('%') == std::string::npos && data.rfind("LIST", 0) != 0)
  {
    const auto slash = path.find_last_of('/');
    const std::string file =
      data.front() == '/' || slash == std::string::npos ? data : path.substr(0, slash + 1) + data;
    std::ifstream in(file, std::ios::binary | std::ios::ate);
    if (!in)
      return "its ElementDataFile '" + data + "' cannot be opened";
    available = static_cast<std::uintmax_t>(in.tellg());
  }
  else
  {
    return ""; // a file list or pattern: VTK's reader reads it
  }
  if (static_cast<double>(available) < expected)
  {
    return "the voxel data is shorter than its header says (" + std::to_string(available) + " of " +
           Fmt(expected) + " bytes: truncated)";
  }
  return "";
}

bool NrrdHasThreeSpatialAxes(const std::string& path, int sizes[3])
{
  const auto fields = HeaderFields(path, ':');
  auto field = [&](const char* key) -> const std::string*
  {
    for (const auto& f : fields)
      if (f.first == key)
        return &f.second;
    return nullptr;
  };
  const std::string* dimension = field("dimension");
  const std::string* s = field("sizes");
  if (!dimension || !s || ParseNumbers(*dimension) != std::vector<double>{ 3 })
    return false;
  const auto v = ParseNumbers(*s);
  if (v.size() != 3)
    return false;
  for (double d : v)
    if (!(d >= 1 && d <= std::numeric_limits<int>::max()))
      return false; // not a size (VTK's reader judges it)
  if (const std::string* kinds = field("kinds"))
  {
    std::istringstream in(Lower(*kinds));
    std::string kind;
    while (in >> kind)
      if (kind != "domain" && kind != "space" && kind != "time" && kind != "???" && kind != "none")
        return false;
  }
  if (const std::string* dirs = field("space directions"))
    if (Lower(*dirs).find("none") != std::string::npos)
      return false;
  for (int a = 0; a < 3; ++a)
    sizes[a] = static_cast<int>(v[a]);
  return true;
}

std::vector<double> ParseNumbers(const std::string& text)
{
  std::vector<double> out;
  std::string t = text;
  for (char& c : t)
    if (c == '(' || c == ')' || c == ',' || c == '\\')
      c = ' ';
  std::istringstream ss(t);
  double v;
  while (ss >> v)
    out.push_back(v);
  return out;
}
} // namespace dg
