// Randomized Hough Transform normals (docs/method.md section 10): the candidate
// points against a brute force, accuracy on planes, sharper edges than II on
// a rotated cube, independence of threads and pieces, bad input, AT on the
// result.
#include "dgGroundTruth.h"
#include "dgRHT.h"
#include "dgTestShapes.h"
#include "dgTestTemp.h"
#include "dgVolFormat.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"
#include "vtkRHTNormalEstimator.h"

#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>
#include <vector>

namespace
{
using V3 = Eigen::Vector3d;

double Median(std::vector<double> v)
{
  if (v.empty())
  {
    return 0;
  }
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

vtkSmartPointer<vtkPolyData> RunRHT(vtkImageData* image, double r = 6, int trials = 648,
  std::uint64_t seed = 0)
{
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkRHTNormalEstimator> rht;
  rht->SetInputConnection(surface->GetOutputPort());
  rht->SetSourceData(image);
  rht->SetRadius(r);
  rht->SetNumberOfTrials(trials);
  rht->SetSeed(seed);
  rht->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(rht->GetOutput());
  return out;
}

vtkSmartPointer<vtkPolyData> RunII(vtkImageData* image, double r)
{
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkIINormalEstimator> ii;
  ii->SetInputConnection(surface->GetOutputPort());
  ii->SetSourceData(image);
  ii->SetRadius(r);
  ii->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(ii->GetOutput());
  return out;
}

V3 NormalOf(vtkPolyData* p, const char* name, vtkIdType c)
{
  vtkDataArray* a = p->GetCellData()->GetArray(name);
  return V3(a->GetComponent(c, 0), a->GetComponent(c, 1), a->GetComponent(c, 2));
}
} // namespace

//------------------------------------------------------------------------------
TEST(RHTCore, NeighboursMatchBruteForceIncludingImageBorders)
{
  std::mt19937 rng(3);
  for (int trial = 0; trial < 4; ++trial)
  {
    const int dims[3] = { 9 + trial, 11, 8 };
    std::vector<std::uint8_t> m(dims[0] * dims[1] * dims[2]);
    std::bernoulli_distribution inside(0.55);
    for (auto& v : m)
    {
      v = inside(rng);
    }
    dg::SurfelRows rows;
    rows.Build(m.data(), dims, dims[0], 0);
    std::vector<std::int32_t> fast, slow;
    std::int64_t count = 0;
    for (double r : { 1.0, 2.5, 3.0, 4.2 })
      for (int k = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
          for (int i = 0; i < dims[0]; ++i)
          {
            if (!m[(k * dims[1] + j) * dims[0] + i])
            {
              continue;
            }
            for (int d = 0; d < 6; d += 3)
            {
              rows.Neighbours(i, j, k, d, r, fast);
              dg::BruteForceNeighbours(m.data(), dims, r, i, j, k, d, slow);
              ASSERT_EQ(fast, slow) << i << " " << j << " " << k << " " << d << " r " << r;
              count += static_cast<std::int64_t>(fast.size() / 3);
            }
          }
    EXPECT_GT(count, 1000);
  }
}

TEST(RHTCore, AccumulatorBinsAreNearlyEqualAreaAndCoverTheHemisphere)
{
  dg::HoughAccumulator acc;
  acc.Build(10);
  EXPECT_NEAR(acc.NumberOfBins(), 200, 20);
  // Uniform directions on the hemisphere: every bin hit, counts within a
  // factor 2 of the mean.
  std::mt19937_64 rng(1);
  std::normal_distribution<double> g;
  std::vector<int> counts(acc.NumberOfBins(), 0);
  const int samples = 400000;
  for (int s = 0; s < samples; ++s)
  {
    V3 v(g(rng), g(rng), g(rng));
    v.normalize();
    if (v.z() < 0)
    {
      v = -v;
    }
    const int b = acc.Bin(v.x(), v.y(), v.z());
    ASSERT_GE(b, 0);
    ASSERT_LT(b, acc.NumberOfBins());
    ++counts[b];
  }
  const double mean = double(samples) / acc.NumberOfBins();
  for (int c : counts)
  {
    EXPECT_GT(c, 0.5 * mean);
    EXPECT_LT(c, 2.0 * mean);
  }
  // The equator and the pole.
  EXPECT_GE(acc.Bin(1, 0, 0), 0);
  EXPECT_LT(acc.Bin(0, 0, 1), 3); // the polar band's few bins
}

//------------------------------------------------------------------------------
TEST(RHTEstimator, PlanesWithinOneDegree)
{
  const int n = 32;
  const V3 c(15.7, 16.2, 15.4);
  for (V3 normal : { V3(0, 0, 1), V3(1, 1, 0), V3(1, 1, 1), V3(1, 2, 3), V3(0.3, -0.5, 0.8),
         V3(-2, 1, 0.5) })
  {
    normal.normalize();
    auto image = dgtest::Digitize(n, [&](double x, double y, double z) {
      return normal.dot(V3(x, y, z) - c) <= 0;
    });
    auto out = RunRHT(image);
    auto centres = dgtest::SurfelCenters(out);
    std::vector<double> errors;
    for (vtkIdType s = 0; s < out->GetNumberOfCells(); ++s)
    {
      const V3& p = centres[s];
      if (std::abs(normal.dot(p - c)) > 1.0 || p.minCoeff() < 8.5 || p.maxCoeff() > n - 9.5)
      {
        continue; // not on the plane, or near the image border
      }
      errors.push_back(dgtest::AngleDegrees(NormalOf(out, "RHTNormals", s), normal));
    }
    ASSERT_GT(errors.size(), 50u);
    const double med = Median(errors);
    std::printf("plane (%.3f, %.3f, %.3f): %zu surfels, median error %.3f deg, max %.2f\n",
      normal.x(), normal.y(), normal.z(), errors.size(), med,
      *std::max_element(errors.begin(), errors.end()));
    EXPECT_LT(med, 1.0) << normal.transpose();
  }
}

TEST(RHTEstimator, SharperThanIIOnRotatedCubeEdges)
{
  auto shape = dgtest::MakeRotatedCube(V3(31.6, 32.3, 31.8), 19, 20, 30, 40);
  auto image = dgtest::Digitize(*shape, 64);
  auto rht = RunRHT(image);
  auto ii = RunII(image, 6);
  auto centres = dgtest::SurfelCenters(rht);
  std::vector<double> eR, eI, fR, fI;
  for (vtkIdType s = 0; s < rht->GetNumberOfCells(); ++s)
  {
    const V3& p = centres[s];
    const V3 truth = shape->Normal(p);
    const double dist = shape->DistanceToSharpEdge(p, 8.0);
    const double a = dgtest::AngleDegrees(NormalOf(rht, "RHTNormals", s), truth);
    const double b = dgtest::AngleDegrees(NormalOf(ii, "IINormals", s), truth);
    if (dist <= 2.0)
    {
      eR.push_back(a);
      eI.push_back(b);
    }
    else if (dist > 7.0)
    {
      fR.push_back(a);
      fI.push_back(b);
    }
  }
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v)
      s += x;
    return v.empty() ? 0.0 : s / v.size();
  };
  std::printf("rotated cube 64^3, within 2 voxels of the edges (%zu surfels): RHT mean %.2f median "
              "%.2f deg, II r=6 mean %.2f median %.2f; farther than 7: RHT %.2f / %.2f, II %.2f / "
              "%.2f\n",
    eR.size(), mean(eR), Median(eR), mean(eI), Median(eI), mean(fR), Median(fR), mean(fI),
    Median(fI));
  ASSERT_GT(eR.size(), 1000u);
  EXPECT_LT(Median(eR), Median(eI));
  EXPECT_LT(mean(eR), mean(eI));
  EXPECT_LT(Median(fR), 2.0);
}

