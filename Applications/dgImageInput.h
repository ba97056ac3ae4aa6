// Reads a segmented volume in any format the program accepts: DGtal .vol,
// VTK .vti or .pvti, NIfTI .nii/.nii.gz (with its orientation, vtkNIfTIVolumeReader),
// MetaImage .mha/.mhd (Offset, ElementSpacing, TransformMatrix) and NRRD
// .nrrd/.nhdr (space origin, space directions, space) through VTK's readers
// with the geometry read from their headers, or a DICOM series (directory)
// or file through GDCM (dgDicomSeries.h). Patient-space inputs come out in
// LPS, or RAS on request. Errors come back as one line, never as VTK's
// multi-line reports.
#ifndef dgImageInput_h
#define dgImageInput_h

#include <vtkAlgorithm.h>
#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <string>
#include <vector>

namespace dg
{
struct ReadOptions
{
  /// Patient-space inputs (NIfTI, DICOM, MetaImage, NRRD) in RAS instead of
  /// LPS (DICOM's and ITK's): world coordinates x and y negated.
  bool Ras = false;
  /// The DICOM series to read when a directory holds several (empty: the
  /// only one, an error listing them otherwise).
  std::string DicomSeries;
};

/// Returns nullptr and sets error on failure.
vtkSmartPointer<vtkImageData> ReadImage(const std::string& path, std::string& error, const ReadOptions& options = {});

/// For a run in pieces (several processes): the reader of path, its header
/// read (UpdateInformation) but no voxel, when it can give any sub-extent
/// the pipeline asks for (VTK's XML .vti/.pvti, MetaImage, NRRD, the
/// module's .vol and NIfTI readers: any reader that sets
/// CAN_PRODUCE_SUB_EXTENT). nullptr with error empty for a format read
/// whole only (DICOM): use ReadImage then; nullptr with error set when the
/// header is bad.
vtkSmartPointer<vtkAlgorithm> OpenImagePieces(const std::string& path, std::string& error, const ReadOptions& options = {});

/// After the pipeline ran: false with error set when the reader's piece
/// lacks its voxels (truncated or corrupt file).
bool CheckImagePiece(vtkAlgorithm* reader, const std::string& path, std::string& error);

/// The lower-case extension of path ("vol", "nrrd", ...; "" for none).
std::string Extension(const std::string& path);
}

#endif
