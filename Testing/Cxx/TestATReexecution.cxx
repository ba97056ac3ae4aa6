// vtkAmbrosioTortorelliFilter in a pipeline a ParaView user drives: which
// changes solve again (counted), how outputs are named for normal and other
// fields, invariance to a field's unit, and the warnings for surfaces whose
// polygons do not share their points.
#include "dgGroundTruth.h"
#include "dgTestShapes.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCellData.h>
#include <vtkCleanPolyData.h>
#include <vtkCubeSource.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
using V3 = Eigen::Vector3d;

using dgtest::EdgePairs;

double MaxDifference(vtkDataArray* a, vtkDataArray* b)
{
  double worst = 0;
  for (vtkIdType t = 0; t < a->GetNumberOfTuples(); ++t)
  {
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
    {
      worst = std::max(worst, std::abs(a->GetComponent(t, c) - b->GetComponent(t, c)));
    }
  }
  return worst;
}
} // namespace

TEST(ATReexecution, OnlySolveParametersAndInputSolveAgain)
{
  auto cube = dgtest::MakeRotatedCube(V3(12.1, 11.9, 12.2), 7, 20, 30, 10);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(dgtest::Digitize(*cube, 25));
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(surface->GetInput());
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetInputConnection(ii->GetOutputPort());
  at->Update();
  ASSERT_EQ(at->GetNumberOfSolves(), 1);
  const auto edges05 = EdgePairs(at->GetOutput(1));
  ASSERT_GT(edges05.size(), 10u);

  // Output parameters: the outputs change, the solve is reused.
  at->SetFeatureThreshold(0.2);
  at->Update();
  EXPECT_EQ(at->GetNumberOfSolves(), 1);
  const auto edges02 = EdgePairs(at->GetOutput(1));
  EXPECT_LT(edges02.size(), edges05.size());
  at->SetNormalizeVectorField(false);
  at->Update();
  EXPECT_EQ(at->GetNumberOfSolves(), 1);
  vtkDataArray* raw = at->GetOutput()->GetCellData()->GetArray("ATNormals");
  ASSERT_NE(raw, nullptr);
  double shortest = 1;
  for (vtkIdType c = 0; c < raw->GetNumberOfTuples(); ++c)
  {
    const double* n = raw->GetTuple3(c);
    shortest = std::min(shortest, std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
  }
  EXPECT_LT(shortest, 0.99) << "unnormalised u is shorter than 1 across the edges";
  at->Update(); // nothing changed: not even re-executed
  EXPECT_EQ(at->GetNumberOfSolves(), 1);

  // The reused solve gives what a fresh filter gives.
  vtkNew<vtkAmbrosioTortorelliFilter> fresh;
  fresh->SetInputConnection(ii->GetOutputPort());
  fresh->SetFeatureThreshold(0.2);
  fresh->SetNormalizeVectorField(false);
  fresh->Update();
  EXPECT_EQ(EdgePairs(fresh->GetOutput(1)), edges02);
  EXPECT_EQ(MaxDifference(fresh->GetOutput()->GetCellData()->GetArray("ATNormals"),
              at->GetOutput()->GetCellData()->GetArray("ATNormals")),
    0.0);

  // A solve parameter, then the input: solve again.
  at->SetAlpha(0.2);
  at->Update();
  EXPECT_EQ(at->GetNumberOfSolves(), 2);
  ii->SetRadius(4);
  at->Update();
  EXPECT_EQ(at->GetNumberOfSolves(), 3);
  // The early levels' CG tolerance is a solve parameter too. The last level
  // still solves to SolverTolerance: v stays within the accuracy budget
  // (1e-3) of the run at 1, and it is not the same run.
  vtkNew<vtkDoubleArray> v1;
  v1->DeepCopy(at->GetOutput()->GetPointData()->GetArray("ATFeatureIndicator"));
  at->SetSolverToleranceEarlyFactor(6);
  at->Update();
  EXPECT_EQ(at->GetNumberOfSolves(), 4);
  vtkDataArray* v6 = at->GetOutput()->GetPointData()->GetArray("ATFeatureIndicator");
  ASSERT_NE(v6, nullptr);
  const double dv = MaxDifference(v1, v6);
  EXPECT_LT(dv, 1e-3);
  EXPECT_GT(dv, 0.0) << "the factor reached the solver";
  at->SetLinearSolver(vtkAmbrosioTortorelliFilter::SIMPLICIAL_LDLT);
  at->Update();
  EXPECT_EQ(at->GetNumberOfSolves(), 5);
  at->SetFeatureThreshold(0.5);
  at->Update();
  EXPECT_EQ(at->GetNumberOfSolves(), 5);
}

TEST(ATReexecution, OutputNamesFollowTheField)
{
  auto cube = dgtest::MakeRotatedCube(V3(10.1, 9.9, 10.2), 5.5, 20, 30, 10);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(dgtest::Digitize(*cube, 21));
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(surface->GetInput());
  ii->Update();
  vtkNew<vtkPolyData> mesh;
  mesh->ShallowCopy(ii->GetOutput());
  vtkDataArray* n = mesh->GetCellData()->GetNormals();
  ASSERT_NE(n, nullptr);
  // A velocity: twice the normal plus a constant drift (not unit).
  vtkNew<vtkDoubleArray> velocity;
  velocity->SetName("Velocity");
  velocity->SetNumberOfComponents(3);
  // A unit field that is not the active normals.
  vtkNew<vtkDoubleArray> unit;
  unit->SetName("MyNormals");
  unit->SetNumberOfComponents(3);
  for (vtkIdType c = 0; c < n->GetNumberOfTuples(); ++c)
  {
    const double* t = n->GetTuple3(c);
    velocity->InsertNextTuple3(2 * t[0] + 0.5, 2 * t[1], 2 * t[2]);
    unit->InsertNextTuple3(t[0], t[1], t[2]);
  }
  mesh->GetCellData()->AddArray(velocity);
  mesh->GetCellData()->AddArray(unit);

  vtkNew<vtkAmbrosioTortorelliFilter> at;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(at);
  at->SetInputData(mesh);
  at->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "Velocity");
  at->Update();
  EXPECT_EQ(obs->Errors + obs->Warnings, 0) << obs->Messages;
  vtkPolyData* out = at->GetOutput();
  vtkDataArray* u = out->GetCellData()->GetArray("Velocity_AT");
  ASSERT_NE(u, nullptr);
  EXPECT_EQ(out->GetCellData()->GetArray("ATNormals"), nullptr);
  ASSERT_NE(out->GetCellData()->GetNormals(), nullptr);
  EXPECT_STREQ(out->GetCellData()->GetNormals()->GetName(), "IINormals"); // left active
  // Not normalised: the velocity keeps its magnitude (about 2) on the faces.
  int longVectors = 0;
  for (vtkIdType c = 0; c < u->GetNumberOfTuples(); ++c)
  {
    const double* t = u->GetTuple3(c);
    longVectors += std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) > 1.5;
  }
  EXPECT_GT(longVectors, 0.9 * u->GetNumberOfTuples());
  // Scaled by half its largest component range: the x component spans
  // about [-1.5, 2.5], the others [-2, 2].
  EXPECT_GT(at->GetFieldScale(), 1.8);
  EXPECT_LT(at->GetFieldScale(), 2.2);
  // The regularised velocity is 2 n + drift with n the regularised normal:
  // the same features as AT on the normals themselves, up to a few edges.
  const auto velocityEdges = EdgePairs(at->GetOutput(1));

  at->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "MyNormals");
  at->Update();
  out = at->GetOutput();
  ASSERT_NE(out->GetCellData()->GetArray("ATNormals"), nullptr) << "a unit field is a normal field";
  EXPECT_STREQ(out->GetCellData()->GetNormals()->GetName(), "ATNormals");
  EXPECT_EQ(out->GetCellData()->GetArray("MyNormals_AT"), nullptr);
  EXPECT_EQ(at->GetFieldScale(), 1.0);
  const auto normalEdges = EdgePairs(at->GetOutput(1));
  ASSERT_GT(normalEdges.size(), 10u);
  std::vector<std::pair<vtkIdType, vtkIdType>> common;
  std::set_intersection(velocityEdges.begin(), velocityEdges.end(), normalEdges.begin(),
    normalEdges.end(), std::back_inserter(common));
  EXPECT_GT(common.size(), 0.8 * normalEdges.size());
}

