// Transparent huge pages for the large arrays the filters fill.
//
// Every 4 KiB page of a fresh allocation costs a page fault when first
// written; on the VM these figures come from, a fault costs several
// microseconds (a paravirtualised exit), and a 512^3 run of the whole
// pipeline made about 450 000 of them: octa-flower's surface, II and the AT
// complex ran 2-4x slower in a fresh process than their arithmetic needs.
// With the kernel's THP in "madvise" mode (Debian's default), a range that
// is advised MADV_HUGEPAGE before it is first touched is backed by 2 MiB
// pages: one fault instead of 512. glibc's own switch for this
// (GLIBC_TUNABLES=glibc.malloc.hugetlb=1) is an environment variable read at
// start-up, which a library cannot set for its host (ParaView, Python);
// advising our own large arrays can (docs/at-speed.md has the figures).
//
// Elsewhere (no MADV_HUGEPAGE, or THP "never") the calls do nothing, and
// DG_HUGEPAGES=0 in the environment turns them off.
#ifndef dgHugePages_h
#define dgHugePages_h

#include <cstddef>
#include <vector>

namespace dg
{

/// Below this many bytes advising buys nothing (it needs whole, aligned
/// 2 MiB pages inside the range).
constexpr std::size_t HugePagesMinimumBytes = std::size_t(4) << 20;

/// True when DG_HUGEPAGES=0 is in the environment: no advice here, and no
/// huge-page malloc in the program (read once).
bool HugePagesDisabled();

/// Advises [p, p + bytes) for transparent huge pages; call before the range
/// is first written. Ranges below HugePagesMinimumBytes are left alone.
void AdviseHugePages(void* p, std::size_t bytes);

/// v.assign(n, value), with new storage advised before it is first touched;
/// `capacity` (if larger than n) is reserved, for a vector that will grow
/// (counts that become offsets take one more element).
template<class T>
void AssignHuge(std::vector<T>& v, std::size_t n, const T& value = T(), std::size_t capacity = 0)
{
  const std::size_t c = capacity > n ? capacity : n;
  if (v.capacity() < c && c * sizeof(T) >= HugePagesMinimumBytes)
  {
    std::vector<T>().swap(v); // the old contents are not kept: no copy
    v.reserve(c);
    AdviseHugePages(v.data(), c * sizeof(T));
  }
  else if (v.capacity() < c)
  {
    v.reserve(c);
  }
  v.assign(n, value);
}

/// v.assign(first, last), the same way.
template<class T, class It>
void AssignHuge(std::vector<T>& v, It first, It last)
{
  const std::size_t n = static_cast<std::size_t>(last - first);
  if (v.capacity() < n && n * sizeof(T) >= HugePagesMinimumBytes)
  {
    std::vector<T>().swap(v);
    v.reserve(n);
    AdviseHugePages(v.data(), n * sizeof(T));
  }
  v.assign(first, last);
}

/// v.resize(n), advising new storage first; contents are kept.
template<class T>
void ResizeHuge(std::vector<T>& v, std::size_t n)
{
  if (v.capacity() < n && n * sizeof(T) >= HugePagesMinimumBytes)
  {
    std::vector<T> w;
    w.reserve(n);
    AdviseHugePages(w.data(), n * sizeof(T));
    w.assign(v.begin(), v.end());
    v.swap(w);
  }
  v.resize(n);
}

} // namespace dg

#endif
