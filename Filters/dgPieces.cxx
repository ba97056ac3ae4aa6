#include "dgPieces.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkIdList.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>
#include <vtkCommunicator.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkExtentTranslator.h>
#include <vtkInformation.h>
#include <vtkInformationIntegerRequestKey.h>
#include <vtkMultiProcessController.h>
#include <vtkNew.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace dg
{
vtkMultiProcessController* PieceController(vtkInformation* outInfo)
{
  vtkMultiProcessController* c = vtkMultiProcessController::GetGlobalController();
  if (!c || c->GetNumberOfProcesses() < 2 || !outInfo ||
    !outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) ||
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) < 2)
  {
    return nullptr;
  }
  return c;
}

vtkDataArray* GlobalIdArray(vtkDataSetAttributes* a, long long n)
{
  vtkDataArray* ids = a->GetGlobalIds() ? a->GetGlobalIds() : a->GetArray("GlobalIds");
  if (!ids || ids->GetNumberOfComponents() != 1 || ids->GetNumberOfTuples() != n ||
    ids->GetDataType() == VTK_FLOAT || ids->GetDataType() == VTK_DOUBLE)
    return nullptr;
  return ids;
}

bool AllPiecesOk(vtkInformation* outInfo, bool ok)
{
  vtkMultiProcessController* c = PieceController(outInfo);
  if (!c)
  {
    return ok;
  }
  int mine = ok ? 1 : 0, all = 0;
  c->AllReduce(&mine, &all, 1, vtkCommunicator::MIN_OP);
  return all == 1;
}

bool ExtentEmpty(const int e[6])
{
  return e[0] > e[1] || e[2] > e[3] || e[4] > e[5];
}

bool PieceExtent(const int whole[6], int piece, int numberOfPieces, int out[6])
{
  for (int a = 0; a < 6; ++a)
  {
    out[a] = whole[a];
  }
  if (ExtentEmpty(whole) || numberOfPieces < 1 || piece < 0 || piece >= numberOfPieces)
  {
    out[0] = 0;
    out[1] = -1;
    return false;
  }
  if (numberOfPieces == 1)
  {
    return true;
  }
  vtkNew<vtkExtentTranslator> t;
  t->SetSplitModeToBlock();
  int w[6];
  std::copy(whole, whole + 6, w);
  // By points: a voxel is an image point, and pieces must not share voxels.
  // The translator reports an empty piece by returning 0.
  if (!t->PieceToExtentThreadSafe(piece, numberOfPieces, 0, w, out, t->GetSplitMode(), 1) ||
    ExtentEmpty(out))
  {
    out[0] = 0;
    out[1] = -1;
    return false;
  }
  return true;
}

void GrowExtent(const int in[6], int layers, const int whole[6], int out[6])
{
  if (ExtentEmpty(in))
  {
    std::copy(in, in + 6, out);
    return;
  }
  for (int a = 0; a < 3; ++a)
  {
    out[2 * a] = std::max(whole[2 * a], in[2 * a] - layers);
    out[2 * a + 1] = std::min(whole[2 * a + 1], in[2 * a + 1] + layers);
  }
}

bool ExtentContains(const int outer[6], const int inner[6])
{
  if (ExtentEmpty(inner))
  {
    return true;
  }
  for (int a = 0; a < 3; ++a)
  {
    if (inner[2 * a] < outer[2 * a] || inner[2 * a + 1] > outer[2 * a + 1])
    {
      return false;
    }
  }
  return true;
}
void CopyExtent(
  const void* src, const int extent[6], const int box[6], std::size_t voxelBytes, void* dst)
{
  if (ExtentEmpty(box))
  {
    return;
  }
  const std::size_t nx = static_cast<std::size_t>(extent[1] - extent[0] + 1);
  const std::size_t ny = static_cast<std::size_t>(extent[3] - extent[2] + 1);
  const std::size_t row = static_cast<std::size_t>(box[1] - box[0] + 1) * voxelBytes;
  const auto* in = static_cast<const std::uint8_t*>(src);
  auto* out = static_cast<std::uint8_t*>(dst);
  for (int k = box[4]; k <= box[5]; ++k)
  {
    for (int j = box[2]; j <= box[3]; ++j, out += row)
    {
      const std::size_t first = (static_cast<std::size_t>(k - extent[4]) * ny +
                                  static_cast<std::size_t>(j - extent[2])) * nx +
        static_cast<std::size_t>(box[0] - extent[0]);
      std::memcpy(out, in + first * voxelBytes, row);
    }
  }
}
void CropImageToExtent(vtkImageData* image, const int box[6], vtkImageData* output)
{
  int whole[6];
  image->GetExtent(whole);
  vtkPointData* in = image->GetPointData();
  bool standard = image->GetCellData()->GetNumberOfArrays() == 0;
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    standard = standard && in->GetArray(a) && in->GetArray(a)->HasStandardMemoryLayout();
  }
  if (std::equal(box, box + 6, whole) || !standard)
  {
    output->ShallowCopy(image);
    output->Crop(box); // nothing to do on the whole extent
  }
  else
  {
    output->SetExtent(const_cast<int*>(box));
    for (int a = 0; a < in->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* from = in->GetArray(a);
      vtkSmartPointer<vtkDataArray> to = vtk::TakeSmartPointer(from->NewInstance());
      to->SetName(from->GetName());
      to->SetNumberOfComponents(from->GetNumberOfComponents());
      to->SetNumberOfTuples(output->GetNumberOfPoints());
      CopyExtent(from->GetVoidPointer(0), whole, box,
        static_cast<std::size_t>(from->GetDataTypeSize()) * from->GetNumberOfComponents(),
        to->GetVoidPointer(0));
      if (from == in->GetScalars())
      {
        output->GetPointData()->SetScalars(to);
      }
      else
      {
        output->GetPointData()->AddArray(to);
      }
    }
  }
}


