#include "dgRender.h"
#include "dgRenderParts.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkCoordinate.h>
#include <vtkDataArray.h>
#include <vtkLight.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dg
{
namespace
{
// A copy of the surface that shares its arrays, with the given cell normals
// (none: the mapper lights each quad by its own plane) and no point normals.
vtkSmartPointer<vtkPolyData> WithNormals(vtkPolyData* surface, vtkDataArray* normals)
{
  auto shaded = vtkSmartPointer<vtkPolyData>::New();
  shaded->ShallowCopy(surface);
  shaded->GetPointData()->SetNormals(nullptr);
  shaded->GetCellData()->SetNormals(normals);
  return shaded;
}

vtkSmartPointer<vtkActor> Actor(vtkPolyData* data, vtkPolyDataMapper* mapper)
{
  mapper->SetInputData(data);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetInterpolationToFlat();
  return actor;
}

// Light grey, lit by the given cell normals (or by the quads' planes).
vtkSmartPointer<vtkActor> GreyActor(vtkPolyData* surface, vtkDataArray* normals)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->ScalarVisibilityOff();
  auto actor = Actor(WithNormals(surface, normals), mapper);
  actor->GetProperty()->SetColor(0.86, 0.87, 0.9);
  actor->GetProperty()->SetAmbient(0.12);
  actor->GetProperty()->SetDiffuse(0.88);
  actor->GetProperty()->SetSpecular(0.1);
  return actor;
}

// One colour per quad, RGB = (n + 1) / 2, unlit: the colour is the normal.
vtkSmartPointer<vtkActor> NormalColourActor(vtkPolyData* surface, vtkDataArray* normals)
{
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("NormalColours");
  colours->SetNumberOfComponents(3);
  const vtkIdType n = normals->GetNumberOfTuples();
  colours->SetNumberOfTuples(n);
  for (vtkIdType c = 0; c < n; ++c)
  {
    double v[3];
    normals->GetTuple(c, v);
    for (int k = 0; k < 3; ++k)
    {
      const double x = std::isfinite(v[k]) ? std::clamp(v[k], -1.0, 1.0) : 0.0;
      colours->SetTypedComponent(c, k, static_cast<unsigned char>(std::lround(127.5 * (x + 1.0))));
    }
  }
  auto data = WithNormals(surface, nullptr);
  data->GetCellData()->SetScalars(colours);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->ScalarVisibilityOn();
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();
  auto actor = Actor(data, mapper);
  actor->GetProperty()->LightingOff();
  return actor;
}

} // namespace

namespace render
{
// The feature lines, moved shift towards the viewer: they lie on the
// surface, often in the concave corners of its staircase, and a depth offset
// in the mapper is not a safe cure (a slope-scaled one lets the tubes of the
// far side show through the object). Moved by less than a voxel, a line stays
// behind every surface that is more than that in front of it.
vtkSmartPointer<vtkActor> FeatureActor(
  vtkPolyData* features, double lineWidth, const double direction[3], double shift)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  const vtkIdType n = features->GetNumberOfPoints();
  points->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    double p[3];
    features->GetPoint(i, p);
    points->SetPoint(
      i, p[0] - shift * direction[0], p[1] - shift * direction[1], p[2] - shift * direction[2]);
  }
  vtkNew<vtkPolyData> moved;
  moved->ShallowCopy(features);
  moved->SetPoints(points);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(moved);
  mapper->ScalarVisibilityOff();
  mapper->SetRelativeCoincidentTopologyLineOffsetParameters(0.0, 0.0);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.9, 0.05, 0.05);
  actor->GetProperty()->SetLineWidth(static_cast<float>(lineWidth));
  actor->GetProperty()->SetRenderLinesAsTubes(true);
  actor->GetProperty()->LightingOff();
  return actor;
}

// The longest edge of the surface's first cell: a voxel side.
double VoxelSide(vtkPolyData* surface)
{
  vtkCell* cell = surface->GetCell(0);
  double side = 0;
  for (int e = 0; e < cell->GetNumberOfEdges(); ++e)
  {
    vtkCell* edge = cell->GetEdge(e);
    double a[3], b[3];
    surface->GetPoint(edge->GetPointId(0), a);
    surface->GetPoint(edge->GetPointId(1), b);
    side = std::max(side, std::sqrt(vtkMath::Distance2BetweenPoints(a, b)));
  }
  return side > 0 ? side : 1e-3 * surface->GetLength();
}

// A line of text centred at the top of its renderer, y pixels below the top.
void AddText(vtkRenderer* ren, const std::string& text, int fontSize, bool bold, double y,
  double panelHeight)
{
  vtkNew<vtkTextActor> label;
  label->SetInput(text.c_str());
  label->SetTextScaleModeToNone();
  vtkTextProperty* tp = label->GetTextProperty();
  tp->SetFontSize(fontSize);
  tp->SetBold(bold);
  tp->SetColor(0.1, 0.1, 0.1);
  tp->SetJustificationToCentered();
  tp->SetVerticalJustificationToTop();
  // Display coordinates would place every panel's label in the first panel.
  label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  label->GetPositionCoordinate()->SetValue(0.5, 1.0 - y / panelHeight);
  ren->AddViewProp(label);
}

