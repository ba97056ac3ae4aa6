// Abort as a ParaView user meets it: aborting any stage of reader -> noise
// -> islands -> digital surface -> II -> AT from a progress observer stops it with
// empty outputs and no error anywhere in the pipeline (not the executive's
// "returned failure"), leaves no stale output downstream, and the next
// Update recomputes to the result of a run that was never aborted. Also how
// finely each filter reports progress.
#include "dgGroundTruth.h"
#include "dgTestShapes.h"
#include "dgTestTemp.h"
#include "dgVolFormat.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalIslandFilter.h"
#include "vtkDigitalNoiseFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>

#include <set>

namespace
{
// Aborts its algorithm at the first progress report inside RequestData
// (value strictly between 0 and 1) while armed; counts executions and
// distinct progress values.
class Aborter : public vtkCommand
{
public:
  static Aborter* New() { return new Aborter; }
  void Execute(vtkObject* caller, unsigned long event, void* data) override
  {
    if (event == vtkCommand::StartEvent)
    {
      ++this->Executions;
      return;
    }
    const double p = *static_cast<double*>(data);
    this->Values.insert(p);
    if (this->Armed && p > 0 && p < 1)
    {
      vtkAlgorithm::SafeDownCast(caller)->SetAbortExecute(1);
      ++this->Aborts;
    }
  }
  bool Armed = false;
  int Executions = 0, Aborts = 0;
  std::set<double> Values;
};

struct Pipeline
{
  vtkNew<vtkDGtalVolReader> Reader;
  vtkNew<vtkDigitalNoiseFilter> Noise;
  vtkNew<vtkDigitalIslandFilter> Islands;
  vtkNew<vtkDigitalSurfaceFilter> Surface;
  vtkNew<vtkIINormalEstimator> II;
  vtkNew<vtkAmbrosioTortorelliFilter> AT;
  vtkNew<dgtest::ErrorObserver> Messages;

  explicit Pipeline(const std::string& vol)
  {
    this->Reader->SetFileName(vol.c_str());
    this->Noise->SetInputConnection(this->Reader->GetOutputPort());
    this->Noise->SetNoiseLevel(0.2);
    this->Islands->SetInputConnection(this->Noise->GetOutputPort());
    this->Surface->SetInputConnection(this->Islands->GetOutputPort());
    this->II->SetInputConnection(this->Surface->GetOutputPort());
    this->II->SetSourceConnection(this->Islands->GetOutputPort());
    this->AT->SetInputConnection(this->II->GetOutputPort());
    for (vtkAlgorithm* a : this->Stages())
    {
      this->Messages->Observe(a);
      this->Messages->Observe(a->GetExecutive()); // "returned failure" comes from here
    }
  }
  std::vector<vtkAlgorithm*> Stages()
  {
    return { this->Reader, this->Noise, this->Islands, this->Surface, this->II, this->AT };
  }
};

std::string WriteCubeVol(int n)
{
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(n / 2.0 + 0.1, n / 2.0 - 0.1, n / 2.0 + 0.2),
    n / 3.5, 20, 30, 10);
  auto image = dgtest::Digitize(*cube, n);
  const int dims[3] = { n, n, n };
  std::vector<std::uint8_t> voxels(static_cast<std::size_t>(n) * n * n);
  vtkDataArray* s = image->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < s->GetNumberOfTuples(); ++i)
  {
    voxels[i] = static_cast<std::uint8_t>(s->GetTuple1(i));
  }
  const std::string path = dgtest::TempPath("cube.vol");
  std::string error;
  EXPECT_TRUE(dg::WriteVolFile(path, dims, voxels.data(), 3, error)) << error;
  return path;
}

// An aborted surface has no points and no cells; an aborted image keeps its
// extent (see dgPipelineAbort.h) but has no array.
bool Empty(vtkDataObject* d)
{
  if (vtkImageData* image = vtkImageData::SafeDownCast(d))
  {
    return image->GetPointData()->GetNumberOfArrays() == 0 &&
      image->GetCellData()->GetNumberOfArrays() == 0;
  }
  vtkDataSet* ds = vtkDataSet::SafeDownCast(d);
  return ds && ds->GetNumberOfPoints() == 0 && ds->GetNumberOfCells() == 0;
}
} // namespace

