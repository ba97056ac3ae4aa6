// The program under mpirun with N > 1 ranks: rank r runs the pipeline for
// piece r of N and writes its piece of each .pvtp; rank 0 writes the summary
// and, unless --no-png, the picture from the gathered surface.
#include "dgBuiltinShape.h"
#include "dgImageInput.h"
#include "dgRender.h"
#include "dgRenderCurvature.h"
#include "dgRenderMesh.h"
#include "vtkPiecewiseSmoothMeshFilter.h"
#include "dgLabels.h"
#include "dgPieces.h"
#include "dgPipeline.h"
#include "dgProcesses.h"

#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkInformation.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkStringOutputWindow.h>
#include <vtkPolyData.h>
#include <vtkOBJWriter.h>
#include <vtkPLYWriter.h>
#include <vtkSTLWriter.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLWriter.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>
#include "dgProgramSupport.h"

namespace dgapp
{
int RunPieces(Options opt, dg::Processes& procs)
{
  const int rank = procs.Rank(), size = procs.Size();
  const bool root = rank == 0;
  // A failure only this rank sees: say it with the rank, and exit non-zero
  // at once (mpirun then ends the ranks that wait for this one in a
  // collective step, within seconds).
  auto rankFail = [&](const std::string& message)
  {
    std::cerr << Program << ": rank " << rank << " of " << size << ": " << message << "\n";
    std::cerr.flush();
    return 1;
  };
  // A collective check: every rank learns whether all are fine; the lowest
  // failing rank alone prints its message (one message, not N).
  auto agreeOrFail = [&](bool ok, const std::string& message)
  {
    const long long first =
      -procs.Max(ok ? -static_cast<double>(size) : -static_cast<double>(rank));
    if (first >= size)
      return true;
    if (first == rank)
      std::cerr << Program << ": "
                << (size > 1 ? "rank " + std::to_string(rank) + " of " + std::to_string(size) + ": "
                             : std::string())
                << message << "\n";
    // Every rank leaves only once the message is out: a rank that exits
    // first can make mpirun end the printing one before it has written.
    procs.Barrier();
    return false;
  };

  if (!opt.Labels.empty())
  {
    if (root)
      std::cerr << Program << ": --labels is not available with " << size
                << " processes (run one process per label, or one process)\n";
    procs.Barrier(); // as in agreeOrFail
    return 2;
  }
  // Only rank 0 renders; it asks for its display before any work.
  {
    const std::string why = root && opt.Png ? PictureUnavailable() : std::string();
    if (!agreeOrFail(why.empty(), why))
      return 1;
  }

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  {
    std::error_code ec;
    std::filesystem::create_directories(opt.OutputDir, ec);
    const bool ok = !ec && std::filesystem::is_directory(opt.OutputDir);
    if (!agreeOrFail(ok,
          "cannot create the output directory '" + opt.OutputDir +
            "': " + (ec ? ec.message() : std::string("a file of that name exists"))))
      return 1;
  }

  vtkNew<ProgressBar> progress;
  progress->Enabled = root && !opt.Quiet && isatty(2);
  vtkNew<ErrorCatcher> errors;
  vtkNew<StageClock> clock;
  clock->Progress = progress;
  auto watch = [&](vtkAlgorithm* algo, const std::string& name, bool warningsFail)
  {
    algo->AddObserver(vtkCommand::ErrorEvent, errors);
    if (warningsFail)
      algo->AddObserver(vtkCommand::WarningEvent, errors);
    algo->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    algo->AddObserver(vtkCommand::ProgressEvent, progress);
    clock->Watch(algo, name);
  };

  // 1. Input: a reader that gives each piece its sub-extent (the noise too
  // reads only its piece and the layers its reach needs), or (formats read
  // whole, the built-in shape) the whole volume on every rank.
  vtkSmartPointer<vtkImageData> image;
  vtkSmartPointer<vtkAlgorithm> reader;
  std::string prefix = opt.Prefix;
  double readTime = 0;
  {
    const auto t0 = Clock::now();
    std::string error;
    if (opt.Input.empty())
    {
      image = dg::MakeBuiltinShape(opt.BuiltinSize);
      if (prefix.empty())
        prefix = "builtin";
    }
    else
    {
      reader = dg::OpenImagePieces(opt.Input, error, opt.Read);
      if (!reader && error.empty())
        image = dg::ReadImage(opt.Input, error, opt.Read);
      if (prefix.empty())
        prefix = Stem(opt.Input);
      // Float or signed values need an explicit selection (every rank
      // reads the same header, so every rank agrees).
      if (error.empty())
      {
        int type = -1;
        if (image && image->GetPointData()->GetScalars())
          type = image->GetPointData()->GetScalars()->GetDataType();
        else if (reader)
        {
          vtkInformation* scalarInfo = vtkDataObject::GetActiveFieldInformation(
            reader->GetOutputInformation(0), vtkDataObject::FIELD_ASSOCIATION_POINTS,
            vtkDataSetAttributes::SCALARS);
          if (scalarInfo && scalarInfo->Has(vtkDataObject::FIELD_ARRAY_TYPE()))
            type = scalarInfo->Get(vtkDataObject::FIELD_ARRAY_TYPE());
        }
        error = DefaultSelectionRefusal(opt, type, opt.Input);
      }
    }
    // A bad header is every rank's failure: one message.
    if (!agreeOrFail(error.empty(), error))
      return 1;
    readTime = std::chrono::duration<double>(Clock::now() - t0).count();
  }

  // 2. The pipeline for this rank's piece, updated once from its last stage.
  dg::Pipeline pipeline;
  if (reader)
  {
    pipeline.Build(reader->GetOutputPort(), opt.P);
    watch(reader, "read", !reader->IsA("vtkDICOMImageReader"));
  }
  else
    pipeline.Build(image, opt.P);
  for (const auto& stage : pipeline.Stages)
    watch(stage.Algorithm, stage.Name, false);
  vtkAlgorithm* last = pipeline.Stages.back().Algorithm;
  // The noise and island stages produce this rank's voxels and the layers
  // the later stages read around them, which the neighbours produce too:
  // their counts are of this rank's own voxels, so that the summary's sums
  // are one process's.
  {
    vtkAlgorithm* first = pipeline.Stages.front().Algorithm;
    first->UpdateInformation();
    vtkInformation* info = first->GetInputInformation(0, 0);
    int wholeExtent[6], own[6];
    if (info && info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    {
      info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), wholeExtent);
      dg::PieceExtent(wholeExtent, rank, size, own);
      pipeline.Noise->SetCountedExtent(own);
      pipeline.Islands->SetCountedExtent(own);
    }
  }
  // Objects inside the stages (a .pvti's piece readers) report to VTK's
  // output window, which no observer sees: collect it, so that a failure
  // says one line (naming the first error) and a success passes the
  // warnings on.
  vtkSmartPointer<vtkOutputWindow> previousWindow = vtkOutputWindow::GetInstance();
  vtkNew<vtkStringOutputWindow> collected;
  vtkOutputWindow::SetInstance(collected);
  const int updated = last->UpdatePiece(rank, size, 0);
  vtkOutputWindow::SetInstance(previousWindow);
  const std::string vtkText = collected->GetOutput();
  if (errors->Failed || !updated)
  {
    std::string message = errors->Failed ? errors->Message : "the pipeline failed on this piece";
    const std::string first = FirstVTKError(vtkText);
    if (!first.empty() && message.find(first) == std::string::npos)
      message += " (first error: " + first + ")";
    return rankFail(message);
  }
  if (!vtkText.empty())
    std::cerr << vtkText;
  if (reader)
  {
    std::string error;
    if (!dg::CheckImagePiece(reader, opt.Input, error))
      return rankFail(error);
  }
  vtkPolyData* result = pipeline.Result();
  vtkPolyData* features = pipeline.Features();
  // The mesh of this rank's faces: the stage is piece-aware, so it is
  // updated as a piece of the same partition.
  vtkNew<vtkPiecewiseSmoothMeshFilter> mesh;
  if (opt.Mesh)
  {
    mesh->SetInputConnection(last->GetOutputPort(0));
    mesh->SetInputArrayToProcess(
      0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, pipeline.NormalsName());
    mesh->SetOutputTriangles(opt.MeshTriangles);
    mesh->SetSolverTolerance(opt.MeshTolerance);
    watch(mesh, "mesh", false);
    if (!mesh->UpdatePiece(rank, size, 0) || errors->Failed)
      return rankFail(errors->Failed ? errors->Message : "the mesh failed on this piece");
  }
  // Every piece is done before any file is made: a rank that failed has
  // exited, and mpirun ends this one while it waits here, with nothing
  // written.
  procs.Barrier();

