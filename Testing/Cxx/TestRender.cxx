// The program's picture (Applications/dgRender): its size in both layouts,
// four panels each filled by the object, normals as colours in panels 2 and 3,
// red feature lines in panel 4 only, and the degraded inputs (no II normals,
// no active normals, no or empty features, no surface). Runs under its own X
// server (Testing/with-own-display.sh, from the CMake).
#include "dgRender.h"
#include "dgTestShapes.h"
#include "dgTestTemp.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCellData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace
{
struct Result
{
  vtkSmartPointer<vtkPolyData> Surface, Features;
};

// A box (sharp edges, so AT gives feature lines) in a 24^3 image, through
// surface -> II (r = 3) -> AT; or the digital surface alone.
Result Box(bool full)
{
  auto image = dgtest::MakeImage(24, 24, 24, [](int i, int j, int k) {
    return (i >= 5 && i <= 18 && j >= 4 && j <= 16 && k >= 6 && k <= 19) ? 1.0 : 0.0;
  });
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  Result r;
  r.Surface = vtkSmartPointer<vtkPolyData>::New();
  r.Features = vtkSmartPointer<vtkPolyData>::New();
  if (!full)
  {
    surface->Update();
    r.Surface->ShallowCopy(surface->GetOutput());
    return r;
  }
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadius(3);
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetInputConnection(ii->GetOutputPort());
  at->Update();
  r.Surface->ShallowCopy(at->GetOutput(0));
  r.Features->ShallowCopy(at->GetOutput(1));
  return r;
}

struct Picture
{
  int Width = 0, Height = 0;
  std::vector<unsigned char> Rgb; // row 0 at the top
  const unsigned char* At(int x, int y) const { return &Rgb[3 * (y * Width + x)]; }
};

Picture Read(const std::string& path)
{
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  Picture p;
  int dims[3];
  reader->GetOutput()->GetDimensions(dims);
  vtkDataArray* s = reader->GetOutput()->GetPointData()->GetScalars();
  if (!s || s->GetNumberOfComponents() < 3)
  {
    return p;
  }
  p.Width = dims[0];
  p.Height = dims[1];
  p.Rgb.resize(3 * static_cast<size_t>(p.Width) * p.Height);
  for (int y = 0; y < p.Height; ++y)
  {
    for (int x = 0; x < p.Width; ++x)
    {
      for (int c = 0; c < 3; ++c)
      {
        // VTK's image rows go up: flip them.
        p.Rgb[3 * ((p.Height - 1 - y) * p.Width + x) + c] =
          static_cast<unsigned char>(s->GetComponent(x + y * p.Width, c));
      }
    }
  }
  return p;
}

struct PanelStats
{
  double Object = 0;    // share of the panel's pixels that are not background
  double Colourful = 0; // share with clearly unequal R, G, B (normal colours)
  double SpanX = 0, SpanY = 0; // extent of the object pixels / the panel's size
  long Red = 0;
};

// Panel index (0..3) in a columns x rows layout; a few pixels at each side are
// skipped (the dividing lines), text pixels (dark grey) are not the object.
PanelStats Stats(const Picture& p, int index, int columns, int rows)
{
  const int pw = p.Width / columns, ph = p.Height / rows;
  const int x0 = (index % columns) * pw, y0 = (index / columns) * ph;
  PanelStats s;
  long object = 0, colourful = 0, n = 0;
  int lo[2] = { pw, ph }, hi[2] = { -1, -1 };
  for (int y = 2; y < ph - 2; ++y)
  {
    for (int x = 2; x < pw - 2; ++x, ++n)
    {
      const unsigned char* c = p.At(x0 + x, y0 + y);
      const int mx = std::max({ c[0], c[1], c[2] }), mn = std::min({ c[0], c[1], c[2] });
      const bool background = mn > 245;
      const bool text = mx < 60;
      if (!background && !text)
      {
        ++object;
        lo[0] = std::min(lo[0], x);
        hi[0] = std::max(hi[0], x);
        lo[1] = std::min(lo[1], y);
        hi[1] = std::max(hi[1], y);
      }
      colourful += (mx - mn > 40);
      s.Red += (c[0] > 150 && c[1] < 80 && c[2] < 80);
    }
  }
  s.Object = static_cast<double>(object) / n;
  s.Colourful = static_cast<double>(colourful) / n;
  s.SpanX = hi[0] >= lo[0] ? static_cast<double>(hi[0] - lo[0] + 1) / pw : 0;
  s.SpanY = hi[1] >= lo[1] ? static_cast<double>(hi[1] - lo[1] + 1) / ph : 0;
  return s;
}

std::string RenderOrFail(vtkPolyData* surface, const char* input, vtkPolyData* features,
  const dg::RenderOptions& o, const std::string& name)
{
  const std::string path = dgtest::TempPath(name);
  std::remove(path.c_str());
  std::string error;
  EXPECT_TRUE(dg::RenderPicture(surface, input, features, o, path, error)) << error;
  return path;
}

// Each panel holds the object, filled to the panel's width or height.
void ExpectFilled(const Picture& p, int columns, int rows)
{
  for (int i = 0; i < 4; ++i)
  {
    const PanelStats s = Stats(p, i, columns, rows);
    EXPECT_GT(s.Object, 0.15) << "panel " << i + 1;
    EXPECT_GT(std::max(s.SpanX, s.SpanY), 0.8)
      << "panel " << i + 1 << ": object spans " << s.SpanX << " x " << s.SpanY;
  }
}
} // namespace

