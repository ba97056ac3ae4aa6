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

bool LabelSpec::Contains(long long label) const
{
  if (this->All)
  {
    return true;
  }
  for (const auto& r : this->Ranges)
  {
    if (label >= r.first && label <= r.second)
    {
      return true;
    }
  }
  return false;
}

bool ParseLabelSpec(const std::string& text, LabelSpec& spec, std::string& error)
{
  spec = LabelSpec();
  if (text == "all")
  {
    spec.All = true;
    return true;
  }
  std::stringstream items(text);
  std::string item;
  auto integer = [](const std::string& s, long long& v) {
    if (s.empty())
    {
      return false;
    }
    std::size_t used = 0;
    try
    {
      v = std::stoll(s, &used);
    }
    catch (...)
    {
      return false;
    }
    return used == s.size();
  };
  while (std::getline(items, item, ','))
  {
    // A range is "A-B"; a leading '-' belongs to a negative label.
    const std::size_t dash = item.find('-', 1);
    long long a, b;
    const bool ok = dash == std::string::npos
      ? integer(item, a) && (b = a, true)
      : integer(item.substr(0, dash), a) && integer(item.substr(dash + 1), b);
    if (!ok || a > b)
    {
      error = "'" + item + "' is not a label or a range A-B with A <= B";
      return false;
    }
    spec.Ranges.emplace_back(a, b);
  }
  if (spec.Ranges.empty())
  {
    error = "no label given";
    return false;
  }
  return true;
}

namespace
{
struct FindWorker
{
  const int* Dims;
  const int* Origin; // extent minimum
  std::map<long long, LabelBox>* Found;
  bool NotInteger = false;
  double Bad = 0;

  template <typename Array>
  void operator()(Array* array)
  {
    const auto values = vtk::DataArrayValueRange<1>(array);
    auto it = values.begin();
    for (int k = 0; k < this->Dims[2]; ++k)
      for (int j = 0; j < this->Dims[1]; ++j)
        for (int i = 0; i < this->Dims[0]; ++i, ++it)
        {
          const double x = static_cast<double>(*it);
          if (x == 0)
          {
            continue;
          }
          if (x != std::floor(x) || !std::isfinite(x) || std::abs(x) > 9.0e15)
          {
            this->NotInteger = true;
            this->Bad = x;
            return;
          }
          const int ijk[3] = { i + this->Origin[0], j + this->Origin[1], k + this->Origin[2] };
          auto found = this->Found->find(static_cast<long long>(x));
          if (found == this->Found->end())
          {
            LabelBox b;
            b.Label = static_cast<long long>(x);
            for (int a = 0; a < 3; ++a)
            {
              b.Extent[2 * a] = b.Extent[2 * a + 1] = ijk[a];
            }
            found = this->Found->emplace(b.Label, b).first;
          }
          LabelBox& b = found->second;
          ++b.Voxels;
          for (int a = 0; a < 3; ++a)
          {
            b.Extent[2 * a] = std::min(b.Extent[2 * a], ijk[a]);
            b.Extent[2 * a + 1] = std::max(b.Extent[2 * a + 1], ijk[a]);
          }
        }
  }
};
} // namespace

bool FindLabels(vtkImageData* image, const LabelSpec& spec, std::vector<LabelBox>& labels,
  std::string& error)
{
  labels.clear();
  vtkDataArray* scalars = image ? image->GetPointData()->GetScalars() : nullptr;
  if (!scalars)
  {
    error = "the volume has no scalars to read labels from";
    return false;
  }
  if (scalars->GetNumberOfComponents() != 1)
  {
    error = "the volume's scalars have " + std::to_string(scalars->GetNumberOfComponents()) +
      " components; a label map has one";
    return false;
  }
  int extent[6], dims[3];
  image->GetExtent(extent);
  image->GetDimensions(dims);
  std::map<long long, LabelBox> found;
  const int origin[3] = { extent[0], extent[2], extent[4] };
  FindWorker worker{ dims, origin, &found };
  if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker))
  {
    worker(scalars);
  }
  if (worker.NotInteger)
  {
    std::ostringstream s;
    s << "the volume holds the value " << worker.Bad
      << ", not an integer: --labels needs a label map (use --range for other volumes)";
    error = s.str();
    return false;
  }
  for (const auto& f : found)
  {
    if (spec.Contains(f.first))
    {
      labels.push_back(f.second);
    }
  }
  if (labels.empty())
  {
    std::ostringstream s;
    s << "no voxel of the selected labels (the volume holds " << found.size() << " non-zero label"
      << (found.size() == 1 ? "" : "s");
    std::size_t shown = 0;
    for (const auto& f : found)
    {
      s << (shown ? ", " : ": ") << f.first;
      if (++shown == 10)
      {
        s << ", ...";
        break;
      }
    }
    s << ")";
    error = s.str();
    return false;
  }
  return true;
}

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

vtkSmartPointer<vtkImageData> CropImage(vtkImageData* image, const int extent[6], int margin)
{
  int whole[6], crop[6];
  image->GetExtent(whole);
  for (int a = 0; a < 3; ++a)
  {
    crop[2 * a] = std::max(whole[2 * a], extent[2 * a] - margin);
    crop[2 * a + 1] = std::min(whole[2 * a + 1], extent[2 * a + 1] + margin);
  }
  vtkDataArray* in = image->GetPointData()->GetScalars();
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->SetExtent(crop);
  out->SetOrigin(image->GetOrigin());
  out->SetSpacing(image->GetSpacing());
  out->SetDirectionMatrix(image->GetDirectionMatrix());
  vtkSmartPointer<vtkDataArray> values = vtk::TakeSmartPointer(in->NewInstance());
  values->SetName(in->GetName());
  values->SetNumberOfComponents(1);
  const int n[3] = { crop[1] - crop[0] + 1, crop[3] - crop[2] + 1, crop[5] - crop[4] + 1 };
  values->SetNumberOfTuples(static_cast<vtkIdType>(n[0]) * n[1] * n[2]);
  const int wdims[3] = { whole[1] - whole[0] + 1, whole[3] - whole[2] + 1, whole[5] - whole[4] + 1 };
  const int size = in->GetDataTypeSize();
  const auto* src = static_cast<const unsigned char*>(in->GetVoidPointer(0));
  auto* dst = static_cast<unsigned char*>(values->GetVoidPointer(0));
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
    {
      const vtkIdType from = (static_cast<vtkIdType>(crop[4] - whole[4] + k) * wdims[1] +
                               (crop[2] - whole[2] + j)) * wdims[0] + (crop[0] - whole[0]);
      const vtkIdType to = (static_cast<vtkIdType>(k) * n[1] + j) * n[0];
      std::memcpy(dst + to * size, src + from * size, static_cast<std::size_t>(n[0]) * size);
    }
  out->GetPointData()->SetScalars(values);
  return out;
}

} // namespace dg