TEST(ATReexecution, ScalarFieldsGiveTheSameFeaturesWhateverTheirUnit)
{
  auto base = dgtest::FlatSquare(40, 20, 20.0, false);
  vtkDataArray* step = base->GetCellData()->GetArray("Step");
  std::vector<std::pair<vtkIdType, vtkIdType>> reference;
  for (double unit : { 1.0, 10.0, 100.0, 0.01 })
  {
    vtkNew<vtkPolyData> pd;
    pd->ShallowCopy(base);
    vtkNew<vtkDoubleArray> f;
    f->SetName("Height");
    for (vtkIdType c = 0; c < step->GetNumberOfTuples(); ++c)
    {
      f->InsertNextValue(unit * (step->GetTuple1(c) + 0.05 * std::sin(12.9898 * c)));
    }
    pd->GetCellData()->AddArray(f);
    vtkNew<vtkAmbrosioTortorelliFilter> at;
    vtkNew<dgtest::ErrorObserver> obs;
    obs->Observe(at);
    at->SetInputData(pd);
    at->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "Height");
    at->Update();
    EXPECT_EQ(obs->Errors + obs->Warnings, 0) << obs->Messages;
    const auto edges = EdgePairs(at->GetOutput(1));
    if (unit == 1.0)
    {
      reference = edges;
      ASSERT_GE(reference.size(), 20u); // the jump, along its 20 units
    }
    else
    {
      EXPECT_EQ(edges, reference) << "unit " << unit;
    }
    vtkDataArray* u = at->GetOutput()->GetCellData()->GetArray("Height_AT");
    ASSERT_NE(u, nullptr);
    EXPECT_NEAR(u->GetRange()[1], unit, 0.1 * unit) << "u in the field's own unit";

    // Unscaled, the same field is over- or under-segmented, and says so.
    if (unit == 100.0 || unit == 0.01)
    {
      at->SetFieldScaling(vtkAmbrosioTortorelliFilter::FIELD_SCALING_NONE);
      obs->Clear();
      at->Update();
      EXPECT_EQ(obs->Warnings, 1) << obs->Messages;
      EXPECT_NE(obs->Messages.find(unit > 1 ? "nearly every edge" : "almost no features"),
        std::string::npos)
        << obs->Messages;
      const auto unscaled = EdgePairs(at->GetOutput(1));
      if (unit > 1)
      {
        EXPECT_GT(unscaled.size(), 3 * reference.size());
      }
      else
      {
        EXPECT_LT(unscaled.size(), reference.size() / 2);
      }
    }
  }
}