  // 3. Files: this rank's pieces and (rank 0) the summaries, in a folder of
  // their own until every rank has written, then moved into place.
  const std::filesystem::path outDir(opt.OutputDir);
  const std::filesystem::path partDir = outDir / ("." + prefix + ".parts");
  std::vector<std::string> mine; // file names this rank moves into place
  {
    std::error_code ec;
    std::filesystem::create_directories(partDir, ec);
    // The folder is shared: rank 0 may not remove it before all made it.
    if (!agreeOrFail(!ec, "cannot create '" + partDir.string() + "': " + ec.message()))
      return 1;
  }
  const auto writeStart = Clock::now();
  auto writePieces = [&](vtkPolyData* pd, const std::string& name)
  {
    vtkSmartPointer<vtkXMLWriter> w = procs.PieceWriter(pd, (partDir / (name + ".pvtp")).string());
    ConfigureXMLWriter(w, opt.Compression);
    w->AddObserver(vtkCommand::ErrorEvent, errors);
    w->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    mine.push_back(name + "_" + std::to_string(rank) + ".vtp");
    if (root)
      mine.push_back(name + ".pvtp");
    // Collective (rank 0 learns which pieces hold data): a rank whose piece
    // fails leaves the others waiting, so it exits at once (below) and
    // mpirun ends them; the final names never hold a partial file.
    return w->Write() == 1 && w->GetErrorCode() == vtkErrorCode::NoError && !errors->Failed;
  };
  auto writeFailure = [&](const std::string& name)
  {
    return rankFail("cannot write " + (outDir / (name + ".pvtp")).string() +
                    (errors->Message.empty() ? "" : " (" + errors->Message + ")"));
  };
  if (!writePieces(result, prefix + "_surface"))
    return writeFailure(prefix + "_surface");
  if (!writePieces(features, prefix + "_features"))
    return writeFailure(prefix + "_features");
  if (opt.P.Curvature && !writePieces(pipeline.Creases(), prefix + "_creases"))
    return writeFailure(prefix + "_creases");
  if (opt.Mesh && !writePieces(mesh->GetOutput(0), prefix + "_mesh"))
    return writeFailure(prefix + "_mesh");
  if (opt.Mesh && !writePieces(mesh->GetOutput(1), prefix + "_mesh_creases"))
    return writeFailure(prefix + "_mesh_creases");
  // Formats without pieces: gathered on rank 0, written there (the pieces'
  // border points stay repeated, as the .pvtp's pieces repeat them).
  auto writeGathered = [&](vtkPolyData* pd, const std::vector<std::string>& cells,
                         const std::vector<std::string>& points, const std::string& name,
                         auto makeWriter)
  {
    vtkSmartPointer<vtkPolyData> whole = procs.GatherToRoot(pd, cells, points);
    bool ok = true;
    if (root)
    {
      auto w = makeWriter();
      w->SetInputData(whole);
      w->SetFileName((partDir / name).string().c_str());
      w->AddObserver(vtkCommand::ErrorEvent, errors);
      ok = w->Write() == 1 && w->GetErrorCode() == vtkErrorCode::NoError && !errors->Failed;
      mine.push_back(name);
    }
    return agreeOrFail(ok, "cannot write " + (outDir / name).string());
  };
  const std::vector<std::string> surfaceArrays = { pipeline.NormalsName(), "FeatureRegion" };
  if (opt.Ply && !writeGathered(result, surfaceArrays, {}, prefix + "_surface.ply",
                   [] { return vtkSmartPointer<vtkPLYWriter>::New(); }))
    return 1;
  if (opt.Obj && !writeGathered(result, surfaceArrays, {}, prefix + "_surface.obj",
                   [] { return vtkSmartPointer<vtkOBJWriter>::New(); }))
    return 1;
  if (opt.MeshStl && !writeGathered(mesh->GetOutput(0), {}, {}, prefix + "_mesh.stl", []
                       {
                         auto w = vtkSmartPointer<vtkSTLWriter>::New();
                         w->SetFileTypeToBinary();
                         return w;
                       }))
    return 1;
  if (opt.MeshPly && !writeGathered(mesh->GetOutput(0), {}, { "Normals" }, prefix + "_mesh.ply", []
                       {
                         auto w = vtkSmartPointer<vtkPLYWriter>::New();
                         w->SetFileTypeToBinary();
                         return w;
                       }))
    return 1;
  if (opt.MeshObj && !writeGathered(mesh->GetOutput(0), {}, { "Normals" }, prefix + "_mesh.obj",
                       [] { return vtkSmartPointer<vtkOBJWriter>::New(); }))
    return 1;
  const double writeTime = std::chrono::duration<double>(Clock::now() - writeStart).count();

