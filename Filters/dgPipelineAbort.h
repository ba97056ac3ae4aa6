// Abort as VTK's newer executives define it (empty outputs, no error, the
// next Update recomputes), for the VTK 9.1/9.2 executives this module runs
// under. Those mark an aborted execution's outputs as generated and up to
// date, so a filter that returned 0 logs "returned failure" and keeps
// downstream stale, and one that returned 1 is never re-run. Each filter
// holds one PipelineAbort and:
// - keeps the guard Begin() returns for the whole of RequestData (the last
//   abort is over, the outputs lose their aborted mark; when RequestData
//   returns, AbortExecute is cleared: VTK 9.2 never clears it, so one abort
//   would abort every later execution), then returns Abort() when
//   InputAborted();
// - returns Abort() (which is 1) when its AbortExecute flag is set;
// - folds MTime() into its GetMTime(), which is newer than any output while
//   the last execution was aborted, so the next Update runs it again.
// Outputs of an aborted execution carry ABORTED() in their information, so
// that this module's downstream filters abort too instead of reporting an
// empty input as an error. Aborted images keep their extent (with no
// arrays): an empty extent would make the executive run the filter again
// within the same Update for its next consumer.
#ifndef dgPipelineAbort_h
#define dgPipelineAbort_h

#include <vtkTimeStamp.h>
#include <vtkType.h>

class vtkAlgorithm;
class vtkInformationIntegerKey;
class vtkInformationVector;

namespace dg
{

class PipelineAbort
{
public:
  static vtkInformationIntegerKey* ABORTED();

  class Guard
  {
  public:
    explicit Guard(vtkAlgorithm* a)
      : Algorithm(a)
    {
    }
    ~Guard();
    Guard(const Guard&) = delete;
    Guard& operator=(const Guard&) = delete;
    Guard(Guard&& other) noexcept
      : Algorithm(other.Algorithm)
    {
      other.Algorithm = nullptr;
    }

  private:
    vtkAlgorithm* Algorithm;
  };

  [[nodiscard]] Guard Begin(vtkAlgorithm* algorithm, vtkInformationVector* outputs);
  /// Empties every output and marks it aborted; returns 1 (RequestData's
  /// success: an abort is not a failure).
  int Abort(vtkInformationVector* outputs);
  /// True when an input data object on any of the ports carries ABORTED().
  static bool InputAborted(vtkInformationVector** inputs, int numberOfPorts);
  vtkMTimeType MTime(vtkMTimeType base) const;
  bool LastAborted() const { return this->Aborted; }

private:
  bool Aborted = false;
  mutable vtkTimeStamp Stamp;
};

} // namespace dg

#endif
