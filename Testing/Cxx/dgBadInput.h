// The bad-input matrix's table form, shared by its two halves
// (TestBadInputMatrix: filters; TestBadInputReaders: readers): a row names
// what it feeds, which stage should object, and how:
//   Error    an ErrorEvent whose message contains Word, and an empty output;
//   Warning  a WarningEvent whose message contains Word, no error, and a
//            complete result (every cell present, every value finite);
//   Result   no error, a complete finite result.
#ifndef dgBadInput_h
#define dgBadInput_h

#include "dgTestShapes.h"

#include <vtkAlgorithm.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkCellData.h>
#include <vtkPolyData.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

namespace dgtest
{
enum class Expect
{
  Error,
  Warning,
  Result
};

struct Outcome
{
  int Errors = 0;
  int Warnings = 0;
  std::string Messages;
  vtkIdType Cells = 0;         // cells of the main output (points for images)
  vtkIdType ExpectedCells = 0; // for Warning / Result rows
  bool Finite = true;          // every output array value finite
};

struct Row
{
  const char* Name;
  Expect What;
  const char* Word;
  std::function<Outcome()> Run;
};

inline bool AllFinite(vtkFieldData* fd)
{
  for (int a = 0; a < fd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* arr = fd->GetArray(a);
    if (!arr)
    {
      continue;
    }
    for (vtkIdType t = 0; t < arr->GetNumberOfTuples(); ++t)
    {
      for (int c = 0; c < arr->GetNumberOfComponents(); ++c)
      {
        if (!std::isfinite(arr->GetComponent(t, c)))
        {
          return false;
        }
      }
    }
  }
  return true;
}

// Runs `algorithm` with an observer on it and on its executive (pipeline
// errors such as a missing input come from the executive).
inline Outcome Run(vtkAlgorithm* algorithm)
{
  vtkNew<dgtest::ErrorObserver> obs;
  obs->Observe(algorithm);
  obs->Observe(algorithm->GetExecutive());
  algorithm->Update();
  Outcome o;
  o.Errors = obs->Errors;
  o.Warnings = obs->Warnings;
  o.Messages = obs->Messages;
  if (auto* pd = vtkPolyData::SafeDownCast(algorithm->GetOutputDataObject(0)))
  {
    o.Cells = pd->GetNumberOfCells();
    o.Finite = AllFinite(pd->GetCellData()) && AllFinite(pd->GetPointData());
  }
  else if (auto* im = vtkImageData::SafeDownCast(algorithm->GetOutputDataObject(0)))
  {
    o.Cells = im->GetNumberOfPoints();
  }
  else if (auto* pdc =
             vtkPartitionedDataSetCollection::SafeDownCast(algorithm->GetOutputDataObject(0)))
  {
    for (unsigned int b = 0; b < pdc->GetNumberOfPartitionedDataSets(); ++b)
    {
      for (unsigned int p = 0; p < pdc->GetNumberOfPartitions(b); ++p)
      {
        auto* part = vtkPolyData::SafeDownCast(pdc->GetPartition(b, p));
        o.Cells += part ? part->GetNumberOfCells() : 0;
      }
    }
  }
  return o;
}

/// The row's expectation, as gtest assertions.
inline void CheckRow(const Row& row)
{
  const Outcome o = row.Run();
  switch (row.What)
  {
    case Expect::Error:
      EXPECT_GE(o.Errors, 1) << o.Messages;
      EXPECT_NE(o.Messages.find(row.Word), std::string::npos) << o.Messages;
      EXPECT_EQ(o.Cells, 0);
      break;
    case Expect::Warning:
      EXPECT_EQ(o.Errors, 0) << o.Messages;
      EXPECT_GE(o.Warnings, 1);
      EXPECT_NE(o.Messages.find(row.Word), std::string::npos) << o.Messages;
      EXPECT_EQ(o.Cells, o.ExpectedCells);
      EXPECT_TRUE(o.Finite);
      break;
    case Expect::Result:
      EXPECT_EQ(o.Errors, 0) << o.Messages;
      EXPECT_EQ(o.Warnings, 0) << o.Messages;
      EXPECT_EQ(o.Cells, o.ExpectedCells);
      EXPECT_GT(o.Cells, 0);
      EXPECT_TRUE(o.Finite);
      break;
  }
}

// ctest shows the row's name rather than its bytes.
inline void PrintTo(const Row& row, std::ostream* os)
{
  *os << row.Name;
}
} // namespace dgtest

// One ctest entry per row, named Matrix/BadInput.Row/<row name>.
#define DG_BAD_INPUT_MATRIX(rows)                                                                  \
  class BadInput : public ::testing::TestWithParam<dgtest::Row>                                    \
  {                                                                                                \
  };                                                                                               \
  TEST_P(BadInput, Row)                                                                            \
  {                                                                                                \
    dgtest::CheckRow(GetParam());                                                                  \
  }                                                                                                \
  INSTANTIATE_TEST_SUITE_P(Matrix,                                                                 \
    BadInput,                                                                                      \
    ::testing::ValuesIn(rows),                                                                     \
    [](const ::testing::TestParamInfo<dgtest::Row>& info)                                          \
    { return std::string(info.param.Name); })

#endif
