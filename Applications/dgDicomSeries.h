// DICOM input with GDCM: a directory holding one series (or the series
// named by its SeriesInstanceUID), or a single file, read into a vtkImageData
// with its patient geometry (LPS): slices ordered by ImagePositionPatient
// projected on the slice normal, orientation from ImageOrientationPatient,
// origin at the first slice in that order, spacing from PixelSpacing and the
// slice positions. Non-uniform slice spacing, slices not stacked along their
// normal (gantry tilt), several series without a choice and missing tags are
// refused with a one-line error.
#ifndef dgDicomSeries_h
#define dgDicomSeries_h

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <string>

namespace dg
{
/// True when the program was built with GDCM (DG_HAVE_GDCM).
bool HaveDicom();

/// path: a directory of DICOM files or one DICOM file. seriesUID: the
/// series to read when the directory holds several (empty: the only one).
/// Returns nullptr and sets error (one line) on failure.
vtkSmartPointer<vtkImageData> ReadDicom(const std::string& path, const std::string& seriesUID, std::string& error);
}

#endif
