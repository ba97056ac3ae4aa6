// The pieces of the program's pictures that its two pictures share
// (dgRender.cxx: the normals and features; dgRenderCurvature.cxx: the
// curvature): one three-quarter view framing the whole object, titles, the
// feature lines drawn in front of the surface.
#ifndef dgRenderParts_h
#define dgRenderParts_h

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <string>

namespace dg
{
namespace render
{
/// The feature lines as red tubes, moved `shift` towards the viewer.
vtkSmartPointer<vtkActor> FeatureActor(
  vtkPolyData* features, double lineWidth, const double direction[3], double shift);
/// The longest edge of the surface's first cell: a voxel side.
double VoxelSide(vtkPolyData* surface);
/// A line of text centred at the top of its renderer, y pixels below the top.
void AddText(vtkRenderer* ren, const std::string& text, int fontSize, bool bold, double y,
  double panelHeight);
/// The shared three-quarter view: direction of projection and view up.
void ThreeQuarterView(double direction[3], double up[3]);

struct Frame
{
  double Center[3];     // of the object's projected extent, at the bounds' depth
  double Width, Height; // of that extent, in world units
};
/// The extent of the surface's points across and up the view.
Frame Framing(vtkPolyData* surface, const double direction[3], const double up[3]);
/// A parallel camera that frames `frame` in a panel of panelW x panelH
/// pixels, below a text band of `band` pixels, with `margin` pixels around.
void FrameCamera(vtkCamera* camera, const Frame& frame, const double direction[3],
  const double up[3], double diagonal, double panelW, double panelH, double band, double margin);
/// The two-panel pictures (Width x Width / 2): panel size, fonts, margin,
/// the titles' and notes' heights and the text band above the object.
struct TwoPanels
{
  explicit TwoPanels(int width);
  int Width, Height;
  double PanelW, PanelH;
  int TitleFont, NoteFont;
  double Margin, TitleTop, NoteTop, Band;
};
/// An off-screen window of width x height with the grey background
/// renderer that shows between panels.
vtkSmartPointer<vtkRenderWindow> PictureWindow(int width, int height);
/// Writes the rendered window (its back buffer) as a PNG;
/// false with error set when the file cannot be written.
bool SavePicture(vtkRenderWindow* window, const std::string& pngPath, std::string& error);
} // namespace render
} // namespace dg

#endif
