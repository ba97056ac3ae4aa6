#include "dgLabelMap.h"

#include <vtkArrayDispatch.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkMatrix3x3.h>
#include <vtkPointData.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

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
  int Component;
  std::map<long long, LabelBox>* Found;
  bool NotInteger = false;
  double Bad = 0;

  template <typename Array>
  void operator()(Array* array)
  {
    const auto values = vtk::DataArrayValueRange(array);
    const int nc = array->GetNumberOfComponents();
    vtkIdType id = 0;
    for (int k = 0; k < this->Dims[2]; ++k)
      for (int j = 0; j < this->Dims[1]; ++j)
        for (int i = 0; i < this->Dims[0]; ++i, ++id)
        {
          const double x = static_cast<double>(values[id * nc + this->Component]);
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

bool FindLabels(vtkDataArray* scalars, int component, const int extent[6], const LabelSpec& spec,
  std::vector<LabelBox>& labels, std::string& error)
{
  labels.clear();
  const int dims[3] = { extent[1] - extent[0] + 1, extent[3] - extent[2] + 1, extent[5] - extent[4] + 1 };
  if (!scalars || component < 0 || component >= scalars->GetNumberOfComponents() ||
    scalars->GetNumberOfTuples() != static_cast<vtkIdType>(dims[0]) * dims[1] * dims[2])
  {
    error = "the labels' array does not match the image";
    return false;
  }
  std::map<long long, LabelBox> found;
  const int origin[3] = { extent[0], extent[2], extent[4] };
  FindWorker worker{ dims, origin, component, &found };
  if (!vtkArrayDispatch::Dispatch::Execute(scalars, worker))
  {
    worker(scalars);
  }
  if (worker.NotInteger)
  {
    std::ostringstream s;
    s << "the volume holds the value " << worker.Bad
      << ", not an integer: it is not a label map (select a range instead)";
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
  int extent[6];
  image->GetExtent(extent);
  return FindLabels(scalars, 0, extent, spec, labels, error);
}

vtkSmartPointer<vtkImageData> CropImage(
  vtkImageData* image, const int extent[6], int margin, vtkDataArray* in, int component)
{
  int whole[6], crop[6];
  image->GetExtent(whole);
  for (int a = 0; a < 3; ++a)
  {
    crop[2 * a] = std::max(whole[2 * a], extent[2 * a] - margin);
    crop[2 * a + 1] = std::min(whole[2 * a + 1], extent[2 * a + 1] + margin);
  }
  if (!in)
  {
    in = image->GetPointData()->GetScalars();
    component = 0;
  }
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
  const int nc = in->GetNumberOfComponents();
  const auto* src = static_cast<const unsigned char*>(in->GetVoidPointer(0));
  auto* dst = static_cast<unsigned char*>(values->GetVoidPointer(0));
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
    {
      const vtkIdType from = (static_cast<vtkIdType>(crop[4] - whole[4] + k) * wdims[1] +
                               (crop[2] - whole[2] + j)) * wdims[0] + (crop[0] - whole[0]);
      const vtkIdType to = (static_cast<vtkIdType>(k) * n[1] + j) * n[0];
      if (nc == 1)
      {
        std::memcpy(dst + to * size, src + from * size, static_cast<std::size_t>(n[0]) * size);
        continue;
      }
      for (int i = 0; i < n[0]; ++i)
      {
        std::memcpy(dst + (to + i) * size, src + ((from + i) * nc + component) * size, size);
      }
    }
  out->GetPointData()->SetScalars(values);
  return out;
}

bool LabelComponent(vtkDataArray* scalars, int selected, int& component, std::string& error)
{
  if (!scalars)
  {
    error = "the image has no point scalars to read labels from";
    return false;
  }
  const int nc = scalars->GetNumberOfComponents();
  component = selected < 0 && nc == 1 ? 0 : selected;
  if (component < 0 || component >= nc)
  {
    error = "array has " + std::to_string(nc) + " components, SelectedComponent is " +
      std::to_string(selected);
    return false;
  }
  return true;
}

} // namespace dg
