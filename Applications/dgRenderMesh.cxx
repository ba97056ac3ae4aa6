#include "dgRenderMesh.h"
#include "dgRenderParts.h"

#include <vtkLight.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <cmath>

namespace dg
{
bool RenderMeshPicture(vtkPolyData* digital, vtkPolyData* mesh, vtkPolyData* creases, int width,
  const std::string& pngPath, std::string& error)
{
  using namespace render;
  if (!digital || !mesh || digital->GetNumberOfCells() == 0 || mesh->GetNumberOfCells() == 0)
  {
    error = "no mesh to render";
    return false;
  }
  const TwoPanels layout(width);
  const int height = layout.Height;
  const double panelW = layout.PanelW, panelH = layout.PanelH;
  const int titleFont = layout.TitleFont, noteFont = layout.NoteFont;
  const double margin = layout.Margin, titleTop = layout.TitleTop, noteTop = layout.NoteTop;
  const double band = layout.Band;
  vtkSmartPointer<vtkRenderWindow> window = PictureWindow(width, height);

  double direction[3], up[3];
  ThreeQuarterView(direction, up);
  // Both panels framed on the digital surface, so that they line up.
  const Frame frame = Framing(digital, direction, up);
  const double diagonal = std::max(digital->GetLength(), 1e-9);
  const vtkIdType lines = creases ? creases->GetNumberOfLines() : 0;
  struct Panel
  {
    vtkPolyData* Surface;
    const char* Title;
    std::string Note;
    double X0, X1;
  };
  const Panel panels[2] = {
    { digital, "digital surface (voxel faces)", "the input of the normal estimators", 0,
      0.5 - 0.5 / width },
    { mesh, "piecewise-smooth mesh",
      lines > 0 ? "flat shaded; creases in red" : "flat shaded; no crease", 0.5 + 0.5 / width, 1 },
  };
  for (const Panel& p : panels)
  {
    vtkNew<vtkRenderer> ren;
    ren->SetViewport(p.X0, 0, p.X1, 1);
    ren->SetBackground(1, 1, 1);
    window->AddRenderer(ren);
    vtkNew<vtkLight> light;
    light->SetLightTypeToCameraLight();
    light->SetPosition(0.0, 0.4, 1.0);
    light->SetFocalPoint(0.0, 0.0, 0.0);
    light->SetIntensity(1.0);
    ren->AddLight(light);
    // Flat shading by each face's own geometry: the point normals (which
    // would smooth the faces) are left out.
    vtkNew<vtkPolyData> shown;
    shown->CopyStructure(p.Surface);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(shown);
    mapper->ScalarVisibilityOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->SetInterpolationToFlat();
    actor->GetProperty()->SetColor(0.85, 0.85, 0.82);
    actor->GetProperty()->SetAmbient(0.25);
    actor->GetProperty()->SetDiffuse(0.8);
    ren->AddActor(actor);
    FrameCamera(ren->GetActiveCamera(), frame, direction, up, diagonal, panelW, panelH, band, margin);
    if (p.Surface == mesh && lines > 0)
      ren->AddActor(FeatureActor(creases, std::max(1.5, panelH / 300.0), direction,
        0.6 * VoxelSide(digital)));
    AddText(ren, p.Title, titleFont, true, titleTop, panelH);
    AddText(ren, p.Note, noteFont, false, noteTop, panelH);
    ren->ResetCameraClippingRange();
  }
  window->Render();
  return SavePicture(window, pngPath, error);
}
} // namespace dg
