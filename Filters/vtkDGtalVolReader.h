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
