#include "dgRender.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkCoordinate.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>

namespace dg
{
namespace
{
vtkSmartPointer<vtkActor> SurfaceActor(vtkPolyData* surface, vtkDataArray* normals)
{
  auto shaded = vtkSmartPointer<vtkPolyData>::New();
  shaded->ShallowCopy(surface);
  if (normals)
  {
    shaded->GetCellData()->SetNormals(normals);
  }
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(shaded);
  mapper->ScalarVisibilityOff();
  // Feature lines lie on the surface, often in the concave corners of its
  // staircase: push the polygons well back so that the lines stay visible.
  mapper->SetResolveCoincidentTopologyToPolygonOffset();
  mapper->SetRelativeCoincidentTopologyPolygonOffsetParameters(0.0, 0.0);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.86, 0.87, 0.92);
  actor->GetProperty()->SetInterpolationToFlat();
  actor->GetProperty()->SetSpecular(0.15);
  return actor;
}

vtkSmartPointer<vtkActor> FeatureActor(vtkPolyData* features, double lineWidth)
{
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(features);
  mapper->ScalarVisibilityOff();
  mapper->SetRelativeCoincidentTopologyLineOffsetParameters(-2.0, -150.0);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.9, 0.05, 0.05);
  actor->GetProperty()->SetLineWidth(static_cast<float>(lineWidth));
  actor->GetProperty()->SetRenderLinesAsTubes(true);
  actor->GetProperty()->LightingOff();
  return actor;
}

void AddLabel(vtkRenderer* ren, const char* text)
{
  vtkNew<vtkTextActor> label;
  label->SetInput(text);
  label->GetTextProperty()->SetFontSize(20);
  label->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
  // Display coordinates would place every panel's label in the first panel.
  label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  label->GetPositionCoordinate()->SetValue(0.03, 0.03);
  ren->AddViewProp(label);
}
} // namespace

bool RenderPicture(vtkPolyData* surface, const char* inputNormals, vtkPolyData* features,
  const RenderOptions& options, const std::string& pngPath, std::string& error)
{
  if (!surface || surface->GetNumberOfCells() == 0)
  {
    error = "nothing to render";
    return false;
  }
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  // Panels sit side by side: each gets a third of the width and a matching height.
  const int height = options.Panels ? std::max(200, options.Width / 3) : options.Height;
  window->SetSize(options.Width, height);
  window->SetMultiSamples(4);
  vtkNew<vtkCamera> camera;
  vtkDataArray* input = inputNormals ? surface->GetCellData()->GetArray(inputNormals) : nullptr;
  const bool hasFeatures = features && features->GetNumberOfCells() > 0;
  const double lineWidth = std::max(3.0, height / 200.0);

  std::vector<vtkSmartPointer<vtkRenderer>> renderers;
  auto addRenderer = [&](double x0, double x1) {
    auto ren = vtkSmartPointer<vtkRenderer>::New();
    ren->SetViewport(x0, 0.0, x1, 1.0);
    ren->SetBackground(1.0, 1.0, 1.0);
    ren->SetActiveCamera(camera);
    window->AddRenderer(ren);
    renderers.push_back(ren);
    return ren.Get();
  };
  if (options.Panels)
  {
    auto* r0 = addRenderer(0.0, 1.0 / 3);
    r0->AddActor(SurfaceActor(surface, input));
    AddLabel(r0, input ? "input normals" : "input normals (absent)");
    auto* r1 = addRenderer(1.0 / 3, 2.0 / 3);
    r1->AddActor(SurfaceActor(surface, nullptr));
    AddLabel(r1, "regularised normals");
    auto* r2 = addRenderer(2.0 / 3, 1.0);
    r2->AddActor(SurfaceActor(surface, nullptr));
    if (hasFeatures)
    {
      r2->AddActor(FeatureActor(features, lineWidth));
    }
    AddLabel(r2, "features");
  }
  else
  {
    auto* r = addRenderer(0.0, 1.0);
    r->AddActor(SurfaceActor(surface, nullptr));
    if (hasFeatures)
    {
      r->AddActor(FeatureActor(features, lineWidth));
    }
  }
  // A three-quarter view that frames the whole object.
  renderers.back()->ResetCamera();
  camera->Azimuth(35);
  camera->Elevation(25);
  camera->OrthogonalizeViewUp();
  renderers.back()->ResetCamera();
  camera->Zoom(1.25);
  for (auto& r : renderers)
  {
    r->ResetCameraClippingRange();
  }
  window->Render();

  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
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
} // namespace dg
