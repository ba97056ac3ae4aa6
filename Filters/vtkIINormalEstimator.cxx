#include "vtkIINormalEstimator.h"

#include "dgPipelineAbort.h"
#include "dgIntegralInvariant.h"
#include "dgLabelMap.h"
#include "dgVoxelSelection.h"
#include "dgPieces.h"
#include "dgSurfaceEstimator.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <map>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

vtkStandardNewMacro(vtkIINormalEstimator);


vtkIINormalEstimator::~vtkIINormalEstimator() = default;

vtkIINormalEstimator::vtkIINormalEstimator()
{
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetNumberOfInputPorts(2);
  this->SetInputArrayToProcess(
    0, 1, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

void vtkIINormalEstimator::SetSourceConnection(vtkAlgorithmOutput* algOutput)
{
  this->SetInputConnection(1, algOutput);
}

void vtkIINormalEstimator::SetSourceData(vtkDataObject* input)
{
  this->SetInputData(1, input);
}

vtkDataObject* vtkIINormalEstimator::GetSource()
{
  if (this->GetNumberOfInputConnections(1) < 1)
  {
    return nullptr;
  }
  return this->GetExecutive()->GetInputData(1, 0);
}

int vtkIINormalEstimator::FillInputPortInformation(int port, vtkInformation* info)
{
  return dg::FillEstimatorInputPort(port, info);
}

int vtkIINormalEstimator::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (!this->Superclass::RequestUpdateExtent(request, inputVector, outputVector))
  {
    return 0;
  }
  vtkInformation* sourceInfo = inputVector[1]->GetInformationObject(0);
  if (sourceInfo)
  {
    dg::RequestEstimatorExtents(inputVector, outputVector,
      dg::BallReach(this->Radius, this->RadiusUnits == WORLD, sourceInfo));
  }
  return 1;
}

vtkMTimeType vtkIINormalEstimator::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkIINormalEstimator::RequestData(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  return dg::FinishPiece(outputVector, this->ExecutePiece(request, inputVector, outputVector));
}

int vtkIINormalEstimator::ExecutePiece(
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
  if (!(this->Radius > 0) || !std::isfinite(this->Radius))
  {
    vtkErrorMacro("Radius must be positive and finite (it is " << this->Radius << ").");
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
  const int* dims = on.Dims;
  const double* spacing = on.Spacing;

  // 2. Radius in voxels: of the smallest spacing when the spacing is
  // anisotropic, where the ball is a ball of world space (an ellipsoid of
  // index space, scale = spacing / smallest spacing).
  const bool isotropic = on.Isotropic;
  const double sMin = std::min({ std::abs(spacing[0]), std::abs(spacing[1]), std::abs(spacing[2]) });
  double scaleStorage[3];
  const double* scale = nullptr;
  if (!isotropic)
  {
    for (int a = 0; a < 3; ++a)
    {
      scaleStorage[a] = std::abs(spacing[a]) / sMin;
    }
    scale = scaleStorage;
  }
  double radius = this->Radius;
  if (this->RadiusUnits == WORLD)
  {
    std::string error;
    if (isotropic && !dg::RadiiToVoxels(on, &radius, 1, error))
    {
      vtkErrorMacro(<< error);
      return 0;
    }
    if (!isotropic)
    {
      radius /= sMin;
    }
  }
  // A piece's image must hold every ball: a cropped ball would be a wrong
  // normal without a word.
  {
    std::string error;
    int need[6];
    if (!dg::RadiusFitsImage(on, "Radius", radius, error))
    {
      vtkErrorMacro(<< error);
      return 0;
    }
    if (!dg::ImageHoldsReach(on, static_cast<int>(std::ceil(radius)) + 1, need))
    {
      std::ostringstream reads;
      reads << "the balls of radius " << radius << " around these surfels read";
      vtkErrorMacro(<< dg::MissingReachMessage(on, need, reads.str(), ""));
      return 0;
    }
  }

  if (this->SelectionMode == EACH_LABEL)
  {
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) &&
      outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) > 1)
    {
      vtkErrorMacro("SelectionMode EachLabel runs in one piece only.");
      return 0;
    }
    return this->ExecuteEachLabel(surface, image,
      dg::SelectionArray(this->GetInputArrayToProcess(0, inputVector),
        this->GetInputArrayInformation(0), image),
      on.Voxels.data(), static_cast<int>(std::ceil(radius)) + 1, output, outputVector);
  }

  // 3. Inside voxels as runs along x; the byte mask lives only until then.
  dg::IntegralInvariantKernel kernel;
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
  }
  kernel.SetRadius(radius, scale);
  this->UpdateProgress(0.1);
  if (this->GetAbortExecute())
  {
    return this->Abort->Abort(outputVector);
  }

  // 4. Grid to world: tangents go through M = direction * diag(spacing),
  // normals through M^-T.
  double M[9], Minv[9];
  {
    const double* d = image->GetDirectionMatrix()->GetData();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
      {
        M[3 * r + c] = d[3 * r + c] * spacing[c];
      }
    vtkMatrix3x3::Invert(M, Minv);
  }
  const double curvatureScale = 1.0 / (isotropic ? std::abs(spacing[0]) : sMin);

  const bool curv = this->ComputeCurvatures;
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("IINormals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(nSurfels);
  vtkNew<vtkDoubleArray> mean, gauss, k1, k2, dir1, dir2;
  if (curv)
  {
    mean->SetName("IIMeanCurvature");
    gauss->SetName("IIGaussianCurvature");
    k1->SetName("IIK1");
    k2->SetName("IIK2");
    dir1->SetName("IIK1Direction");
    dir2->SetName("IIK2Direction");
    dir1->SetNumberOfComponents(3);
    dir2->SetNumberOfComponents(3);
    for (vtkDoubleArray* a : { mean.Get(), gauss.Get(), k1.Get(), k2.Get(), dir1.Get(), dir2.Get() })
    {
      a->SetNumberOfTuples(nSurfels);
    }
  }
  double* nrm = normals->GetPointer(0);
  double* pm = curv ? mean->GetPointer(0) : nullptr;
  double* pg = curv ? gauss->GetPointer(0) : nullptr;
  double* p1 = curv ? k1->GetPointer(0) : nullptr;
  double* p2 = curv ? k2->GetPointer(0) : nullptr;
  double* pd1 = curv ? dir1->GetPointer(0) : nullptr;
  double* pd2 = curv ? dir2->GetPointer(0) : nullptr;

  const auto reference = static_cast<dg::IICurvatureReference>(this->CurvatureReference);
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
      dg::IIEstimate est;
      dg::EstimateFromMoments(kernel.Moments(i, j, k, d), d, radius, curv, est,
        reference, &kernel.GetBall(d / 2));
      localFallbacks += est.TrivialFallback;
      dg::NormalToWorld(Minv, est.Normal, nrm + 3 * s);
      if (curv)
      {
        pm[s] = est.Mean * curvatureScale;
        p1[s] = est.K1 * curvatureScale;
        p2[s] = est.K2 * curvatureScale;
        pg[s] = est.Gaussian * curvatureScale * curvatureScale;
        const double* src[2] = { est.Direction1, est.Direction2 };
        double* dst[2] = { pd1 + 3 * s, pd2 + 3 * s };
        for (int t = 0; t < 2; ++t)
        {
          double v[3], l = 0;
          for (int r = 0; r < 3; ++r)
          {
            v[r] = M[3 * r] * src[t][0] + M[3 * r + 1] * src[t][1] + M[3 * r + 2] * src[t][2];
            l += v[r] * v[r];
          }
          l = std::sqrt(l);
          for (int r = 0; r < 3; ++r)
          {
            dst[t][r] = v[r] / l;
          }
        }
      }
    }
    fallbacks += localFallbacks;
  };
  // Blocks of surfels so that progress is reported and abort honoured from
  // the calling thread (every 1% from 200 000 surfels, at least every 2 000
  // surfels below); each surfel's result is independent of the others.
  const vtkIdType blocks = std::max<vtkIdType>(1, std::min<vtkIdType>(100, nSurfels / 2000));
  for (vtkIdType blk = 0; blk < blocks; ++blk)
  {
    vtkSMPTools::For(nSurfels * blk / blocks, nSurfels * (blk + 1) / blocks, work);
    this->UpdateProgress(0.1 + 0.9 * (blk + 1) / blocks);
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
  // SetNormals would delete the current normals array (the trivial
  // "Normals"): demote it to an ordinary array first, it stays useful.
  output->GetCellData()->SetActiveAttribute(-1, vtkDataSetAttributes::NORMALS);
  output->GetCellData()->SetNormals(normals);
  if (curv)
  {
    for (vtkDoubleArray* a : { mean.Get(), gauss.Get(), k1.Get(), k2.Get(), dir1.Get(), dir2.Get() })
    {
      output->GetCellData()->AddArray(a);
    }
  }
  return 1;
}