TEST(RHTEstimator, SameResultWhateverTheThreadCount)
{
  auto shape = dgtest::MakeRotatedCube(V3(15.6, 16.3, 15.8), 9, 20, 30, 40);
  auto image = dgtest::Digitize(*shape, 32);
  const std::string backend = vtkSMPTools::GetBackend();
  vtkSMPTools::SetBackend("Sequential");
  auto a = RunRHT(image, 6, 200, 7);
  vtkSMPTools::SetBackend("STDThread");
  vtkSMPTools::Initialize(1);
  auto b = RunRHT(image, 6, 200, 7);
  vtkSMPTools::Initialize(2);
  auto c = RunRHT(image, 6, 200, 7);
  auto d = RunRHT(image, 6, 200, 8);
  vtkSMPTools::SetBackend(backend.c_str());
  vtkDataArray* x = a->GetCellData()->GetArray("RHTNormals");
  ASSERT_TRUE(x);
  ASSERT_EQ(x, a->GetCellData()->GetNormals());
  bool seedMatters = false;
  for (vtkPolyData* other : { b.Get(), c.Get() })
  {
    vtkDataArray* y = other->GetCellData()->GetArray("RHTNormals");
    ASSERT_EQ(x->GetNumberOfValues(), y->GetNumberOfValues());
    for (vtkIdType v = 0; v < x->GetNumberOfValues(); ++v)
    {
      ASSERT_EQ(x->GetVariantValue(v).ToDouble(), y->GetVariantValue(v).ToDouble());
    }
  }
  vtkDataArray* z = d->GetCellData()->GetArray("RHTNormals");
  for (vtkIdType v = 0; v < x->GetNumberOfValues(); ++v)
  {
    seedMatters |= x->GetVariantValue(v).ToDouble() != z->GetVariantValue(v).ToDouble();
  }
  EXPECT_TRUE(seedMatters);
}

