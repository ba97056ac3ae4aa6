// The geometry of a DICOM series from its slices' tag strings, apart from
// GDCM (dgDicomSeries.cxx reads the tags and the pixels), so that it can be
// tested and fuzzed on its own (Testing/Fuzz/fuzz_header.cxx): one
// orientation for every slice, slices sorted along the slice normal, and a
// uniform step along it, or the reason the series cannot be one volume.
#ifndef dgDicomGeometry_h
#define dgDicomGeometry_h

#include <array>
#include <string>
#include <vector>

namespace dg
{
using DicomVec = std::array<double, 3>;

/// One slice's tags as the file holds them (multi-valued decimal strings,
/// "a\\b\\c"; empty when the tag is missing).
struct DicomSliceTags
{
  std::string File;
  std::string Position;     // ImagePositionPatient (0020,0032)
  std::string Orientation;  // ImageOrientationPatient (0020,0037)
  std::string PixelSpacing; // PixelSpacing (0028,0030): row spacing, column spacing
};

/// The slices sorted along the normal, with the series' orientation.
struct DicomStack
{
  std::vector<std::string> Files;   // sorted along the normal (stable)
  std::vector<DicomVec> Positions;  // ImagePositionPatient, same order
  std::vector<double> Along;        // position along the normal, same order
  DicomVec Row{}, Column{}, Normal{}; // unit; Normal = Row x Column
  double PixelSpacing[2] = { 1, 1 };  // as the tag: between rows, between columns
};

/// Checks every slice's tags (unit, orthogonal row and column cosines, the
/// same orientation and pixel spacing in every slice) and sorts the slices
/// along the normal. False with the reason in one line otherwise.
bool OrderDicomSlices(const std::vector<DicomSliceTags>& slices, DicomStack& stack, std::string& error);

/// For two slices or more: the step between consecutive slices along the
/// normal, when every slice lies within 1 % of a step of the uniform grid
/// and on the normal through the first slice's corner (within 1 % of the
/// smallest spacing). False with the reason otherwise: two slices at one
/// position, missing slices, a gantry tilt.
bool UniformDicomStep(const DicomStack& stack, double& step, std::string& error);

/// The file's name without its directory, for messages.
std::string DicomFileName(const std::string& path);

/// A number as messages print it (%.6g).
std::string DicomNumber(double v);
} // namespace dg

#endif
