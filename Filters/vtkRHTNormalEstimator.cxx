#include "vtkRHTNormalEstimator.h"

#include "dgIntegralInvariant.h"
#include "dgPieces.h"
#include "dgPipelineAbort.h"
#include "dgRHT.h"
#include "dgSurfaceEstimator.h"
#include "dgVoxelSelection.h"

#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkRHTNormalEstimator);

vtkRHTNormalEstimator::~vtkRHTNormalEstimator() = default;

vtkRHTNormalEstimator::vtkRHTNormalEstimator()
{
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetNumberOfInputPorts(2);
  this->SetInputArrayToProcess(
    0, 1, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

void vtkRHTNormalEstimator::SetSourceConnection(vtkAlgorithmOutput* algOutput)
{
  this->SetInputConnection(1, algOutput);
}

void vtkRHTNormalEstimator::SetSourceData(vtkDataObject* input)
{
  this->SetInputData(1, input);
}

vtkDataObject* vtkRHTNormalEstimator::GetSource()
{
  if (this->GetNumberOfInputConnections(1) < 1)
  {
    return nullptr;
  }
  return this->GetExecutive()->GetInputData(1, 0);
}

int vtkRHTNormalEstimator::FillInputPortInformation(int port, vtkInformation* info)
{
  return dg::FillEstimatorInputPort(port, info);
}

int vtkRHTNormalEstimator::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  // Every candidate surfel's inside and outside voxels and the orientation
  // ball lie within ceil(r) + 1 voxels of the surfel's inside voxel.
  const int reach = dg::BallReach(
    this->Radius, this->RadiusUnits == WORLD, inputVector[1]->GetInformationObject(0));
  dg::RequestEstimatorExtents(inputVector, outputVector, reach);
  return 1;
}

vtkMTimeType vtkRHTNormalEstimator::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkRHTNormalEstimator::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return dg::FinishPiece(outputVector, this->ExecutePiece(request, inputVector, outputVector));
}