TEST(RHTEstimator, PiecesEqualTheWholeRun)
{
  // A rotated cube and a ball across the piece boundaries, read from a .vol
  // file (the reader produces sub-extents): every piece, with and without
  // ghost levels, gives bitwise the whole run's normals on its surfels.
  auto cube = dgtest::MakeRotatedCube(V3(13.6, 14.3, 15.8), 8, 20, 30, 40);
  const int n = 30;
  std::vector<std::uint8_t> m(n * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const V3 p(i, j, k);
        m[(k * n + j) * n + i] = cube->Inside(p) || (p - V3(21.3, 20.6, 19.2)).norm() < 6.5;
      }
  const int dims[3] = { n, n, n };
  const std::string path = dgtest::TempPath("rht_pieces.vol");
  std::string error;
  ASSERT_TRUE(dg::WriteVolFile(path, dims, m.data(), 2, error)) << error;

  auto run = [&](int p, int pieces, int ghosts, std::map<vtkIdType, V3>& out, int& boxVoxels) {
    vtkNew<vtkDGtalVolReader> reader;
    reader->SetFileName(path.c_str());
    vtkNew<vtkDigitalSurfaceFilter> surface;
    surface->SetInputConnection(reader->GetOutputPort());
    surface->GenerateGlobalIdsOn();
    vtkNew<vtkRHTNormalEstimator> rht;
    rht->SetInputConnection(surface->GetOutputPort());
    rht->SetSourceConnection(reader->GetOutputPort());
    rht->SetRadius(4.5);
    rht->SetNumberOfTrials(100);
    ASSERT_TRUE(rht->UpdatePiece(p, pieces, ghosts));
    vtkPolyData* o = rht->GetOutput();
    auto* ids = vtkIdTypeArray::SafeDownCast(o->GetCellData()->GetArray("GlobalIds"));
    ASSERT_TRUE(ids);
    for (vtkIdType c = 0; c < o->GetNumberOfCells(); ++c)
    {
      out[ids->GetValue(c)] = NormalOf(o, "RHTNormals", c);
    }
    boxVoxels = static_cast<int>(reader->GetOutput()->GetNumberOfPoints());
  };
  std::map<vtkIdType, V3> whole;
  int wholeVoxels = 0;
  run(0, 1, 0, whole, wholeVoxels);
  ASSERT_GT(whole.size(), 1000u);
  for (int pieces : { 2, 3 })
    for (int ghosts : { 0, 1 })
    {
      std::size_t covered = 0;
      std::map<vtkIdType, V3> all;
      for (int p = 0; p < pieces; ++p)
      {
        SCOPED_TRACE(testing::Message() << "piece " << p << " of " << pieces << ", ghosts " << ghosts);
        std::map<vtkIdType, V3> piece;
        int boxVoxels = 0;
        run(p, pieces, ghosts, piece, boxVoxels);
        EXPECT_LT(boxVoxels, wholeVoxels) << "the piece read the whole image";
        for (const auto& kv : piece)
        {
          auto it = whole.find(kv.first);
          ASSERT_NE(it, whole.end());
          ASSERT_EQ(it->second.x(), kv.second.x());
          ASSERT_EQ(it->second.y(), kv.second.y());
          ASSERT_EQ(it->second.z(), kv.second.z());
          all[kv.first] = kv.second;
        }
        covered += piece.size();
      }
      EXPECT_EQ(all.size(), whole.size());
      if (ghosts == 0)
      {
        EXPECT_EQ(covered, whole.size());
      }
    }
}

