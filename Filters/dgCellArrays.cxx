#include "dgCellArrays.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSet.h>

namespace dg
{
vtkDataArray* OneComponentCellArray(vtkDataArray* chosen, int association, vtkDataSet* input,
  const char* fallback, const char* what, std::string& problem)
{
  if (!chosen)
    return input->GetCellData()->GetArray(fallback);
  if (association == vtkDataObject::FIELD_ASSOCIATION_CELLS && chosen->GetNumberOfComponents() == 1)
    return chosen;
  problem = std::string("The ") + what + " array '" + (chosen->GetName() ? chosen->GetName() : "") +
    "' must be cell data with one component.";
  return nullptr;
}
} // namespace dg
