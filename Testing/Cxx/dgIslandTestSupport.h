// What the island-filter tests share: the filter's definition done the slow
// way (breadth-first search over face neighbours), and masks to images.
#ifndef dgIslandTestSupport_h
#define dgIslandTestSupport_h

#include "dgTestShapes.h"

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <cstdint>
#include <deque>
#include <vector>

namespace dgtest
{
using Mask = std::vector<std::uint8_t>;

struct Reference
{
  Mask Result;
  std::int64_t Islands = 0, Cavities = 0, Changed = 0;
};

// Components of the voxels equal to value, by breadth-first search over the
// six face neighbours: a label per voxel (-1 for the others), then per label
// its size and whether it has a voxel on the image border.
inline int BruteForceComponents(const Mask& m,
  const int d[3],
  std::uint8_t value,
  std::vector<int>& label,
  std::vector<std::int64_t>& size,
  std::vector<bool>& border)
{
  label.assign(m.size(), -1);
  size.clear();
  border.clear();
  const auto id = [d](int i, int j, int k) { return (std::size_t(k) * d[1] + j) * d[0] + i; };
  int n = 0;
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i)
      {
        if (m[id(i, j, k)] != value || label[id(i, j, k)] >= 0)
        {
          continue;
        }
        std::deque<std::array<int, 3>> queue{ { i, j, k } };
        label[id(i, j, k)] = n;
        size.push_back(0);
        border.push_back(false);
        while (!queue.empty())
        {
          const auto p = queue.front();
          queue.pop_front();
          ++size[n];
          for (int a = 0; a < 3; ++a)
          {
            if (p[a] == 0 || p[a] == d[a] - 1)
            {
              border[n] = true;
            }
          }
          static const int step[6][3] = {
            { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 }
          };
          for (const auto& s : step)
          {
            const int q[3] = { p[0] + s[0], p[1] + s[1], p[2] + s[2] };
            if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= d[0] || q[1] >= d[1] || q[2] >= d[2])
            {
              continue;
            }
            const std::size_t v = id(q[0], q[1], q[2]);
            if (m[v] == value && label[v] < 0)
            {
              label[v] = n;
              queue.push_back({ q[0], q[1], q[2] });
            }
          }
        }
        ++n;
      }
  return n;
}

// The filter's definition, done the slow way: islands first, then the
// cavities of that result.
inline Reference BruteForce(const Mask& original,
  const int d[3],
  int minimumSize,
  bool islands,
  bool cavities)
{
  Reference r;
  r.Result = original;
  std::vector<int> label;
  std::vector<std::int64_t> size;
  std::vector<bool> border;
  if (islands)
  {
    BruteForceComponents(r.Result, d, 1, label, size, border);
    for (std::size_t c = 0; c < size.size(); ++c)
      r.Islands += size[c] < minimumSize;
    for (std::size_t v = 0; v < r.Result.size(); ++v)
      if (label[v] >= 0 && size[label[v]] < minimumSize)
        r.Result[v] = 0;
  }
  if (cavities)
  {
    BruteForceComponents(r.Result, d, 0, label, size, border);
    for (std::size_t c = 0; c < size.size(); ++c)
      r.Cavities += size[c] < minimumSize && !border[c];
    for (std::size_t v = 0; v < r.Result.size(); ++v)
      if (label[v] >= 0 && size[label[v]] < minimumSize && !border[label[v]])
        r.Result[v] = 1;
  }
  for (std::size_t v = 0; v < r.Result.size(); ++v)
    r.Changed += r.Result[v] != original[v];
  return r;
}

inline Mask ValuesOf(vtkImageData* image)
{
  vtkDataArray* s = image->GetPointData()->GetScalars();
  Mask m(s ? s->GetNumberOfTuples() : 0);
  for (std::size_t v = 0; v < m.size(); ++v)
    m[v] = static_cast<std::uint8_t>(s->GetTuple1(static_cast<vtkIdType>(v)));
  return m;
}

inline vtkSmartPointer<vtkImageData> FromMask(const Mask& m, const int d[3])
{
  return dgtest::MakeImage(d[0],
    d[1],
    d[2],
    [&](int i, int j, int k) { return m[(std::size_t(k) * d[1] + j) * d[0] + i]; });
}

} // namespace dgtest

#endif
