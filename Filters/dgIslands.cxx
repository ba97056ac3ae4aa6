#include "dgIslands.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <utility>

namespace dg
{
namespace
{
// Mask values during RemoveSmallComponents: bit 0 is the current state
// (1 inside); an island voxel turned outside is 2, so that filling it again
// as part of a cavity does not count it as changed.
constexpr std::uint8_t RemovedIsland = 2;

// The 6-connected components of the voxels whose bit 0 equals Want, as runs
// along x joined by union-find. Run indices follow the voxel order (rows
// r = k * ny + j, then x), and every component's root is its smallest run
// index, so labels, sizes and their order do not depend on threads.
class RunLabelling
{
public:
  RunLabelling(const std::uint8_t* mask, const int dims[3], std::uint8_t want)
    : Mask(mask)
    , Want(want)
  {
    for (int a = 0; a < 3; ++a)
    {
      this->Dims[a] = dims[a];
    }
    this->Rows = static_cast<std::int64_t>(dims[1]) * dims[2];
  }

  // Finds the runs and joins them; false when progress asked to stop.
  // progress receives the done fraction of this labelling.
  bool Label(const std::function<bool(double)>& progress)
  {
    this->FindRuns();
    if (progress && !progress(0.3))
    {
      return false;
    }
    const std::int64_t ny = this->Dims[1];
    const std::int64_t step = std::max<std::int64_t>(1, this->Rows / 16);
    for (std::int64_t r = 0; r < this->Rows; ++r)
    {
      if (r % ny > 0)
      {
        this->JoinRows(r, r - 1);
      }
      if (r >= ny)
      {
        this->JoinRows(r, r - ny);
      }
      if (progress && (r + 1) % step == 0 &&
        !progress(0.3 + 0.6 * static_cast<double>(r + 1) / this->Rows))
      {
        return false;
      }
    }
    // Roots are the smallest index of their tree and every link points to a
    // smaller index: in increasing order, one pass points each run at its root.
    for (std::size_t i = 0; i < this->Parent.size(); ++i)
    {
      this->Parent[i] = this->Parent[this->Parent[i]];
    }
    // Sizes and the faces of the box touched, accumulated on the roots.
    this->Size.assign(this->Parent.size(), 0);
    this->Border.assign(this->Parent.size(), 0);
    const int nx = this->Dims[0], nz = this->Dims[2];
    for (std::int64_t r = 0; r < this->Rows; ++r)
    {
      const std::int64_t j = r % ny, k = r / ny;
      const std::uint8_t rowFaces = static_cast<std::uint8_t>((j == 0 ? 4 : 0) |
        (j == ny - 1 ? 8 : 0) | (k == 0 ? 16 : 0) | (k == nz - 1 ? 32 : 0));
      for (std::int64_t i = this->RowStart[r]; i < this->RowStart[r + 1]; ++i)
      {
        const std::int64_t root = this->Parent[i];
        this->Size[root] += this->X1[i] - this->X0[i];
        this->Border[root] |= rowFaces | (this->X0[i] == 0 ? 1 : 0) | (this->X1[i] == nx ? 2 : 0);
      }
    }
    return true;
  }

  std::int64_t NumberOfRuns() const { return static_cast<std::int64_t>(this->Parent.size()); }
  bool IsRoot(std::int64_t i) const { return this->Parent[i] == i; }
  std::int64_t Root(std::int64_t i) const { return this->Parent[i]; }
  std::int64_t SizeOf(std::int64_t root) const { return this->Size[root]; }
  std::int64_t RunBegin(std::int64_t i) const { return this->RowOf(i) * this->Dims[0] + this->X0[i]; }
  std::int64_t RunEnd(std::int64_t i) const { return this->RowOf(i) * this->Dims[0] + this->X1[i]; }
  bool OnBorder(std::int64_t root) const { return this->Border[root] != 0; }
  // The faces of the box the component touches (bits as in ComponentWindow).
  unsigned Faces(std::int64_t root) const { return this->Border[root]; }

  // Calls f(run, first voxel, past-the-end voxel) for every run, rows in
  // parallel.
  template <typename F>
  void ForRuns(F f) const
  {
    vtkSMPTools::For(0, this->Rows, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t r = b; r < e; ++r)
      {
        const std::int64_t row = r * this->Dims[0];
        for (std::int64_t i = this->RowStart[r]; i < this->RowStart[r + 1]; ++i)
        {
          f(i, row + this->X0[i], row + this->X1[i]);
        }
      }
    });
  }

private:
  bool Taken(std::uint8_t v) const { return (v & 1) == this->Want; }

  // The first x' >= x with Taken(row[x']) != taken (nx if none): eight
  // voxels at a time through uniform stretches, which most of a volume is.
  int Skip(const std::uint8_t* row, int x, int nx, bool taken) const
  {
    constexpr std::uint64_t ones = 0x0101010101010101ull;
    // Bit 0 of every byte equal to this when the eight voxels are all `taken`.
    const std::uint64_t same = (taken == (this->Want == 1)) ? ones : 0;
    while (x + 8 <= nx)
    {
      std::uint64_t word;
      std::memcpy(&word, row + x, 8);
      if ((word & ones) != same)
      {
        break;
      }
      x += 8;
    }
    while (x < nx && this->Taken(row[x]) == taken)
    {
      ++x;
    }
    return x;
  }

