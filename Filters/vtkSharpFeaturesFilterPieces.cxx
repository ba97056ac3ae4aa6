// vtkSharpFeaturesFilter over pieces: the surface is gathered on process 0
// in one process's order (faces and points sorted by their global ids,
// which is the order vtkDigitalSurfaceFilter gives one process), the stage
// runs there exactly as in one process, and each process gets back the
// arrays of its own faces and the feature lines it owns. The result is one
// process's, bit for bit, for the same input arrays. Process 0 holds the
// whole surface while the stage runs (about 150 bytes per face on top of
// the stage's own memory): docs/distributed.md says where that stops
// scaling.
#include "vtkSharpFeaturesFilter.h"

#include "dgLineCells.h"
#include "dgPieces.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCommunicator.h>
#include <vtkDataArray.h>
#include <vtkDataArrayRange.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>
#include <vector>

namespace
{

// The configured name of input array `idx` ("" when ParaView has not set one).
std::string SelectedName(vtkInformation* info)
{
  return info && info->Has(vtkDataObject::FIELD_NAME()) && info->Get(vtkDataObject::FIELD_NAME())
    ? info->Get(vtkDataObject::FIELD_NAME())
    : "";
}

constexpr int TagFaces = 9301, TagLineCount = 9302, TagLineIds = 9303, TagLineAngles = 9304;
} // namespace

