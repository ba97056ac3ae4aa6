// The bad-input matrix (issue 5), filters' half: one row per case, each its
// own ctest entry (dgBadInput.h says how a row is judged; the readers' rows
// are in TestBadInputReaders). The scattered per-filter tests check the same
// messages in context; this table is the one place where a regression of any
// row shows by name.
#include "dgGroundTruth.h"
#include "dgBadInput.h"
#include "dgTestShapes.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDigitalIslandFilter.h"
#include "vtkSharpFeaturesFilter.h"
#include "vtkPiecewiseSmoothMeshFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"
#include "vtkSplitByLabelFilter.h"
#include "vtkVCMNormalEstimator.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>
#include "dgTestTemp.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>

namespace
{
using dgtest::Expect;
using dgtest::Outcome;
using dgtest::Row;
using dgtest::Run;

vtkSmartPointer<vtkImageData> Block(int n)
{
  return dgtest::MakeImage(n,
    n,
    n,
    [n](int i, int j, int k)
    { return (i > 0 && j > 0 && k > 0 && i < n - 1 && j < n - 1 && k < n - 1) ? 1.0 : 0.0; });
}

Outcome Surface(vtkImageData* image, const std::function<void(vtkDigitalSurfaceFilter*)>& set = {})
{
  vtkNew<vtkDigitalSurfaceFilter> f;
  if (set)
  {
    set(f);
  }
  f->SetInputData(image);
  return Run(f);
}

// Two touching boxes of labels 3 (5 x 9 x 9 voxels) and 7 (4 x 7 x 7).
vtkSmartPointer<vtkImageData> TwoLabels()
{
  return dgtest::MakeImage(12,
    12,
    12,
    [](int i, int j, int k)
    {
      if (i >= 1 && i <= 5 && j >= 1 && j <= 9 && k >= 1 && k <= 9)
        return 3.0;
      if (i >= 6 && i <= 9 && j >= 2 && j <= 8 && k >= 2 && k <= 8)
        return 7.0;
      return 0.0;
    });
}

Outcome EachLabel(vtkImageData* image, const char* labels)
{
  return Surface(image,
    [labels](vtkDigitalSurfaceFilter* f)
    {
      f->SetSelectionModeToEachLabel();
      f->SetLabels(labels);
    });
}

Outcome Island(vtkImageData* image, const std::function<void(vtkDigitalIslandFilter*)>& set = {})
{
  vtkNew<vtkDigitalIslandFilter> f;
  if (set)
  {
    set(f);
  }
  f->SetInputData(image);
  Outcome o = Run(f);
  o.ExpectedCells = image->GetNumberOfPoints();
  return o;
}

Outcome II(vtkImageData* source, double radius, vtkImageData* surfaceOf = nullptr)
{
  auto image = Block(12);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(surfaceOf ? surfaceOf : image.Get());
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  if (source)
  {
    ii->SetSourceData(source);
  }
  ii->SetRadius(radius);
  return Run(ii);
}

Outcome VCM(vtkImageData* source,
  double offsetRadius,
  double convolutionRadius,
  vtkImageData* surfaceOf = nullptr)
{
  auto image = Block(12);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(surfaceOf ? surfaceOf : image.Get());
  vtkNew<vtkVCMNormalEstimator> vcm;
  vcm->SetInputConnection(surface->GetOutputPort());
  if (source)
  {
    vcm->SetSourceData(source);
  }
  vcm->SetOffsetRadius(offsetRadius);
  vcm->SetConvolutionRadius(convolutionRadius);
  return Run(vcm);
}

// A digital surface of a small rotated cube with its trivial normals.
vtkSmartPointer<vtkPolyData> CubeSurface()
{
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(8.1, 7.9, 8.2), 4.5, 20, 30, 10);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(dgtest::Digitize(*cube, 17));
  surface->Update();
  vtkSmartPointer<vtkPolyData> out = surface->GetOutput();
  return out;
}

Outcome AT(vtkPolyData* input, const std::function<void(vtkAmbrosioTortorelliFilter*)>& set = {})
{
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetMaximumIterations(2);
  if (set)
  {
    set(at);
  }
  at->SetInputData(input);
  Outcome o = Run(at);
  o.Cells += at->GetOutput(1)->GetNumberOfCells(); // an error must empty both ports
  if (o.Errors == 0)
  {
    o.Cells = at->GetOutput(0)->GetNumberOfPolys();
  }
  o.ExpectedCells = input->GetNumberOfPolys();
  return o;
}

