// The program's pipeline and its defaults, in one place so that the tests
// run exactly what piecewise-normals runs:
//   volume -> [noise] -> islands and cavities removed -> digital surface ->
//   II (or VCM, RHT) normals -> Ambrosio-Tortorelli -> sharp features (one
//   line per edge)
// Build() only connects the stages; the caller updates them (the program one
// stage at a time, for its progress bar and timings).
#ifndef dgPipeline_h
#define dgPipeline_h

#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkCorrectedCurvatureFilter.h"
#include "vtkDigitalIslandFilter.h"
#include "vtkDigitalNoiseFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"
#include "vtkRHTNormalEstimator.h"
#include "vtkVCMNormalEstimator.h"
#include "vtkSharpFeaturesFilter.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>

#include <string>
#include <vector>

namespace dg
{

struct PipelineSettings
{
  // Inside voxels.
  int SelectionMode = vtkDigitalSurfaceFilter::NON_ZERO;
  double Lower = 1, Upper = VTK_DOUBLE_MAX, Label = 1;
  // The paper's noise model (docs/method.md section 7); 0 = none.
  double Noise = 0;
  int Seed = 0;
  // Inside components and cavities smaller than this many voxels are
  // removed before the surface is built (docs/islands.md); 0 = keep all.
  int MinimumComponentSize = 8;
  // The input normals: "ii" (integral invariant, default), "vcm" (Voronoi
  // covariance measure) or "rht" (randomized Hough transform), docs/method.md
  // sections 6, 9, 10; each with the paper's parameters.
  std::string Estimator = "ii";
  // Integral invariant.
  double Radius = 4;
  bool Curvatures = false;
  // VCM offset and convolution radii; RHT radius and trials.
  double VCMOffsetRadius = 10, VCMConvolutionRadius = 4;
  double RHTRadius = 6;
  int RHTTrials = 648;
  // Ambrosio-Tortorelli. Alpha is the paper's Figure 5 value; Lambda is half
  // the paper's 0.01: the sharp-features stage removes AT's extra lines, and
  // a generous AT closes the bands along shallow edges
  // (docs/sharp-features.md).
  double Alpha = 0.05, Lambda = 0.005, EpsStart = 2, EpsEnd = 0.25, EpsRatio = 2;
  int Iterations = 5;
  double Tolerance = 1e-4, FeatureThreshold = 0.5;
  int Solver = vtkAmbrosioTortorelliFilter::CONJUGATE_GRADIENT_IC;
  int Metric = vtkAmbrosioTortorelliFilter::METRIC_GRID;
  // CG's relative residual (the filter's default).
  double SolverTolerance = 1e-5;
  // Multiple of it on the epsilon levels before the last (the filter's
  // SolverToleranceEarlyFactor; 1 = every level at SolverTolerance).
  double SolverToleranceEarlyFactor = 1.0;
  // One line per sharp edge and side normals (vtkSharpFeaturesFilter); off
  // gives the paper's own output (AT's lines and normals).
  bool Sharpen = true;
  // A second AT pass fed with the first pass's side normals (an input that
  // does not blur across the edges: AT alone then draws one line per edge),
  // then the sharp stage again: normals 10-30 % closer near the edges, twice
  // AT's time (docs/sharp-features.md). Needs Sharpen.
  bool SecondPass = false;
  // Corrected curvature measures of the final normals, per side of the
  // sharp stage's creases (vtkCorrectedCurvatureFilter), ball radius in
  // voxels: each face's own from that scale (AdaptiveRadius), or that one
  // for every face (CurvatureFixedRadius).
  bool Curvature = false;
  double CurvatureRadius = 6;
  bool CurvatureFixedRadius = false;
};

/// The settings' AT parameters on an AT filter (every AT the program runs).
void ConfigureAT(vtkAmbrosioTortorelliFilter* at, const PipelineSettings& settings);

class Pipeline
{
public:
  /// Connects the stages for `image` with `settings` (nothing runs).
  void Build(vtkImageData* image, const PipelineSettings& settings);
  /// The same, fed by a source's output port (a reader that produces the
  /// sub-extent each piece asks for), for runs in pieces.
  void Build(vtkAlgorithmOutput* source, const PipelineSettings& settings);

  struct Stage
  {
    std::string Name;
    vtkAlgorithm* Algorithm;
  };
  /// The stages in execution order (only those in use).
  std::vector<Stage> Stages;

  /// After the last stage ran: the surface with all normal fields (the
  /// final ones active) and the feature lines.
  vtkPolyData* Result();
  vtkPolyData* Features();
  /// With Curvature: the creases between the sharp stage's regions and
  /// their angles (vtkCorrectedCurvatureFilter's port 1).
  vtkPolyData* Creases() { return this->Curvature->GetOutput(1); }
  /// The voxels the surface was built from (after noise and islands; a
  /// piece of them when the pipeline ran for a piece).
  vtkImageData* Volume();
  /// Name of the input normal field ("IINormals", "VCMNormals", "RHTNormals").
  const char* InputNormalsName() const;
  /// Name of the final normal field ("SharpNormals" or "ATNormals").
  const char* NormalsName() const { return this->Settings.Sharpen ? "SharpNormals" : "ATNormals"; }
  /// The AT stage whose lines the sharp stage read (the second one if any).
  vtkAmbrosioTortorelliFilter* LastAT() { return this->UseSecondPass() ? this->AT2.Get() : this->AT.Get(); }

  vtkNew<vtkDigitalNoiseFilter> Noise;
  vtkNew<vtkDigitalIslandFilter> Islands;
  vtkNew<vtkDigitalSurfaceFilter> Surface;
  vtkNew<vtkIINormalEstimator> II;
  vtkNew<vtkVCMNormalEstimator> VCM;
  vtkNew<vtkRHTNormalEstimator> RHT;
  vtkNew<vtkAmbrosioTortorelliFilter> AT;
  vtkNew<vtkSharpFeaturesFilter> Sharp;
  vtkNew<vtkAmbrosioTortorelliFilter> AT2;
  vtkNew<vtkSharpFeaturesFilter> Sharp2;
  vtkNew<vtkCorrectedCurvatureFilter> Curvature;

private:
  void Build(vtkImageData* image, vtkAlgorithmOutput* source, const PipelineSettings& settings);
  /// The stage whose port 0 holds the final normals.
  vtkAlgorithm* Normals();
  bool UseSecondPass() const { return this->Settings.Sharpen && this->Settings.SecondPass; }
  PipelineSettings Settings;
  vtkImageData* Input = nullptr;
  vtkAlgorithmOutput* InputPort = nullptr;
};

} // namespace dg

#endif