int vtkSharpFeaturesFilter::RequestDataPieces(vtkMultiProcessController* controller,
  vtkPolyData* input, vtkPolyData* output, vtkPolyData* lines)
{
  const int rank = controller->GetLocalProcessId();
  const int size = controller->GetNumberOfProcesses();
  // What this process sends plus receives (payload), per communication call.
  this->ExchangedBytes = 0;
  this->ExchangedMessages = 0;
  auto exchanged = [this](double bytes) {
    this->ExchangedBytes += bytes;
    ++this->ExchangedMessages;
  };
  auto allOk = [controller, &exchanged](bool ok)
  {
    int mine = ok ? 1 : 0, all = 0;
    controller->AllReduce(&mine, &all, 1, vtkCommunicator::MIN_OP);
    exchanged(2 * sizeof(int));
    return all == 1;
  };
  std::string problem;

  // 1. The arrays Execute reads, found as it finds them.
  vtkCellArray* polys = input->GetPolys();
  const vtkIdType nFaces = polys ? polys->GetNumberOfCells() : 0;
  const vtkIdType nCells = input->GetNumberOfCells(), nPoints = input->GetNumberOfPoints();
  const vtkIdType polyOffset = input->GetNumberOfVerts() + input->GetNumberOfLines();
  const std::string normalsName = SelectedName(this->GetInputArrayInformation(0)).empty()
    ? "ATNormals"
    : SelectedName(this->GetInputArrayInformation(0));
  const std::string indicatorName = SelectedName(this->GetInputArrayInformation(1)).empty()
    ? "ATFeatureIndicator"
    : SelectedName(this->GetInputArrayInformation(1));
  vtkDataArray* normals = input->GetCellData()->GetArray(normalsName.c_str());
  vtkDataArray* indicator = input->GetPointData()->GetArray(indicatorName.c_str());
  const char* inputNames[4] = { this->InputNormalsName.c_str(), "IINormals", "VCMNormals",
    "RHTNormals" };
  int inputIndex = -1; // which of inputNames this piece has (Execute's order)
  for (int i = this->InputNormalsName.empty() ? 1 : 0; i < 4 && inputIndex < 0; ++i)
  {
    if (input->GetCellData()->GetArray(inputNames[i]))
      inputIndex = i;
    if (i == 0)
      break; // a named input field is the only one Execute reads
  }
  vtkDataArray* inputField = inputIndex >= 0 ? input->GetCellData()->GetArray(inputNames[inputIndex]) : nullptr;
  vtkDataArray* cellIds = dg::GlobalIdArray(input->GetCellData(), nCells);
  vtkDataArray* pointIds = dg::GlobalIdArray(input->GetPointData(), nPoints);
  vtkDataArray* ghosts = input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
  if (ghosts && ghosts->GetNumberOfTuples() != nCells)
    ghosts = nullptr;
  if (nFaces > 0)
  {
    if (!normals || normals->GetNumberOfComponents() != 3)
      problem = "no 3-component cell normal field '" + normalsName + "'.";
    else if (!indicator || indicator->GetNumberOfComponents() != 1)
      problem = "no point feature indicator '" + indicatorName + "'.";
    else if (inputField && inputField->GetNumberOfComponents() != 3)
      problem = std::string("the input normal field '") + inputNames[inputIndex] +
        "' must have 3 components.";
    else if (!cellIds || !pointIds)
      problem = "a distributed run needs cell and point global ids (the 'GlobalIds' arrays of "
                "vtkDigitalSurfaceFilter) to match faces and points across pieces.";
  }
  // Every piece with faces must see the same input normal field.
  int lowest = nFaces > 0 ? inputIndex : 4, highest = nFaces > 0 ? inputIndex : -2;
  int allLowest = lowest, allHighest = highest;
  controller->AllReduce(&lowest, &allLowest, 1, vtkCommunicator::MIN_OP);
  controller->AllReduce(&highest, &allHighest, 1, vtkCommunicator::MAX_OP);
  exchanged(2 * sizeof(lowest));
  exchanged(2 * sizeof(highest));
  if (problem.empty() && allHighest >= -1 && allLowest != allHighest)
    problem = "the pieces do not all have the same input normal field.";
  if (!allOk(problem.empty()))
  {
    if (!problem.empty())
      vtkErrorMacro("Piece " << rank << " of " << size << ": " << problem);
    return 0;
  }
  const bool hasInput = allHighest >= 0;
  const int inputName = allHighest;

  // 2. This piece's own faces: ids as integers, values as doubles.
  std::vector<vtkIdType> faceIds, pointGids;      // per face: gid, size, point gids
  std::vector<double> faceValues, pointValues;    // per face: u (3), input (3); per point: xyz, v
  std::vector<vtkIdType> ownCell;                 // input cell of each own face
  // Ghost faces get their owner's results too: a stage after this one that
  // reads its input on the ghost ring (AT's second pass) must see there what
  // one process gives, not this piece's AT normals.
  std::vector<vtkIdType> ghostIds, ghostCell;     // gid and input cell of each ghost face
  {
    std::vector<char> used(nPoints, 0);
    vtkIdType npts = 0;
    const vtkIdType* ids = nullptr;
    for (vtkIdType f = 0; f < nFaces; ++f)
    {
      const vtkIdType cell = polyOffset + f;
      if (ghosts &&
        (static_cast<int>(ghosts->GetComponent(cell, 0)) &
          (vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL)))
      {
        ghostIds.push_back(static_cast<vtkIdType>(cellIds->GetComponent(cell, 0)));
        ghostCell.push_back(cell);
        continue;
      }
      polys->GetCellAtId(f, npts, ids);
      faceIds.push_back(static_cast<vtkIdType>(cellIds->GetComponent(cell, 0)));
      faceIds.push_back(npts);
      for (vtkIdType k = 0; k < npts; ++k)
      {
        faceIds.push_back(static_cast<vtkIdType>(pointIds->GetComponent(ids[k], 0)));
        used[ids[k]] = 1;
      }
      double t[3];
      normals->GetTuple(cell, t);
      faceValues.insert(faceValues.end(), t, t + 3);
      if (hasInput)
      {
        inputField->GetTuple(cell, t);
        faceValues.insert(faceValues.end(), t, t + 3);
      }
      ownCell.push_back(cell);
    }
    for (vtkIdType p = 0; p < nPoints; ++p)
    {
      if (!used[p])
        continue;
      double x[3];
      input->GetPoint(p, x);
      pointGids.push_back(static_cast<vtkIdType>(pointIds->GetComponent(p, 0)));
      pointValues.insert(pointValues.end(), x, x + 3);
      pointValues.push_back(indicator->GetComponent(p, 0));
    }
  }

  // 3. Everything to process 0.
  auto gather = [&](const auto& mine, auto& all, std::vector<vtkIdType>& counts)
  {
    vtkIdType n = static_cast<vtkIdType>(mine.size());
    counts.assign(size, 0);
    controller->Gather(&n, counts.data(), 1, 0);
    std::vector<vtkIdType> offsets(size, 0);
    for (int r = 1; r < size; ++r)
      offsets[r] = offsets[r - 1] + counts[r - 1];
    all.resize(rank == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
    controller->GatherV(mine.data(), all.data(), n, counts.data(), offsets.data(), 0);
    const double item = sizeof(mine[0]);
    if (rank == 0)
    {
      exchanged(sizeof(vtkIdType) * (size - 1.0));
      exchanged(item * static_cast<double>(all.size() - mine.size()));
    }
    else
    {
      exchanged(sizeof(vtkIdType));
      exchanged(item * static_cast<double>(n));
    }
  };
  std::vector<vtkIdType> allFaceIds, allPointGids, nFaceIds, nPointGids, nFaceValues, nPointValues;
  std::vector<double> allFaceValues, allPointValues;
  gather(faceIds, allFaceIds, nFaceIds);
  gather(faceValues, allFaceValues, nFaceValues);
  gather(pointGids, allPointGids, nPointGids);
  gather(pointValues, allPointValues, nPointValues);
  std::vector<vtkIdType> allGhostIds, nGhostIds;
  gather(ghostIds, allGhostIds, nGhostIds);

  // 4. Process 0: the whole surface in one process's order, and the stage.
  int status = 1;
  std::vector<std::vector<double>> faceResults(size);            // per process: sharp (3), region, sides
  std::vector<std::vector<vtkIdType>> lineIds(size);             // per process: point gid pairs
  std::vector<std::vector<double>> lineAngles(size);
  double stats[12] = { 0 };
  if (rank == 0)
  {
    struct Face
    {
      vtkIdType Gid, IdStart, ValueStart;
      int Rank;
      vtkIdType Index; // within its process's faces
    };
    std::vector<Face> faces;
    const int per = hasInput ? 6 : 3;
    {
      vtkIdType k = 0, valueStart = 0;
      for (int r = 0; r < size; ++r)
      {
        const vtkIdType end = k + nFaceIds[r];
        vtkIdType index = 0;
        while (k < end)
        {
          faces.push_back({ allFaceIds[k], k, valueStart, r, index++ });
          valueStart += per;
          k += 2 + allFaceIds[k + 1];
        }
      }
    }
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) { return a.Gid < b.Gid; });
    // Points by gid (a point shared by pieces comes from each: the same).
    std::vector<std::pair<vtkIdType, vtkIdType>> byGid; // gid, index in allPointGids
    for (vtkIdType i = 0; i < static_cast<vtkIdType>(allPointGids.size()); ++i)
      byGid.emplace_back(allPointGids[i], i);
    std::sort(byGid.begin(), byGid.end());
    byGid.erase(std::unique(byGid.begin(), byGid.end(),
                  [](const auto& a, const auto& b) { return a.first == b.first; }),
      byGid.end());
    std::unordered_map<vtkIdType, vtkIdType> pointIndex;
    pointIndex.reserve(byGid.size());
    auto whole = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetNumberOfPoints(static_cast<vtkIdType>(byGid.size()));
    vtkNew<vtkDoubleArray> v;
    v->SetName(indicatorName.c_str());
    v->SetNumberOfTuples(static_cast<vtkIdType>(byGid.size()));
    for (vtkIdType i = 0; i < static_cast<vtkIdType>(byGid.size()); ++i)
    {
      const double* x = &allPointValues[4 * byGid[i].second];
      pts->SetPoint(i, x);
      v->SetValue(i, x[3]);
      pointIndex[byGid[i].first] = i;
    }
    vtkNew<vtkCellArray> cells;
    vtkNew<vtkDoubleArray> u, in;
    u->SetName(normalsName.c_str());
    u->SetNumberOfComponents(3);
    u->SetNumberOfTuples(static_cast<vtkIdType>(faces.size()));
    in->SetName(hasInput ? inputNames[inputName] : "unused");
    in->SetNumberOfComponents(3);
    in->SetNumberOfTuples(hasInput ? static_cast<vtkIdType>(faces.size()) : 0);
    std::vector<vtkIdType> corner;
    for (std::size_t f = 0; f < faces.size(); ++f)
    {
      const vtkIdType n = allFaceIds[faces[f].IdStart + 1];
      corner.resize(n);
      for (vtkIdType k = 0; k < n; ++k)
        corner[k] = pointIndex.at(allFaceIds[faces[f].IdStart + 2 + k]);
      cells->InsertNextCell(n, corner.data());
      u->SetTuple(static_cast<vtkIdType>(f), &allFaceValues[faces[f].ValueStart]);
      if (hasInput)
        in->SetTuple(static_cast<vtkIdType>(f), &allFaceValues[faces[f].ValueStart + 3]);
    }
    whole->SetPoints(pts);
    whole->SetPolys(cells);
    whole->GetCellData()->AddArray(u);
    if (hasInput)
      whole->GetCellData()->AddArray(in);
    whole->GetPointData()->AddArray(v);
    whole->GetFieldData()->ShallowCopy(input->GetFieldData());
    vtkNew<vtkPolyData> wholeOut, wholeLines;
    status = this->Execute(whole, wholeOut, wholeLines);
    if (status == 1)
    {
      vtkDataArray* sharp = wholeOut->GetCellData()->GetArray("SharpNormals");
      vtkDataArray* region = wholeOut->GetCellData()->GetArray("FeatureRegion");
      vtkDataArray* sides = wholeOut->GetCellData()->GetArray("CreaseSides");
      for (int r = 0; r < size; ++r)
        faceResults[r].resize(5 * (nFaceValues[r] / per + nGhostIds[r]));
      for (std::size_t f = 0; f < faces.size(); ++f)
      {
        double* o = &faceResults[faces[f].Rank][5 * faces[f].Index];
        sharp->GetTuple(static_cast<vtkIdType>(f), o);
        o[3] = region->GetComponent(static_cast<vtkIdType>(f), 0);
        o[4] = sides->GetComponent(static_cast<vtkIdType>(f), 0);
      }
      // Then each process's ghost faces, in the order it listed them (faces
      // is sorted by gid); a ghost no process owns keeps region -2 and the
      // receiver its own values.
      vtkIdType listed = 0; // index in allGhostIds
      for (int r = 0; r < size; ++r)
        for (vtkIdType g = 0; g < nGhostIds[r]; ++g, ++listed)
        {
          double* o = &faceResults[r][5 * (nFaceValues[r] / per + g)];
          const auto it = std::lower_bound(faces.begin(), faces.end(), allGhostIds[listed],
            [](const Face& a, vtkIdType gid) { return a.Gid < gid; });
          if (it == faces.end() || it->Gid != allGhostIds[listed])
          {
            o[3] = -2;
            continue;
          }
          const vtkIdType f = static_cast<vtkIdType>(it - faces.begin());
          sharp->GetTuple(f, o);
          o[3] = region->GetComponent(f, 0);
          o[4] = sides->GetComponent(f, 0);
        }
      // Each line to the process of the first face (in gid order) on it.
      std::map<std::pair<vtkIdType, vtkIdType>, int> sideOwner;
      for (std::size_t f = 0; f < faces.size(); ++f)
      {
        const vtkIdType n = allFaceIds[faces[f].IdStart + 1];
        for (vtkIdType k = 0; k < n; ++k)
        {
          vtkIdType a = allFaceIds[faces[f].IdStart + 2 + k];
          vtkIdType b = allFaceIds[faces[f].IdStart + 2 + (k + 1) % n];
          if (a > b)
            std::swap(a, b);
          sideOwner.emplace(std::make_pair(a, b), faces[f].Rank);
        }
      }
      vtkDataArray* angle = wholeLines->GetCellData()->GetArray("FeatureAngle");
      vtkIdType npts = 0;
      const vtkIdType* ids = nullptr;
      for (vtkIdType l = 0; l < wholeLines->GetNumberOfLines(); ++l)
      {
        wholeLines->GetLines()->GetCellAtId(l, npts, ids);
        vtkIdType a = byGid[ids[0]].first, b = byGid[ids[1]].first;
        const auto owner = sideOwner.find(std::make_pair(std::min(a, b), std::max(a, b)));
        const int r = owner == sideOwner.end() ? 0 : owner->second;
        lineIds[r].push_back(a);
        lineIds[r].push_back(b);
        lineAngles[r].push_back(angle ? angle->GetComponent(l, 0) : 0.0);
      }
      const double s[12] = { static_cast<double>(this->NumberOfBandFaces),
        static_cast<double>(this->NumberOfUnassignedFaces), static_cast<double>(this->NumberOfRegions),
        static_cast<double>(this->NumberOfPlanarRegions),
        static_cast<double>(this->NumberOfQuadricRegions),
        static_cast<double>(this->NumberOfQuadricMerges), static_cast<double>(this->NumberOfCreases),
        static_cast<double>(this->NumberOfBends), this->NoiseShare, this->UsedFieldWidth,
        this->CreaseTestTime, this->FieldTime };
      std::copy(s, s + 12, stats);
    }
  }
  controller->Broadcast(&status, 1, 0);
  exchanged(sizeof(status) * (rank == 0 ? size - 1.0 : 1.0));
  if (status != 1)
    return 0; // process 0 said why (or was aborted)
  controller->Broadcast(stats, 12, 0);
  exchanged(sizeof(stats) * (rank == 0 ? size - 1.0 : 1.0));
  this->NumberOfBandFaces = static_cast<vtkIdType>(stats[0]);
  this->NumberOfUnassignedFaces = static_cast<vtkIdType>(stats[1]);
  this->NumberOfRegions = static_cast<int>(stats[2]);
  this->NumberOfPlanarRegions = static_cast<int>(stats[3]);
  this->NumberOfQuadricRegions = static_cast<int>(stats[4]);
  this->NumberOfQuadricMerges = static_cast<int>(stats[5]);
  this->NumberOfCreases = static_cast<int>(stats[6]);
  this->NumberOfBends = static_cast<int>(stats[7]);
  this->NoiseShare = stats[8];
  this->UsedFieldWidth = stats[9];
  this->CreaseTestTime = stats[10];
  this->FieldTime = stats[11];

  // 5. Each process's part back.
  std::vector<double> mine(5 * (ownCell.size() + ghostCell.size()));
  std::vector<vtkIdType> myLineIds;
  std::vector<double> myLineAngles;
  if (rank == 0)
  {
    for (int r = 1; r < size; ++r)
    {
      controller->Send(faceResults[r].data(), static_cast<vtkIdType>(faceResults[r].size()), r, TagFaces);
      vtkIdType n = static_cast<vtkIdType>(lineAngles[r].size());
      controller->Send(&n, 1, r, TagLineCount);
      controller->Send(lineIds[r].data(), 2 * n, r, TagLineIds);
      controller->Send(lineAngles[r].data(), n, r, TagLineAngles);
      exchanged(sizeof(double) * static_cast<double>(faceResults[r].size()));
      exchanged(sizeof(n));
      exchanged(sizeof(vtkIdType) * 2.0 * n);
      exchanged(sizeof(double) * static_cast<double>(n));
    }
    mine = std::move(faceResults[0]);
    myLineIds = std::move(lineIds[0]);
    myLineAngles = std::move(lineAngles[0]);
  }
  else
  {
    controller->Receive(mine.data(), static_cast<vtkIdType>(mine.size()), 0, TagFaces);
    vtkIdType n = 0;
    controller->Receive(&n, 1, 0, TagLineCount);
    myLineIds.resize(2 * n);
    myLineAngles.resize(n);
    controller->Receive(myLineIds.data(), 2 * n, 0, TagLineIds);
    controller->Receive(myLineAngles.data(), n, 0, TagLineAngles);
    exchanged(sizeof(double) * static_cast<double>(mine.size()));
    exchanged(sizeof(n));
    exchanged(sizeof(vtkIdType) * 2.0 * n);
    exchanged(sizeof(double) * static_cast<double>(n));
  }

  // 6. The outputs on this piece, as Execute writes them.
  output->ShallowCopy(input);
  vtkNew<vtkDoubleArray> sharp;
  sharp->SetName("SharpNormals");
  sharp->SetNumberOfComponents(3);
  sharp->SetNumberOfTuples(nCells);
  vtkNew<vtkIntArray> region;
  region->SetName("FeatureRegion");
  region->SetNumberOfTuples(nCells);
  vtkNew<vtkUnsignedCharArray> sides;
  sides->SetName("CreaseSides");
  sides->SetNumberOfTuples(nCells);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    double t[3] = { 0, 0, 0 };
    if (normals)
      normals->GetTuple(c, t);
    sharp->SetTuple(c, t);
    region->SetValue(c, -1);
    sides->SetValue(c, 0);
  }
  for (std::size_t f = 0; f < ownCell.size(); ++f)
  {
    sharp->SetTuple(ownCell[f], &mine[5 * f]);
    region->SetValue(ownCell[f], static_cast<int>(mine[5 * f + 3]));
    sides->SetValue(ownCell[f], static_cast<unsigned char>(mine[5 * f + 4]));
  }
  for (std::size_t g = 0; g < ghostCell.size(); ++g)
  {
    const double* o = &mine[5 * (ownCell.size() + g)];
    if (o[3] == -2)
      continue;
    sharp->SetTuple(ghostCell[g], o);
    region->SetValue(ghostCell[g], static_cast<int>(o[3]));
    sides->SetValue(ghostCell[g], static_cast<unsigned char>(o[4]));
  }
  output->GetCellData()->AddArray(sharp);
  output->GetCellData()->SetActiveNormals("SharpNormals");
  output->GetCellData()->AddArray(region);
  output->GetCellData()->AddArray(sides);
  std::unordered_map<vtkIdType, vtkIdType> local;
  for (vtkIdType p = 0; pointIds && p < nPoints; ++p)
    local[static_cast<vtkIdType>(pointIds->GetComponent(p, 0))] = p;
  std::vector<vtkIdType> ends(myLineIds.size());
  for (std::size_t i = 0; i < myLineIds.size(); ++i)
    ends[i] = local.at(myLineIds[i]);
  lines->SetPoints(input->GetPoints());
  lines->GetPointData()->PassData(input->GetPointData());
  lines->SetLines(dg::TwoPointLines(ends));
  lines->GetCellData()->AddArray(dg::LineValues("FeatureAngle", myLineAngles));
  this->UpdateProgress(1.0);
  return 1;
}
