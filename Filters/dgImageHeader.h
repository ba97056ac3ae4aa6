// The world geometry in MetaImage and NRRD headers, which VTK's readers
// drop: MetaImage's Offset, ElementSpacing and TransformMatrix; NRRD's
// space, space origin and space directions.
#ifndef dgImageHeader_h
#define dgImageHeader_h

#include <string>
#include <vector>

namespace dg
{
// The geometry of a MetaImage or NRRD header, which VTK's readers drop
// (TransformMatrix, space directions, space): world = Origin + Direction ·
// diag(Spacing) · index, in LPS (RAS when asked).
struct HeaderGeometry
{
  bool Has = false; // false: keep what VTK's reader gives (axis-aligned)
  double Origin[3] = { 0, 0, 0 };
  double Spacing[3] = { 1, 1, 1 };
  double Direction[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 }; // row-major
};

/// Reads the header of path (MetaImage when nrrd is false, NRRD when
/// true): world = Origin + Direction diag(Spacing) index, in LPS (RAS when
/// ras). Empty on success, else the problem in one line without the file's
/// name: numbers that do not parse, an unknown NRRD space, a sheared or
/// degenerate transform (origin, spacing and direction cannot carry it).
/// g.Has stays false for a header without orientation (an axis-aligned
/// grid, or a MetaImage that is not 3-D): VTK's reader's geometry stands.
std::string ReadHeaderGeometry(const std::string& path, bool nrrd, bool ras, HeaderGeometry& g);

/// MetaImage: empty when the uncompressed voxel data (LOCAL, after the
/// header, or in the ElementDataFile next to it) holds at least what
/// DimSize, ElementType and ElementNumberOfChannels say, else the problem.
/// VTK's vtkMetaImageReader returns a short read as a full volume without a
/// word. Compressed data (CompressedData = True) is not checked here.
std::string CheckMetaImageDataSize(const std::string& path);

/// NRRD: true when the header has three spatial axes (dimension 3, no
/// non-spatial kind such as "vector" and no "none" space direction): VTK's
/// vtkNrrdReader takes a first axis shorter than 10 for components.
bool NrrdHasThreeSpatialAxes(const std::string& path, int sizes[3]);

/// The numbers of a header value, separated by blanks, commas, parentheses
/// (NRRD's "(1,0,0)") or backslashes (DICOM's "1.5\\-2\\3"); what does not
/// parse ends the list.
std::vector<double> ParseNumbers(const std::string& text);
} // namespace dg

#endif
