// Pieces of a structured volume (the distributed design, docs/distributed.md):
// which voxels a piece owns and how far its inputs must reach beyond them.
//
// Every piece-aware filter of the module computes a piece's own (non-ghost)
// voxel extent with PieceExtent, so that the image readers, the island
// filter, the surface filter and the II estimator agree on ownership without
// talking to each other: a voxel belongs to exactly one piece, a surfel to
// the piece that owns its inside voxel.
#ifndef dgPieces_h
#define dgPieces_h

#include <vtkSmartPointer.h>

#include <cstddef>

class vtkDataArray;
class vtkDataSetAttributes;
class vtkImageData;
class vtkPolyData;
class vtkInformation;
class vtkMultiProcessController;

namespace dg
{
/// The controller of a distributed execution: VTK's global controller when
/// it has more than one process and `outInfo` requests one of several
/// pieces; null otherwise (one process, or a piece streamed alone).
vtkMultiProcessController* PieceController(vtkInformation* outInfo);

/// In a distributed execution, true on every process when `ok` is true on
/// every process (a collective call); `ok` as it is otherwise.
bool AllPiecesOk(vtkInformation* outInfo, bool ok);

/// The global ids of `n` cells or points: the attribute's global ids, else
/// an array named "GlobalIds"; null when missing or not one integer per
/// tuple (what every piece-aware filter matches pieces by).
vtkDataArray* GlobalIdArray(vtkDataSetAttributes* a, long long n);

/// The own voxel extent of `piece` of `numberOfPieces` in `whole` (VTK's
/// vtkExtentTranslator in block mode, without ghost levels). Returns false
/// (and an empty extent, min > max) when the piece holds no voxel.
bool PieceExtent(const int whole[6], int piece, int numberOfPieces, int out[6]);

/// `in` grown by `layers` voxels on every side, clipped to `whole`. An empty
/// `in` stays empty.
void GrowExtent(const int in[6], int layers, const int whole[6], int out[6]);

/// True when `inner` lies inside `outer` (an empty `inner` always does).
bool ExtentContains(const int outer[6], const int inner[6]);

/// True when the extent holds no voxel.
bool ExtentEmpty(const int e[6]);

/// Copies the voxels of `box` out of an array over `extent` (x fastest,
/// `voxelBytes` bytes a voxel) into dst, box-sized, row by row. `box` must
/// lie inside `extent`. For readers that decode a whole volume and hand
/// out a sub-extent.
void CopyExtent(const void* src, const int extent[6], const int box[6], std::size_t voxelBytes,
  void* dst);

/// output = the voxels of `box` (inside image's extent) of every point
/// array of image, as new box-sized arrays copied row by row
/// (vtkImageData::Crop copies tuple by tuple: 1.7 s instead of 0.03 s for
/// half of a 256^3 volume), or a shallow copy when box is the whole extent
/// (or an array has a non-standard layout: then Crop). Geometry and scalars
/// as image's.
void CropImageToExtent(vtkImageData* image, const int box[6], vtkImageData* output);

/// For an image filter that produces sub-extents and reads a grown box: the
/// whole extent of its input and the box its RequestData will be asked for
/// (outInfo's update extent, split by piece and ghost levels as the
/// executive splits it just before RequestData). False when the input has no
/// whole extent yet.
bool RequestedImageBox(vtkInformation* inInfo, vtkInformation* outInfo, int whole[6], int requested[6]);

/// Asks upstream for exactly `box`, as one piece without ghost levels (a
/// reader or another sub-extent source would otherwise split it again).
void RequestImageBox(vtkInformation* inInfo, const int box[6]);

/// The cells of `input` not marked as ghosts (DUPLICATECELL or HIDDENCELL),
/// with only the points they use and their cell and point data (global ids
/// included), in input order; null when `input` has no ghost cell. For a
/// filter whose output cannot give ghost cells their owners' values: a
/// downstream request for ghost levels reaches the producers upstream, and
/// ghost cells passed on with values of this piece's making would be
/// silently wrong.
vtkSmartPointer<vtkPolyData> WithoutGhostCells(vtkPolyData* input);
} // namespace dg

#endif
