// Reads a segmented volume in any format the program accepts: DGtal .vol,
// VTK .vti, NIfTI .nii/.nii.gz (with its orientation, vtkNIfTIVolumeReader),
// MetaImage .mha/.mhd, NRRD .nrrd/.nhdr, or a directory of DICOM slices.
// Errors come back as one line, never as VTK's multi-line reports.
#ifndef dgImageInput_h
#define dgImageInput_h

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <string>

namespace dg
{
/// Returns nullptr and sets error on failure. ras: NIfTI in its own RAS
/// coordinates instead of LPS (DICOM's and ITK's).
vtkSmartPointer<vtkImageData> ReadImage(const std::string& path, std::string& error, bool ras = false);

/// The lower-case extension of path ("vol", "nrrd", ...; "" for none).
std::string Extension(const std::string& path);
}

#endif