TEST(PipelineAbort, EveryStageAbortsCleanlyAndRecomputes)
{
  const std::string vol = WriteCubeVol(40);
  Pipeline reference(vol);
  reference.AT->Update();
  const vtkIdType refCells = reference.AT->GetOutput(0)->GetNumberOfCells();
  const vtkIdType refLines = reference.AT->GetOutput(1)->GetNumberOfCells();
  ASSERT_GT(refCells, 1000);
  ASSERT_GT(refLines, 50);
  ASSERT_EQ(reference.Messages->Errors + reference.Messages->Warnings, 0)
    << reference.Messages->Messages;

  const char* names[] = { "reader", "noise", "islands", "surface", "II", "AT" };
  const int stages = 6;
  for (int stage = 0; stage < stages; ++stage)
  {
    SCOPED_TRACE(names[stage]);
    Pipeline p(vol);
    vtkAlgorithm* victim = p.Stages()[stage];
    vtkNew<Aborter> aborter;
    victim->AddObserver(vtkCommand::ProgressEvent, aborter);
    victim->AddObserver(vtkCommand::StartEvent, aborter);
    // A good run first, so that stale outputs would show.
    p.AT->Update();
    ASSERT_EQ(p.AT->GetOutput(1)->GetNumberOfCells(), refLines);

    victim->Modified();
    aborter->Armed = true;
    p.AT->Update();
    EXPECT_EQ(aborter->Aborts, 1);
    EXPECT_EQ(p.Messages->Errors, 0) << p.Messages->Messages;
    for (int s = stage; s < stages; ++s)
    {
      for (int port = 0; port < p.Stages()[s]->GetNumberOfOutputPorts(); ++port)
      {
        EXPECT_TRUE(Empty(p.Stages()[s]->GetOutputDataObject(port)))
          << names[s] << " port " << port << " is not empty after the abort";
      }
    }

    // Disarmed, a plain Update (nothing modified) recomputes everything.
    aborter->Armed = false;
    const int executions = aborter->Executions;
    p.AT->Update();
    EXPECT_EQ(aborter->Executions, executions + 1);
    EXPECT_EQ(p.Messages->Errors, 0) << p.Messages->Messages;
    EXPECT_EQ(p.AT->GetOutput(0)->GetNumberOfCells(), refCells);
    EXPECT_EQ(p.AT->GetOutput(1)->GetNumberOfCells(), refLines);
    // ... and once up to date, stays so.
    p.AT->Update();
    EXPECT_EQ(aborter->Executions, executions + 1);
  }
}

TEST(PipelineAbort, ProgressIsFineGrained)
{
  const std::string vol = WriteCubeVol(96);
  Pipeline p(vol);
  std::vector<vtkNew<Aborter>> counters(6);
  for (int s = 0; s < 6; ++s)
  {
    p.Stages()[s]->AddObserver(vtkCommand::ProgressEvent, counters[s]);
  }
  p.AT->Update();
  ASSERT_EQ(p.Messages->Errors, 0) << p.Messages->Messages;
  const vtkIdType surfels = p.Surface->GetOutput()->GetNumberOfCells();
  ASSERT_GT(surfels, 20000);
  // Distinct values strictly inside (0, 1): the II estimator reports every
  // 2 000 surfels (was: 0, 0.1 and 1 only), AT at every step.
  auto inner = [](const std::set<double>& v) {
    return std::count_if(v.begin(), v.end(), [](double x) { return x > 0 && x < 1; });
  };
  EXPECT_GE(inner(counters[4]->Values), std::min<vtkIdType>(100, surfels / 2000));
  EXPECT_GE(inner(counters[5]->Values), p.AT->GetNumberOfIterations());
  EXPECT_GE(inner(counters[3]->Values), 5); // surface
  EXPECT_GE(inner(counters[2]->Values), 10); // islands
  EXPECT_GE(inner(counters[1]->Values), 3); // noise
  EXPECT_GE(inner(counters[0]->Values), 1); // reader (one zlib piece at this size)
}