TEST(Render, GridFourPanelsFilled)
{
  const Result r = Box(true);
  ASSERT_GT(r.Features->GetNumberOfLines(), 0);
  ASSERT_NE(r.Surface->GetCellData()->GetArray("IINormals"), nullptr);
  dg::RenderOptions o;
  o.Width = 480;
  o.Height = 360;
  const Picture p = Read(RenderOrFail(r.Surface, "IINormals", r.Features, o, "grid.png"));
  ASSERT_EQ(p.Width, 480);
  ASSERT_EQ(p.Height, 360);
  ExpectFilled(p, 2, 2);
  // Panels 1 and 4 are grey, 2 and 3 normal colours; red only in panel 4.
  EXPECT_LT(Stats(p, 0, 2, 2).Colourful, 0.01);
  EXPECT_GT(Stats(p, 1, 2, 2).Colourful, 0.15);
  EXPECT_GT(Stats(p, 2, 2, 2).Colourful, 0.15);
  EXPECT_GT(Stats(p, 3, 2, 2).Red, 200);
  EXPECT_EQ(Stats(p, 0, 2, 2).Red, 0);
}

TEST(Render, StripFourSquarePanels)
{
  const Result r = Box(true);
  dg::RenderOptions o;
  o.Width = 800;
  o.Height = 900; // not used by the strip
  o.Panels = true;
  int w = 0, h = 0;
  dg::PictureSize(o, w, h);
  EXPECT_EQ(w, 800);
  EXPECT_EQ(h, 200);
  const Picture p = Read(RenderOrFail(r.Surface, "IINormals", r.Features, o, "strip.png"));
  ASSERT_EQ(p.Width, 800);
  ASSERT_EQ(p.Height, 200);
  ExpectFilled(p, 4, 1);
  EXPECT_GT(Stats(p, 3, 4, 1).Red, 100);
}

TEST(Render, NoInputNormalsNoFeatures)
{
  // The digital surface alone: trivial normals only (active), no IINormals,
  // no feature lines: panel 2 is plainly shaded, panel 4 has no red.
  const Result r = Box(false);
  ASSERT_EQ(r.Surface->GetCellData()->GetArray("IINormals"), nullptr);
  dg::RenderOptions o;
  o.Width = 400;
  o.Height = 300;
  vtkNew<vtkPolyData> empty;
  for (vtkPolyData* features : { static_cast<vtkPolyData*>(empty), static_cast<vtkPolyData*>(nullptr) })
  {
    const Picture p = Read(RenderOrFail(r.Surface, "IINormals", features, o, "plain.png"));
    ASSERT_EQ(p.Width, 400);
    ASSERT_EQ(p.Height, 300);
    ExpectFilled(p, 2, 2);
    EXPECT_LT(Stats(p, 1, 2, 2).Colourful, 0.01);
    EXPECT_EQ(Stats(p, 3, 2, 2).Red, 0);
  }
  const Picture p = Read(RenderOrFail(r.Surface, nullptr, nullptr, o, "noname.png"));
  ExpectFilled(p, 2, 2);
}

TEST(Render, NoActiveNormals)
{
  // Neither active normals nor the trivial array: every panel still shaded.
  const Result r = Box(true);
  vtkNew<vtkPolyData> bare;
  bare->ShallowCopy(r.Surface);
  bare->GetCellData()->SetNormals(nullptr);
  bare->GetCellData()->RemoveArray("Normals");
  ASSERT_EQ(bare->GetCellData()->GetNormals(), nullptr);
  dg::RenderOptions o;
  o.Width = 400;
  o.Height = 300;
  const Picture p = Read(RenderOrFail(bare, "IINormals", r.Features, o, "bare.png"));
  ExpectFilled(p, 2, 2);
  EXPECT_GT(Stats(p, 1, 2, 2).Colourful, 0.15);
  EXPECT_LT(Stats(p, 2, 2, 2).Colourful, 0.01);
  EXPECT_GT(Stats(p, 3, 2, 2).Red, 100);
}

TEST(Render, NothingToRender)
{
  vtkNew<vtkPolyData> empty;
  std::string error;
  const std::string path = dgtest::TempPath("none.png");
  EXPECT_FALSE(dg::RenderPicture(empty, "IINormals", nullptr, dg::RenderOptions(), path, error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(dg::RenderPicture(nullptr, nullptr, nullptr, dg::RenderOptions(), path, error));
}
