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

namespace
{
// The quads' corner offsets per direction, as vtkDigitalSurfaceFilter
// writes them (counter-clockwise seen from outside; reversed when the
// index-to-world map reflects).
const int QuadCorner[6][4][3] = {
  { { 0, 0, 0 }, { 0, 0, 1 }, { 0, 1, 1 }, { 0, 1, 0 } },
  { { 1, 0, 0 }, { 1, 1, 0 }, { 1, 1, 1 }, { 1, 0, 1 } },
  { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 0, 1 }, { 0, 0, 1 } },
  { { 0, 1, 0 }, { 0, 1, 1 }, { 1, 1, 1 }, { 1, 1, 0 } },
  { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 1, 0, 0 } },
  { { 0, 0, 1 }, { 1, 0, 1 }, { 1, 1, 1 }, { 0, 1, 1 } },
};
} // namespace

vtkSmartPointer<vtkPolyData> LabelInterfaces(vtkImageData* image,
  const std::vector<LabelBox>& labels, const PipelineSettings& settings,
  const std::function<bool(vtkAlgorithm*, const std::string&)>& run, std::string& error)
{
  int whole[6];
  image->GetExtent(whole);
  const std::int64_t wn[3] = { whole[1] - whole[0] + 1, whole[3] - whole[2] + 1,
    whole[5] - whole[4] + 1 };
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  std::unordered_map<long long, bool> selected;
  for (const LabelBox& b : labels)
  {
    selected[b.Label] = true;
  }
  // The label of a voxel (structured index); outside the image and labels
  // not selected: 0.
  auto labelAt = [&](const int v[3]) -> long long {
    for (int a = 0; a < 3; ++a)
    {
      if (v[a] < whole[2 * a] || v[a] > whole[2 * a + 1])
      {
        return 0;
      }
    }
    const vtkIdType id = ((static_cast<vtkIdType>(v[2] - whole[4]) * wn[1]) + (v[1] - whole[2])) * wn[0] +
      (v[0] - whole[0]);
    const long long l = static_cast<long long>(scalars->GetComponent(id, 0));
    return selected.count(l) ? l : 0;
  };
  double dir[9], spacing[3];
  std::copy(image->GetDirectionMatrix()->GetData(), image->GetDirectionMatrix()->GetData() + 9, dir);
  image->GetSpacing(spacing);
  const double det = dir[0] * (dir[4] * dir[8] - dir[5] * dir[7]) -
    dir[1] * (dir[3] * dir[8] - dir[5] * dir[6]) + dir[2] * (dir[3] * dir[7] - dir[4] * dir[6]);
  const bool reflect = det * spacing[0] * spacing[1] * spacing[2] < 0;

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::unordered_map<std::int64_t, vtkIdType> pointOf; // corner key -> merged id
  vtkNew<vtkCellArray> quads;
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("IINormals");
  normals->SetNumberOfComponents(3);
  vtkNew<vtkIntArray> inside, outside, voxels;
  inside->SetName("LabelInside");
  outside->SetName("LabelOutside");
  voxels->SetName("InsideVoxel");
  voxels->SetNumberOfComponents(3);
  vtkNew<vtkUnsignedCharArray> directions;
  directions->SetName("SurfelDirection");
  const int margin = LabelMargin(settings);
  for (const LabelBox& box : labels)
  {
    auto crop = CropImage(image, box.Extent, margin);
    vtkNew<vtkDigitalSurfaceFilter> surface;
    surface->SetInputData(crop);
    surface->SetSelectionModeToLabel();
    surface->SetLabel(static_cast<double>(box.Label));
    vtkNew<vtkIINormalEstimator> ii;
    ii->SetInputConnection(surface->GetOutputPort());
    ii->SetSourceData(crop);
    ii->SetSelectionModeToLabel();
    ii->SetLabel(static_cast<double>(box.Label));
    ii->SetRadius(settings.Radius);
    const std::string name = "label " + std::to_string(box.Label) + ": ";
    if (!run(surface, name + "digital surface") || !run(ii, name + "II normals"))
    {
      return nullptr;
    }
    vtkPolyData* pd = ii->GetOutput();
    vtkDataArray* vox = pd->GetCellData()->GetArray("InsideVoxel");
    vtkDataArray* dirs = pd->GetCellData()->GetArray("SurfelDirection");
    vtkDataArray* nrm = pd->GetCellData()->GetArray("IINormals");
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
    {
      int v[3], o[3];
      for (int a = 0; a < 3; ++a)
      {
        v[a] = o[a] = static_cast<int>(vox->GetComponent(c, a));
      }
      const int d = static_cast<int>(dirs->GetTuple1(c));
      o[d / 2] += (d & 1) ? 1 : -1;
      const long long other = labelAt(o);
      if (other > box.Label)
      {
        continue; // this face is the larger label's
      }
      pd->GetCellPoints(c, ids);
      vtkIdType merged[4];
      for (int q = 0; q < 4; ++q)
      {
        const int* off = QuadCorner[d][reflect ? 3 - q : q];
        const std::int64_t key = ((static_cast<std::int64_t>(v[2] + off[2] - whole[4]) * (wn[1] + 1)) +
                                   (v[1] + off[1] - whole[2])) * (wn[0] + 1) + (v[0] + off[0] - whole[0]);
        auto it = pointOf.find(key);
        double x[3];
        pd->GetPoint(ids->GetId(q), x);
        if (it == pointOf.end())
        {
          it = pointOf.emplace(key, points->InsertNextPoint(x)).first;
        }
        else
        {
          double y[3];
          points->GetPoint(it->second, y);
          if (std::abs(x[0] - y[0]) + std::abs(x[1] - y[1]) + std::abs(x[2] - y[2]) >
            1e-9 * (1 + std::abs(y[0]) + std::abs(y[1]) + std::abs(y[2])))
          {
            error = "internal error: label " + std::to_string(box.Label) +
              " puts a voxel corner elsewhere than another label";
            return nullptr;
          }
        }
        merged[q] = it->second;
      }
      quads->InsertNextCell(4, merged);
      normals->InsertNextTuple(nrm->GetTuple3(c));
      inside->InsertNextValue(static_cast<int>(box.Label));
      outside->InsertNextValue(static_cast<int>(other));
      voxels->InsertNextTuple3(v[0], v[1], v[2]);
      directions->InsertNextValue(static_cast<unsigned char>(d));
    }
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  out->SetPolys(quads);
  out->GetCellData()->SetNormals(normals);
  for (vtkDataArray* a : { static_cast<vtkDataArray*>(inside.Get()), static_cast<vtkDataArray*>(outside.Get()),
         static_cast<vtkDataArray*>(voxels.Get()), static_cast<vtkDataArray*>(directions.Get()) })
  {
    out->GetCellData()->AddArray(a);
  }
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
