#include "vtkDigitalSurfaceFilter.h"

#include "dgPipelineAbort.h"
#include "dgCubicalSurface.h"
#include "dgPieces.h"
#include "dgVoxelSelection.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkInformationIntegerKey.h>
#include <vtkInformationIntegerRequestKey.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>
#include <sstream>

vtkStandardNewMacro(vtkDigitalSurfaceFilter);

namespace
{
// A request key, like the piece keys: the executive copies it upstream
// through any filter in between (ParaView puts a vtkPVPostFilter after every
// output), and re-executes the stages above when its value changes.
class ImageReachKey : public vtkInformationIntegerRequestKey
{
public:
  ImageReachKey()
    : vtkInformationIntegerRequestKey("IMAGE_GHOST_LEVELS", "vtkDigitalSurfaceFilter")
  {
    static vtkInformationIntegerKey* data =
      new vtkInformationIntegerKey("DATA_IMAGE_GHOST_LEVELS", "vtkDigitalSurfaceFilter");
    this->DataKey = data;
  }
};
} // namespace

vtkInformationIntegerKey* vtkDigitalSurfaceFilter::IMAGE_GHOST_LEVELS()
{
  static ImageReachKey* key = new ImageReachKey;
  return key;
}

namespace
{
using SDDP = vtkStreamingDemandDrivenPipeline;

// The piece this execution is asked for: its own voxels and the extent of
// surfels it emits (own grown by the ghost levels).
struct PieceRequest
{
  int Piece = 0, Pieces = 1, Ghosts = 0;
  int Whole[6] = { 0, -1, 0, -1, 0, -1 };
  int Own[6] = { 0, -1, 0, -1, 0, -1 };
  int Emit[6] = { 0, -1, 0, -1, 0, -1 };
  bool Distributed() const { return this->Pieces > 1; }
};

PieceRequest ReadPieceRequest(vtkInformation* outInfo, vtkInformation* inInfo)
{
  PieceRequest r;
  if (outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES()))
  {
    r.Pieces = std::max(1, outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()));
    r.Piece = outInfo->Get(SDDP::UPDATE_PIECE_NUMBER());
    r.Ghosts = std::max(0, outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS()));
  }
  if (inInfo && inInfo->Has(SDDP::WHOLE_EXTENT()))
  {
    inInfo->Get(SDDP::WHOLE_EXTENT(), r.Whole);
  }
  dg::PieceExtent(r.Whole, r.Piece, r.Pieces, r.Own);
  dg::GrowExtent(r.Own, r.Ghosts, r.Whole, r.Emit);
  return r;
}

// Keeps the surfels whose inside voxel lies in `emit` (in their order) and
// the points they use (renumbered by first use); returns each kept surfel's
// ghost flag (DUPLICATECELL outside `own`).
std::vector<unsigned char> KeepPieceSurfels(dg::CubicalSurface& s,
  const int ext[6],
  const int own[6],
  const int emit[6])
{
  const std::int64_t n = s.NumberOfSurfels();
  std::vector<std::int64_t> pointMap(s.NumberOfPoints(), -1);
  std::vector<unsigned char> ghost;
  std::int64_t kept = 0, points = 0;
  auto within = [](const int v[3], const int e[6])
  {
    return v[0] >= e[0] && v[0] <= e[1] && v[1] >= e[2] && v[1] <= e[3] && v[2] >= e[4] &&
           v[2] <= e[5];
  };
  for (std::int64_t c = 0; c < n; ++c)
  {
    const int v[3] = {
      s.Voxels[3 * c] + ext[0], s.Voxels[3 * c + 1] + ext[2], s.Voxels[3 * c + 2] + ext[4]
    };
    if (!within(v, emit))
    {
      continue;
    }
    ghost.push_back(within(v, own) ? 0 : vtkDataSetAttributes::DUPLICATECELL);
    for (int q = 0; q < 4; ++q)
    {
      std::int64_t& m = pointMap[s.Quads[4 * c + q]];
      if (m < 0)
      {
        m = points++;
      }
      s.Quads[4 * kept + q] = m;
    }
    for (int a = 0; a < 3; ++a)
    {
      s.Voxels[3 * kept + a] = s.Voxels[3 * c + a];
    }
    s.Directions[kept] = s.Directions[c];
    ++kept;
  }
  std::vector<std::int32_t> corners(3 * points);
  for (std::size_t p = 0; p < pointMap.size(); ++p)
  {
    for (int a = 0; pointMap[p] >= 0 && a < 3; ++a)
    {
      corners[3 * pointMap[p] + a] = s.Corners[3 * p + a];
    }
  }
  s.Corners.swap(corners);
  s.Quads.resize(4 * kept);
  s.Voxels.resize(3 * kept);
  s.Directions.resize(kept);
  return ghost;
}
} // namespace

