// piecewise-normals: from a segmented volume to its digital surface,
// integral-invariant normals, Ambrosio-Tortorelli regularised normals, sharp
// features, and a picture. See --help. The options are in
// dgProgramOptions.cxx, the run under mpirun in dgRunPieces.cxx.
#include "dgBuiltinShape.h"
#include "dgImageInput.h"
#include "dgRender.h"
#include "dgRenderCurvature.h"
#include "dgRenderMesh.h"
#include "dgLabels.h"
#include "dgPipeline.h"
#include "dgProcesses.h"
#include "vtkPiecewiseSmoothMeshFilter.h"

#include <vtkAppendPolyData.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkOBJWriter.h>
#include <vtkPLYWriter.h>
#include <vtkSTLWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkXMLPolyDataWriter.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>
#include "dgProgramOptions.h"
#include "dgProgramSupport.h"

using namespace dgapp;

int main(int argc, char* argv[])
{
  ReexecWithHugePages(argv); // before anything is allocated or printed
  const Options opt = ParseOptions(argc, argv);
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
  {
    vtkSMPTools::SetBackend("STDThread"); // Debian's ParaView VTK defaults to sequential
  }
  // Launched by mpirun with N > 1 processes: one piece per rank.
  dg::Processes procs;
  {
    std::string error;
    if (!procs.Initialize(&argc, &argv, error))
    {
      if (PrintsCommonMessages())
        std::cerr << Program << ": " << error << "\n";
      return 2;
    }
  }
  if (procs.Distributed())
  {
    return RunPieces(opt, procs);
  }
  if (opt.Png)
  {
    const std::string why = PictureUnavailable();
    if (!why.empty())
      return Fail(why);
  }
  using Clock = std::chrono::steady_clock;
  std::vector<std::pair<std::string, double>> times;
  auto t = Clock::now();
  auto lap = [&](const std::string& stage)
  {
    const auto now = Clock::now();
    times.emplace_back(stage, std::chrono::duration<double>(now - t).count());
    t = now;
  };

  // Before any work: a run that cannot write its results should not take
  // minutes to say so.
  {
    std::error_code ec;
    std::filesystem::create_directories(opt.OutputDir, ec);
    if (ec || !std::filesystem::is_directory(opt.OutputDir))
      return Fail("cannot create the output directory '" + opt.OutputDir +
                  "': " + (ec ? ec.message() : std::string("a file of that name exists")));
  }

  vtkNew<ProgressBar> progress;
  progress->Enabled = !opt.Quiet && isatty(2);
  vtkNew<ErrorCatcher> errors;
  auto watch = [&](vtkAlgorithm* algo)
  {
    algo->AddObserver(vtkCommand::ErrorEvent, errors);
    algo->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    algo->AddObserver(vtkCommand::ProgressEvent, progress);
  };

  // 1. Input volume.
  vtkSmartPointer<vtkImageData> image;
  std::string prefix = opt.Prefix;
  if (opt.Input.empty())
  {
    image = dg::MakeBuiltinShape(opt.BuiltinSize);
    if (prefix.empty())
      prefix = "builtin";
  }
  else
  {
    std::string error;
    image = dg::ReadImage(opt.Input, error, opt.Read);
    if (!image)
      return Fail(error);
    if (vtkDataArray* scalars = image->GetPointData()->GetScalars())
    {
      const std::string refusal = DefaultSelectionRefusal(opt, scalars->GetDataType(), opt.Input);
      if (!refusal.empty())
        return Fail(refusal);
      const std::string empty = EmptySelectionMessage(opt, scalars);
      if (!empty.empty())
        return Fail("'" + opt.Input + "': " + empty);
    }
    if (prefix.empty())
      prefix = Stem(opt.Input);
  }
  lap("read");

  // 2. The pipeline, one stage at a time (progress bar, timings, errors):
  // once on the whole volume, or with --labels once per label on that
  // label's box of the volume grown by the stages' reach.
  struct Run
  {
    vtkSmartPointer<vtkImageData> Image;
    dg::PipelineSettings Settings;
    long long Label = 0;
  };
  std::vector<Run> runs;
  std::vector<dg::LabelBox> labelBoxes;
  if (opt.Labels.empty())
  {
    runs.push_back({ image, opt.P, 0 });
  }
  else
  {
    dg::LabelSpec spec;
    std::string error;
    if (!dg::ParseLabelSpec(opt.Labels, spec, error) ||
        !dg::FindLabels(image, spec, labelBoxes, error))
      return Fail("--labels: " + error);
    const int margin = dg::LabelMargin(opt.P);
    for (const dg::LabelBox& box : opt.Interfaces ? std::vector<dg::LabelBox>() : labelBoxes)
    {
      Run run{ dg::CropImage(image, box.Extent, margin), opt.P, box.Label };
      run.Settings.SelectionMode = vtkDigitalSurfaceFilter::LABEL;
      run.Settings.Label = static_cast<double>(box.Label);
      runs.push_back(run);
    }
    lap("labels");
  }
  vtkNew<vtkAppendPolyData> appendSurfaces, appendFeatures;
  std::unique_ptr<dg::Pipeline> pipelinePtr;
  long long surfels = 0, atLines = 0, removed = 0, filled = 0, changed = 0, flipped = 0;
  std::vector<std::string> perLabel;
  std::map<std::string, double> stageTimes;
  std::vector<std::string> stageOrder;
  double creaseTime = 0, fieldTime = 0; // the sharp stage's crease test and output field
  for (Run& run : runs)
  {
    pipelinePtr.reset(new dg::Pipeline);
    dg::Pipeline& pipeline = *pipelinePtr;
    pipeline.Build(run.Image, run.Settings);
    for (const auto& stage : pipeline.Stages)
    {
      watch(stage.Algorithm);
      progress->Stage =
        labelBoxes.empty() ? stage.Name : "label " + std::to_string(run.Label) + ": " + stage.Name;
      const auto t0 = Clock::now();
      stage.Algorithm->Update();
      if (errors->Failed)
        return Fail((labelBoxes.empty() ? "" : "label " + std::to_string(run.Label) + ": ") +
                    errors->Message);
      if (!stageTimes.count(stage.Name))
        stageOrder.push_back(stage.Name);
      stageTimes[stage.Name] += std::chrono::duration<double>(Clock::now() - t0).count();
    }
    const long long n = pipeline.Surface->GetOutput()->GetNumberOfPolys();
    surfels += n;
    atLines += pipeline.AT->GetOutput(1)->GetNumberOfLines();
    creaseTime += pipeline.Sharp->GetCreaseTestTime();
    fieldTime += pipeline.Sharp->GetFieldTime();
    if (run.Settings.Noise > 0)
      flipped += pipeline.Noise->GetNumberOfFlippedVoxels();
    if (run.Settings.MinimumComponentSize > 1)
    {
      removed += pipeline.Islands->GetNumberOfRemovedIslands();
      filled += pipeline.Islands->GetNumberOfFilledCavities();
      changed += pipeline.Islands->GetNumberOfChangedVoxels();
    }
    if (labelBoxes.empty())
      break;
    // Each label's outputs, tagged, into one surface and one set of lines.
    for (vtkPolyData* pd : { pipeline.Result(), pipeline.Features() })
    {
      vtkNew<vtkPolyData> tagged;
      tagged->ShallowCopy(pd);
      vtkNew<vtkIntArray> label;
      label->SetName("Label");
      label->SetNumberOfTuples(pd->GetNumberOfCells());
      label->FillValue(static_cast<int>(run.Label));
      tagged->GetCellData()->AddArray(label);
      (pd == pipeline.Result() ? appendSurfaces.Get() : appendFeatures.Get())->AddInputData(tagged);
    }
    std::ostringstream line;
    line << "  label " << run.Label << ": " << n << " surfels, "
         << pipeline.Features()->GetNumberOfLines() << " feature edges";
    perLabel.push_back(line.str());
    run.Image = nullptr; // the crop is no longer needed
  }
  // --interfaces: every interface face once, one AT on the whole complex.
  vtkNew<vtkAmbrosioTortorelliFilter> interfacesAT;
  if (opt.Interfaces)
  {
    auto runStage = [&](vtkAlgorithm* algorithm, const std::string& name)
    {
      watch(algorithm);
      progress->Stage = name;
      const auto t0 = Clock::now();
      algorithm->Update();
      const std::string key =
        name.substr(name.find(": ") == std::string::npos ? 0 : name.find(": ") + 2);
      if (!stageTimes.count(key))
        stageOrder.push_back(key);
      stageTimes[key] += std::chrono::duration<double>(Clock::now() - t0).count();
      return !errors->Failed;
    };
    std::string error;
    auto merged = dg::LabelInterfaces(image, labelBoxes, opt.P, runStage, error);
    if (!merged)
      return Fail(errors->Failed ? errors->Message : error);
    interfacesAT->SetInputData(merged);
    dg::ConfigureAT(interfacesAT, opt.P);
    if (!runStage(interfacesAT, "Ambrosio-Tortorelli"))
      return Fail(errors->Message);
    surfels = merged->GetNumberOfPolys();
    atLines = interfacesAT->GetOutput(1)->GetNumberOfLines();
  }
  for (const auto& name : stageOrder)
  {
    times.emplace_back(name, stageTimes[name]);
  }
  t = Clock::now();
  vtkPolyData* result = nullptr;
  vtkPolyData* features = nullptr;
  const char* inputNormalsName = "IINormals";
  if (opt.Interfaces)
  {
    result = interfacesAT->GetOutput(0);
    features = interfacesAT->GetOutput(1);
  }
  else if (labelBoxes.empty())
  {
    result = pipelinePtr->Result();
    features = pipelinePtr->Features();
    inputNormalsName = pipelinePtr->InputNormalsName();
  }
  else
  {
    appendSurfaces->Update();
    appendFeatures->Update();
    result = appendSurfaces->GetOutput();
    features = appendFeatures->GetOutput();
    inputNormalsName = pipelinePtr->InputNormalsName();
    // The picture shows the active normals: keep the pipeline's choice.
    result->GetCellData()->SetActiveNormals(pipelinePtr->NormalsName());
    lap("append");
  }

  // 4b. The piecewise-smooth mesh of the final normals (every mode: one
  // surface, labels appended, label interfaces).
  vtkNew<vtkPiecewiseSmoothMeshFilter> mesh;
  if (opt.Mesh)
  {
    vtkDataArray* normals = result->GetCellData()->GetNormals();
    mesh->SetInputData(result);
    mesh->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS,
      normals && normals->GetName() ? normals->GetName() : "SharpNormals");
    mesh->SetOutputTriangles(opt.MeshTriangles);
    mesh->SetSolverTolerance(opt.MeshTolerance);
    watch(mesh);
    progress->Stage = "mesh";
    t = Clock::now();
    mesh->Update();
    if (errors->Failed)
      return Fail(errors->Message);
    lap("mesh");
  }

  // 5. Files.
  OutputFiles files;
  const std::string base = (std::filesystem::path(opt.OutputDir) / prefix).string();
  // The writers' errors go to the catcher too: one line instead of VTK's
  // multi-line report, and the reason (errno text) is in it.
  auto written = [&](auto* w)
  {
    w->AddObserver(vtkCommand::ErrorEvent, errors);
    w->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    // Write() can return 1 when the file did not open; the error code tells.
    return w->Write() == 1 && w->GetErrorCode() == vtkErrorCode::NoError && !errors->Failed;
  };
  auto writeFailure = [&](const std::string& path)
  {
    return Fail(
      "cannot write " + path + (errors->Message.empty() ? "" : " (" + errors->Message + ")"));
  };
  auto writeVtp = [&](vtkPolyData* pd, const std::string& path)
  {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetInputData(pd);
    w->SetFileName(files.Temporary(path).c_str());
    w->SetDataModeToBinary(); // appended data trips Debian's expat + VTK 9.2 reader
    // LZ4 by default: on octa-flower 512^3 it writes in 1.1-1.4 s against
    // zlib's 2.8-3.4 s (a fifth of the whole program), for files 1.35x larger
    // (101 against 74 MB).
    if (opt.Compression == "zlib")
      w->SetCompressorTypeToZLib();
    else if (opt.Compression == "none")
      w->SetCompressorTypeToNone();
    else
      w->SetCompressorTypeToLZ4();
    return written(w.Get());
  };
  if (!writeVtp(result, base + "_surface.vtp"))
    return writeFailure(base + "_surface.vtp");
  if (!writeVtp(features, base + "_features.vtp"))
    return writeFailure(base + "_features.vtp");
  if (opt.P.Curvature && !writeVtp(pipelinePtr->Creases(), base + "_creases.vtp"))
    return writeFailure(base + "_creases.vtp");
  if (opt.Mesh)
  {
    if (!writeVtp(mesh->GetOutput(0), base + "_mesh.vtp"))
      return writeFailure(base + "_mesh.vtp");
    if (!writeVtp(mesh->GetOutput(1), base + "_mesh_creases.vtp"))
      return writeFailure(base + "_mesh_creases.vtp");
    if (opt.MeshStl)
    {
      vtkNew<vtkSTLWriter> w;
      w->SetInputData(mesh->GetOutput(0));
      w->SetFileTypeToBinary();
      w->SetFileName(files.Temporary(base + "_mesh.stl").c_str());
      if (!written(w.Get()))
        return writeFailure(base + "_mesh.stl");
    }
    if (opt.MeshPly)
    {
      vtkNew<vtkPLYWriter> w;
      w->SetInputData(mesh->GetOutput(0));
      w->SetFileTypeToBinary();
      w->SetFileName(files.Temporary(base + "_mesh.ply").c_str());
      if (!written(w.Get()))
        return writeFailure(base + "_mesh.ply");
    }
    if (opt.MeshObj)
    {
      vtkNew<vtkOBJWriter> w;
      w->SetInputData(mesh->GetOutput(0));
      w->SetFileName(files.Temporary(base + "_mesh.obj").c_str());
      if (!written(w.Get()))
        return writeFailure(base + "_mesh.obj");
    }
  }
  if (opt.Ply)
  {
    vtkNew<vtkPLYWriter> w;
    w->SetInputData(result);
    w->SetFileName(files.Temporary(base + "_surface.ply").c_str());
    if (!written(w.Get()))
      return writeFailure(base + "_surface.ply");
  }
  if (opt.Obj)
  {
    vtkNew<vtkOBJWriter> w;
    w->SetInputData(result);
    w->SetFileName(files.Temporary(base + "_surface.obj").c_str());
    if (!written(w.Get()))
      return writeFailure(base + "_surface.obj");
  }
  lap("write");
  if (opt.Png)
  {
    dg::RenderOptions ro;
    ro.Width = opt.Width;
    ro.Height = opt.Height;
    ro.Panels = opt.Panels;
    std::string error;
    const std::string png = files.Temporary(base + ".png");
    if (!dg::RenderPicture(result, inputNormalsName, features, ro, png, error))
      return Fail(error);
    if (opt.P.Curvature &&
      !dg::RenderCurvaturePicture(result, pipelinePtr->Creases(), opt.Width,
        files.Temporary(base + "_curvature.png"), error))
      return Fail(error);
    if (opt.Mesh &&
      !dg::RenderMeshPicture(result,
        mesh->GetOutput(0), mesh->GetOutput(1), opt.Width, files.Temporary(base + "_mesh.png"),
        error))
      return Fail(error);
    lap("render");
  }
  if (!files.Commit())
    return Fail("cannot rename the output files in '" + opt.OutputDir + "'");

  int dims[3];
  image->GetDimensions(dims);
  std::ostringstream stages;
  double total = 0;
  for (const auto& s : times)
  {
    stages << (total > 0 || &s != &times.front() ? ", " : "") << s.first << " " << std::fixed;
    stages.precision(3);
    stages << s.second << " s";
    total += s.second;
  }
  std::cout << Program << ": " << (opt.Input.empty() ? "built-in shape" : opt.Input) << " "
            << dims[0] << "x" << dims[1] << "x" << dims[2] << ": " << surfels << " surfels, "
            << features->GetNumberOfLines() << " feature edges";
  if (opt.Interfaces)
    std::cout << " (label interfaces, Ambrosio-Tortorelli's own output)";
  else if (opt.P.Sharpen && opt.P.SecondPass)
    std::cout << " (one line per edge, second pass; the first Ambrosio-Tortorelli alone: "
              << atLines << ")";
  else if (opt.P.Sharpen)
    std::cout << " (one line per edge; Ambrosio-Tortorelli alone: " << atLines << ")";
  if (!labelBoxes.empty())
    std::cout << ", " << labelBoxes.size() << " label" << (labelBoxes.size() == 1 ? "" : "s");
  std::cout << "\n";
  for (const auto& line : perLabel)
    std::cout << line << "\n";
  if (opt.P.Noise > 0)
    std::cout << "  noise k = " << opt.P.Noise << " (seed " << opt.P.Seed << "): " << flipped
              << " voxels flipped\n";
  if (opt.P.MinimumComponentSize > 1)
    std::cout << "  removed " << removed << " inside components and filled " << filled
              << " cavities smaller than " << opt.P.MinimumComponentSize << " voxels (" << changed
              << " voxels)\n";
  std::cout << "  time: " << stages.str() << " (total " << total << " s); peak memory "
            << static_cast<long>(PeakMemoryMiB()) << " MiB" << (HugePageMalloc() ? " (huge-page malloc)" : "") << "\n";
  if (opt.P.Sharpen && !opt.Interfaces)
    std::cout << "  sharp features: crease test " << creaseTime << " s, output field " << fieldTime
              << " s\n";
  if (opt.P.Curvature)
  {
    vtkCorrectedCurvatureFilter* cc = pipelinePtr->Curvature;
    const double area = cc->GetArea(), volume = cc->GetVolume();
    std::cout << "  curvature (" << dg::CurvatureBallText(opt.P.CurvatureRadius, !opt.P.CurvatureFixedRadius,
                                    cc->GetUsedRadius(), cc->GetOutput(0)) << "): area " << area;
    if (std::isfinite(volume) && volume != 0)
      std::cout << ", volume " << std::abs(volume) << ", specific surface area "
                << area / std::abs(volume);
    std::cout << ", integral of H " << cc->GetIntegralMeanCurvature() << " (creases "
              << cc->GetCreaseIntegralMeanCurvature() << "), Euler characteristic "
              << std::fixed << std::setprecision(4)
              << cc->GetIntegralGaussianCurvature() / (2 * M_PI) + 0.0 << std::defaultfloat
              << " by Gauss-Bonnet, "
              << cc->GetEulerCharacteristic() << " by V - E + F\n";
  }
  if (opt.Mesh)
    std::cout << "  mesh: " << mesh->GetOutput(0)->GetNumberOfPolys()
              << (opt.MeshTriangles ? " triangles" : " faces") << ", "
              << mesh->GetNumberOfCreaseEdges() << " crease edges, largest move "
              << mesh->GetMaximumDisplacement() << " voxel along an axis, "
              << mesh->GetNumberOfBoundCoordinates() << " coordinates at their cell's bound\n";
  for (const auto& f : files.Finals)
    std::cout << "  wrote " << f << "\n";
  return 0;
}
