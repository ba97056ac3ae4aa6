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
 * direction (the extent carries the offset). vtkNIFTIImageReader reads
 * whole volumes only (a .nii.gz is one gzip stream), so each request reads
 * the whole volume and copies the box out (dg::CopyExtent): a piece costs
 * the time of a full read and holds the whole volume, at its voxel type,
 * while it runs, besides its own box (fandisk-256 as .nii.gz, one piece
 * of 2: docs/pieces-readers.md). A piece request is turned into the extent by VTK's
 * executive (vtkExtentTranslator, block mode, by cells: neighbouring pieces
 * share one layer of voxels), grown by the ghost layers asked for, which the
 * executive marks in vtkGhostType (point and cell arrays) as for any
 * structured source. The header is read once per RequestInformation, and
 * RequestData reads the voxels through the same vtkNIFTIImageReader (two
 * opens of the file per update instead of seven before).
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