vtkDigitalSurfaceFilter::~vtkDigitalSurfaceFilter()
{
  this->SetLabels(nullptr);
}

vtkDigitalSurfaceFilter::vtkDigitalSurfaceFilter()
{
  this->SetLabels("all");
  this->Abort = std::make_unique<dg::PipelineAbort>();
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::SCALARS);
}

int vtkDigitalSurfaceFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

vtkMTimeType vtkDigitalSurfaceFilter::GetMTime()
{
  const vtkMTimeType base = this->Superclass::GetMTime();
  return this->Abort ? this->Abort->MTime(base) : base;
}

int vtkDigitalSurfaceFilter::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  // Pieces are cut from the image by this filter (RequestUpdateExtent).
  outputVector->GetInformationObject(0)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkDigitalSurfaceFilter::RequestUpdateExtent(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (!inInfo || !inInfo->Has(SDDP::WHOLE_EXTENT()))
  {
    return 1;
  }
  const PieceRequest r = ReadPieceRequest(outInfo, inInfo);
  const int extra = outInfo->Has(IMAGE_GHOST_LEVELS()) ? outInfo->Get(IMAGE_GHOST_LEVELS()) : 0;
  int need[6];
  // One layer beyond the emitted surfels decides whether their faces are
  // surfels at all.
  dg::GrowExtent(r.Own, std::max(r.Ghosts + 1, extra), r.Whole, need);
  if (dg::ExtentEmpty(need))
  {
    // VTK's convention for "nothing": the executive then does not run the
    // upstream for this piece.
    const int none[6] = { 0, -1, 0, -1, 0, -1 };
    inInfo->Set(SDDP::UPDATE_EXTENT(), none, 6);
  }
  else
  {
    inInfo->Set(SDDP::UPDATE_EXTENT(), need, 6);
  }
  // The extent says it all: piece keys would have the executive cut it again.
  inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  return 1;
}

int vtkDigitalSurfaceFilter::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  const int status = this->ExecutePiece(request, inputVector, outputVector);
  // In a distributed run every piece stops when one fails: the later
  // stages' collective steps would otherwise wait for it forever.
  if (!dg::AllPiecesOk(outputVector->GetInformationObject(0), status != 0))
  {
    vtkPolyData::GetData(outputVector)->Initialize();
    return 0;
  }
  return status;
}