  // 4. The picture, on rank 0, from the gathered pieces: points, quads and
  // the three normal fields travel (per surfel about one point, 24 bytes,
  // a quad, 40, and three normals, 12 + 24 + 24: 125 bytes on rank 0, twice
  // that while the received pieces are appended).
  double renderTime = 0;
  if (opt.Png)
  {
    const auto t0 = Clock::now();
    vtkSmartPointer<vtkPolyData> whole =
      procs.GatherToRoot(result, { "Normals", pipeline.InputNormalsName(), pipeline.NormalsName() });
    vtkSmartPointer<vtkPolyData> lines = procs.GatherToRoot(features, {});
    if (root)
    {
      dg::RenderOptions ro;
      ro.Width = opt.Width;
      ro.Height = opt.Height;
      ro.Panels = opt.Panels;
      std::string error;
      mine.push_back(prefix + ".png");
      if (!dg::RenderPicture(whole,
            pipeline.InputNormalsName(),
            lines,
            ro,
            (partDir / (prefix + ".png")).string(),
            error))
        return rankFail(error);
    }
    if (opt.P.Curvature)
    {
      vtkSmartPointer<vtkPolyData> curved = procs.GatherToRoot(
        result, { "CorrectedMeanCurvature", "CorrectedK1", "CorrectedK2" });
      vtkSmartPointer<vtkPolyData> creases = procs.GatherToRoot(pipeline.Creases(), {});
      std::string error;
      if (root)
      {
        mine.push_back(prefix + "_curvature.png");
        if (!dg::RenderCurvaturePicture(
              curved, creases, opt.Width, (partDir / (prefix + "_curvature.png")).string(), error))
          return rankFail(error);
      }
    }
    if (opt.Mesh)
    {
      vtkSmartPointer<vtkPolyData> moved = procs.GatherToRoot(mesh->GetOutput(0), {});
      vtkSmartPointer<vtkPolyData> creases = procs.GatherToRoot(mesh->GetOutput(1), {});
      std::string error;
      if (root)
      {
        mine.push_back(prefix + "_mesh.png");
        if (!dg::RenderMeshPicture(
              whole, moved, creases, opt.Width, (partDir / (prefix + "_mesh.png")).string(), error))
          return rankFail(error);
      }
    }
    renderTime = std::chrono::duration<double>(Clock::now() - t0).count();
  }

