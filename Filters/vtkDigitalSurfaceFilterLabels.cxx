// vtkDigitalSurfaceFilter on a label map: the EachLabel and Interfaces
// modes (docs/labels.md). The class description says what the output holds;
// this file holds those modes' execution only, the one-region modes' is in
// vtkDigitalSurfaceFilter.cxx.
#include "vtkDigitalSurfaceFilter.h"

#include "dgCubicalSurface.h"
#include "dgLabelMap.h"
#include "dgPipelineAbort.h"
#include "dgVoxelSelection.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <Eigen/Dense>

#include <cmath>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

int vtkDigitalSurfaceFilter::ExecuteEachLabel(vtkImageData* input,
  vtkDataArray* scalars,
  const int whole[6],
  vtkPolyData* output,
  vtkInformationVector* outputVector)
{
  int component = 0;
  {
    std::string why;
    if (!dg::LabelComponent(scalars, this->SelectedComponent, component, why))
    {
      vtkErrorMacro("Cannot select voxels: " << why << ".");
      return 0;
    }
  }
  int ext[6];
  input->GetExtent(ext);
  dg::LabelSpec spec;
  std::vector<dg::LabelBox> boxes;
  std::string error;
  if (!dg::ParseLabelSpec(this->Labels ? this->Labels : "", spec, error) ||
      !dg::FindLabels(scalars, component, ext, spec, boxes, error))
  {
    vtkErrorMacro(
      "EachLabel (Labels '" << (this->Labels ? this->Labels : "") << "'): " << error << ".");
    return 0;
  }
  for (const dg::LabelBox& box : boxes)
  {
    if (box.Label < VTK_INT_MIN || box.Label > VTK_INT_MAX)
    {
      vtkErrorMacro("EachLabel: label " << box.Label << " does not fit the int Label array.");
      return 0;
    }
  }
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->InsertNextValue(0);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  vtkNew<vtkIntArray> voxels, labels;
  voxels->SetName("InsideVoxel");
  voxels->SetNumberOfComponents(3);
  labels->SetName("Label");
  vtkNew<vtkUnsignedCharArray> directions;
  directions->SetName("SurfelDirection");
  // Interfaces: the label across each face (0 outside the selection), and
  // the merged points, keyed by voxel corner.
  const bool interfaces = this->SelectionMode == INTERFACES;
  vtkNew<vtkIntArray> outsideLabels;
  outsideLabels->SetName("LabelOutside");
  std::unordered_set<long long> selected;
  for (const dg::LabelBox& box : boxes)
  {
    selected.insert(box.Label);
  }
  const std::int64_t en[3] = { ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1 };
  auto labelAt = [&](const int v[3]) -> long long
  {
    for (int a = 0; a < 3; ++a)
    {
      if (v[a] < ext[2 * a] || v[a] > ext[2 * a + 1])
      {
        return 0;
      }
    }
    const vtkIdType id =
      ((static_cast<vtkIdType>(v[2] - ext[4]) * en[1]) + (v[1] - ext[2])) * en[0] + (v[0] - ext[0]);
    const double value = scalars->GetComponent(id, component);
    const long long l = static_cast<long long>(value);
    return static_cast<double>(l) == value && selected.count(l) ? l : 0;
  };
  // A point's voxel corner: twice its continuous structured index, rounded
  // (corners sit at half-integer indices), packed into one key.
  Eigen::Matrix3d toIndex;
  {
    const double* d = input->GetDirectionMatrix()->GetData();
    Eigen::Matrix3d m;
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a)
        m(r, a) = d[3 * r + a] * input->GetSpacing()[a];
    toIndex = m.inverse();
  }
  const Eigen::Vector3d origin(input->GetOrigin()[0], input->GetOrigin()[1], input->GetOrigin()[2]);
  auto cornerKey = [&](const double x[3]) -> std::int64_t
  {
    const Eigen::Vector3d idx = toIndex * (Eigen::Vector3d(x[0], x[1], x[2]) - origin);
    std::int64_t k[3];
    for (int a = 0; a < 3; ++a)
    {
      k[a] = std::llround(2 * idx[a]) - 2 * ext[2 * a] + 1; // >= 0: corners from ext - 1/2
    }
    return (k[2] * (2 * en[1] + 2) + k[1]) * (2 * en[0] + 2) + k[0];
  };
  std::unordered_map<std::int64_t, vtkIdType> pointOfCorner;
  for (std::size_t l = 0; l < boxes.size(); ++l)
  {
    // One voxel around the box decides every face of the label; the copy
    // keeps the structured indices, so points and InsideVoxel are the whole
    // image's.
    auto crop = dg::CropImage(input, boxes[l].Extent, 1, scalars, component);
    vtkNew<vtkDigitalSurfaceFilter> one;
    one->SetInputData(crop);
    one->SetSelectionModeToLabel();
    one->SetLabel(static_cast<double>(boxes[l].Label));
    one->Update();
    vtkPolyData* part = one->GetOutput();
    vtkCellArray* polys = part->GetPolys();
    if (part->GetNumberOfCells() == 0 || !polys)
    {
      vtkErrorMacro("EachLabel: label " << boxes[l].Label << " gave no surface.");
      return 0;
    }
    vtkNew<vtkIdTypeArray> partConn;
    polys->ExportLegacyFormat(partConn);
    vtkCellData* cd = part->GetCellData();
    if (interfaces)
    {
      vtkDataArray* partVoxels = cd->GetArray("InsideVoxel");
      vtkDataArray* partDirections = cd->GetArray("SurfelDirection");
      vtkDataArray* partNormals = cd->GetArray("Normals");
      for (vtkIdType c = 0; c < part->GetNumberOfCells(); ++c)
      {
        int v[3], o[3];
        for (int a = 0; a < 3; ++a)
        {
          v[a] = o[a] = static_cast<int>(partVoxels->GetComponent(c, a));
        }
        const int d = static_cast<int>(partDirections->GetTuple1(c));
        o[d / 2] += (d & 1) ? 1 : -1;
        const long long other = labelAt(o);
        if (other > boxes[l].Label)
        {
          continue; // the larger label's face
        }
        for (int q = 0; q < 4; ++q)
        {
          double x[3];
          part->GetPoint(partConn->GetValue(5 * c + 1 + q), x);
          auto it = pointOfCorner.find(cornerKey(x));
          if (it == pointOfCorner.end())
          {
            it = pointOfCorner.emplace(cornerKey(x), points->InsertNextPoint(x)).first;
          }
          connectivity->InsertNextValue(it->second);
        }
        offsets->InsertNextValue(connectivity->GetNumberOfValues());
        normals->InsertNextTuple(partNormals->GetTuple3(c));
        voxels->InsertNextTuple3(v[0], v[1], v[2]);
        directions->InsertNextValue(static_cast<unsigned char>(d));
        labels->InsertNextValue(static_cast<int>(boxes[l].Label));
        outsideLabels->InsertNextValue(static_cast<int>(other));
      }
      this->UpdateProgress(static_cast<double>(l + 1) / boxes.size());
      if (this->GetAbortExecute())
      {
        return this->Abort->Abort(outputVector);
      }
      continue;
    }
    const vtkIdType base = points->GetNumberOfPoints();
    const vtkIdType cellBase = connectivity->GetNumberOfValues();
    points->InsertPoints(base, part->GetNumberOfPoints(), 0, part->GetPoints());
    // Legacy format: 4, a, b, c, d per quad.
    for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c)
    {
      for (int q = 0; q < 4; ++q)
      {
        connectivity->InsertNextValue(base + partConn->GetValue(5 * c + 1 + q));
      }
      offsets->InsertNextValue(cellBase + 4 * (c + 1));
    }
    const vtkIdType n = part->GetNumberOfCells();
    normals->InsertTuples(normals->GetNumberOfTuples(), n, 0, cd->GetArray("Normals"));
    voxels->InsertTuples(voxels->GetNumberOfTuples(), n, 0, cd->GetArray("InsideVoxel"));
    directions->InsertTuples(
      directions->GetNumberOfTuples(), n, 0, cd->GetArray("SurfelDirection"));
    for (vtkIdType c = 0; c < n; ++c)
    {
      labels->InsertNextValue(static_cast<int>(boxes[l].Label));
    }
    this->UpdateProgress(static_cast<double>(l + 1) / boxes.size());
    if (this->GetAbortExecute())
    {
      return this->Abort->Abort(outputVector);
    }
  }
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetCellData()->SetNormals(normals);
  output->GetCellData()->AddArray(voxels);
  output->GetCellData()->AddArray(directions);
  output->GetCellData()->AddArray(labels);
  if (interfaces)
  {
    vtkNew<vtkIntArray> inside;
    inside->DeepCopy(labels);
    inside->SetName("LabelInside");
    output->GetCellData()->AddArray(inside);
    output->GetCellData()->AddArray(outsideLabels);
  }

  AddImageRecord(output, whole, input->GetOrigin(), input->GetSpacing());
  return 1;
}
