// What the benchmarks print about the machine and how they summarise runs:
// shared by BenchATPipeline and BenchPreconditioners.
#ifndef dgBenchMachine_h
#define dgBenchMachine_h

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace dgbench
{
/// The first line of a file (/proc/loadavg), empty when unreadable.
inline std::string FirstLine(const char* path)
{
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  return line;
}

/// The CPU's model name from /proc/cpuinfo.
inline std::string CpuModel()
{
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
  {
    if (line.compare(0, 10, "model name") == 0)
    {
      const auto c = line.find(':');
      return c == std::string::npos ? line : line.substr(c + 2);
    }
  }
  return "unknown";
}

/// The median (mean of the two middle values for an even count; 0 if empty).
inline double MedianOf(std::vector<double> v)
{
  if (v.empty())
  {
    return 0.0;
  }
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}
} // namespace dgbench

#endif
