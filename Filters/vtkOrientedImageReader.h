/**
 * @class   vtkOrientedImageReader
 * @brief   Read MetaImage (.mha, .mhd) and NRRD (.nrrd, .nhdr) volumes with
 *          their world geometry: origin, spacing and direction matrix on
 *          the vtkImageData.
 *
 * VTK's vtkMetaImageReader and vtkNrrdReader read the voxels but drop the
 * orientation: MetaImage's TransformMatrix and NRRD's space directions are
 * ignored without a warning, so an oblique scan comes out straightened, in
 * the wrong place. This reader reads the header's geometry itself
 * (dgImageHeader.h) and puts it on the image, as every filter of this module
 * honours it (world = origin + D diag(spacing) index, D the direction
 * matrix):
 * - MetaImage: Offset (or Origin, Position), ElementSpacing, and the
 *   TransformMatrix (or Rotation, Orientation) whose i-th triple is the
 *   direction of axis i, as ITK writes it. MetaImage's world is LPS.
 * - NRRD: space directions (each axis's step vector: direction times
 *   spacing), space origin, and space, converted to LPS from
 *   right-anterior-superior and left-anterior-superior.
 * - A sheared or degenerate transform is refused with an error naming the
 *   file, never applied approximately.
 * - A header without orientation (NRRD with spacings only, a MetaImage that
 *   is not 3-D) keeps VTK's reader's geometry.
 * - Coordinates: LPS (DICOM's and ITK's) by default, RAS with
 *   CoordinateSystem RAS (x and y negated).
 *
 * The format is chosen by the file name's extension. Two flaws of VTK's
 * readers are handled: vtkMetaImageReader returns uncompressed data shorter
 * than its header says as a whole volume without a word (checked against
 * the file's size here: an error), and vtkNrrdReader takes the first axis
 * of a 3-D NRRD for components when it is shorter than 10 voxels (the
 * array is re-read as one component on the 3-D grid). A short read
 * (truncated raw data), which VTK's image readers report only as a warning
 * on the global output window, is an error here with an empty output: the
 * window is captured for the duration of the read.
 *
 * Pieces and sub-extents (CAN_PRODUCE_SUB_EXTENT): the output is exactly
 * the requested UPDATE_EXTENT with the whole volume's geometry. NRRD is
 * read by extent (vtkNrrdReader reads the box's rows); MetaImage is read
 * whole and the box copied out (vtkMetaImageReader cannot read a
 * sub-extent: asked for one, it overruns the output buffer), so a
 * MetaImage piece costs a full read and holds the whole volume while it
 * runs.
 */
#ifndef vtkOrientedImageReader_h
#define vtkOrientedImageReader_h

#include "vtkDigitalGeometryModule.h"
#include "vtkImageAlgorithm.h"
#include "vtkSmartPointer.h"

#include <string>

class vtkImageReader2;

class VTKDIGITALGEOMETRY_EXPORT vtkOrientedImageReader : public vtkImageAlgorithm
{
public:
  static vtkOrientedImageReader* New();
  vtkTypeMacro(vtkOrientedImageReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);

  enum CoordinateSystems
  {
    LPS = 0,
    RAS = 1
  };
  ///@{
  /**
   * The patient coordinate convention of the output (default LPS).
   */
  vtkSetClampMacro(CoordinateSystem, int, LPS, RAS);
  vtkGetMacro(CoordinateSystem, int);
  ///@}

  /**
   * 1 when fname has a MetaImage or NRRD extension and VTK's reader for it
   * accepts the file.
   */
  int CanReadFile(const char* fname);

  /**
   * True when the last read's header carried an orientation (a
   * TransformMatrix, or NRRD space directions), false when VTK's reader's
   * axis-aligned geometry was kept.
   */
  vtkGetMacro(Oriented, bool);

protected:
  vtkOrientedImageReader();
  ~vtkOrientedImageReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  int CoordinateSystem = LPS;
  bool Oriented = false;

private:
  // The geometry of the last RequestInformation, put on every output.
  double Origin[3] = { 0, 0, 0 };
  double Spacing[3] = { 1, 1, 1 };
  double Direction[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  // vtkNrrdReader reads a 3-D NRRD whose first axis is shorter than 10 as a
  // 2-D image with that many components: the voxels are in the right order,
  // so the array is re-read as one component on the 3-D extent.
  bool FirstAxisAsComponents = false;
  int Whole[6] = { 0, -1, 0, -1, 0, -1 };
  // VTK's reader of the last RequestInformation (MetaImage or NRRD).
  vtkSmartPointer<vtkImageReader2> Inner;

  vtkOrientedImageReader(const vtkOrientedImageReader&) = delete;
  void operator=(const vtkOrientedImageReader&) = delete;
};

#endif