TEST(ATReexecution, WarnsWhenPolygonsDoNotSharePoints)
{
  // A box's digital surface with its points split along the sharp edges by
  // vtkPolyDataNormals (Splitting on, its default): AT cannot see those
  // jumps, and says to merge the points.
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(dgtest::MakeImage(14, 14, 14, [](int i, int j, int k) {
    return (i >= 3 && i <= 10 && j >= 3 && j <= 10 && k >= 3 && k <= 10) ? 1.0 : 0.0;
  }));
  vtkNew<vtkPolyDataNormals> split;
  split->SetInputConnection(surface->GetOutputPort());
  split->ComputeCellNormalsOn();
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(at);
  at->SetInputConnection(split->GetOutputPort());
  at->Update();
  EXPECT_EQ(obs->Errors, 0) << obs->Messages;
  EXPECT_EQ(obs->Warnings, 1) << obs->Messages;
  EXPECT_NE(obs->Messages.find("another polygon's edge"), std::string::npos) << obs->Messages;
  EXPECT_NE(obs->Messages.find("vtkCleanPolyData"), std::string::npos) << obs->Messages;
  EXPECT_EQ(at->GetOutput(1)->GetNumberOfCells(), 0) << "no feature across split edges";

  // Splitting off: the points are shared, no warning, the 12 edges found.
  split->SplittingOff();
  obs->Clear();
  at->Update();
  EXPECT_EQ(obs->Errors + obs->Warnings, 0) << obs->Messages;
  EXPECT_GE(at->GetOutput(1)->GetNumberOfCells(), 12 * 8);

  // vtkCubeSource's six faces have their own points: no shared edge at all.
  vtkNew<vtkCubeSource> cubeSource;
  vtkNew<vtkPolyDataNormals> cellNormals;
  cellNormals->SetInputConnection(cubeSource->GetOutputPort());
  cellNormals->ComputeCellNormalsOn();
  cellNormals->SplittingOff();
  at->SetInputConnection(cellNormals->GetOutputPort());
  obs->Clear();
  at->Update();
  EXPECT_EQ(obs->Warnings, 1) << obs->Messages;
  EXPECT_NE(obs->Messages.find("No two polygons share an edge"), std::string::npos)
    << obs->Messages;
  // ... and once cleaned, they do.
  vtkNew<vtkCleanPolyData> clean;
  clean->SetInputConnection(cubeSource->GetOutputPort());
  cellNormals->SetInputConnection(clean->GetOutputPort());
  obs->Clear();
  at->Update();
  EXPECT_EQ(obs->Warnings, 0) << obs->Messages;
}
