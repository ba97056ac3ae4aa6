// Small connected components of a binary volume: "islands" (components of
// inside voxels) and "cavities" (components of outside voxels that do not
// touch the image border), found with 6-connectivity (voxels sharing a face)
// by run-length labelling: the runs of equal voxels along x are joined with
// union-find to the overlapping runs of the row below (y - 1) and of the row
// behind (z - 1). Memory: a few words per run, not per voxel.
#ifndef dgIslands_h
#define dgIslands_h

#include <cstdint>
#include <functional>
#include <vector>

namespace dg
{

struct IslandCounts
{
  std::int64_t RemovedIslands = 0; // inside components turned outside
  std::int64_t FilledCavities = 0; // outside components turned inside
  std::int64_t ChangedVoxels = 0;  // voxels whose value differs from the input
};

/// A window on a larger volume (a piece's grown box): the faces of the
/// mask's box beyond which the volume continues, and the box whose
/// components and voxels are counted.
struct ComponentWindow
{
  /// Bit 2a: the low face of axis a (index 0), bit 2a + 1: the high face
  /// (dims[a] - 1). A component touching an open face may continue beyond
  /// it: it is kept (taken as large), island or cavity. The other faces
  /// are the image's border. 0: the mask is the whole image.
  unsigned OpenFaces = 0;
  /// Local index box (i0, i1, j0, j1, k0, k1): IslandCounts count the
  /// components whose first voxel (x fastest) lies in it and the changed
  /// voxels in it, so that the counts of disjoint boxes add up to the
  /// whole image's.
  int Counted[6] = { 0, -1, 0, -1, 0, -1 };
};

/// mask: dims[0] * dims[1] * dims[2] values 0 (outside) or 1 (inside), x
/// fastest; changed in place. With removeIslands, every 6-connected
/// component of inside voxels with fewer than minimumSize voxels becomes
/// outside (a component may touch the image border). Then, with
/// fillCavities, every 6-connected component of outside voxels of that
/// result with fewer than minimumSize voxels and no voxel on the image
/// border becomes inside: voxels beyond the extent are outside, so a
/// component on the border is part of the exterior, whatever its size.
/// Islands go first, so that a speck inside a small cavity does not leave a
/// hole once the cavity is filled; the result has no inside component and
/// no cavity smaller than minimumSize (applying it again changes nothing).
/// minimumSize <= 1 changes nothing. progress(f), f in [0, 1], is called
/// now and then; when it returns false the function stops and returns false
/// (the mask is then partly processed). The result does not depend on the
/// number of threads. With a window (nullptr: the whole image, every
/// component counted), components on its open faces are kept and only its
/// counted box is counted.
bool RemoveSmallComponents(std::uint8_t* mask, const int dims[3], std::int64_t minimumSize,
  bool removeIslands, bool fillCavities, IslandCounts& counts,
  const std::function<bool(double)>& progress = {}, const ComponentWindow* window = nullptr);

/// How many voxel layers around a box B a window must add so that
/// RemoveSmallComponents on the window (its faces inside the image open)
/// gives, on B, exactly what it gives on the whole image. One pass needs
/// minimumSize - 1: a component of fewer than minimumSize voxels that meets
/// B lies within minimumSize - 2 layers of it, so it is complete in the
/// window and off its open faces, while a larger one either is complete or
/// reaches an open face (kept either way). Both passes need twice that:
/// the cavities of B depend on the islands removed up to minimumSize - 1
/// layers out, and those islands on the layers beyond. 0 when nothing
/// changes (minimumSize <= 1 or both passes off).
int ComponentReach(std::int64_t minimumSize, bool removeIslands, bool fillCavities);

/// Sizes of the 6-connected components of the voxels equal to value (0 or
/// 1), in the order of their first voxel (x fastest), and whether each has
/// a voxel on the image border. For tests and measurements.
void ComponentSizes(const std::vector<std::uint8_t>& mask, const int dims[3], std::uint8_t value,
  std::vector<std::int64_t>& sizes, std::vector<std::uint8_t>& touchesBorder);

} // namespace dg

#endif
