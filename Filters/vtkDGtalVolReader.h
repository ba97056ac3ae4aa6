/**
 * @class   vtkDGtalVolReader
 * @brief   Read DGtal's VOL volumes (Version 2 raw, Version 3 zlib) as vtkImageData.
 *
 * A VOL file is an ASCII header of "Key: value" lines (X, Y, Z, Version,
 * Voxel-Size, ...), a line holding a single ".", then X*Y*Z bytes with x
 * fastest: raw in Version 2, one zlib stream in Version 3. The output is an
 * image of extent [0, X-1] x [0, Y-1] x [0, Z-1], origin (0, 0, 0), spacing
 * Voxel-Size (1 when absent), with one unsigned char point array "Value"
 * set as the active scalars.
 *
 * Pieces and sub-extents (CAN_PRODUCE_SUB_EXTENT): the output is exactly
 * the requested UPDATE_EXTENT, with the whole read's origin and spacing
 * (VTK keeps the origin of a sub-extent: the extent carries the offset).
 * Only the box is read into memory (dg::VolStream), straight into the
 * output's scalars: Version 2 seeks to the box's rows; Version 3, one zlib
 * stream without an index, is inflated from its start through a bounded
 * window (256 KiB of input, 1 MiB of output) of which the box's bytes are
 * kept. A piece's peak memory is its box plus about 1.3 MiB, not the whole
 * volume; its time is that of inflating the whole stream (inflated to its
 * end, so that a corrupt file fails in every piece as in the whole read;
 * in a distributed run the last piece needs the whole stream anyway), less
 * the copy (figures: docs/pieces-readers.md). A whole read holds one copy
 * of the volume. A piece request (UpdatePiece(p, n, g), or
 * ParaView's per-rank request) is turned into the extent by VTK's executive
 * (vtkExtentTranslator, block mode, by cells: neighbouring pieces share one
 * layer of voxels, unlike dg::PieceExtent), grown by the g ghost layers
 * asked for; the executive then marks those layers in a point and a cell
 * array vtkGhostType (DUPLICATEPOINT, DUPLICATECELL), as for any structured
 * source (2 more bytes per voxel of the piece). An empty extent gives an
 * empty image, no error (the file is still checked).
 *
 * A missing or truncated file, a bad header, dimensions that disagree with
 * the data or a corrupt zlib stream give an error (vtkErrorMacro, also
 * available from GetErrorMessage) and an empty output.
 */
#ifndef vtkDGtalVolReader_h
#define vtkDGtalVolReader_h

#include "vtkDigitalGeometryModule.h"
#include "vtkImageAlgorithm.h"

#include <memory>

namespace dg
{
class PipelineAbort;
}

#include <string>

class VTKDIGITALGEOMETRY_EXPORT vtkDGtalVolReader : public vtkImageAlgorithm
{
public:
  static vtkDGtalVolReader* New();
  vtkTypeMacro(vtkDGtalVolReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The file to read.
   */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /**
   * Returns 1 when the file starts like a VOL file (a header with X, Y, Z and
   * a Version of 2 or 3), 0 otherwise.
   */
  int CanReadFile(const char* fname);

  /**
   * The reason of the last failure, empty after a success.
   */
  const char* GetErrorMessage() const { return this->LastError.c_str(); }

  /**
   * Includes the aborted state: after an aborted execution (SetAbortExecute
   * from a progress observer: empty outputs, no error) the filter is out of
   * date until it has run again.
   */
  vtkMTimeType GetMTime() override;

protected:
  vtkDGtalVolReader();
  ~vtkDGtalVolReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  std::string LastError;

private:
  std::unique_ptr<dg::PipelineAbort> Abort;
  vtkDGtalVolReader(const vtkDGtalVolReader&) = delete;
  void operator=(const vtkDGtalVolReader&) = delete;
};

#endif