int vtkRHTNormalEstimator::ExecutePiece(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0]);
  vtkImageData* image = vtkImageData::GetData(inputVector[1]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->NumberOfFallbacks = 0;
  this->NumberOfTrivialFallbacks = 0;
  if (!surface || !output)
  {
    vtkErrorMacro("Missing input surface.");
    return 0;
  }
  const auto abortGuard = this->Abort->Begin(this, outputVector);
  if (dg::PipelineAbort::InputAborted(inputVector, this->GetNumberOfInputPorts()))
  {
    return this->Abort->Abort(outputVector);
  }
  if (!image)
  {
    vtkErrorMacro(<< dg::NoSourceImageMessage);
    return 0;
  }
  if (!(this->Radius > 0) || !std::isfinite(this->Radius))
  {
    vtkErrorMacro("Radius must be positive and finite (it is " << this->Radius << ").");
    return 0;
  }
  if (this->NumberOfTrials < 1)
  {
    vtkErrorMacro("NumberOfTrials must be at least 1 (it is " << this->NumberOfTrials << ").");
    return 0;
  }
  if (this->NumberOfAccumulators < 1)
  {
    vtkErrorMacro(
      "NumberOfAccumulators must be at least 1 (it is " << this->NumberOfAccumulators << ").");
    return 0;
  }
  if (this->AccumulatorResolution < 1 || this->AccumulatorResolution > 100)
  {
    vtkErrorMacro("AccumulatorResolution must be in 1..100 (it is "
      << this->AccumulatorResolution << ").");
    return 0;
  }

  // 1. The surface must come from this image, and a piece's image must hold
  // every surfel's reach.
  dg::SurfaceOnImage in;
  std::string error;
  double radius = this->Radius;
  int need[6];
  if (!dg::ReadSurfaceOnImage(surface, image, inputVector[1]->GetInformationObject(0), in, error) ||
    (this->RadiusUnits == WORLD && !dg::RadiiToVoxels(in, &radius, 1, error)) ||
    !dg::RadiusFitsImage(in, "Radius", radius, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  if (!dg::ImageHoldsReach(in, static_cast<int>(std::ceil(radius)) + 1, need))
  {
    std::ostringstream reads;
    reads << "the balls of radius " << radius << " around these surfels read";
    vtkErrorMacro(<< dg::MissingReachMessage(in, need, reads.str(), ""));
    return 0;
  }
  const vtkIdType nSurfels = static_cast<vtkIdType>(in.Directions.size());
  const int* dims = in.Dims;

  // 2. The image box's inside voxels: runs (orientation balls) and surfels
  // (candidate points); the byte mask lives only until then.
  dg::IntegralInvariantKernel kernel;
  dg::SurfelRows surfels;
  if (nSurfels > 0)
  {
    vtkDataArray* scalars = dg::SelectionArray(this->GetInputArrayToProcess(0, inputVector),
      this->GetInputArrayInformation(0), image);
    const dg::VoxelSelection select{ this->SelectionMode, this->LowerThreshold,
      this->UpperThreshold, this->Label, this->SelectedComponent };
    std::vector<std::uint8_t> mask;
    if (!dg::SelectInside(scalars, select, dims, mask, error))
    {
      vtkErrorMacro(<< error);
      return 0;
    }
    kernel.SetVolume(mask.data(), dims, dims[0], 0);
    surfels.Build(mask.data(), dims, dims[0], 0);
  }
  kernel.SetRadius(radius);
  // The accumulators' rotations and look-up tables, shared by all surfels.
  dg::HoughTables tables;
  tables.Build(this->AccumulatorResolution, this->NumberOfAccumulators,
    static_cast<std::uint64_t>(this->Seed));
  dg::RHTParameters parameters;
  parameters.Radius = radius;
  parameters.Trials = this->NumberOfTrials;
  parameters.Accumulators = this->NumberOfAccumulators;
  parameters.Seed = this->Seed;
  this->UpdateProgress(0.05);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }

  double Minv[9];
  dg::NormalToWorldMatrix(image, Minv);
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("RHTNormals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(nSurfels);
  double* nrm = normals->GetPointer(0);

  std::atomic<vtkIdType> fallbacks(0), trivial(0), badSurfel(-1), notSelected(-1);
  const dg::RowRuns& runs = kernel.GetRuns();
  const std::vector<int>& vox = in.Voxels;
  vtkSMPThreadLocal<dg::RHTWorkspace> workspaces;
  auto work = [&](vtkIdType b, vtkIdType e) {
    dg::RHTWorkspace& ws = workspaces.Local();
    vtkIdType localFallbacks = 0, localTrivial = 0;
    for (vtkIdType s = b; s < e; ++s)
    {
      int ijk[3], d;
      const dg::SurfelCheck check = dg::CheckSurfel(in, runs, s, ijk, d);
      if (check != dg::SurfelCheck::Ok)
      {
        (check == dg::SurfelCheck::Bad ? badSurfel : notSelected) = s;
        continue;
      }
      const int i = ijk[0], j = ijk[1], k = ijk[2];
      // The reference: from the barycentre of the ball's inside voxels to
      // the surfel centre (docs/method.md section 6), the trivial normal when zero.
      const dg::IIMoments m = kernel.Moments(i, j, k, d);
      double ref[3] = { -static_cast<double>(m.Sum[0]), -static_cast<double>(m.Sum[1]),
        -static_cast<double>(m.Sum[2]) };
      double len = std::sqrt(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2]);
      if (!(len > 0))
      {
        ref[0] = ref[1] = ref[2] = 0;
        ref[d / 2] = (d & 1) ? 1 : -1;
        len = 1;
        ++localTrivial;
      }
      for (double& c : ref)
      {
        c /= len;
      }
      surfels.Neighbours(i, j, k, d, radius, ws.Points);
      dg::RHTEstimate est;
      dg::EstimateRHT(ws.Points.data(), static_cast<int>(ws.Points.size() / 3), ref, parameters,
        dg::SurfelSeed(parameters.Seed, vox[3 * s], vox[3 * s + 1], vox[3 * s + 2], d),
        tables, ws, est);
      localFallbacks += est.Fallback;
      dg::NormalToWorld(Minv, est.Normal, nrm + 3 * s);
    }
    fallbacks += localFallbacks;
    trivial += localTrivial;
  };
  // Blocks of surfels for progress and abort from the calling thread.
  const vtkIdType blocks = std::max<vtkIdType>(1, std::min<vtkIdType>(100, nSurfels / 500));
  for (vtkIdType blk = 0; blk < blocks; ++blk)
  {
    vtkSMPTools::For(nSurfels * blk / blocks, nSurfels * (blk + 1) / blocks, work);
    this->UpdateProgress(0.05 + 0.95 * (blk + 1) / blocks);
    if (this->GetAbortExecute())
    {
      return this->Abort->Abort(outputVector);
    }
  }
  if (badSurfel >= 0)
  {
    vtkErrorMacro(<< dg::BadSurfelMessage(badSurfel.load()));
    return 0;
  }
  if (notSelected >= 0)
  {
    vtkErrorMacro(<< dg::NotSelectedMessage(in, notSelected.load()));
    return 0;
  }
  this->NumberOfFallbacks = fallbacks;
  this->NumberOfTrivialFallbacks = trivial;

  output->ShallowCopy(surface);
  output->GetCellData()->SetActiveAttribute(-1, vtkDataSetAttributes::NORMALS);
  output->GetCellData()->SetNormals(normals);
  return 1;
}

void vtkRHTNormalEstimator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* modes[] = { "NonZero", "Range", "Label" };
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusUnits: " << (this->RadiusUnits == WORLD ? "World" : "Voxels") << "\n";
  os << indent << "NumberOfTrials: " << this->NumberOfTrials << "\n";
  os << indent << "NumberOfAccumulators: " << this->NumberOfAccumulators << "\n";
  os << indent << "AccumulatorResolution: " << this->AccumulatorResolution << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "SelectionMode: " << modes[this->SelectionMode] << "\n";
  os << indent << "LowerThreshold: " << this->LowerThreshold << "\n";
  os << indent << "UpperThreshold: " << this->UpperThreshold << "\n";
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "SelectedComponent: " << this->SelectedComponent << "\n";
  os << indent << "NumberOfFallbacks: " << this->NumberOfFallbacks << "\n";
  os << indent << "NumberOfTrivialFallbacks: " << this->NumberOfTrivialFallbacks << "\n";
}
