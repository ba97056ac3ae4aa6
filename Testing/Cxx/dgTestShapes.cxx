#include "dgTestShapes.h"

#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkCellData.h>
#include <vtkDataSet.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>

#include <algorithm>

namespace dgtest
{

vtkSmartPointer<vtkImageData> MakeImage(
  int nx, int ny, int nz, const std::function<double(int, int, int)>& value, int vtkType)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, nz);
  image->AllocateScalars(vtkType, 1);
  vtkDataArray* s = image->GetPointData()->GetScalars();
  s->SetName("Value");
  vtkIdType id = 0;
  for (int k = 0; k < nz; ++k)
  {
    for (int j = 0; j < ny; ++j)
    {
      for (int i = 0; i < nx; ++i)
      {
        s->SetTuple1(id++, value(i, j, k));
      }
    }
  }
  return image;
}

vtkSmartPointer<vtkImageData> Digitize(
  int n, const std::function<bool(double, double, double)>& inside)
{
  return MakeImage(n, n, n, [&](int i, int j, int k) { return inside(i, j, k) ? 1.0 : 0.0; });
}

vtkSmartPointer<vtkImageData> Ball(int n, double r)
{
  const double c = 0.5 * (n - 1) + 0.123;
  return Digitize(n, [=](double x, double y, double z) {
    return (x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c) <= r * r;
  });
}

vtkSmartPointer<vtkImageData> RandomVoxels(int nx, int ny, int nz, double p, unsigned seed)
{
  std::mt19937 rng(seed);
  std::bernoulli_distribution coin(p);
  return MakeImage(nx, ny, nz, [&](int, int, int) { return coin(rng) ? 1.0 : 0.0; });
}

void ErrorObserver::Execute(vtkObject*, unsigned long event, void* data)
{
  if (event == vtkCommand::ErrorEvent)
  {
    ++this->Errors;
  }
  else if (event == vtkCommand::WarningEvent)
  {
    ++this->Warnings;
  }
  if (data)
  {
    this->Messages += static_cast<const char*>(data);
    this->Messages += "\n";
  }
}

void ErrorObserver::Observe(vtkObject* o)
{
  o->AddObserver(vtkCommand::ErrorEvent, this);
  o->AddObserver(vtkCommand::WarningEvent, this);
}

void ErrorObserver::Clear()
{
  this->Errors = this->Warnings = 0;
  this->Messages.clear();
}

vtkSmartPointer<vtkPolyData> QuadGrid3x3(bool reverseCentre, double zWiggle)
{
  vtkNew<vtkPoints> pts;
  for (int j = 0; j < 4; ++j)
  {
    for (int i = 0; i < 4; ++i)
    {
      pts->InsertNextPoint(i, j, zWiggle * ((i + j) % 2));
    }
  }
  vtkNew<vtkCellArray> polys;
  for (int j = 0; j < 3; ++j)
  {
    for (int i = 0; i < 3; ++i)
    {
      vtkIdType q[4] = { j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i };
      if (reverseCentre && i == 1 && j == 1)
      {
        std::swap(q[1], q[3]);
      }
      polys->InsertNextCell(4, q);
    }
  }
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->SetPoints(pts);
  mesh->SetPolys(polys);
  return mesh;
}

vtkSmartPointer<vtkPolyData> FlatSquare(int nx, int ny, double jump, bool triangles)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      pts->InsertNextPoint(i, j, 0);
  vtkNew<vtkCellArray> polys;
  vtkNew<vtkDoubleArray> step;
  step->SetName("Step");
  auto id = [nx](int i, int j) { return static_cast<vtkIdType>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const double value = i + 0.5 < jump ? 0.0 : 1.0;
      if (triangles)
      {
        const vtkIdType t1[3] = { id(i, j), id(i + 1, j), id(i + 1, j + 1) };
        const vtkIdType t2[3] = { id(i, j), id(i + 1, j + 1), id(i, j + 1) };
        polys->InsertNextCell(3, t1);
        polys->InsertNextCell(3, t2);
        step->InsertNextValue(value);
        step->InsertNextValue(value);
      }
      else
      {
        const vtkIdType q[4] = { id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1) };
        polys->InsertNextCell(4, q);
        step->InsertNextValue(value);
      }
    }
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  pd->GetCellData()->AddArray(step);
  return pd;
}

std::vector<std::pair<vtkIdType, vtkIdType>> EdgePairs(vtkPolyData* lines)
{
  std::vector<std::pair<vtkIdType, vtkIdType>> e;
  for (vtkIdType c = 0; c < lines->GetNumberOfCells(); ++c)
  {
    vtkIdType n;
    const vtkIdType* p;
    lines->GetCellPoints(c, n, p);
    e.emplace_back(std::min(p[0], p[1]), std::max(p[0], p[1]));
  }
  std::sort(e.begin(), e.end());
  return e;
}

std::vector<Eigen::Vector3d> CellCentres(vtkPolyData* pd)
{
  std::vector<Eigen::Vector3d> out(pd->GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    pd->GetCellPoints(c, ids);
    Eigen::Vector3d centre(0, 0, 0);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      Eigen::Vector3d p;
      pd->GetPoint(ids->GetId(k), p.data());
      centre += p / static_cast<double>(ids->GetNumberOfIds());
    }
    out[c] = centre;
  }
  return out;
}

vtkSmartPointer<vtkPolyData> ReversedKeepingCellData(vtkPolyData* surface)
{
  auto reversed = vtkSmartPointer<vtkPolyData>::New();
  reversed->ShallowCopy(surface);
  vtkNew<vtkCellArray> polys;
  for (vtkIdType c = 0; c < surface->GetNumberOfCells(); ++c)
  {
    vtkIdType m = 0;
    const vtkIdType* ids = nullptr;
    surface->GetCellPoints(c, m, ids);
    std::vector<vtkIdType> r(ids, ids + m);
    std::reverse(r.begin(), r.end());
    polys->InsertNextCell(m, r.data());
  }
  reversed->SetPolys(polys);
  return reversed;
}

bool RefusedWith(vtkAlgorithm* algorithm, const std::string& words, std::string* why)
{
  vtkNew<ErrorObserver> errors;
  errors->Observe(algorithm);
  algorithm->Update();
  vtkIdType cells = 0;
  for (int port = 0; port < algorithm->GetNumberOfOutputPorts(); ++port)
    if (auto* data = vtkDataSet::SafeDownCast(algorithm->GetOutputDataObject(port)))
      cells += data->GetNumberOfCells();
  *why = std::to_string(errors->Errors) + " errors, " + std::to_string(cells) +
    " output cells: " + errors->Messages;
  return errors->Errors == 1 && errors->Messages.find(words) != std::string::npos && cells == 0;
}

vtkSmartPointer<vtkPoints> FlattenedPoints(vtkPoints* points)
{
  auto flat = vtkSmartPointer<vtkPoints>::New();
  flat->DeepCopy(points);
  for (vtkIdType p = 0; p < flat->GetNumberOfPoints(); ++p)
  {
    double x[3];
    flat->GetPoint(p, x);
    flat->SetPoint(p, x[0], x[1], 0.0);
  }
  return flat;
}

} // namespace dgtest
