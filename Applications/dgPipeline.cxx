#include "dgPipeline.h"

#include <vtkAlgorithmOutput.h>

namespace dg
{

void ConfigureAT(vtkAmbrosioTortorelliFilter* a, const PipelineSettings& s)
{
  a->SetAlpha(s.Alpha);
  a->SetLambda(s.Lambda);
  a->SetEpsilonStart(s.EpsStart);
  a->SetEpsilonEnd(s.EpsEnd);
  a->SetEpsilonRatio(s.EpsRatio);
  a->SetMaximumIterations(s.Iterations);
  a->SetTolerance(s.Tolerance);
  a->SetFeatureThreshold(s.FeatureThreshold);
  a->SetLinearSolver(s.Solver);
  a->SetSolverTolerance(s.SolverTolerance);
  a->SetSolverToleranceEarlyFactor(s.SolverToleranceEarlyFactor);
  a->SetMetric(s.Metric);
}

void Pipeline::Build(vtkImageData* image, const PipelineSettings& s)
{
  this->Build(image, nullptr, s);
}

void Pipeline::Build(vtkAlgorithmOutput* source, const PipelineSettings& s)
{
  this->Build(nullptr, source, s);
}

void Pipeline::Build(vtkImageData* image, vtkAlgorithmOutput* source, const PipelineSettings& s)
{
  this->Settings = s;
  this->Input = image;
  this->InputPort = source;
  this->Stages.clear();
  // The selection applies to the input; every stage after the noise or the
  // island filter sees a 0/1 volume and selects it as it is.
  int mode = s.SelectionMode;
  // The stages' input: the image itself, or a source's port (a reader that
  // gives each piece its sub-extent).
  vtkAlgorithmOutput* volume = nullptr;
  auto connectInput = [&](vtkAlgorithm* stage) {
    if (source)
      stage->SetInputConnection(source);
    else
      stage->SetInputDataObject(image);
  };
  if (s.Noise > 0)
  {
    connectInput(this->Noise);
    this->Noise->SetSelectionMode(mode);
    this->Noise->SetLowerThreshold(s.Lower);
    this->Noise->SetUpperThreshold(s.Upper);
    this->Noise->SetLabel(s.Label);
    this->Noise->SetNoiseLevel(s.Noise);
    this->Noise->SetSeed(s.Seed);
    volume = this->Noise->GetOutputPort();
    mode = vtkDigitalSurfaceFilter::NON_ZERO;
    this->Stages.push_back({ "noise", this->Noise });
  }
  if (s.MinimumComponentSize > 1)
  {
    if (volume)
      this->Islands->SetInputConnection(volume);
    else
      connectInput(this->Islands);
    this->Islands->SetSelectionMode(mode);
    this->Islands->SetLowerThreshold(s.Lower);
    this->Islands->SetUpperThreshold(s.Upper);
    this->Islands->SetLabel(s.Label);
    this->Islands->SetMinimumSize(s.MinimumComponentSize);
    volume = this->Islands->GetOutputPort();
    mode = vtkDigitalSurfaceFilter::NON_ZERO;
    this->Stages.push_back({ "islands", this->Islands });
  }
  if (volume)
    this->Surface->SetInputConnection(volume);
  else
    connectInput(this->Surface);
  this->Surface->SetSelectionMode(mode);
  this->Surface->SetLowerThreshold(s.Lower);
  this->Surface->SetUpperThreshold(s.Upper);
  this->Surface->SetLabel(s.Label);
  this->Stages.push_back({ "digital surface", this->Surface });

  // The estimators read the same image and count the same voxels as inside
  // as the surface did.
  auto connectEstimator = [&](auto* e) {
    e->SetInputConnection(this->Surface->GetOutputPort());
    if (volume)
      e->SetSourceConnection(volume);
    else if (source)
      e->SetSourceConnection(source);
    else
      e->SetSourceData(image);
    e->SetSelectionMode(this->Surface->GetSelectionMode());
    e->SetLowerThreshold(s.Lower);
    e->SetUpperThreshold(s.Upper);
    e->SetLabel(s.Label);
  };
  vtkAlgorithm* estimator = this->II;
  if (s.Estimator == "vcm")
  {
    connectEstimator(this->VCM.Get());
    this->VCM->SetOffsetRadius(s.VCMOffsetRadius);
    this->VCM->SetConvolutionRadius(s.VCMConvolutionRadius);
    estimator = this->VCM;
    this->Stages.push_back({ "VCM normals", this->VCM });
  }
  else if (s.Estimator == "rht")
  {
    connectEstimator(this->RHT.Get());
    this->RHT->SetRadius(s.RHTRadius);
    this->RHT->SetNumberOfTrials(s.RHTTrials);
    this->RHT->SetSeed(s.Seed);
    estimator = this->RHT;
    this->Stages.push_back({ "RHT normals", this->RHT });
  }
  else
  {
    connectEstimator(this->II.Get());
    this->II->SetRadius(s.Radius);
    this->II->SetComputeCurvatures(s.Curvatures);
    this->Stages.push_back({ "II normals", this->II });
  }

  // AT reads the active cell normals: the estimator's.
  this->AT->SetInputConnection(estimator->GetOutputPort());
  ConfigureAT(this->AT, s);
  this->Stages.push_back({ "Ambrosio-Tortorelli", this->AT });

  // How far the input normals blur a crease: the estimator's radius.
  const double blur = s.Estimator == "vcm" ? s.VCMConvolutionRadius
    : s.Estimator == "rht"                 ? s.RHTRadius
                                           : s.Radius;
  if (s.Sharpen)
  {
    this->Sharp->SetInputConnection(this->AT->GetOutputPort());
    this->Sharp->SetFeatureThreshold(s.FeatureThreshold);
    this->Sharp->SetInputRadius(blur);
    this->Stages.push_back({ "sharp features", this->Sharp });
  }
  if (this->UseSecondPass())
  {
    this->AT2->SetInputConnection(this->Sharp->GetOutputPort());
    this->AT2->SetInputArrayToProcess(
      0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "SharpNormals");
    ConfigureAT(this->AT2, s);
    this->Stages.push_back({ "Ambrosio-Tortorelli 2", this->AT2 });
    this->Sharp2->SetInputConnection(this->AT2->GetOutputPort());
    this->Sharp2->SetFeatureThreshold(s.FeatureThreshold);
    this->Sharp2->SetInputRadius(blur);
    this->Stages.push_back({ "sharp features 2", this->Sharp2 });
  }
  if (s.Curvature)
  {
    // Reads the active normals of the stage before (the final field).
    this->Curvature->SetInputConnection(this->Normals()->GetOutputPort(0));
    this->Curvature->SetRadius(s.CurvatureRadius);
    this->Curvature->SetAdaptiveRadius(!s.CurvatureFixedRadius);
    this->Stages.push_back({ "corrected curvature", this->Curvature });
  }
}

vtkAlgorithm* Pipeline::Normals()
{
  if (this->UseSecondPass())
    return this->Sharp2;
  return this->Settings.Sharpen ? static_cast<vtkAlgorithm*>(this->Sharp) : this->AT;
}

const char* Pipeline::InputNormalsName() const
{
  if (this->Settings.Estimator == "vcm")
    return "VCMNormals";
  if (this->Settings.Estimator == "rht")
    return "RHTNormals";
  return "IINormals";
}

vtkPolyData* Pipeline::Result()
{
  if (this->Settings.Curvature)
    return this->Curvature->GetOutput(0);
  return vtkPolyData::SafeDownCast(this->Normals()->GetOutputDataObject(0));
}

vtkPolyData* Pipeline::Features()
{
  if (this->UseSecondPass())
    return this->Sharp2->GetOutput(1);
  return this->Settings.Sharpen ? this->Sharp->GetOutput(1) : this->AT->GetOutput(1);
}

vtkImageData* Pipeline::Volume()
{
  if (this->Settings.MinimumComponentSize > 1)
    return this->Islands->GetOutput();
  if (this->Settings.Noise > 0)
    return this->Noise->GetOutput();
  if (this->InputPort)
    return vtkImageData::SafeDownCast(this->InputPort->GetProducer()->GetOutputDataObject(
      this->InputPort->GetIndex()));
  return this->Input;
}

} // namespace dg