TEST(RHTEstimator, BadInputGivesAnError)
{
  auto image = dgtest::Ball(20, 6);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkRHTNormalEstimator> rht;
  rht->SetInputConnection(surface->GetOutputPort());
  rht->SetNumberOfTrials(50);
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(rht);
  obs->Observe(rht->GetExecutive());
  auto expectError = [&](const char* what, const char* word) {
    obs->Clear();
    rht->Modified();
    rht->Update();
    EXPECT_GE(obs->Errors, 1) << what;
    EXPECT_NE(obs->Messages.find(word), std::string::npos) << what << ": " << obs->Messages;
    EXPECT_EQ(rht->GetOutput()->GetNumberOfCells(), 0) << what;
  };
  expectError("missing image", "SetSource");
  rht->SetSourceData(image);
  rht->SetRadius(0);
  expectError("radius 0", "Radius");
  rht->SetRadius(-1);
  expectError("negative radius", "Radius");
  rht->SetRadius(3);
  rht->SetNumberOfTrials(0);
  expectError("no trials", "NumberOfTrials");
  rht->SetNumberOfTrials(50);
  rht->SetNumberOfAccumulators(0);
  expectError("no accumulator", "NumberOfAccumulators");
  rht->SetNumberOfAccumulators(5);
  rht->SetAccumulatorResolution(0);
  expectError("resolution 0", "AccumulatorResolution");
  rht->SetAccumulatorResolution(10);
  auto other = dgtest::Ball(22, 6);
  rht->SetSourceData(other);
  expectError("image of another size", "does not match");
  rht->SetSourceData(image);
  rht->SetSelectionModeToLabel();
  rht->SetLabel(7);
  expectError("other selection", "same selection");
  rht->SetSelectionModeToNonZero();

  obs->Clear();
  rht->Update();
  EXPECT_EQ(obs->Errors, 0) << obs->Messages;
  EXPECT_EQ(rht->GetOutput()->GetNumberOfCells(), surface->GetOutput()->GetNumberOfCells());
  EXPECT_EQ(rht->GetNumberOfFallbacks(), 0);

  vtkNew<vtkPolyData> plain;
  rht->SetInputData(plain);
  expectError("plain polydata", "not a digital surface");
}

TEST(RHTEstimator, ProgressAbortAndPrintSelf)
{
  auto image = dgtest::Ball(24, 8);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkRHTNormalEstimator> rht;
  rht->SetInputConnection(surface->GetOutputPort());
  rht->SetSourceData(image);
  rht->SetNumberOfTrials(50);
  std::vector<double> progress;
  vtkNew<vtkCallbackCommand> cb;
  struct Ctx
  {
    std::vector<double>* P;
    bool AbortNow;
  } ctx{ &progress, true };
  cb->SetClientData(&ctx);
  cb->SetCallback([](vtkObject* caller, unsigned long, void* cd, void* data) {
    auto* c = static_cast<Ctx*>(cd);
    const double p = *static_cast<double*>(data);
    c->P->push_back(p);
    if (c->AbortNow && p > 0.3)
    {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
    }
  });
  rht->AddObserver(vtkCommand::ProgressEvent, cb);
  rht->Update();
  EXPECT_EQ(rht->GetOutput()->GetNumberOfCells(), 0);
  ctx.AbortNow = false;
  progress.clear();
  rht->SetAbortExecute(0);
  rht->Update(); // out of date after the abort, without Modified()
  EXPECT_GT(rht->GetOutput()->GetNumberOfCells(), 0);
  ASSERT_GT(progress.size(), 3u);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
  std::ostringstream os;
  rht->Print(os);
  for (const char* word : { "Radius: 6", "NumberOfTrials: 50", "NumberOfAccumulators: 5",
         "AccumulatorResolution: 10", "Seed: 0" })
  {
    EXPECT_NE(os.str().find(word), std::string::npos) << word;
  }
}

TEST(RHTEstimator, AmbrosioTortorelliOnRHTNormals)
{
  auto shape = dgtest::MakeRotatedCube(V3(15.6, 16.3, 15.8), 10, 20, 30, 40);
  auto image = dgtest::Digitize(*shape, 32);
  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->SetInputData(image);
  vtkNew<vtkRHTNormalEstimator> rht;
  rht->SetInputConnection(surface->GetOutputPort());
  rht->SetSourceData(image);
  rht->SetNumberOfTrials(200);
  vtkNew<vtkAmbrosioTortorelliFilter> at;
  at->SetInputConnection(rht->GetOutputPort());
  at->Update();
  vtkPolyData* out = at->GetOutput();
  ASSERT_EQ(out->GetNumberOfCells(), surface->GetOutput()->GetNumberOfCells());
  vtkDataArray* u = out->GetCellData()->GetArray("ATNormals");
  ASSERT_TRUE(u);
  EXPECT_EQ(u, out->GetCellData()->GetNormals());
  auto centres = dgtest::SurfelCenters(out);
  std::vector<double> away;
  for (vtkIdType s = 0; s < out->GetNumberOfCells(); ++s)
  {
    if (shape->DistanceToSharpEdge(centres[s], 8.0) > 3)
    {
      away.push_back(dgtest::AngleDegrees(NormalOf(out, "ATNormals", s), shape->Normal(centres[s])));
    }
  }
  EXPECT_LT(Median(away), 3.0);
  EXPECT_GT(at->GetOutput(1)->GetNumberOfLines(), 0);
}
