// The program's mesh picture (--mesh): the digital surface the program
// started from (its voxel faces) beside the piecewise-smooth mesh, both
// flat shaded by their own faces in the same three-quarter view, the
// mesh's creases drawn over it. Width x Width / 2 pixels.
#ifndef dgRenderMesh_h
#define dgRenderMesh_h

#include <vtkPolyData.h>

#include <string>

namespace dg
{
/// digital: the voxel-face surface; mesh: vtkPiecewiseSmoothMeshFilter's
/// port 0; creases (may be null or empty): its port 1. Writes a PNG; false
/// with error set when it cannot.
bool RenderMeshPicture(vtkPolyData* digital, vtkPolyData* mesh, vtkPolyData* creases, int width,
  const std::string& pngPath, std::string& error);
}

#endif
