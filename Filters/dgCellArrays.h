// The optional one-component cell arrays the stages after the sharp stage
// read (its regions and crease sides), looked up one way.
#ifndef dgCellArrays_h
#define dgCellArrays_h

#include <string>

class vtkDataArray;
class vtkDataSet;

namespace dg
{
/// `chosen` (an algorithm's GetInputArrayToProcess result, with the
/// association it gave), else the input's cell array named `fallback`
/// (ParaView sends an empty name until it knows the input's arrays: that
/// means the default); null when neither exists. A chosen array that is
/// not cell data with one component is refused: null, and `problem` says
/// so, naming it as "the `what` array".
vtkDataArray* OneComponentCellArray(vtkDataArray* chosen, int association, vtkDataSet* input,
  const char* fallback, const char* what, std::string& problem);
} // namespace dg

#endif
