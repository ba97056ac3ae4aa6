// The line outputs of the stages (AT's feature edges, the sharp stage's
// lines, the creases of the curvature and mesh filters): cells of two
// points each, with one value per line.
#ifndef dgLineCells_h
#define dgLineCells_h

#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <vector>

class vtkCellArray;
class vtkDoubleArray;

namespace dg
{
/// One line cell per pair of point ids in `ends` (2 per line).
vtkSmartPointer<vtkCellArray> TwoPointLines(const std::vector<vtkIdType>& ends);

/// One value per line, as a double array named `name`.
vtkSmartPointer<vtkDoubleArray> LineValues(const char* name, const std::vector<double>& values);
} // namespace dg

#endif
