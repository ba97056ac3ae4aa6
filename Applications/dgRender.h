// Off-screen picture of a result, as in the paper's Fig. 1: four panels,
// (1) the input digital surface shaded flat by its own quads, (2) the input
// normals g and (3) the regularised normals u as colours RGB = (n + 1) / 2,
// one colour per quad, (4) the feature lines as red tubes on a light grey
// surface. Every panel frames the whole object in the same three-quarter view.
// Layout: a 2 x 2 grid at Width x Height (1 2 / 3 4), or with Panels a 1 x 4
// strip at Width x Width / 4 (square panels, 1 2 3 4 from the left).
#ifndef dgRender_h
#define dgRender_h

#include <vtkPolyData.h>

#include <string>

namespace dg
{
struct RenderOptions
{
  int Width = 1200;
  int Height = 900; // ignored with Panels: the strip's height is Width / 4
  bool Panels = false;
  /// cell array that shades panel 1 (the trivial normals of the quads);
  /// when absent, the quads are lit by their own geometric normals.
  std::string SurfaceNormals = "Normals";
  std::string InputTitle = "input normals (II)";
  std::string RegularisedTitle = "regularised normals";
};

/// Picture size RenderPicture writes for these options (width, height).
void PictureSize(const RenderOptions& options, int& width, int& height);

/// surface must carry the regularised normals as its active cell normals
/// (panel 3; without them the panel is plainly shaded and says so);
/// inputNormals (may be null or name no array: then panel 2 is plainly shaded
/// with a note) names the cell array of panel 2; features (may be null or
/// empty) holds line cells on the surface's points, drawn in red in panel 4.
/// Writes a PNG; false with error set when it cannot.
bool RenderPicture(vtkPolyData* surface, const char* inputNormals, vtkPolyData* features,
  const RenderOptions& options, const std::string& pngPath, std::string& error);
}

#endif