vtkSmartPointer<vtkPolyData> WithoutGhostCells(vtkPolyData* input)
{
  const vtkIdType nCells = input ? input->GetNumberOfCells() : 0;
  vtkDataArray* ghosts = input ? input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()) : nullptr;
  if (!ghosts || ghosts->GetNumberOfTuples() != nCells)
    return nullptr;
  const int mask = vtkDataSetAttributes::DUPLICATECELL | vtkDataSetAttributes::HIDDENCELL;
  vtkNew<vtkIdList> keep;
  for (vtkIdType c = 0; c < nCells; ++c)
    if (!(static_cast<int>(ghosts->GetComponent(c, 0)) & mask))
      keep->InsertNextId(c);
  if (keep->GetNumberOfIds() == nCells)
    return nullptr;
  const vtkIdType nPoints = input->GetNumberOfPoints();
  std::vector<vtkIdType> newPoint(nPoints, -1);
  vtkNew<vtkIdList> usedPoints, pts;
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->AllocateExact(keep->GetNumberOfIds(), 4 * keep->GetNumberOfIds());
  for (vtkIdType i = 0; i < keep->GetNumberOfIds(); ++i)
  {
    const vtkIdType c = keep->GetId(i);
    input->GetCellPoints(c, pts);
    for (vtkIdType k = 0; k < pts->GetNumberOfIds(); ++k)
    {
      vtkIdType& id = newPoint[pts->GetId(k)];
      if (id < 0)
      {
        id = usedPoints->GetNumberOfIds();
        usedPoints->InsertNextId(pts->GetId(k));
      }
      pts->SetId(k, id);
    }
    output->InsertNextCell(input->GetCellType(c), pts);
  }
  vtkNew<vtkPoints> points;
  points->SetDataType(input->GetPoints()->GetDataType());
  points->SetNumberOfPoints(usedPoints->GetNumberOfIds());
  for (vtkIdType i = 0; i < usedPoints->GetNumberOfIds(); ++i)
    points->SetPoint(i, input->GetPoint(usedPoints->GetId(i)));
  output->SetPoints(points);
  output->GetCellData()->CopyGlobalIdsOn();
  output->GetCellData()->CopyAllocate(input->GetCellData(), keep->GetNumberOfIds());
  for (vtkIdType i = 0; i < keep->GetNumberOfIds(); ++i)
    output->GetCellData()->CopyData(input->GetCellData(), keep->GetId(i), i);
  output->GetPointData()->CopyGlobalIdsOn();
  output->GetPointData()->CopyAllocate(input->GetPointData(), usedPoints->GetNumberOfIds());
  for (vtkIdType i = 0; i < usedPoints->GetNumberOfIds(); ++i)
    output->GetPointData()->CopyData(input->GetPointData(), usedPoints->GetId(i), i);
  output->GetCellData()->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  output->GetFieldData()->ShallowCopy(input->GetFieldData());
  return output;
}

bool RequestedImageBox(vtkInformation* inInfo, vtkInformation* outInfo, int whole[6], int requested[6])
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  if (!inInfo || !inInfo->Has(SDDP::WHOLE_EXTENT()))
    return false;
  inInfo->Get(SDDP::WHOLE_EXTENT(), whole);
  std::copy(whole, whole + 6, requested);
  if (outInfo && outInfo->Has(SDDP::UPDATE_EXTENT()))
    outInfo->Get(SDDP::UPDATE_EXTENT(), requested);
  const int pieces = outInfo && outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES())
    : 1;
  if (pieces > 1)
  {
    // The executive splits the requested extent just before RequestData
    // (vtkStreamingDemandDrivenPipeline::ExecuteDataStart), by cells,
    // ghost levels included; the same here.
    const int piece = outInfo->Get(SDDP::UPDATE_PIECE_NUMBER());
    const int ghosts = outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS());
    vtkInformationIntegerKey* splitKey = vtkExtentTranslator::UPDATE_SPLIT_MODE();
    const int mode =
      outInfo->Has(splitKey) ? outInfo->Get(splitKey) : vtkExtentTranslator::BLOCK_MODE;
    int all[6];
    std::copy(requested, requested + 6, all);
    vtkNew<vtkExtentTranslator> translator;
    translator->PieceToExtentThreadSafe(piece, pieces, ghosts, all, requested, mode, 0);
  }
  return true;
}

void RequestImageBox(vtkInformation* inInfo, const int box[6])
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  inInfo->Set(SDDP::UPDATE_EXTENT(), box, 6);
  inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), 0);
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), 1);
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
}
} // namespace dg