int vtkDigitalSurfaceFilter::ExecutePiece(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro("Missing input image or output.");
    return 0;
  }
  const auto abortGuard = this->Abort->Begin(this, outputVector);
  if (dg::PipelineAbort::InputAborted(inputVector, this->GetNumberOfInputPorts()))
  {
    return this->Abort->Abort(outputVector);
  }
  int ext[6];
  input->GetExtent(ext);
  PieceRequest piece = ReadPieceRequest(
    outputVector->GetInformationObject(0), inputVector[0]->GetInformationObject(0));
  if (!piece.Distributed() || dg::ExtentEmpty(piece.Whole))
  {
    // One piece: the surface of the image as given (SetInputData included).
    piece.Pieces = 1;
    std::copy(ext, ext + 6, piece.Own);
    std::copy(ext, ext + 6, piece.Emit);
    if (dg::ExtentEmpty(piece.Whole))
    {
      std::copy(ext, ext + 6, piece.Whole);
    }
  }
  const int* checked = piece.Distributed() ? piece.Whole : ext;
  const int dims[3] = { ext[1] - ext[0] + 1, ext[3] - ext[2] + 1, ext[5] - ext[4] + 1 };
  const int checkedDims[3] = {
    checked[1] - checked[0] + 1, checked[3] - checked[2] + 1, checked[5] - checked[4] + 1
  };
  if (checkedDims[0] <= 0 || checkedDims[1] <= 0 || checkedDims[2] <= 0)
  {
    vtkErrorMacro("Input image is empty (extent " << checked[0] << ".." << checked[1] << ", "
                                                  << checked[2] << ".." << checked[3] << ", "
                                                  << checked[4] << ".." << checked[5] << ").");
    return 0;
  }
  // A one-voxel-thick image would still bound a closed surface, but it is
  // almost always a 2D slice given by mistake: say so rather than guess.
  if (checkedDims[0] == 1 || checkedDims[1] == 1 || checkedDims[2] == 1)
  {
    vtkErrorMacro("Input image is 2D; a digital surface needs a 3D image, at least 2 voxels "
                  "along each axis (dimensions "
                  << checkedDims[0] << " x " << checkedDims[1] << " x " << checkedDims[2] << ").");
    return 0;
  }
  if (this->SelectionMode == EACH_LABEL || this->SelectionMode == INTERFACES)
  {
    if (piece.Distributed())
    {
      vtkErrorMacro("SelectionMode "
                    << (this->SelectionMode == EACH_LABEL ? "EachLabel" : "Interfaces")
                    << " runs in one piece only (asked for piece " << piece.Piece << " of "
                    << piece.Pieces << ").");
      return 0;
    }
    return this->ExecuteEachLabel(input,
      dg::SelectionArray(
        this->GetInputArrayToProcess(0, inputVector), this->GetInputArrayInformation(0), input),
      piece.Whole,
      output,
      outputVector);
  }
  dg::CubicalSurface surface;
  const bool emptyPiece = dg::ExtentEmpty(piece.Own);
  if (piece.Distributed() && !emptyPiece)
  {
    int need[6];
    dg::GrowExtent(piece.Own, piece.Ghosts + 1, piece.Whole, need);
    if (!dg::ExtentContains(ext, need))
    {
      vtkErrorMacro("Piece " << piece.Piece << " of " << piece.Pieces << " needs the voxels "
                             << need[0] << ".." << need[1] << ", " << need[2] << ".." << need[3]
                             << ", " << need[4] << ".." << need[5]
                             << " but the input image holds only " << ext[0] << ".." << ext[1]
                             << ", " << ext[2] << ".." << ext[3] << ", " << ext[4] << ".." << ext[5]
                             << ": its source does not produce the requested sub-extents.");
      return 0;
    }
  }
  if (!emptyPiece)
  {
    vtkDataArray* scalars = dg::SelectionArray(
      this->GetInputArrayToProcess(0, inputVector), this->GetInputArrayInformation(0), input);

    // 1. Selection mask.
    dg::PaddedMask mask;
    mask.Allocate(dims[0], dims[1], dims[2]);
    const dg::VoxelSelection select{ this->SelectionMode,
      this->LowerThreshold,
      this->UpperThreshold,
      this->Label,
      this->SelectedComponent };
    std::int64_t insideCount = 0;
    std::string error;
    if (!dg::SelectVoxels(
          scalars, dims, select, mask.Data.data(), mask.RowLength(), 1, insideCount, error))
    {
      vtkErrorMacro("Cannot select voxels: " << error << ".");
      return 0;
    }
    // In a piece, no inside voxel is normal (the shape lies elsewhere).
    if (insideCount == 0 && !piece.Distributed())
    {
      // Say what was asked, in the user's terms (the program's options).
      std::ostringstream asked;
      switch (this->SelectionMode)
      {
        case LABEL:
          asked << "No voxel has the label " << this->Label;
          break;
        case RANGE:
          asked << "No voxel value is in the range [" << this->LowerThreshold << ", "
                << this->UpperThreshold << "]";
          break;
        default:
          asked << "No voxel is non-zero";
          break;
      }
      if (scalars && this->SelectedComponent < scalars->GetNumberOfComponents())
      {
        double range[2];
        scalars->GetRange(range, this->SelectedComponent);
        asked << " (the values are " << range[0] << " to " << range[1] << ")";
      }
      vtkErrorMacro(<< asked.str() << ": the surface is empty.");
      return 0;
    }
    if (insideCount == static_cast<std::int64_t>(dims[0]) * dims[1] * dims[2] &&
        !piece.Distributed())
    {
      vtkWarningMacro("Every voxel is inside: the surface is the border of the image.");
    }
    mask.UpdateRowBounds();
    this->UpdateProgress(0.3);
    if (this->GetAbortExecute())
    {
      return this->Abort->Abort(outputVector);
    }

    // 2. The cubical complex.
    const bool done = dg::ExtractCubicalSurface(mask,
      surface,
      [this](double f)
      {
        this->UpdateProgress(0.3 + 0.6 * f);
        return !this->GetAbortExecute();
      });
    if (!done)
    {
      return this->Abort->Abort(outputVector);
    }
  }
  // 2b. A piece keeps the surfels it emits (own, then ghosts) and their points.
  std::vector<unsigned char> ghost;
  if (piece.Distributed())
  {
    ghost = KeepPieceSurfels(surface, ext, piece.Own, piece.Emit);
  }

  // 3. World geometry. The index-to-physical matrix includes the image's
  // direction; a reflection flips the winding, so quads are then reversed.
  double origin[3], spacing[3];
  input->GetOrigin(origin);
  input->GetSpacing(spacing);
  double dir[9];
  {
    vtkMatrix3x3* d = input->GetDirectionMatrix();
    for (int a = 0; a < 9; ++a)
    {
      dir[a] = d->GetData()[a];
    }
  }
  const double det = vtkMatrix3x3::Determinant(dir);
  const bool reflect = det * spacing[0] * spacing[1] * spacing[2] < 0;

  const std::int64_t nPoints = surface.NumberOfPoints();
  const std::int64_t nSurfels = surface.NumberOfSurfels();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nPoints);
  auto* pts = vtkDoubleArray::SafeDownCast(points->GetData())->GetPointer(0);
  vtkSMPTools::For(0,
    nPoints,
    [&](std::int64_t b, std::int64_t e)
    {
      for (std::int64_t p = b; p < e; ++p)
      {
        double idx[3];
        for (int a = 0; a < 3; ++a)
        {
          idx[a] = spacing[a] * (ext[2 * a] + surface.Corners[3 * p + a] - 0.5);
        }
        for (int r = 0; r < 3; ++r)
        {
          pts[3 * p + r] =
            origin[r] + dir[3 * r] * idx[0] + dir[3 * r + 1] * idx[1] + dir[3 * r + 2] * idx[2];
        }
      }
    });

  vtkNew<vtkIdTypeArray> offsets, connectivity;
  offsets->SetNumberOfValues(nSurfels + 1);
  connectivity->SetNumberOfValues(4 * nSurfels);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(nSurfels);
  vtkNew<vtkIntArray> voxels;
  voxels->SetName("InsideVoxel");
  voxels->SetNumberOfComponents(3);
  voxels->SetNumberOfTuples(nSurfels);
  vtkNew<vtkUnsignedCharArray> directions;
  directions->SetName("SurfelDirection");
  directions->SetNumberOfTuples(nSurfels);
  // Outward normal of each direction: sign(d) * (column d/2 of the direction
  // matrix), with the spacing's sign folded in.
  float dirNormals[6][3];
  for (int d = 0; d < 6; ++d)
  {
    const int axis = d / 2;
    const double sign = ((d & 1) ? 1.0 : -1.0) * (spacing[axis] < 0 ? -1.0 : 1.0);
    double n[3] = { sign * dir[axis], sign * dir[3 + axis], sign * dir[6 + axis] };
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 3; ++a)
    {
      dirNormals[d][a] = static_cast<float>(len > 0 ? n[a] / len : 0.0);
    }
  }
  vtkIdType* off = offsets->GetPointer(0);
  vtkIdType* conn = connectivity->GetPointer(0);
  float* nrm = normals->GetPointer(0);
  int* vox = voxels->GetPointer(0);
  unsigned char* dirs = directions->GetPointer(0);
  vtkSMPTools::For(0,
    nSurfels,
    [&](std::int64_t b, std::int64_t e)
    {
      for (std::int64_t s = b; s < e; ++s)
      {
        off[s] = 4 * s;
        for (int c = 0; c < 4; ++c)
        {
          conn[4 * s + c] = surface.Quads[4 * s + (reflect ? 3 - c : c)];
        }
        const int d = surface.Directions[s];
        for (int a = 0; a < 3; ++a)
        {
          nrm[3 * s + a] = dirNormals[d][a];
          vox[3 * s + a] = surface.Voxels[3 * s + a] + ext[2 * a];
        }
        dirs[s] = static_cast<unsigned char>(d);
      }
    });
  off[nSurfels] = 4 * nSurfels;

  // Global ids from the whole extent's grid (see the class description).
  const std::int64_t wn[3] = { piece.Whole[1] - piece.Whole[0] + 1,
    piece.Whole[3] - piece.Whole[2] + 1,
    piece.Whole[5] - piece.Whole[4] + 1 };
  vtkNew<vtkIdTypeArray> cellIds, pointIds;
  cellIds->SetName("GlobalIds");
  pointIds->SetName("GlobalIds");
  cellIds->SetNumberOfValues(nSurfels);
  pointIds->SetNumberOfValues(nPoints);
  vtkIdType* cid = cellIds->GetPointer(0);
  vtkIdType* pid = pointIds->GetPointer(0);
  int shift[3];
  for (int a = 0; a < 3; ++a)
  {
    shift[a] = ext[2 * a] - piece.Whole[2 * a];
  }
  vtkSMPTools::For(0,
    nSurfels,
    [&](std::int64_t b, std::int64_t e)
    {
      for (std::int64_t c = b; c < e; ++c)
      {
        const std::int64_t i = surface.Voxels[3 * c] + shift[0],
                           j = surface.Voxels[3 * c + 1] + shift[1],
                           k = surface.Voxels[3 * c + 2] + shift[2];
        cid[c] = ((k * wn[1] + j) * wn[0] + i) * 6 + surface.Directions[c];
      }
    });
  vtkSMPTools::For(0,
    nPoints,
    [&](std::int64_t b, std::int64_t e)
    {
      for (std::int64_t p = b; p < e; ++p)
      {
        const std::int64_t i = surface.Corners[3 * p] + shift[0],
                           j = surface.Corners[3 * p + 1] + shift[1],
                           k = surface.Corners[3 * p + 2] + shift[2];
        pid[p] = (k * (wn[1] + 1) + j) * (wn[0] + 1) + i;
      }
    });
  vtkNew<vtkCellArray> polys;
  polys->SetData(offsets, connectivity);

  output->SetPoints(points);
  output->SetPolys(polys);
  output->GetCellData()->SetNormals(normals);
  output->GetCellData()->AddArray(voxels);
  output->GetCellData()->AddArray(directions);
  if (piece.Distributed() || this->GenerateGlobalIds)
  {
    output->GetCellData()->SetGlobalIds(cellIds);
    output->GetPointData()->SetGlobalIds(pointIds);
  }
  if (piece.Distributed() && piece.Ghosts > 0)
  {
    vtkNew<vtkUnsignedCharArray> ghostArray;
    ghostArray->SetName(vtkDataSetAttributes::GhostArrayName());
    ghostArray->SetNumberOfValues(nSurfels);
    std::copy(ghost.begin(), ghost.end(), ghostArray->GetPointer(0));
    output->GetCellData()->AddArray(ghostArray);
  }

  AddImageRecord(output, piece.Whole, origin, spacing);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkDigitalSurfaceFilter::AddImageRecord(
  vtkPolyData* output, const int whole[6], const double origin[3], const double spacing[3])
{
  vtkNew<vtkIntArray> extArray;
  extArray->SetName("ImageExtent");
  extArray->SetNumberOfValues(6);
  for (int a = 0; a < 6; ++a)
  {
    extArray->SetValue(a, whole[a]);
  }
  vtkNew<vtkDoubleArray> originArray, spacingArray;
  originArray->SetName("ImageOrigin");
  spacingArray->SetName("ImageSpacing");
  originArray->SetNumberOfValues(3);
  spacingArray->SetNumberOfValues(3);
  for (int a = 0; a < 3; ++a)
  {
    originArray->SetValue(a, origin[a]);
    spacingArray->SetValue(a, spacing[a]);
  }
  output->GetFieldData()->AddArray(extArray);
  output->GetFieldData()->AddArray(originArray);
  output->GetFieldData()->AddArray(spacingArray);
}

void vtkDigitalSurfaceFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  const char* modes[] = { "NonZero", "Range", "Label", "EachLabel", "Interfaces" };
  os << indent << "SelectionMode: " << modes[this->SelectionMode] << "\n";
  os << indent << "LowerThreshold: " << this->LowerThreshold << "\n";
  os << indent << "UpperThreshold: " << this->UpperThreshold << "\n";
  os << indent << "Label: " << this->Label << "\n";
  os << indent << "SelectedComponent: " << this->SelectedComponent << "\n";
  os << indent << "Labels: " << (this->Labels ? this->Labels : "(none)") << "\n";
  os << indent << "GenerateGlobalIds: " << (this->GenerateGlobalIds ? "On" : "Off") << "\n";
}