// The shared three-quarter view: direction of projection and view up.
void ThreeQuarterView(double direction[3], double up[3])
{
  vtkNew<vtkCamera> c;
  c->SetFocalPoint(0, 0, 0);
  c->SetPosition(0, 0, 1);
  c->SetViewUp(0, 1, 0);
  c->Azimuth(35);
  c->Elevation(25);
  c->OrthogonalizeViewUp();
  c->GetDirectionOfProjection(direction);
  c->GetViewUp(up);
}

// The extent of the surface's points across and up the view.
Frame Framing(vtkPolyData* surface, const double direction[3], const double up[3])
{
  double right[3];
  vtkMath::Cross(direction, up, right);
  double lo[2] = { VTK_DOUBLE_MAX, VTK_DOUBLE_MAX }, hi[2] = { -VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX };
  vtkPoints* points = surface->GetPoints();
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    double p[3];
    points->GetPoint(i, p);
    const double a = vtkMath::Dot(p, right), b = vtkMath::Dot(p, up);
    lo[0] = std::min(lo[0], a);
    hi[0] = std::max(hi[0], a);
    lo[1] = std::min(lo[1], b);
    hi[1] = std::max(hi[1], b);
  }
  double bounds[6];
  surface->GetBounds(bounds);
  double c[3] = { (bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2,
    (bounds[4] + bounds[5]) / 2 };
  const double da = (lo[0] + hi[0]) / 2 - vtkMath::Dot(c, right);
  const double db = (lo[1] + hi[1]) / 2 - vtkMath::Dot(c, up);
  Frame f;
  for (int k = 0; k < 3; ++k)
  {
    f.Center[k] = c[k] + da * right[k] + db * up[k];
  }
  f.Width = std::max(hi[0] - lo[0], 1e-9);
  f.Height = std::max(hi[1] - lo[1], 1e-9);
  return f;
}

void FrameCamera(vtkCamera* camera, const Frame& frame, const double direction[3],
  const double up[3], double diagonal, double panelW, double panelH, double band, double margin)
{
  // Parallel projection: the object fills the panel below the text band,
  // with a small margin, whatever its shape.
  const double availW = panelW - 2 * margin, availH = panelH - band - 2 * margin;
  const double perPixel = std::max(frame.Width / availW, frame.Height / std::max(availH, 1.0));
  camera->ParallelProjectionOn();
  double focal[3], position[3];
  for (int k = 0; k < 3; ++k)
  {
    // The object's centre sits band / 2 pixels below the panel's centre.
    focal[k] = frame.Center[k] + up[k] * perPixel * band / 2;
    position[k] = focal[k] - direction[k] * 2 * diagonal;
  }
  camera->SetFocalPoint(focal);
  camera->SetPosition(position);
  camera->SetViewUp(up);
  camera->SetParallelScale(perPixel * panelH / 2);
}

TwoPanels::TwoPanels(int width)
  : Width(width)
  , Height(std::max(64, width / 2))
  , PanelW(width / 2.0)
  , PanelH(std::max(64, width / 2))
{
  this->TitleFont = std::clamp(static_cast<int>(std::lround(this->PanelH * 0.045)), 10, 48);
  this->NoteFont = std::max(9, static_cast<int>(std::lround(this->TitleFont * 0.75)));
  this->Margin = std::max(3.0, 0.035 * this->PanelH);
  this->TitleTop = 0.4 * this->Margin;
  this->NoteTop = this->TitleTop + 1.3 * this->TitleFont;
  this->Band = this->NoteTop + 1.35 * this->NoteFont;
}

vtkSmartPointer<vtkRenderWindow> PictureWindow(int width, int height)
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetSize(width, height);
  window->SetMultiSamples(0);
  vtkNew<vtkRenderer> back;
  back->SetBackground(0.8, 0.8, 0.8);
  window->AddRenderer(back);
  return window;
}

bool SavePicture(vtkRenderWindow* window, const std::string& pngPath, std::string& error)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->SetFileName(pngPath.c_str());
  writer->Write();
  if (writer->GetErrorCode() != 0)
  {
    error = "cannot write " + pngPath;
    return false;
  }
  return true;
}
} // namespace render
using namespace render;

void PictureSize(const RenderOptions& options, int& width, int& height)
{
  width = options.Width;
  height = options.Panels ? std::max(64, options.Width / 4) : options.Height;
}