  // 5. Every rank wrote: move the files into place.
  const bool allWritten = procs.All(true);
  bool moved = true;
  long long surfacePieces = 0, featurePieces = 0;
  for (const auto& name : mine)
  {
    const auto from = partDir / name;
    std::error_code ec;
    if (!std::filesystem::exists(from, ec))
      continue; // an empty piece the writer left out of the summary
    if (allWritten)
    {
      std::filesystem::rename(from, outDir / name, ec);
      moved = moved && !ec;
      if (name == prefix + "_surface_" + std::to_string(rank) + ".vtp")
        ++surfacePieces;
      if (name == prefix + "_features_" + std::to_string(rank) + ".vtp")
        ++featurePieces;
    }
    else
      std::filesystem::remove(from, ec);
  }
  surfacePieces = procs.Sum(surfacePieces);
  featurePieces = procs.Sum(featurePieces);
  const bool allMoved =
    agreeOrFail(moved || !allWritten, "cannot rename the output files in '" + opt.OutputDir + "'");
  if (root)
  {
    std::error_code ec;
    std::filesystem::remove_all(partDir, ec);
  }
  if (!allWritten || !allMoved)
    return 1;

  // 6. The summary, from rank 0, with the counts of all pieces.
  int whole[6] = { 0, -1, 0, -1, 0, -1 };
  if (vtkInformation* info = pipeline.Surface->GetInputInformation(0, 0))
    if (info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
      info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  const long long surfels = procs.Sum(OwnedCells(pipeline.Surface->GetOutput()));
  const long long edges = procs.Sum(static_cast<long long>(features->GetNumberOfLines()));
  const long long atEdges = procs.Sum(static_cast<long long>(pipeline.AT->GetOutput(1)->GetNumberOfLines()));
  const long long islands = procs.Sum(static_cast<long long>(
    opt.P.MinimumComponentSize > 1 ? pipeline.Islands->GetNumberOfRemovedIslands() : 0));
  const long long cavities = procs.Sum(static_cast<long long>(
    opt.P.MinimumComponentSize > 1 ? pipeline.Islands->GetNumberOfFilledCavities() : 0));
  const long long changed = procs.Sum(static_cast<long long>(
    opt.P.MinimumComponentSize > 1 ? pipeline.Islands->GetNumberOfChangedVoxels() : 0));
  const long long flipped = procs.Sum(
    static_cast<long long>(opt.P.Noise > 0 ? pipeline.Noise->GetNumberOfFlippedVoxels() : 0));
  const double memory = PeakMemoryMiB();
  const double memoryMax = procs.Max(memory), memorySum = procs.Sum(memory);
  const double sharpBytes = opt.P.Sharpen ? pipeline.Sharp->GetExchangedBytes() : 0.0;
  const long long sharpMessages =
    opt.P.Sharpen ? static_cast<long long>(pipeline.Sharp->GetExchangedMessages()) : 0;
  const double sharpBytesSum = procs.Sum(sharpBytes);
  const long long sharpMessagesSum = procs.Sum(sharpMessages);
  const double total = std::chrono::duration<double>(Clock::now() - start).count();
  if (!root)
  {
    procs.Finalize();
    return 0;
  }
  std::vector<std::pair<std::string, double>> times;
  bool readSeen = false;
  for (const auto& t : clock->Times)
    readSeen = readSeen || t.first == "read";
  if (!readSeen)
    times.emplace_back("read", readTime);
  for (const auto& t : clock->Times)
    times.push_back(t);
  times.emplace_back("write", writeTime);
  if (opt.Png)
    times.emplace_back("gather + render", renderTime);
  std::ostringstream stages;
  stages << std::fixed;
  stages.precision(3);
  for (const auto& t : times)
    stages << (&t != &times.front() ? ", " : "") << t.first << " " << t.second << " s";
  std::cout << Program << ": " << (opt.Input.empty() ? "built-in shape" : opt.Input) << " "
            << whole[1] - whole[0] + 1 << "x" << whole[3] - whole[2] + 1 << "x"
            << whole[5] - whole[4] + 1 << ": " << surfels << " surfels, " << edges << " feature edges";
  if (opt.P.Sharpen && opt.P.SecondPass)
    std::cout << " (one line per edge, second pass; the first Ambrosio-Tortorelli alone: " << atEdges
              << "; " << size << " processes)\n";
  else if (opt.P.Sharpen)
    std::cout << " (one line per edge; Ambrosio-Tortorelli alone: " << atEdges << "; " << size
              << " processes)\n";
  else
    std::cout << " (Ambrosio-Tortorelli, " << size << " processes)\n";
  if (opt.P.Noise > 0)
    std::cout << "  noise k = " << opt.P.Noise << " (seed " << opt.P.Seed << "): " << flipped
              << " voxels flipped\n";
  if (opt.P.MinimumComponentSize > 1)
    std::cout << "  removed " << islands << " inside components and filled " << cavities
              << " cavities smaller than " << opt.P.MinimumComponentSize << " voxels (" << changed
              << " voxels)\n";
  std::cout << std::fixed;
  std::cout.precision(3);
  std::cout << "  time (rank 0): " << stages.str() << " (total " << total << " s); peak memory "
            << static_cast<long>(memoryMax) << " MiB per rank at most (rank 0 "
            << static_cast<long>(memory) << " MiB, all ranks " << static_cast<long>(memorySum)
            << " MiB)\n";
  if (opt.P.Curvature)
  {
    vtkCorrectedCurvatureFilter* cc = pipeline.Curvature;
    std::cout << "  curvature (" << dg::CurvatureBallText(opt.P.CurvatureRadius, !opt.P.CurvatureFixedRadius,
                                    cc->GetUsedRadius(), nullptr) << "): area " << cc->GetArea()
              << ", integral of H " << cc->GetIntegralMeanCurvature() << ", Euler characteristic "
              << cc->GetIntegralGaussianCurvature() / (2 * M_PI) << " by Gauss-Bonnet, "
              << cc->GetEulerCharacteristic() << " by V - E + F\n";
  }
  if (opt.Mesh)
    std::cout << "  mesh: " << mesh->GetNumberOfCreaseEdges() << " crease edges, largest move "
              << mesh->GetMaximumDisplacement() << " voxel along an axis, "
              << mesh->GetNumberOfBoundCoordinates() << " coordinates at their cell's bound\n";
  if (opt.P.Sharpen)
    std::cout << "  sharp features (gathered on rank 0): crease test " << pipeline.Sharp->GetCreaseTestTime()
              << " s, output field " << pipeline.Sharp->GetFieldTime() << " s; rank 0 sent and received "
              << sharpBytes / (1 << 20) << " MiB in " << sharpMessages << " calls (all ranks: "
              << sharpBytesSum / (1 << 20) << " MiB, " << sharpMessagesSum << " calls)\n";
  for (const auto& [name, pieces] : { std::make_pair(prefix + "_surface", surfacePieces),
         std::make_pair(prefix + "_features", featurePieces) })
    std::cout << "  wrote " << (outDir / (name + ".pvtp")).string() << " and " << pieces
              << " non-empty piece" << (pieces == 1 ? "" : "s") << " " << name
              << "_R.vtp (R = rank)\n";
  if (opt.Png)
    std::cout << "  wrote " << (outDir / (prefix + ".png")).string() << "\n";
  // The other files rank 0 placed: the stages' .pvtp summaries, the
  // gathered formats and the other pictures.
  for (const auto& name : mine)
  {
    const bool piece = name.size() > 4 && name.compare(name.size() - 4, 4, ".vtp") == 0;
    if (!piece && name != prefix + "_surface.pvtp" && name != prefix + "_features.pvtp" &&
      name != prefix + ".png")
      std::cout << "  wrote " << (outDir / name).string() << "\n";
  }
  procs.Finalize();
  return 0;
}
} // namespace dgapp