  // The row of run i (binary search in RowStart).
  std::int64_t RowOf(std::int64_t i) const
  {
    return std::upper_bound(this->RowStart.begin(), this->RowStart.end(), i) -
      this->RowStart.begin() - 1;
  }

  void FindRuns()
  {
    const int nx = this->Dims[0];
    this->RowStart.assign(this->Rows + 1, 0);
    vtkSMPTools::For(0, this->Rows, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t r = b; r < e; ++r)
      {
        const std::uint8_t* row = this->Mask + r * nx;
        std::int64_t n = 0;
        for (int x = this->Skip(row, 0, nx, false); x < nx;
             x = this->Skip(row, this->Skip(row, x, nx, true), nx, false))
        {
          ++n;
        }
        this->RowStart[r + 1] = n;
      }
    });
    for (std::int64_t r = 0; r < this->Rows; ++r)
    {
      this->RowStart[r + 1] += this->RowStart[r];
    }
    const std::int64_t runs = this->RowStart[this->Rows];
    this->X0.resize(runs);
    this->X1.resize(runs);
    this->Parent.resize(runs);
    vtkSMPTools::For(0, this->Rows, [&](std::int64_t b, std::int64_t e) {
      for (std::int64_t r = b; r < e; ++r)
      {
        const std::uint8_t* row = this->Mask + r * nx;
        std::int64_t i = this->RowStart[r];
        for (int x = this->Skip(row, 0, nx, false); x < nx; x = this->Skip(row, x, nx, false))
        {
          const int start = x;
          x = this->Skip(row, x, nx, true);
          this->X0[i] = start;
          this->X1[i] = x;
          this->Parent[i] = i;
          ++i;
        }
      }
    });
  }

  std::int64_t Find(std::int64_t a)
  {
    while (this->Parent[a] != a)
    {
      this->Parent[a] = this->Parent[this->Parent[a]];
      a = this->Parent[a];
    }
    return a;
  }

  void Union(std::int64_t a, std::int64_t b)
  {
    a = this->Find(a);
    b = this->Find(b);
    if (a < b)
    {
      this->Parent[b] = a;
    }
    else if (b < a)
    {
      this->Parent[a] = b;
    }
  }

  // Joins the runs of row r with the runs of row s that share a face with
  // them: overlapping x intervals (6-connectivity; no diagonal contact).
  void JoinRows(std::int64_t r, std::int64_t s)
  {
    std::int64_t p = this->RowStart[r], q = this->RowStart[s];
    const std::int64_t pe = this->RowStart[r + 1], qe = this->RowStart[s + 1];
    while (p < pe && q < qe)
    {
      if (this->X0[p] < this->X1[q] && this->X0[q] < this->X1[p])
      {
        this->Union(p, q);
      }
      if (this->X1[p] < this->X1[q])
      {
        ++p;
      }
      else
      {
        ++q;
      }
    }
  }

  const std::uint8_t* Mask;
  std::uint8_t Want;
  int Dims[3];
  std::int64_t Rows = 0;
  std::vector<std::int64_t> RowStart; // Rows + 1 offsets into the runs
  std::vector<std::int32_t> X0, X1;   // run i covers x in [X0[i], X1[i])
  std::vector<std::int64_t> Parent;
  std::vector<std::int64_t> Size;
  std::vector<std::uint8_t> Border; // faces touched, on the roots
};

// Voxel v (index in the mask, x fastest) is in the counted box.
bool InBox(std::int64_t v, const int dims[3], const int box[6])
{
  const std::int64_t i = v % dims[0], r = v / dims[0];
  const std::int64_t j = r % dims[1], k = r / dims[1];
  return i >= box[0] && i <= box[1] && j >= box[2] && j <= box[3] && k >= box[4] && k <= box[5];
}

