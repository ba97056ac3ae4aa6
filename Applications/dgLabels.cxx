#include "dgLabels.h"

#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkArrayDispatch.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkMatrix3x3.h>
#include <vtkPointData.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <unordered_map>

namespace dg
{

vtkSmartPointer<vtkPolyData> LabelInterfaces(vtkImageData* image,
  const std::vector<LabelBox>& labels,
  const PipelineSettings& settings,
  const std::function<bool(vtkAlgorithm*, const std::string&)>& run,
  std::string& error)
{
  // The filters' Interfaces and EachLabel modes (docs/labels.md): the
  // labels found here, as their Labels list.
  std::string list;
  for (const LabelBox& box : labels)
  {
    list += (list.empty() ? "" : ",") + std::to_string(box.Label);
  }
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  surface->SetSelectionModeToInterfaces();
  surface->SetLabels(list.c_str());
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetSelectionModeToEachLabel();
  ii->SetRadius(settings.Radius);
  if (!run(surface, "interfaces: digital surface") || !run(ii, "interfaces: II normals"))
  {
    error = "the interfaces' surface or normals failed";
    return nullptr;
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(ii->GetOutput());
  return out;
}

int LabelMargin(const PipelineSettings& s)
{
  double reach = std::ceil(s.Radius) + 1;
  if (s.Estimator == "vcm")
  {
    reach = std::ceil(2 * s.VCMOffsetRadius + s.VCMConvolutionRadius) + 1;
  }
  else if (s.Estimator == "rht")
  {
    reach = std::ceil(s.RHTRadius) + 1;
  }
  return static_cast<int>(reach) + 1;
}

} // namespace dg