int vtkIINormalEstimator::ExecuteEachLabel(vtkPolyData* surface, vtkImageData* image,
  vtkDataArray* scalars, const int* surfelVoxels, int reach, vtkPolyData* output, vtkInformationVector* outputVector)
{
  vtkDataArray* labelArray = surface->GetCellData()->GetArray("Label");
  if (!labelArray || labelArray->GetNumberOfComponents() != 1)
  {
    vtkErrorMacro("SelectionMode EachLabel needs the surface's cell array 'Label' (one "
                  "component), as vtkDigitalSurfaceFilter writes it in EachLabel mode.");
    return 0;
  }
  int component = 0;
  {
    std::string why;
    if (!dg::LabelComponent(scalars, this->SelectedComponent, component, why))
    {
      vtkErrorMacro("Cannot select voxels: " << why << ".");
      return 0;
    }
  }
  const vtkIdType nSurfels = surface->GetNumberOfCells();
  std::map<double, std::vector<vtkIdType>> cellsOf;
  for (vtkIdType c = 0; c < nSurfels; ++c)
  {
    cellsOf[labelArray->GetTuple1(c)].push_back(c);
  }
  vtkDataArray* voxelArray = surface->GetCellData()->GetArray("InsideVoxel");
  vtkDataArray* directionArray = surface->GetCellData()->GetArray("SurfelDirection");
  vtkNew<vtkIdTypeArray> legacy;
  surface->GetPolys()->ExportLegacyFormat(legacy);
  const bool quadsOnly = surface->GetNumberOfCells() == surface->GetNumberOfPolys() &&
    legacy->GetNumberOfValues() == 5 * nSurfels;
  if (!quadsOnly)
  {
    vtkErrorMacro("SelectionMode EachLabel reads a surface of quads only, as "
                  "vtkDigitalSurfaceFilter makes it.");
    return 0;
  }
  // The estimates of all labels, in the surface's cell order.
  std::vector<vtkSmartPointer<vtkDataArray>> results;
  this->NumberOfTrivialFallbacks = 0;
  std::size_t done = 0;
  for (const auto& entry : cellsOf)
  {
    const std::vector<vtkIdType>& cells = entry.second;
    // The label's voxel box: its extreme voxels all carry a surfel.
    int box[6] = { VTK_INT_MAX, VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN, VTK_INT_MAX, VTK_INT_MIN };
    for (vtkIdType c : cells)
    {
      for (int a = 0; a < 3; ++a)
      {
        box[2 * a] = std::min(box[2 * a], surfelVoxels[3 * c + a]);
        box[2 * a + 1] = std::max(box[2 * a + 1], surfelVoxels[3 * c + a]);
      }
    }
    auto crop = dg::CropImage(image, box, reach, scalars, component);
    // The label's cells on the shared points, recorded as made from the crop.
    vtkNew<vtkPolyData> part;
    part->SetPoints(surface->GetPoints());
    vtkNew<vtkCellArray> polys;
    vtkNew<vtkIntArray> voxels;
    voxels->SetName("InsideVoxel");
    voxels->SetNumberOfComponents(3);
    vtkNew<vtkUnsignedCharArray> directions;
    directions->SetName("SurfelDirection");
    for (vtkIdType c : cells)
    {
      const vtkIdType quad[4] = { legacy->GetValue(5 * c + 1), legacy->GetValue(5 * c + 2),
        legacy->GetValue(5 * c + 3), legacy->GetValue(5 * c + 4) };
      polys->InsertNextCell(4, quad);
      voxels->InsertNextTuple(voxelArray->GetTuple3(c));
      directions->InsertNextValue(static_cast<unsigned char>(directionArray->GetTuple1(c)));
    }
    part->SetPolys(polys);
    part->GetCellData()->AddArray(voxels);
    part->GetCellData()->AddArray(directions);
    vtkNew<vtkIntArray> cropExtent;
    cropExtent->SetName("ImageExtent");
    cropExtent->SetNumberOfValues(6);
    for (int a = 0; a < 6; ++a)
    {
      cropExtent->SetValue(a, crop->GetExtent()[a]);
    }
    part->GetFieldData()->AddArray(cropExtent);
    part->GetFieldData()->AddArray(surface->GetFieldData()->GetArray("ImageOrigin"));
    part->GetFieldData()->AddArray(surface->GetFieldData()->GetArray("ImageSpacing"));

    vtkNew<vtkIINormalEstimator> one;
    one->SetInputData(part);
    one->SetSourceData(crop);
    one->SetRadius(this->Radius);
    one->SetRadiusUnits(this->RadiusUnits);
    one->SetComputeCurvatures(this->ComputeCurvatures);
    one->SetCurvatureReference(this->CurvatureReference);
    one->SetSelectionModeToLabel();
    one->SetLabel(entry.first);
    one->Update();
    vtkCellData* cd = one->GetOutput()->GetCellData();
    if (one->GetOutput()->GetNumberOfCells() != static_cast<vtkIdType>(cells.size()) || !cd->GetNormals())
    {
      vtkErrorMacro("EachLabel: the estimate of label " << entry.first << " failed (see above).");
      return 0;
    }
    this->NumberOfTrivialFallbacks += one->GetNumberOfTrivialFallbacks();
    std::vector<vtkDataArray*> arrays{ cd->GetNormals() };
    if (this->ComputeCurvatures)
    {
      for (const char* name :
        { "IIMeanCurvature", "IIGaussianCurvature", "IIK1", "IIK2", "IIK1Direction", "IIK2Direction" })
      {
        arrays.push_back(cd->GetArray(name));
      }
    }
    if (results.empty())
    {
      for (vtkDataArray* a : arrays)
      {
        vtkSmartPointer<vtkDataArray> r = vtk::TakeSmartPointer(a->NewInstance());
        r->SetName(a->GetName());
        r->SetNumberOfComponents(a->GetNumberOfComponents());
        r->SetNumberOfTuples(nSurfels);
        results.push_back(r);
      }
    }
    for (std::size_t a = 0; a < arrays.size(); ++a)
    {
      for (std::size_t i = 0; i < cells.size(); ++i)
      {
        results[a]->SetTuple(cells[i], static_cast<vtkIdType>(i), arrays[a]);
      }
    }
    this->UpdateProgress(static_cast<double>(++done) / cellsOf.size());
    if (this->GetAbortExecute())
    {
      return this->Abort->Abort(outputVector);
    }
  }
  output->ShallowCopy(surface);
  output->GetCellData()->SetActiveAttribute(-1, vtkDataSetAttributes::NORMALS);
  for (std::size_t a = 0; a < results.size(); ++a)
  {
    if (a == 0)
    {
      output->GetCellData()->SetNormals(results[a]);
    }
    else
    {
      output->GetCellData()->AddArray(results[a]);
    }
  }
  return 1;
}

void vtkIINormalEstimator::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* modes[] = { "NonZero", "Range", "Label", "EachLabel" };
  os << indent << "Radius: " << this->Radius << "\n";
  os << indent << "RadiusUnits: " << (this->RadiusUnits == WORLD ? "World" : "Voxels") << "\n";
  os << indent << "ComputeCurvatures: " << (this->ComputeCurvatures ? "On" : "Off") << "\n";
  const char* references[] = { "Continuous", "DigitalBall", "DigitalTangentPlane" };
  os << indent << "CurvatureReference: " << references[this->CurvatureReference] << "\n";
  os << indent << "SelectionMode: " << modes[this->SelectionMode] << "\n";
  os << indent << "LowerThreshold: " << this->LowerThreshold << "\n";
  os << indent << "UpperThreshold: " << this->UpperThreshold << "\n";
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "SelectedComponent: " << this->SelectedComponent << "\n";
  os << indent << "NumberOfTrivialFallbacks: " << this->NumberOfTrivialFallbacks << "\n";
}
