// Reads a segmented volume in any format the program accepts: DGtal .vol,
// VTK .vti, MetaImage .mha/.mhd, NRRD .nrrd/.nhdr, or a directory of DICOM
// slices. Errors come back as one line, never as VTK's multi-line reports.
#ifndef dgImageInput_h
#define dgImageInput_h

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <string>

namespace dg
{
/// Returns nullptr and sets error on failure.
vtkSmartPointer<vtkImageData> ReadImage(const std::string& path, std::string& error);

/// The lower-case extension of path ("vol", "nrrd", ...; "" for none).
std::string Extension(const std::string& path);
}

#endif
