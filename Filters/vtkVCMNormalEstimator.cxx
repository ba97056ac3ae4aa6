#include "vtkVCMNormalEstimator.h"

#include "dgPipelineAbort.h"
#include "dgIntegralInvariant.h"
#include "dgVCM.h"
#include "dgVoxelSelection.h"
#include "dgPieces.h"
#include "dgSurfaceEstimator.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkVCMNormalEstimator);


vtkVCMNormalEstimator::~vtkVCMNormalEstimator() = default;

vtkVCMNormalEstimator::vtkVCMNormalEstimator()
{
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetNumberOfInputPorts(2);
  this->SetInputArrayToProcess(
    0, 1, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

void vtkVCMNormalEstimator::SetSourceConnection(vtkAlgorithmOutput* algOutput)
{
  this->SetInputConnection(1, algOutput);
}

void vtkVCMNormalEstimator::SetSourceData(vtkDataObject* input)
{
  this->SetInputData(1, input);
}

vtkDataObject* vtkVCMNormalEstimator::GetSource()
{
  if (this->GetNumberOfInputConnections(1) < 1)
  {
    return nullptr;
  }
  return this->GetExecutive()->GetInputData(1, 0);
}

int vtkVCMNormalEstimator::FillInputPortInformation(int port, vtkInformation* info)
{
  return dg::FillEstimatorInputPort(port, info);
}

int vtkVCMNormalEstimator::Reach(vtkInformation* sourceInfo) const
{
  double R = this->OffsetRadius, r = this->ConvolutionRadius;
  if (this->RadiusUnits == WORLD && sourceInfo->Has(vtkDataObject::SPACING()))
  {
    const double* sp = sourceInfo->Get(vtkDataObject::SPACING());
    const double h = std::min({ std::abs(sp[0]), std::abs(sp[1]), std::abs(sp[2]) });
    R = h > 0 ? R / h : R;
    r = h > 0 ? r / h : r;
  }
  // V(s) sums the cells of the sites within r of the surfel centre; a
  // lattice point of such a cell lies within R of its site, and deciding its
  // nearest site needs every site within R of it: sites within 2 R + r of
  // the centre, whose voxels lie within 2 R + r + 1 of the inside voxel.
  // Bad radii are reported by RequestData; here they only must not overflow.
  const double reach = 2 * R + r;
  if (!(R > 0) || !(r > 0) || !std::isfinite(reach) || reach > 1e6)
  {
    return 1;
  }
  return static_cast<int>(std::ceil(reach)) + 1;
}

int vtkVCMNormalEstimator::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  vtkInformation* sourceInfo = inputVector[1]->GetInformationObject(0);
  if (sourceInfo)
  {
    dg::RequestEstimatorExtents(inputVector, outputVector, this->Reach(sourceInfo));
  }
  return 1;
}

vtkMTimeType vtkVCMNormalEstimator::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkVCMNormalEstimator::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return dg::FinishPiece(outputVector, this->ExecutePiece(request, inputVector, outputVector));
}

