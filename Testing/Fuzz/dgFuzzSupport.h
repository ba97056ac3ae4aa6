// What the fuzz targets share: a per-process scratch directory for the
// bytes they hand to file readers, and the promise every reader's geometry
// keeps (finite origin, positive finite spacing, unit columns at right
// angles within the shear tolerance the readers accept).
#ifndef dgFuzzSupport_h
#define dgFuzzSupport_h

#include <cmath>
#include <cstdlib>
#include <string>
#include <unistd.h>

namespace dgfuzz
{
/// A new directory under /dev/shm (else /tmp) named dg_fuzz_<name>_XXXXXX;
/// aborts when neither can hold one.
inline std::string MakeScratchDirectory(const std::string& name)
{
  for (const char* root : { "/dev/shm", "/tmp" })
  {
    std::string templ = std::string(root) + "/dg_fuzz_" + name + "_XXXXXX";
    if (mkdtemp(&templ[0]))
      return templ;
  }
  std::abort();
}

/// Aborts unless world = origin + direction diag(spacing) index is a grid
/// the readers promise (direction row-major): columns of unit length within
/// `unit`, at right angles within `cosine` (DICOM's reader accepts 1e-3).
inline void CheckGridGeometry(const double origin[3], const double spacing[3], const double direction[9],
  double unit = 1e-9, double cosine = 1e-4)
{
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(origin[i]) || !std::isfinite(spacing[i]) || !(spacing[i] > 0))
      std::abort();
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(direction[i]))
      std::abort();
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b)
    {
      double dot = 0;
      for (int r = 0; r < 3; ++r)
        dot += direction[3 * r + a] * direction[3 * r + b];
      if (a == b ? std::fabs(dot - 1) > unit : std::fabs(dot) > cosine + 1e-9)
        std::abort();
    }
}
} // namespace dgfuzz

#endif