// vtkSharpFeaturesFilter on AT's output of the small cube (or on what
// `edit` makes of it).
Outcome Sharp(const std::function<void(vtkPolyData*)>& edit,
  const std::function<void(vtkSharpFeaturesFilter*)>& set = {})
{
  // II normals in front, as in the program: the sharp stage reads them for
  // its crease test and warns when no input normal field is there.
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(8.1, 7.9, 8.2), 4.5, 20, 30, 10);
  auto image = dgtest::Digitize(*cube, 17);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadius(3);
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetMaximumIterations(2);
  at->SetInputConnection(ii->GetOutputPort());
  at->Update();
  auto input = vtkSmartPointer<vtkPolyData>::New();
  input->DeepCopy(at->GetOutput(0));
  if (edit)
    edit(input);
  vtkNew<vtkSharpFeaturesFilter> f;
  if (set)
    set(f);
  f->SetInputData(input);
  Outcome o = Run(f);
  o.Cells += f->GetOutput(1)->GetNumberOfCells(); // an error must empty both ports
  if (o.Errors == 0)
    o.Cells = f->GetOutput(0)->GetNumberOfPolys();
  o.ExpectedCells = input->GetNumberOfPolys();
  return o;
}

vtkSmartPointer<vtkPolyData> CubeWithNormal(double value, vtkIdType cell)
{
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->DeepCopy(CubeSurface());
  pd->GetCellData()->GetNormals()->SetTuple3(cell, value, value, value);
  return pd;
}

// Two voxels sharing only an edge (that edge has four quads), plus one point
// that no polygon uses.
vtkSmartPointer<vtkPolyData> NonManifoldWithIsolatedPoint()
{
  auto image = dgtest::MakeImage(4,
    4,
    4,
    [](int i, int j, int k)
    { return ((i == 1 && j == 1 && k == 1) || (i == 2 && j == 2 && k == 1)) ? 1.0 : 0.0; });
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  surface->Update();
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->DeepCopy(surface->GetOutput());
  pd->GetPoints()->InsertNextPoint(40, 40, 40);
  return pd;
}

// A 3 x 3 grid of quads with the centre one reversed.
vtkSmartPointer<vtkPolyData> InconsistentWinding()
{
  auto mesh = dgtest::QuadGrid3x3(true, 0.1);
  vtkNew<vtkDoubleArray> g;
  g->SetNumberOfComponents(3);
  for (int c = 0; c < 9; ++c)
    g->InsertNextTuple3(0.1 * c, 0, 1);
  mesh->GetCellData()->SetNormals(g);
  return mesh;
}

// vtkPiecewiseSmoothMeshFilter on the sharp stage's output of the small cube
// (or on what `edit` makes of it).
Outcome Mesh(const std::function<void(vtkPolyData*)>& edit,
  const std::function<void(vtkPiecewiseSmoothMeshFilter*)>& set = {})
{
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(8.1, 7.9, 8.2), 4.5, 20, 30, 10);
  auto image = dgtest::Digitize(*cube, 17);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadius(3);
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetMaximumIterations(2);
  at->SetInputConnection(ii->GetOutputPort());
  vtkNew<vtkSharpFeaturesFilter> sharp;
  sharp->SetInputConnection(at->GetOutputPort());
  sharp->Update();
  auto input = vtkSmartPointer<vtkPolyData>::New();
  input->DeepCopy(sharp->GetOutput(0));
  if (edit)
    edit(input);
  vtkNew<vtkPiecewiseSmoothMeshFilter> f;
  if (set)
    set(f);
  f->SetInputData(input);
  Outcome o = Run(f);
  o.Cells += f->GetOutput(1)->GetNumberOfCells(); // an error must empty both ports
  if (o.Errors == 0)
    o.Cells = f->GetOutput(0)->GetNumberOfPolys();
  o.ExpectedCells = input->GetNumberOfPolys();
  return o;
}

