// Label maps in one run (--labels): which labels, where each one lies, and
// each label's own box of the volume, so that a label's pipeline costs what
// its surface costs and not a pass over the whole volume.
#ifndef dgLabels_h
#define dgLabels_h

#include "dgLabelMap.h"
#include "dgPipeline.h"

#include <vtkAlgorithm.h>
#include <vtkImageData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace dg
{

/// The interfaces of a label map (--interfaces): every face between two
/// different labels, or a label and the background, once, oriented out of
/// the larger label (LabelInside > LabelOutside; background and labels not
/// selected count as 0), with the II normals of LabelInside's own surface
/// (run on its box, as --labels does) and the points of all labels merged,
/// so that AT sees one complex: non-manifold along the lines where three or
/// more labels meet: vtkDigitalSurfaceFilter in Interfaces mode, then
/// vtkIINormalEstimator in EachLabel mode. `run` updates a filter under the caller's progress and
/// error observers (false: it failed, and the caller holds the message);
/// nullptr then, or with `error` set on an inconsistency.
vtkSmartPointer<vtkPolyData> LabelInterfaces(vtkImageData* image,
  const std::vector<LabelBox>& labels,
  const PipelineSettings& settings,
  const std::function<bool(vtkAlgorithm*, const std::string&)>& run,
  std::string& error);

/// Voxel layers around a label's box that its pipeline reads: the input
/// normals' ball or offset (II ceil(r) + 1, VCM ceil(2R + r) + 1, RHT
/// ceil(r) + 1, as the estimators ask their pieces for), plus one layer so
/// that the outside around the label touches the crop's border (the island
/// filter never fills an outside component that touches the border, as on
/// the whole volume).
int LabelMargin(const PipelineSettings& settings);

} // namespace dg

#endif
