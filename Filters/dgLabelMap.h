// Label maps: which labels a spec selects, where each one lies, and each
// label's own box of the volume, so that a label's surface and normals cost
// what its surface costs and not a pass over the whole volume. Shared by
// the program (--labels) and the filters' SelectionMode EACH_LABEL.
#ifndef dgLabelMap_h
#define dgLabelMap_h

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <string>
#include <utility>
#include <vector>

class vtkDataArray;

namespace dg
{

/// "all", or labels and inclusive ranges separated by commas: "1,4,10-12".
struct LabelSpec
{
  bool All = false;
  std::vector<std::pair<long long, long long>> Ranges;
  bool Contains(long long label) const;
};
/// False with a message naming the bad item (an empty text: "no label given").
bool ParseLabelSpec(const std::string& text, LabelSpec& spec, std::string& error);

struct LabelBox
{
  long long Label;
  int Extent[6]; // the voxels of this label (structured indices)
  long long Voxels = 0;
};

/// The non-zero labels of one component of `scalars` (point data of an
/// image of extent `extent`, x fastest) that `spec` selects, in increasing
/// order, with their voxel boxes: one pass over the volume. False with a
/// message when a value is not an integer (not a label map) or no label
/// present is selected (the message lists the labels there).
bool FindLabels(vtkDataArray* scalars, int component, const int extent[6], const LabelSpec& spec,
  std::vector<LabelBox>& labels, std::string& error);

/// The component of `scalars` that holds the labels: `selected`, or 0 when
/// selected is -1 and the array has one component. False with the one-line
/// reason (no array, a component out of range) otherwise.
bool LabelComponent(vtkDataArray* scalars, int selected, int& component, std::string& error);

/// The same on the image's active scalars, which must have one component.
bool FindLabels(vtkImageData* image, const LabelSpec& spec, std::vector<LabelBox>& labels,
  std::string& error);

/// A copy of one component of `values` (point data of `image`; nullptr: the
/// active scalars, component 0) on the voxels of `extent` grown by `margin`
/// (clipped to the image), set as the copy's active scalars under the same
/// name, with the same origin, spacing and direction: its structured
/// indices are the whole image's, so every output lands where the
/// whole-volume run puts it.
vtkSmartPointer<vtkImageData> CropImage(
  vtkImageData* image, const int extent[6], int margin, vtkDataArray* values = nullptr, int component = 0);

} // namespace dg

#endif