const Row Rows[] = {
  // vtkDigitalSurfaceFilter
  { "EmptyImage",
    Expect::Error,
    "",
    []
    {
      vtkNew<vtkImageData> empty;
      return Surface(empty);
    } },
  { "OneVoxelImage",
    Expect::Error,
    "",
    [] { return Surface(dgtest::MakeImage(1, 1, 1, [](int, int, int) { return 1.0; })); } },
  { "FlatImage",
    Expect::Error,
    "",
    [] { return Surface(dgtest::MakeImage(8, 8, 1, [](int, int, int) { return 1.0; })); } },
  { "NoScalars",
    Expect::Error,
    "scalars",
    []
    {
      vtkNew<vtkImageData> image;
      image->SetDimensions(4, 4, 4);
      return Surface(image);
    } },
  { "ThreeComponentScalars",
    Expect::Error,
    "SelectedComponent",
    []
    {
      vtkNew<vtkImageData> image;
      image->SetDimensions(4, 4, 4);
      image->AllocateScalars(VTK_FLOAT, 3);
      image->GetPointData()->GetScalars()->Fill(1.0);
      return Surface(image);
    } },
  { "NaNScalars",
    Expect::Error,
    "NaN",
    []
    {
      return Surface(dgtest::MakeImage(
        5, 5, 5, [](int i, int, int) { return i == 2 ? std::nan("") : 1.0; }, VTK_FLOAT));
    } },
  { "AllInside",
    Expect::Warning,
    "border",
    []
    {
      Outcome o = Surface(dgtest::MakeImage(5, 5, 5, [](int, int, int) { return 1.0; }));
      o.ExpectedCells = 6 * 5 * 5;
      return o;
    } },
  { "SelectionMatchesNothing",
    Expect::Error,
    "",
    [] { return Surface(dgtest::MakeImage(5, 5, 5, [](int, int, int) { return 0.0; })); } },
  { "LabelNotPresent",
    Expect::Error,
    "",
    []
    {
      return Surface(dgtest::MakeImage(5, 5, 5, [](int i, int, int) { return i; }),
        [](vtkDigitalSurfaceFilter* f)
        {
          f->SetSelectionModeToLabel();
          f->SetLabel(17);
        });
    } },
  // Label maps, EachLabel mode and the split filter (issue 18)
  { "EachLabelEmptyList",
    Expect::Error,
    "no label given",
    [] { return EachLabel(TwoLabels(), ""); } },
  { "EachLabelAbsentLabels",
    Expect::Error,
    "holds 2 non-zero labels: 3, 7",
    [] { return EachLabel(TwoLabels(), "42,50-60"); } },
  { "EachLabelBadList", Expect::Error, "'3-x'", [] { return EachLabel(TwoLabels(), "3-x"); } },
  { "EachLabelNotLabelMap",
    Expect::Error,
    "not an integer",
    []
    {
      return EachLabel(dgtest::MakeImage(
                         6, 6, 6, [](int i, int, int) { return 0.5 * i; }, VTK_FLOAT),
        "all");
    } },
  { "EachLabelGood",
    Expect::Result,
    "",
    []
    {
      Outcome o = EachLabel(TwoLabels(), "all");
      // Each box's own closed surface: the shared faces twice.
      o.ExpectedCells = 2 * (5 * 9 + 5 * 9 + 9 * 9) + 2 * (4 * 7 + 4 * 7 + 7 * 7);
      return o;
    } },
  { "IIEachLabelNoLabelArray",
    Expect::Error,
    "'Label'",
    []
    {
      auto image = TwoLabels();
      vtkNew<vtkDigitalSurfaceFilter> surface;
      surface->SetInputData(image);
      vtkNew<vtkIINormalEstimator> ii;
      ii->SetInputConnection(surface->GetOutputPort());
      ii->SetSourceData(image);
      ii->SetSelectionModeToEachLabel();
      return Run(ii);
    } },
  { "SplitNoLabelArray",
    Expect::Error,
    "'Label'",
    []
    {
      vtkNew<vtkSplitByLabelFilter> split;
      split->SetInputData(CubeSurface());
      return Run(split);
    } },
  // vtkDigitalIslandFilter
  { "IslandEmptyImage",
    Expect::Error,
    "empty",
    []
    {
      vtkNew<vtkImageData> empty;
      return Island(empty);
    } },
  { "IslandNoScalars",
    Expect::Error,
    "scalars",
    []
    {
      vtkNew<vtkImageData> image;
      image->SetDimensions(4, 4, 4);
      return Island(image);
    } },
  { "IslandThreeComponentScalars",
    Expect::Error,
    "SelectedComponent",
    []
    {
      vtkNew<vtkImageData> image;
      image->SetDimensions(4, 4, 4);
      image->AllocateScalars(VTK_FLOAT, 3);
      image->GetPointData()->GetScalars()->Fill(1.0);
      return Island(image);
    } },
  { "IslandNaNScalars",
    Expect::Error,
    "NaN",
    []
    {
      return Island(dgtest::MakeImage(
        5, 5, 5, [](int i, int, int) { return i == 2 ? std::nan("") : 1.0; }, VTK_FLOAT));
    } },
  { "IslandMinimumSizeZero",
    Expect::Error,
    "MinimumSize",
    [] { return Island(Block(8), [](vtkDigitalIslandFilter* f) { f->SetMinimumSize(0); }); } },
  { "IslandMinimumSizeNegative",
    Expect::Error,
    "MinimumSize",
    [] { return Island(Block(8), [](vtkDigitalIslandFilter* f) { f->SetMinimumSize(-5); }); } },
  { "IslandEmptyRange",
    Expect::Error,
    "range",
    []
    {
      return Island(Block(8),
        [](vtkDigitalIslandFilter* f)
        {
          f->SetSelectionModeToRange();
          f->SetLowerThreshold(3);
          f->SetUpperThreshold(2);
        });
    } },
  { "IslandRemovesEverything",
    Expect::Warning,
    "MinimumSize",
    [] { return Island(Block(4), [](vtkDigitalIslandFilter* f) { f->SetMinimumSize(9); }); } },
  { "IslandSelectionMatchesNothing",
    Expect::Result,
    "",
    [] { return Island(dgtest::MakeImage(5, 5, 5, [](int, int, int) { return 0.0; })); } },
  { "IslandFlatImage",
    Expect::Result,
    "",
    [] { return Island(dgtest::MakeImage(8, 8, 1, [](int i, int, int) { return i > 2; })); } },
  { "IslandGood", Expect::Result, "", [] { return Island(Block(12)); } },
  // vtkIINormalEstimator
  { "IIWithoutImage", Expect::Error, "SetSource", [] { return II(nullptr, 3); } },
  { "IIImageDoesNotMatch",
    Expect::Error,
    "does not match",
    []
    {
      auto other = Block(14);
      return II(other, 3);
    } },
  { "IIRadiusZero",
    Expect::Error,
    "Radius",
    []
    {
      auto image = Block(12);
      return II(image, 0, image);
    } },
  { "IIRadiusNegative",
    Expect::Error,
    "Radius",
    []
    {
      auto image = Block(12);
      return II(image, -1.5, image);
    } },
  { "IIRadiusLargerThanVolume",
    Expect::Error,
    "larger than the image",
    []
    {
      auto image = Block(12);
      return II(image, 40, image);
    } },
  { "IIGood",
    Expect::Result,
    "",
    []
    {
      auto image = Block(12);
      Outcome o = II(image, 3, image);
      o.ExpectedCells = 6 * 10 * 10;
      return o;
    } },
  // vtkVCMNormalEstimator
  { "VCMWithoutImage", Expect::Error, "SetSource", [] { return VCM(nullptr, 5, 2); } },
  { "VCMImageDoesNotMatch", Expect::Error, "does not match", [] { return VCM(Block(14), 5, 2); } },
  { "VCMOffsetRadiusZero",
    Expect::Error,
    "positive",
    []
    {
      auto image = Block(12);
      return VCM(image, 0, 2, image);
    } },
  { "VCMConvolutionRadiusNegative",
    Expect::Error,
    "positive",
    []
    {
      auto image = Block(12);
      return VCM(image, 5, -1, image);
    } },
  { "VCMOffsetBelowConvolution",
    Expect::Error,
    "must not exceed OffsetRadius",
    []
    {
      auto image = Block(12);
      return VCM(image, 2, 3, image);
    } },
  { "VCMGood",
    Expect::Result,
    "",
    []
    {
      auto image = Block(12);
      Outcome o = VCM(image, 5, 2, image);
      o.ExpectedCells = 6 * 10 * 10;
      return o;
    } },
  // vtkAmbrosioTortorelliFilter
  { "ATNoPolygons",
    Expect::Error,
    "no polygons",
    []
    {
      vtkNew<vtkPolyData> pd;
      pd->SetPoints(CubeSurface()->GetPoints());
      return AT(pd);
    } },
  { "ATMissingArray",
    Expect::Error,
    "No field",
    []
    {
      return AT(CubeSurface(),
        [](vtkAmbrosioTortorelliFilter* a)
        { a->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "Nope"); });
    } },
  { "ATFieldWithNaN", Expect::Error, "NaN", [] { return AT(CubeWithNormal(std::nan(""), 5)); } },
  { "ATFieldWithZeroVector",
    Expect::Error,
    "zero vector",
    [] { return AT(CubeWithNormal(0.0, 7)); } },
  { "ATAlphaZero",
    Expect::Error,
    "Alpha",
    [] { return AT(CubeSurface(), [](vtkAmbrosioTortorelliFilter* a) { a->SetAlpha(0); }); } },
  { "ATAlphaNegative",
    Expect::Error,
    "Alpha",
    [] { return AT(CubeSurface(), [](vtkAmbrosioTortorelliFilter* a) { a->SetAlpha(-1); }); } },
  { "ATLambdaZero",
    Expect::Error,
    "Lambda",
    [] { return AT(CubeSurface(), [](vtkAmbrosioTortorelliFilter* a) { a->SetLambda(0); }); } },
  { "ATLambdaNegative",
    Expect::Error,
    "Lambda",
    [] { return AT(CubeSurface(), [](vtkAmbrosioTortorelliFilter* a) { a->SetLambda(-0.01); }); } },
  { "ATEpsilonEndAboveStart",
    Expect::Error,
    "EpsilonStart",
    []
    {
      return AT(CubeSurface(),
        [](vtkAmbrosioTortorelliFilter* a)
        {
          a->SetEpsilonStart(0.5);
          a->SetEpsilonEnd(1.0);
        });
    } },
  { "ATRatioOne",
    Expect::Error,
    "EpsilonRatio",
    []
    { return AT(CubeSurface(), [](vtkAmbrosioTortorelliFilter* a) { a->SetEpsilonRatio(1); }); } },
  { "ATRatioBelowOne",
    Expect::Error,
    "EpsilonRatio",
    [] {
      return AT(CubeSurface(), [](vtkAmbrosioTortorelliFilter* a) { a->SetEpsilonRatio(0.5); });
    } },
  { "ATEarlyToleranceFactorBelowOne",
    Expect::Error,
    "SolverToleranceEarlyFactor",
    [] {
      return AT(CubeSurface(),
        [](vtkAmbrosioTortorelliFilter* a) { a->SetSolverToleranceEarlyFactor(0.5); });
    } },
  { "ATZeroIterations",
    Expect::Error,
    "MaximumIterations",
    [] {
      return AT(CubeSurface(), [](vtkAmbrosioTortorelliFilter* a) { a->SetMaximumIterations(0); });
    } },
  { "ATNonManifoldEdgeAndIsolatedPoint",
    Expect::Result,
    "",
    [] { return AT(NonManifoldWithIsolatedPoint()); } },
  { "ATWorldMetricNonManifoldEdgeAndIsolatedPoint",
    Expect::Result,
    "",
    []
    {
      return AT(NonManifoldWithIsolatedPoint(),
        [](vtkAmbrosioTortorelliFilter* a) { a->SetMetricToWorld(); });
    } },
  { "ATWorldMetricFlattenedSurface",
    Expect::Error,
    "world metric",
    []
    {
      // Every point pressed into z = 0: the side faces have no area.
      auto pd = CubeSurface();
      pd->SetPoints(dgtest::FlattenedPoints(pd->GetPoints()));
      return AT(pd, [](vtkAmbrosioTortorelliFilter* a) { a->SetMetricToWorld(); });
    } },
  { "ATInconsistentWinding",
    Expect::Warning,
    "opposite winding",
    [] { return AT(InconsistentWinding()); } },
  // vtkSharpFeaturesFilter
  { "SharpNoPolygons",
    Expect::Error,
    "no polygons",
    [] { return Sharp([](vtkPolyData* pd) { pd->SetPolys(vtkNew<vtkCellArray>()); }); } },
  { "SharpMissingNormals",
    Expect::Error,
    "ATNormals",
    [] { return Sharp([](vtkPolyData* pd) { pd->GetCellData()->RemoveArray("ATNormals"); }); } },
  { "SharpMissingIndicator",
    Expect::Error,
    "ATFeatureIndicator",
    [] {
      return Sharp([](vtkPolyData* pd) { pd->GetPointData()->RemoveArray("ATFeatureIndicator"); });
    } },
  { "SharpNaNNormal",
    Expect::Error,
    "NaN",
    []
    {
      return Sharp([](vtkPolyData* pd)
        { pd->GetCellData()->GetArray("ATNormals")->SetComponent(2, 1, std::nan("")); });
    } },
  { "SharpNaNIndicator",
    Expect::Error,
    "NaN",
    []
    {
      return Sharp([](vtkPolyData* pd)
        { pd->GetPointData()->GetArray("ATFeatureIndicator")->SetComponent(4, 0, std::nan("")); });
    } },
  { "SharpThresholdOne",
    Expect::Error,
    "FeatureThreshold",
    [] { return Sharp({}, [](vtkSharpFeaturesFilter* f) { f->SetFeatureThreshold(1); }); } },
  { "SharpSearchDepthNegative",
    Expect::Error,
    "SearchDepth",
    [] { return Sharp({}, [](vtkSharpFeaturesFilter* f) { f->SetSearchDepth(-1); }); } },
  { "SharpReferenceWeightZero",
    Expect::Error,
    "ReferenceWeight",
    [] { return Sharp({}, [](vtkSharpFeaturesFilter* f) { f->SetReferenceWeight(0); }); } },
  { "SharpGood", Expect::Result, "", [] { return Sharp({}); } },
  // vtkPiecewiseSmoothMeshFilter
  { "MeshNoPolygons",
    Expect::Error,
    "no polygons",
    [] { return Mesh([](vtkPolyData* pd) { pd->SetPolys(vtkNew<vtkCellArray>()); }); } },
  { "MeshMissingNormals",
    Expect::Error,
    "SharpNormals",
    [] { return Mesh([](vtkPolyData* pd) { pd->GetCellData()->RemoveArray("SharpNormals"); }); } },
  { "MeshNonUnitNormals",
    Expect::Error,
    "unit vectors",
    []
    {
      return Mesh([](vtkPolyData* pd)
        { pd->GetCellData()->GetArray("SharpNormals")->SetComponent(5, 0, 3.0); });
    } },
  { "MeshNaNNormal",
    Expect::Error,
    "unit vectors",
    []
    {
      return Mesh([](vtkPolyData* pd)
        { pd->GetCellData()->GetArray("SharpNormals")->SetComponent(2, 1, std::nan("")); });
    } },
  { "MeshNotVoxelFaces",
    Expect::Error,
    "not a digital surface",
    []
    {
      // One corner moved off the grid: the quads are no longer voxel faces.
      return Mesh([](vtkPolyData* pd)
        {
          double p[3];
          pd->GetPoint(7, p);
          p[0] += 0.3;
          pd->GetPoints()->SetPoint(7, p);
        });
    } },
  { "MeshRegionsWrongShape",
    Expect::Error,
    "one component",
    []
    {
      return Mesh([](vtkPolyData* pd)
        {
          vtkNew<vtkDoubleArray> r;
          r->SetName("FeatureRegion");
          r->SetNumberOfComponents(2);
          r->SetNumberOfTuples(pd->GetNumberOfCells());
          r->Fill(0);
          pd->GetCellData()->AddArray(r);
        });
    } },
  { "MeshDataWeightZero",
    Expect::Error,
    "DataWeight",
    [] { return Mesh({}, [](vtkPiecewiseSmoothMeshFilter* f) { f->SetDataWeight(0); }); } },
  { "MeshCreaseWeightNegative",
    Expect::Error,
    "CreaseWeight",
    [] { return Mesh({}, [](vtkPiecewiseSmoothMeshFilter* f) { f->SetCreaseWeight(-1); }); } },
  { "MeshNoIterations",
    Expect::Error,
    "Iterations",
    [] { return Mesh({}, [](vtkPiecewiseSmoothMeshFilter* f) { f->SetNumberOfIterations(0); }); } },
  { "MeshSolverToleranceOne",
    Expect::Error,
    "SolverTolerance",
    [] { return Mesh({}, [](vtkPiecewiseSmoothMeshFilter* f) { f->SetSolverTolerance(1); }); } },
  { "MeshGood", Expect::Result, "", [] { return Mesh({}); } },
};

DG_BAD_INPUT_MATRIX(Rows);
} // namespace
