// Digital surface extraction on a binary voxel grid (docs/method.md section 1).
//
// Plain C++ core of vtkDigitalSurfaceFilter: it knows nothing about VTK
// pipelines so that it can be unit-tested and benchmarked on its own. The
// algorithm follows the flying-edges layout: one pass counts pointels per
// corner row and surfels per voxel row, a prefix sum gives every row its
// output offsets, and a second pass writes points and quads straight to their
// final place. Threads write disjoint ranges, so the output does not depend on
// the number of threads.
#ifndef dgCubicalSurface_h
#define dgCubicalSurface_h

#include <cstdint>
#include <functional>
#include <vector>

namespace dg
{

/// A binary volume stored row by row (x fastest). Each row is padded with one
/// outside voxel at both ends so that x-neighbours never need a bounds check:
/// voxel (i, j, k) lives at Data[(k * Dims[1] + j) * RowLength() + i + 1].
class PaddedMask
{
public:
  void Allocate(int nx, int ny, int nz);
  int Dims[3] = { 0, 0, 0 };
  std::int64_t RowLength() const { return static_cast<std::int64_t>(this->Dims[0]) + 2; }
  std::uint8_t* Row(int j, int k)
  {
    return this->Data.data() + (static_cast<std::int64_t>(k) * this->Dims[1] + j) * this->RowLength();
  }
  const std::uint8_t* Row(int j, int k) const
  {
    return this->Data.data() + (static_cast<std::int64_t>(k) * this->Dims[1] + j) * this->RowLength();
  }
  bool Inside(int i, int j, int k) const;
  /// Recomputes RowMin/RowMax (first/last inside voxel of each row, or
  /// RowMin > RowMax for an empty row). Must be called after filling Data.
  void UpdateRowBounds();

  std::vector<std::uint8_t> Data;
  std::vector<int> RowMin, RowMax;
};

/// The surfel directions: the outward axis of a surfel, seen from its inside
/// voxel. Direction d has axis d / 2 and sign + when d is odd.
enum SurfelDirection : std::uint8_t
{
  MinusX = 0,
  PlusX = 1,
  MinusY = 2,
  PlusY = 3,
  MinusZ = 4,
  PlusZ = 5
};

/// The 2-dimensional cubical complex bounding the inside voxels, in grid
/// (corner index) coordinates: corner (ci, cj, ck) is the lower corner of
/// voxel (ci, cj, ck), so its centre-based grid position is (ci-1/2, ...).
struct CubicalSurface
{
  std::vector<std::int32_t> Corners;  // 3 per point: corner indices
  std::vector<std::int64_t> Quads;    // 4 per surfel, counter-clockwise seen from outside
  std::vector<std::int32_t> Voxels;   // 3 per surfel: the inside voxel
  std::vector<std::uint8_t> Directions; // 1 per surfel: SurfelDirection
  std::int64_t NumberOfPoints() const { return static_cast<std::int64_t>(this->Corners.size() / 3); }
  std::int64_t NumberOfSurfels() const { return static_cast<std::int64_t>(this->Directions.size()); }
};

/// Reports progress in [0, 1]; returns false to abort.
using ProgressCallback = std::function<bool(double)>;

/// Extracts the surfels separating inside voxels from outside ones
/// (everything outside the grid is outside). Returns false when aborted.
bool ExtractCubicalSurface(const PaddedMask& mask, CubicalSurface& out,
  const ProgressCallback& progress = ProgressCallback());

} // namespace dg

#endif
