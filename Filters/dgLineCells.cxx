#include "dgLineCells.h"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>

namespace dg
{
vtkSmartPointer<vtkCellArray> TwoPointLines(const std::vector<vtkIdType>& ends)
{
  const vtkIdType n = static_cast<vtkIdType>(ends.size() / 2);
  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(2 * n);
  for (vtkIdType l = 0; l <= n; ++l)
    offsets->SetValue(l, 2 * l);
  for (vtkIdType i = 0; i < 2 * n; ++i)
    connectivity->SetValue(i, ends[i]);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, connectivity);
  return cells;
}

vtkSmartPointer<vtkDoubleArray> LineValues(const char* name, const std::vector<double>& values)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfValues(static_cast<vtkIdType>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    a->SetValue(static_cast<vtkIdType>(i), values[i]);
  return a;
}
} // namespace dg