// One pass: the components of want-voxels that are small (and, for
// cavities, off the border; for islands, off the open faces) change state.
// Only components whose first voxel is in the counted box, and changed
// voxels in it, are counted. Returns false when aborted.
// Removed island voxels keep the value RemovedIsland; their runs are added
// to removedRuns (first voxel, past-the-end voxel) for the final reset.
bool ChangeSmall(std::uint8_t* mask, const int dims[3], std::uint8_t want,
  std::int64_t minimumSize, const ComponentWindow& window, std::int64_t& components,
  std::int64_t& changed, std::vector<std::pair<std::int64_t, std::int64_t>>& removedRuns,
  const std::function<bool(double)>& progress)
{
  const int* box = window.Counted;
  const bool countAll = box[0] == 0 && box[1] == dims[0] - 1 && box[2] == 0 &&
    box[3] == dims[1] - 1 && box[4] == 0 && box[5] == dims[2] - 1;
  RunLabelling labels(mask, dims, want);
  if (!labels.Label(progress))
  {
    return false;
  }
  const bool cavities = want == 0;
  // A cavity on any face of the box is part of the exterior (an image
  // face) or may continue beyond it (an open face); an island on an open
  // face may continue too. Both are kept, as large components are.
  const unsigned keepFaces = cavities ? 63u : (window.OpenFaces & 63u);
  std::vector<std::uint8_t> small(labels.NumberOfRuns(), 0);
  bool any = false;
  for (std::int64_t i = 0; i < labels.NumberOfRuns(); ++i)
  {
    if (labels.IsRoot(i) && labels.SizeOf(i) < minimumSize && !(labels.Faces(i) & keepFaces))
    {
      small[i] = 1;
      any = true;
      // The root is the component's first run: its first voxel is the
      // component's first voxel (x fastest).
      components += countAll || InBox(labels.RunBegin(i), dims, box);
    }
  }
  if (!any)
  {
    return !progress || progress(1.0);
  }
  std::atomic<std::int64_t> delta(0);
  std::uint8_t* m = mask;
  labels.ForRuns([&](std::int64_t run, std::int64_t begin, std::int64_t end) {
    if (!small[labels.Root(run)])
    {
      return;
    }
    std::int64_t d = 0;
    for (std::int64_t v = begin; v < end; ++v)
    {
      const int counted = countAll || InBox(v, dims, box) ? 1 : 0;
      if (cavities)
      {
        // An island voxel removed before comes back: no change overall.
        d += m[v] == RemovedIsland ? -counted : counted;
        m[v] = 1;
      }
      else
      {
        m[v] = RemovedIsland;
        d += counted;
      }
    }
    delta += d;
  });
  changed += delta;
  if (!cavities)
  {
    for (std::int64_t i = 0; i < labels.NumberOfRuns(); ++i)
    {
      if (small[labels.Root(i)])
      {
        removedRuns.emplace_back(labels.RunBegin(i), labels.RunEnd(i));
      }
    }
  }
  return !progress || progress(1.0);
}
} // namespace

bool RemoveSmallComponents(std::uint8_t* mask, const int dims[3], std::int64_t minimumSize,
  bool removeIslands, bool fillCavities, IslandCounts& counts,
  const std::function<bool(double)>& progress, const ComponentWindow* window)
{
  counts = IslandCounts();
  ComponentWindow whole;
  whole.Counted[1] = dims[0] - 1;
  whole.Counted[3] = dims[1] - 1;
  whole.Counted[5] = dims[2] - 1;
  const ComponentWindow& w = window ? *window : whole;
  if (minimumSize <= 1 || dims[0] <= 0 || dims[1] <= 0 || dims[2] <= 0)
  {
    return !progress || progress(1.0);
  }
  const double share = removeIslands && fillCavities ? 0.5 : 1.0;
  std::vector<std::pair<std::int64_t, std::int64_t>> removedRuns;
  if (removeIslands)
  {
    const auto sub = [&](double f) { return !progress || progress(share * f); };
    if (!ChangeSmall(mask, dims, 1, minimumSize, w, counts.RemovedIslands, counts.ChangedVoxels,
          removedRuns, sub))
    {
      return false;
    }
  }
  if (fillCavities)
  {
    const double start = removeIslands ? share : 0.0;
    const auto sub = [&](double f) { return !progress || progress(start + share * f); };
    if (!ChangeSmall(mask, dims, 0, minimumSize, w, counts.FilledCavities, counts.ChangedVoxels,
          removedRuns, sub))
    {
      return false;
    }
  }
  // Removed island voxels that no cavity took back: outside (0).
  for (const auto& run : removedRuns)
  {
    for (std::int64_t v = run.first; v < run.second; ++v)
    {
      mask[v] &= 1;
    }
  }
  return true;
}

int ComponentReach(std::int64_t minimumSize, bool removeIslands, bool fillCavities)
{
  if (minimumSize <= 1)
  {
    return 0;
  }
  const std::int64_t passes = (removeIslands ? 1 : 0) + (fillCavities ? 1 : 0);
  return static_cast<int>(std::min<std::int64_t>(passes * (minimumSize - 1), 1 << 30));
}

void ComponentSizes(const std::vector<std::uint8_t>& mask, const int dims[3], std::uint8_t value,
  std::vector<std::int64_t>& sizes, std::vector<std::uint8_t>& touchesBorder)
{
  sizes.clear();
  touchesBorder.clear();
  if (mask.empty())
  {
    return;
  }
  RunLabelling labels(mask.data(), dims, value & 1);
  labels.Label({});
  for (std::int64_t i = 0; i < labels.NumberOfRuns(); ++i)
  {
    if (labels.IsRoot(i))
    {
      sizes.push_back(labels.SizeOf(i));
      touchesBorder.push_back(labels.OnBorder(i) ? 1 : 0);
    }
  }
}

} // namespace dg