bool RenderPicture(vtkPolyData* surface, const char* inputNormals, vtkPolyData* features,
  const RenderOptions& options, const std::string& pngPath, std::string& error)
{
  if (!surface || surface->GetNumberOfCells() == 0 || surface->GetNumberOfPoints() == 0)
  {
    error = "nothing to render";
    return false;
  }
  int width = 0, height = 0;
  PictureSize(options, width, height);
  const int columns = options.Panels ? 4 : 2, rows = options.Panels ? 1 : 2;
  const double panelW = static_cast<double>(width) / columns;
  const double panelH = static_cast<double>(height) / rows;
  const double panelMin = std::min(panelW, panelH);

  vtkCellData* cd = surface->GetCellData();
  vtkDataArray* trivial =
    options.SurfaceNormals.empty() ? nullptr : cd->GetArray(options.SurfaceNormals.c_str());
  vtkDataArray* input = inputNormals ? cd->GetArray(inputNormals) : nullptr;
  vtkDataArray* regularised = cd->GetNormals();
  auto usable = [&](vtkDataArray* a) {
    return a && a->GetNumberOfComponents() == 3 &&
      a->GetNumberOfTuples() == surface->GetNumberOfCells();
  };
  trivial = usable(trivial) ? trivial : nullptr;
  input = usable(input) ? input : nullptr;
  regularised = usable(regularised) ? regularised : nullptr;
  const vtkIdType lines = features ? features->GetNumberOfLines() : 0;

  // Text sizes follow the panel: legible at 300 px, not shouting at 1000.
  const int titleFont = std::clamp(static_cast<int>(std::lround(panelMin * 0.062)), 10, 64);
  const int noteFont = std::max(9, static_cast<int>(std::lround(titleFont * 0.75)));
  const double margin = std::max(3.0, 0.035 * panelMin);
  const double titleTop = 0.4 * margin;
  const double noteTop = titleTop + 1.3 * titleFont;
  const double band = noteTop + 1.35 * noteFont; // text band at the top of each panel
  const double lineWidth = std::max(2.0, panelMin / 170.0);

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(width, height);
  window->SetMultiSamples(0);
  // Thin grey lines between the panels: a background renderer under them.
  vtkNew<vtkRenderer> back;
  back->SetBackground(0.8, 0.8, 0.8);
  back->SetViewport(0, 0, 1, 1);
  window->AddRenderer(back);

  double direction[3], up[3];
  ThreeQuarterView(direction, up);
  const Frame frame = Framing(surface, direction, up);
  const double diagonal = std::max(surface->GetLength(), 1e-9);

  auto panel = [&](int index, const std::string& title, const std::string& note) {
    const int col = index % columns, row = index / columns;
    const double gap = 0.5; // pixels on each side of a dividing line
    const double x0 = (col * panelW + (col > 0 ? gap : 0)) / width;
    const double x1 = ((col + 1) * panelW - (col + 1 < columns ? gap : 0)) / width;
    const double y1 = 1.0 - (row * panelH + (row > 0 ? gap : 0)) / height;
    const double y0 = 1.0 - ((row + 1) * panelH - (row + 1 < rows ? gap : 0)) / height;
    auto ren = vtkSmartPointer<vtkRenderer>::New();
    ren->SetViewport(x0, y0, x1, y1);
    ren->SetBackground(1.0, 1.0, 1.0);
    ren->SetUseFXAA(true);
    // One light above the viewer: the three orientations of the voxel faces
    // in this view get three distinct greys (top 0.8, left 0.65, right 0.5).
    vtkNew<vtkLight> light;
    light->SetLightTypeToCameraLight();
    light->SetPosition(0.0, 0.4, 1.0);
    light->SetFocalPoint(0.0, 0.0, 0.0);
    light->SetIntensity(1.1);
    ren->AddLight(light);
    window->AddRenderer(ren);
    FrameCamera(ren->GetActiveCamera(), frame, direction, up, diagonal, panelW, panelH, band, margin);
    AddText(ren, title, titleFont, true, titleTop, panelH);
    AddText(ren, note, noteFont, false, noteTop, panelH);
    return ren.Get();
  };

  const std::string colourNote = "colour RGB = (n + 1) / 2, per quad";
  panel(0, "digital surface",
    std::to_string(surface->GetNumberOfCells()) + " quads, flat shaded")
    ->AddActor(GreyActor(surface, trivial));
  const std::string missing = inputNormals && *inputNormals
    ? "no cell array '" + std::string(inputNormals) + "': plain shading"
    : "no input normals: plain shading";
  panel(1, options.InputTitle, input ? colourNote : missing)
    ->AddActor(input ? NormalColourActor(surface, input) : GreyActor(surface, nullptr));
  panel(2, options.RegularisedTitle,
    regularised ? colourNote : "no active cell normals: plain shading")
    ->AddActor(regularised ? NormalColourActor(surface, regularised) : GreyActor(surface, nullptr));
  auto* last = panel(3, "features",
    lines > 0 ? std::to_string(lines) + " feature edges" : "no feature lines");
  last->AddActor(GreyActor(surface, regularised));
  if (lines > 0)
  {
    last->AddActor(FeatureActor(features, lineWidth, direction, 0.6 * VoxelSide(surface)));
  }
  vtkRendererCollection* all = window->GetRenderers();
  all->InitTraversal();
  while (vtkRenderer* r = all->GetNextItem())
  {
    r->ResetCameraClippingRange();
  }
  window->Render();
  return render::SavePicture(window, pngPath, error);
}
} // namespace dg
