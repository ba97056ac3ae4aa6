#include "dgRenderCurvature.h"
#include "dgRenderParts.h"

#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkLight.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkMath.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextProperty.h>
#ifdef DG_HAVE_CHARTS
#include <vtkAxis.h>
#include <vtkChartHistogram2D.h>
#include <vtkColorLegend.h>
#include <vtkContextActor.h>
#include <vtkContextScene.h>
#include <vtkPen.h>
#include <vtkScalarBarActor.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

namespace dg
{
namespace
{
// The q-quantile of |values| (q in [0, 1]), over the non-zero ones.
double AbsQuantile(vtkDataArray* a, double q)
{
  std::vector<double> v;
  v.reserve(a->GetNumberOfTuples());
  for (vtkIdType i = 0; i < a->GetNumberOfTuples(); ++i)
  {
    const double x = std::abs(a->GetComponent(i, 0));
    if (x > 0 && std::isfinite(x))
      v.push_back(x);
  }
  if (v.empty())
    return 0;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// Blue (concave) - white - red (convex), Moreland's cool-to-warm map.
vtkSmartPointer<vtkColorTransferFunction> Diverging(double range)
{
  auto f = vtkSmartPointer<vtkColorTransferFunction>::New();
  f->SetColorSpaceToDiverging();
  f->AddRGBPoint(-range, 0.230, 0.299, 0.754);
  f->AddRGBPoint(range, 0.706, 0.016, 0.150);
  f->ClampingOn();
  return f;
}

} // namespace

bool RenderCurvaturePicture(vtkPolyData* surface, vtkPolyData* creases, int width,
  const std::string& pngPath, std::string& error)
{
  using namespace render;
  vtkCellData* cd = surface ? surface->GetCellData() : nullptr;
  vtkDataArray* H = cd ? cd->GetArray("CorrectedMeanCurvature") : nullptr;
  vtkDataArray* K1 = cd ? cd->GetArray("CorrectedK1") : nullptr;
  vtkDataArray* K2 = cd ? cd->GetArray("CorrectedK2") : nullptr;
  if (!surface || surface->GetNumberOfCells() == 0 || !H || !K1 || !K2)
  {
    error = "no corrected curvature to render";
    return false;
  }
  const TwoPanels layout(width);
  const int height = layout.Height;
  const double panelW = layout.PanelW, panelH = layout.PanelH;
  const int titleFont = layout.TitleFont, noteFont = layout.NoteFont;
  const double margin = layout.Margin, titleTop = layout.TitleTop, noteTop = layout.NoteTop;
  const double band = layout.Band;
  vtkSmartPointer<vtkRenderWindow> window = PictureWindow(width, height);

  // Left: H on the surface, over a symmetric range (the 98th percentile of
  // |H|: a few faces at corners would otherwise wash everything out).
  const double hRange = std::max(AbsQuantile(H, 0.98), 1e-12);
  vtkNew<vtkRenderer> left;
  left->SetViewport(0, 0, 0.5 - 0.5 / width, 1);
  left->SetBackground(1, 1, 1);
  left->SetUseFXAA(true);
  window->AddRenderer(left);
  vtkNew<vtkLight> light;
  light->SetLightTypeToCameraLight();
  light->SetPosition(0.0, 0.4, 1.0);
  light->SetFocalPoint(0.0, 0.0, 0.0);
  light->SetIntensity(1.0);
  left->AddLight(light);
  vtkNew<vtkPolyData> coloured;
  coloured->ShallowCopy(surface);
  coloured->GetCellData()->SetActiveScalars("CorrectedMeanCurvature");
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(coloured);
  mapper->SetScalarModeToUseCellData();
  auto lut = Diverging(hRange);
  mapper->SetLookupTable(lut);
  mapper->UseLookupTableScalarRangeOn();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetInterpolationToFlat();
  actor->GetProperty()->SetAmbient(0.35);
  actor->GetProperty()->SetDiffuse(0.7);
  left->AddActor(actor);
  double direction[3], up[3];
  ThreeQuarterView(direction, up);
  const Frame frame = Framing(surface, direction, up);
  // Room on the right of the panel for the colour bar.
  const double barW = 0.16 * panelW;
  FrameCamera(left->GetActiveCamera(), frame, direction, up, std::max(surface->GetLength(), 1e-9),
    panelW - barW, panelH, band, margin);
  {
    // The camera framed a narrower panel: widen its view to the real one
    // by moving the focal point right by half the bar's width.
    vtkCamera* c = left->GetActiveCamera();
    const double perPixel = 2 * c->GetParallelScale() / panelH;
    double right[3], f[3], p[3];
    vtkMath::Cross(direction, up, right);
    c->GetFocalPoint(f);
    c->GetPosition(p);
    for (int k = 0; k < 3; ++k)
    {
      f[k] += right[k] * perPixel * barW / 2;
      p[k] += right[k] * perPixel * barW / 2;
    }
    c->SetFocalPoint(f);
    c->SetPosition(p);
  }
  const vtkIdType lines = creases ? creases->GetNumberOfLines() : 0;
  if (lines > 0)
  {
    auto crease = FeatureActor(creases, std::max(1.5, panelH / 300.0), direction, 0.6 * VoxelSide(surface));
    crease->GetProperty()->SetColor(0.1, 0.1, 0.1);
    left->AddActor(crease);
  }
  AddText(left, "mean curvature H (corrected)", titleFont, true, titleTop, panelH);
  AddText(left,
    "blue concave, red convex" + std::string(lines > 0 ? "; creases in black" : ""),
    noteFont, false, noteTop, panelH);
#ifdef DG_HAVE_CHARTS
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  bar->SetNumberOfLabels(5);
  bar->SetLabelFormat("%.3g");
  bar->SetUnconstrainedFontSize(true);
  bar->GetLabelTextProperty()->SetFontSize(noteFont);
  bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetLabelTextProperty()->SetShadow(false);
  bar->GetLabelTextProperty()->SetItalic(false);
  bar->SetTitle("H");
  bar->GetTitleTextProperty()->SetFontSize(titleFont);
  bar->GetTitleTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->GetTitleTextProperty()->SetShadow(false);
  bar->GetTitleTextProperty()->SetItalic(false);
  bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  bar->GetPositionCoordinate()->SetValue(1.0 - barW / panelW, 0.1);
  bar->SetWidth(0.6 * barW / panelW);
  bar->SetHeight(0.7);
  left->AddViewProp(bar);
#endif
  left->ResetCameraClippingRange();

  // Right: the interface shape distribution, area-weighted counts of
  // (k1, k2) on a 96 x 96 grid over a symmetric range, log-coloured.
  vtkNew<vtkRenderer> right;
  right->SetViewport(0.5 + 0.5 / width, 0, 1, 1);
  right->SetBackground(1, 1, 1);
  window->AddRenderer(right);
  AddText(right, "interface shape distribution", titleFont, true, titleTop, panelH);
#ifdef DG_HAVE_CHARTS
  const int bins = 96;
  const double kRange = std::max(std::max(AbsQuantile(K1, 0.98), AbsQuantile(K2, 0.98)), 1e-12);
  vtkNew<vtkImageData> histogram;
  histogram->SetDimensions(bins, bins, 1);
  histogram->SetOrigin(-kRange, -kRange, 0);
  histogram->SetSpacing(2 * kRange / (bins - 1), 2 * kRange / (bins - 1), 1);
  histogram->AllocateScalars(VTK_DOUBLE, 1);
  double* counts = static_cast<double*>(histogram->GetScalarPointer());
  std::fill(counts, counts + bins * bins, 0.0);
  vtkIdType inside = 0;
  for (vtkIdType f = 0; f < surface->GetNumberOfCells(); ++f)
  {
    const double k1 = K1->GetComponent(f, 0), k2 = K2->GetComponent(f, 0);
    const long i = std::lround((k1 + kRange) / (2 * kRange) * (bins - 1));
    const long j = std::lround((k2 + kRange) / (2 * kRange) * (bins - 1));
    if (i < 0 || j < 0 || i >= bins || j >= bins)
      continue;
    counts[j * bins + i] += 1;
    ++inside;
  }
  double top = 0;
  for (int k = 0; k < bins * bins; ++k)
  {
    counts[k] = std::log10(1 + counts[k]);
    top = std::max(top, counts[k]);
  }
  AddText(right,
    "faces per bin (log scale), k1 >= k2; " + std::to_string(inside) + " of " +
      std::to_string(surface->GetNumberOfCells()) + " in range",
    noteFont, false, noteTop, panelH);
  vtkNew<vtkChartHistogram2D> chart;
  chart->SetInputData(histogram);
  vtkNew<vtkColorTransferFunction> heat;
  heat->AddRGBPoint(0, 1, 1, 1);
  heat->AddRGBPoint(std::max(top, 1e-9) * 0.02, 0.85, 0.9, 1.0);
  heat->AddRGBPoint(std::max(top, 1e-9) * 0.5, 0.2, 0.45, 0.85);
  heat->AddRGBPoint(std::max(top, 1e-9), 0.05, 0.05, 0.35);
  chart->SetTransferFunction(heat);
  chart->SetRenderEmpty(true);
  chart->SetShowLegend(false);
  for (int which : { vtkAxis::BOTTOM, vtkAxis::LEFT })
  {
    vtkAxis* axis = chart->GetAxis(which);
    axis->SetTitle(which == vtkAxis::BOTTOM ? "k1, largest principal curvature (1/length)"
                                            : "k2, smallest principal curvature (1/length)");
    axis->GetTitleProperties()->SetFontSize(noteFont);
    axis->GetLabelProperties()->SetFontSize(noteFont);
    axis->SetBehavior(vtkAxis::FIXED);
    axis->SetRange(-kRange, kRange);
  }
  chart->SetAutoSize(false);
  const double chartTop = band + margin;
  chart->SetSize(vtkRectf(static_cast<float>(margin), static_cast<float>(margin),
    static_cast<float>(panelW - 2 * margin), static_cast<float>(panelH - chartTop - margin)));
  vtkNew<vtkContextActor> context;
  context->GetScene()->AddItem(chart);
  right->AddActor(context);
#else
  AddText(right, "not available: this VTK has no charts module", noteFont, false, noteTop, panelH);
#endif

  window->Render();
  return render::SavePicture(window, pngPath, error);
}

std::string CurvatureBallText(
  double radiusVoxels, bool adaptive, double usedRadius, vtkPolyData* surface)
{
  std::ostringstream text;
  text.precision(3);
  if (!adaptive)
  {
    text << "ball " << radiusVoxels << " voxels";
    return text.str();
  }
  text << "ball radius per face from " << radiusVoxels << " voxels";
  vtkDataArray* radius =
    surface ? surface->GetCellData()->GetArray("CorrectedBallRadius") : nullptr;
  std::vector<double> r;
  for (vtkIdType c = 0; radius && c < radius->GetNumberOfTuples(); ++c)
    if (radius->GetComponent(c, 0) > 0)
      r.push_back(radius->GetComponent(c, 0) * radiusVoxels / usedRadius);
  if (r.empty() || !(usedRadius > 0))
    return text.str();
  std::sort(r.begin(), r.end());
  const auto at = [&](double p) { return r[static_cast<std::size_t>(p * (r.size() - 1))]; };
  text << ", 10/50/90 % " << at(0.1) << " / " << at(0.5) << " / " << at(0.9);
  return text.str();
}
} // namespace dg
