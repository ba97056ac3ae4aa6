#include "dgHugePages.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace dg
{

bool HugePagesDisabled()
{
  // For comparisons, and for hosts that want no huge pages.
  static const bool off = [] {
    const char* e = std::getenv("DG_HUGEPAGES");
    return e && std::strcmp(e, "0") == 0;
  }();
  return off;
}

void AdviseHugePages(void* p, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (!p || bytes < HugePagesMinimumBytes || HugePagesDisabled())
  {
    return;
  }
  // madvise needs a page-aligned start; whole 2 MiB pages inside the range
  // are what THP can back, so the ends are trimmed to them.
  constexpr std::uintptr_t huge = std::uintptr_t(2) << 20;
  const std::uintptr_t b = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t first = (b + huge - 1) & ~(huge - 1);
  const std::uintptr_t last = (b + bytes) & ~(huge - 1);
  if (last > first)
  {
    // Advice only: a kernel without THP refuses it, and nothing changes.
    (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
#else
  (void)p;
  (void)bytes;
#endif
}

} // namespace dg
