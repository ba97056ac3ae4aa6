// Off-screen picture of a result: the surface shaded flat by a normal field,
// feature edges drawn as red tubes, optionally as three panels (input normals
// | regularised normals | features), like the paper's figures.
#ifndef dgRender_h
#define dgRender_h

#include <vtkPolyData.h>

#include <string>

namespace dg
{
struct RenderOptions
{
  int Width = 1200;
  int Height = 900;
  bool Panels = false;
};

/// surface must carry the regularised normals as its active cell normals;
/// inputNormals (may be null) names the cell array shown in the first panel;
/// features (may be null) holds line cells drawn in red. Writes a PNG.
bool RenderPicture(vtkPolyData* surface, const char* inputNormals, vtkPolyData* features,
  const RenderOptions& options, const std::string& pngPath, std::string& error);
}

#endif
