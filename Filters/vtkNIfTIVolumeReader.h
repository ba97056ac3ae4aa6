/**
 * @class   vtkNIfTIVolumeReader
 * @brief   Read NIfTI-1/2 volumes (.nii, .nii.gz) with their world geometry:
 *          origin, spacing and direction matrix on the vtkImageData.
 *
 * VTK's vtkNIFTIImageReader reads the voxels but leaves the orientation in
 * side matrices (qform, sform) that downstream filters never see, so a
 * surface built from its output sits in index space scaled by the voxel
 * size. This reader puts the geometry on the image itself, as every filter
 * of this module honours it (world = origin + D diag(spacing) index, D the
 * direction matrix):
 * - which transform: the sform when its code is > 0, else the qform when
 *   its code is > 0, else none (pixdim scaling only, a warning) — nibabel's
 *   rule, since tools that write both usually mean the sform;
 * - the transform's columns give the direction (unit columns) and the
 *   spacing (their lengths times pixdim); a transform whose columns are not
 *   orthogonal (a sheared or otherwise non-rigid sform) is refused with an
 *   error, never applied approximately;
 * - qfac = -1 (left-handed NIfTI indices) is handled by vtkNIFTIImageReader
 *   reversing the slices, so the output's direction always has det +1 for a
 *   qform; an sform with a reflection gives det D = -1, which the digital
 *   surface handles (its quads still face outward);
 * - coordinates: NIfTI's world is RAS (+x right, +y anterior, +z superior).
 *   The output is in LPS (DICOM's and ITK's patient coordinates: x and y
 *   negated) by default, or in RAS with CoordinateSystem RAS.
 *
 * Only the first time point of a 4-D file is read. Errors (missing file,
 * not NIfTI, sheared transform) give an error and an empty output.
 *
 * Pieces and sub-extents (CAN_PRODUCE_SUB_EXTENT): the output is exactly
 * the requested UPDATE_EXTENT with the whole read's origin, spacing and
 * direction (the extent carries the offset). The whole extent is read by
 * vtkNIFTIImageReader (one copy: the output shares its array). A smaller
 * box of a single-file NIfTI (.nii, .nii.gz) is read by this class from
 * the file, into the output's scalars only: a .nii by seeking to each row
 * of the box, a .nii.gz by inflating the gzip stream (zlib's gzread, with
 * a 256 KiB buffer) and keeping the box's rows. The voxels are exactly the
 * box of VTK's whole read: its datatypes, byte swapping, slice reversal
 * for qfac -1 (or an sform with a reflection and no qform), first time
 * point of a 4-D file, and scl_slope / scl_inter left as stored (VTK's
 * reader does not apply them either). A .nii.gz piece is inflated up to
 * the end of the first volume whatever the box, so that a corrupt or
 * truncated stream fails in every piece as in the whole read: its time is
 * that of the whole inflate, its peak memory its box plus about 1 MiB
 * (figures: docs/pieces-readers.md). Analyze or .hdr/.img pairs and files
 * with vector components (dim[5] > 1, stored as one volume per component)
 * are read whole and the box copied out, as before. A piece request is
 * turned into the extent by VTK's executive (vtkExtentTranslator, block
 * mode, by cells: neighbouring pieces share one layer of voxels), grown by
 * the ghost layers asked for, which the executive marks in vtkGhostType
 * (point and cell arrays) as for any structured source. The header is read
 * once per RequestInformation, by a vtkNIFTIImageReader kept for
 * RequestData.
 */
#ifndef vtkNIfTIVolumeReader_h
#define vtkNIfTIVolumeReader_h

#include "vtkDigitalGeometryModule.h"
#include "vtkImageAlgorithm.h"
#include "vtkSmartPointer.h"

#include <string>

class vtkNIFTIImageReader;

class VTKDIGITALGEOMETRY_EXPORT vtkNIfTIVolumeReader : public vtkImageAlgorithm
{
public:
  static vtkNIfTIVolumeReader* New();
  vtkTypeMacro(vtkNIfTIVolumeReader, vtkImageAlgorithm);
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

  enum GeometrySources
  {
    NONE = 0,
    QFORM = 1,
    SFORM = 2
  };
  /**
   * Which header transform the last read used.
   */
  vtkGetMacro(GeometrySource, int);

  /**
   * 1 when the file looks like NIfTI (or Analyze) to vtkNIFTIImageReader.
   */
  int CanReadFile(const char* fname);

protected:
  vtkNIfTIVolumeReader();
  ~vtkNIfTIVolumeReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  int CoordinateSystem = LPS;
  int GeometrySource = NONE;

private:
  // Runs r on FileName (information only, or the voxels too); false with a
  // message.
  bool Open(vtkNIFTIImageReader* r, bool withData, std::string& error);
  // The geometry from r's header (no file access); false with a message.
  bool Geometry(vtkNIFTIImageReader* r, bool warn, double origin[3], double spacing[3],
    double direction[9], std::string& error);

  // VTK's reader of the last RequestInformation: the header is read once
  // per update, by it; RequestData reads the voxels through it.
  vtkSmartPointer<vtkNIFTIImageReader> Inner;

  vtkNIfTIVolumeReader(const vtkNIfTIVolumeReader&) = delete;
  void operator=(const vtkNIfTIVolumeReader&) = delete;
};

#endif