int vtkVCMNormalEstimator::ExecutePiece(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[0]);
  vtkImageData* image = vtkImageData::GetData(inputVector[1]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
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
  if (!(this->OffsetRadius > 0) || !std::isfinite(this->OffsetRadius) ||
    !(this->ConvolutionRadius > 0) || !std::isfinite(this->ConvolutionRadius))
  {
    vtkErrorMacro("OffsetRadius and ConvolutionRadius must be positive and finite (they are "
      << this->OffsetRadius << " and " << this->ConvolutionRadius << ").");
    return 0;
  }
  if (this->ConvolutionRadius > this->OffsetRadius)
  {
    vtkErrorMacro("ConvolutionRadius (" << this->ConvolutionRadius
                                        << ") must not exceed OffsetRadius (" << this->OffsetRadius
                                        << "): the paper uses R = 10, r = 4.");
    return 0;
  }

  // 1. The surface must come from this image.
  dg::SurfaceOnImage on;
  {
    std::string error;
    if (!dg::ReadSurfaceOnImage(
          surface, image, inputVector[1]->GetInformationObject(0), on, error))
    {
      vtkErrorMacro(<< error);
      return 0;
    }
  }
  const vtkIdType nSurfels = surface->GetNumberOfCells();
  const int* ext = on.Extent;
  const int* whole = on.Whole;
  const int* dims = on.Dims;

  // 2. Radii in voxels.
  double R = this->OffsetRadius, r = this->ConvolutionRadius;
  {
    std::string error;
    double radii[2] = { R, r };
    if ((this->RadiusUnits == WORLD && !dg::RadiiToVoxels(on, radii, 2, error)) ||
      !dg::RadiusFitsImage(on, "OffsetRadius", radii[0], error))
    {
      vtkErrorMacro(<< error);
      return 0;
    }
    R = radii[0];
    r = radii[1];
  }
  const int reach = static_cast<int>(std::ceil(2 * R + r)) + 1;
  // A piece's image must hold every site the estimates read: a missing site
  // would be a wrong normal without a word.
  {
    int need[6];
    if (!dg::ImageHoldsReach(on, reach, need))
    {
      std::ostringstream reads;
      reads << "the estimates (R = " << R << ", r = " << r
            << ") around these surfels read the surfels of";
      vtkErrorMacro(
        << dg::MissingReachMessage(on, need, reads.str(), " (2 R + r + 1 voxels around them)"));
      return 0;
    }
  }

  // 3. Inside voxels: runs (for the barycentres) and the sites.
  dg::IntegralInvariantKernel kernel;
  dg::VCMSites sites;
  if (nSurfels > 0)
  {
    vtkDataArray* scalars = dg::SelectionArray(this->GetInputArrayToProcess(0, inputVector),
      this->GetInputArrayInformation(0), image);
    const dg::VoxelSelection select{ this->SelectionMode, this->LowerThreshold,
      this->UpperThreshold, this->Label, this->SelectedComponent };
    std::vector<std::uint8_t> mask;
    std::string error;
    if (!dg::SelectInside(scalars, select, dims, mask, error))
    {
      vtkErrorMacro(<< error);
      return 0;
    }
    kernel.SetVolume(mask.data(), dims, dims[0], 0);
    // A face towards a voxel beyond the image box is a surfel only where
    // the box's side is the whole image's (outside); elsewhere that voxel
    // belongs to another piece and the face is left out (beyond the reach).
    bool beyond[6];
    for (int a = 0; a < 6; ++a)
    {
      beyond[a] = ext[a] == whole[a];
    }
    sites = dg::ExtractSites(mask.data(), dims, beyond);
  }
  if (sites.Size() >= std::numeric_limits<std::int32_t>::max())
  {
    vtkErrorMacro("Too many surfels in the image (" << sites.Size() << "): at most 2^31 - 1.");
    return 0;
  }
  kernel.SetRadius(r);
  this->UpdateProgress(0.1);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }

  // 4. Per-site measures over the R-offset (the whole cost).
  dg::VoronoiCovarianceMeasure vcm;
  if (!vcm.Compute(sites, R, [this](double f) {
        this->UpdateProgress(0.1 + 0.7 * f);
        return !this->GetAbortExecute();
      }))
  {
    return this->Abort->Abort(outputVector);
  }

  // 5. Grid to world: normals through M^-T, M = direction * diag(spacing).
  double Minv[9];
  dg::NormalToWorldMatrix(image, Minv);

  const bool score = this->ComputeFeatureScore;
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("VCMNormals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(nSurfels);
  vtkNew<vtkDoubleArray> scores, eigenvalues;
  if (score)
  {
    scores->SetName("VCMFeatureScore");
    scores->SetNumberOfTuples(nSurfels);
    eigenvalues->SetName("VCMEigenvalues");
    eigenvalues->SetNumberOfComponents(3);
    eigenvalues->SetNumberOfTuples(nSurfels);
  }
  double* nrm = normals->GetPointer(0);
  double* psc = score ? scores->GetPointer(0) : nullptr;
  double* pev = score ? eigenvalues->GetPointer(0) : nullptr;

  std::atomic<vtkIdType> fallbacks(0), badSurfel(-1), notSelected(-1);
  const dg::RowRuns& runs = kernel.GetRuns();
  auto work = [&](vtkIdType b, vtkIdType e) {
    vtkIdType localFallbacks = 0;
    for (vtkIdType s = b; s < e; ++s)
    {
      int ijk[3], d;
      const dg::SurfelCheck check = dg::CheckSurfel(on, runs, s, ijk, d);
      if (check != dg::SurfelCheck::Ok)
      {
        (check == dg::SurfelCheck::Bad ? badSurfel : notSelected) = s;
        continue;
      }
      const int i = ijk[0], j = ijk[1], k = ijk[2];
      const std::int32_t v[3] = { i, j, k };
      std::int64_t measure[6];
      vcm.Convolve(v, d, r, measure);
      const dg::IIMoments m = kernel.Moments(i, j, k, d);
      dg::VCMEstimate est;
      dg::EstimateFromMeasure(measure, m.Sum, d, est);
      localFallbacks += est.TrivialFallback;
      dg::NormalToWorld(Minv, est.Normal, nrm + 3 * s);
      if (score)
      {
        psc[s] = est.FeatureScore;
        std::copy(est.Eigenvalues, est.Eigenvalues + 3, pev + 3 * s);
      }
    }
    fallbacks += localFallbacks;
  };
  const vtkIdType blocks = std::max<vtkIdType>(1, std::min<vtkIdType>(20, nSurfels / 2000));
  for (vtkIdType blk = 0; blk < blocks; ++blk)
  {
    vtkSMPTools::For(nSurfels * blk / blocks, nSurfels * (blk + 1) / blocks, work);
    this->UpdateProgress(0.8 + 0.2 * (blk + 1) / blocks);
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
    vtkErrorMacro(<< dg::NotSelectedMessage(on, notSelected.load()));
    return 0;
  }
  this->NumberOfTrivialFallbacks = fallbacks;

  output->ShallowCopy(surface);
  // Keep the incoming active normals (trivial or another estimator's) as an
  // ordinary array: SetNormals would delete them.
  output->GetCellData()->SetActiveAttribute(-1, vtkDataSetAttributes::NORMALS);
  output->GetCellData()->SetNormals(normals);
  if (score)
  {
    output->GetCellData()->AddArray(scores);
    output->GetCellData()->AddArray(eigenvalues);
  }
  return 1;
}

void vtkVCMNormalEstimator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* modes[] = { "NonZero", "Range", "Label" };
  os << indent << "OffsetRadius: " << this->OffsetRadius << "\n";
  os << indent << "ConvolutionRadius: " << this->ConvolutionRadius << "\n";
  os << indent << "RadiusUnits: " << (this->RadiusUnits == WORLD ? "World" : "Voxels") << "\n";
  os << indent << "ComputeFeatureScore: " << (this->ComputeFeatureScore ? "On" : "Off") << "\n";
  os << indent << "SelectionMode: " << modes[this->SelectionMode] << "\n";
  os << indent << "LowerThreshold: " << this->LowerThreshold << "\n";
  os << indent << "UpperThreshold: " << this->UpperThreshold << "\n";
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "SelectedComponent: " << this->SelectedComponent << "\n";
  os << indent << "NumberOfTrivialFallbacks: " << this->NumberOfTrivialFallbacks << "\n";
}
