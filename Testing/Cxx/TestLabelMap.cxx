// The label-map core shared by the program (--labels) and the filters'
// EachLabel mode (Filters/dgLabelMap.h), without a pipeline: the spec
// parser, the label scan on one component of any array, and the crop.
#include "dgLabelMap.h"

#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkMatrix3x3.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include <gtest/gtest.h>

namespace
{
TEST(LabelMap, ParsesSpecs)
{
  dg::LabelSpec spec;
  std::string error;
  ASSERT_TRUE(dg::ParseLabelSpec("all", spec, error));
  EXPECT_TRUE(spec.All && spec.Contains(-7) && spec.Contains(123456));
  ASSERT_TRUE(dg::ParseLabelSpec("1,4,10-12,-5--3", spec, error)) << error;
  EXPECT_FALSE(spec.All);
  for (long long in : { 1, 4, 10, 11, 12, -5, -4, -3 })
  {
    EXPECT_TRUE(spec.Contains(in)) << in;
  }
  for (long long out : { 0, 2, 3, 5, 9, 13, -6, -2 })
  {
    EXPECT_FALSE(spec.Contains(out)) << out;
  }
  for (const char* bad : { "", "x", "3-", "5-2", "1,,2", "1.5", "2-x" })
  {
    error.clear();
    EXPECT_FALSE(dg::ParseLabelSpec(bad, spec, error)) << bad;
    EXPECT_FALSE(error.empty()) << bad;
  }
  EXPECT_FALSE(dg::ParseLabelSpec("", spec, error));
  EXPECT_EQ(error, "no label given");
}

// A 6 x 5 x 4 image (extent starting at (2, -1, 3)) whose component 1
// holds labels 4 and 9; component 0 is noise that must not be read.
vtkSmartPointer<vtkImageData> TwoComponentMap()
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetExtent(2, 7, -1, 3, 3, 6);
  image->SetSpacing(0.5, 2, 3);
  image->SetOrigin(1, 2, 3);
  vtkNew<vtkFloatArray> values;
  values->SetName("map");
  values->SetNumberOfComponents(2);
  values->SetNumberOfTuples(6 * 5 * 4);
  vtkIdType id = 0;
  for (int k = 3; k <= 6; ++k)
    for (int j = -1; j <= 3; ++j)
      for (int i = 2; i <= 7; ++i, ++id)
      {
        float label = 0;
        if (i >= 3 && i <= 4 && j >= 0 && j <= 1 && k == 4)
          label = 4;
        if (i == 7 && j == 3 && k >= 5)
          label = 9;
        values->SetComponent(id, 0, 0.25f * static_cast<float>(id));
        values->SetComponent(id, 1, label);
      }
  image->GetPointData()->AddArray(values);
  return image;
}

TEST(LabelMap, FindsBoxesOnOneComponent)
{
  auto image = TwoComponentMap();
  vtkDataArray* values = image->GetPointData()->GetArray("map");
  dg::LabelSpec spec;
  std::string error;
  ASSERT_TRUE(dg::ParseLabelSpec("all", spec, error));
  std::vector<dg::LabelBox> labels;
  ASSERT_TRUE(dg::FindLabels(values, 1, image->GetExtent(), spec, labels, error)) << error;
  ASSERT_EQ(labels.size(), 2u);
  EXPECT_EQ(labels[0].Label, 4);
  EXPECT_EQ(labels[0].Voxels, 4);
  const int box4[6] = { 3, 4, 0, 1, 4, 4 };
  const int box9[6] = { 7, 7, 3, 3, 5, 6 };
  for (int a = 0; a < 6; ++a)
  {
    EXPECT_EQ(labels[0].Extent[a], box4[a]);
    EXPECT_EQ(labels[1].Extent[a], box9[a]);
  }
  EXPECT_EQ(labels[1].Label, 9);
  EXPECT_EQ(labels[1].Voxels, 2);

  ASSERT_TRUE(dg::ParseLabelSpec("5-20", spec, error));
  ASSERT_TRUE(dg::FindLabels(values, 1, image->GetExtent(), spec, labels, error));
  ASSERT_EQ(labels.size(), 1u);
  EXPECT_EQ(labels[0].Label, 9);

  ASSERT_TRUE(dg::ParseLabelSpec("1-3", spec, error));
  EXPECT_FALSE(dg::FindLabels(values, 1, image->GetExtent(), spec, labels, error));
  EXPECT_NE(error.find("holds 2 non-zero labels: 4, 9"), std::string::npos) << error;

  // Component 0 holds quarters: not a label map.
  ASSERT_TRUE(dg::ParseLabelSpec("all", spec, error));
  EXPECT_FALSE(dg::FindLabels(values, 0, image->GetExtent(), spec, labels, error));
  EXPECT_NE(error.find("not an integer"), std::string::npos) << error;
  EXPECT_FALSE(dg::FindLabels(values, 2, image->GetExtent(), spec, labels, error));
}

TEST(LabelMap, CropKeepsIndicesAndOneComponent)
{
  auto image = TwoComponentMap();
  vtkDataArray* values = image->GetPointData()->GetArray("map");
  const int box9[6] = { 7, 7, 3, 3, 5, 6 };
  auto crop = dg::CropImage(image, box9, 2, values, 1);
  int ext[6];
  crop->GetExtent(ext);
  const int expected[6] = { 5, 7, 1, 3, 3, 6 }; // grown by 2, clipped to the image
  for (int a = 0; a < 6; ++a)
  {
    EXPECT_EQ(ext[a], expected[a]);
  }
  EXPECT_DOUBLE_EQ(crop->GetSpacing()[1], 2);
  EXPECT_DOUBLE_EQ(crop->GetOrigin()[2], 3);
  vtkDataArray* scalars = crop->GetPointData()->GetScalars();
  ASSERT_NE(scalars, nullptr);
  EXPECT_EQ(scalars->GetNumberOfComponents(), 1);
  EXPECT_STREQ(scalars->GetName(), "map");
  // Every voxel of the crop holds the image's component 1 at the same index.
  for (int k = ext[4]; k <= ext[5]; ++k)
    for (int j = ext[2]; j <= ext[3]; ++j)
      for (int i = ext[0]; i <= ext[1]; ++i)
      {
        int ijk[3] = { i, j, k };
        const vtkIdType from = image->ComputePointId(ijk);
        const vtkIdType to = crop->ComputePointId(ijk);
        EXPECT_EQ(scalars->GetComponent(to, 0), values->GetComponent(from, 1)) << i << " " << j << " " << k;
      }
}
} // namespace
