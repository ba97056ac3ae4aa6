// vtkDigitalIslandFilter against VTK's own vtkImageConnectivityFilter
// (VTK::ImagingMorphological: Debian's VTK 9.1 has it, ParaView 5.11's VTK
// does not, so this test is built only where it exists). VTK's filter
// documents 6-connectivity for 3D images; the same components, sizes and
// results here show that the island filter's connectivity is VTK's.
#include "dgIslands.h"
#include "dgTestShapes.h"
#include "vtkDigitalIslandFilter.h"

#include <vtkDataArray.h>
#include <vtkIdTypeArray.h>
#include <vtkImageConnectivityFilter.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

namespace
{
using Mask = std::vector<std::uint8_t>;

Mask ValuesOf(vtkImageData* image)
{
  vtkDataArray* s = image->GetPointData()->GetScalars();
  Mask m(s ? s->GetNumberOfTuples() : 0);
  for (std::size_t v = 0; v < m.size(); ++v)
    m[v] = static_cast<std::uint8_t>(s->GetTuple1(static_cast<vtkIdType>(v)));
  return m;
}

struct Regions
{
  std::vector<int> Labels;                 // per voxel, 0 outside the regions
  std::map<vtkIdType, vtkIdType> Size;     // label -> voxels
  std::map<vtkIdType, bool> OnBorder;      // label -> touches the image border
};

// vtkImageConnectivityFilter on the voxels equal to value (unsigned char
// scalars: VTK truncates a range's bounds to the scalar type, so [0.5, 1.5]
// would be [0, 1]; give it [value, value]).
Regions VTKRegions(vtkImageData* image, double value, vtkIdType minimumSize = 1)
{
  vtkNew<vtkImageConnectivityFilter> c;
  c->SetInputData(image);
  c->SetScalarRange(value, value);
  c->SetSizeRange(minimumSize, VTK_ID_MAX);
  c->SetExtractionModeToAllRegions();
  c->SetLabelScalarTypeToInt();
  c->GenerateRegionExtentsOn();
  c->Update();
  Regions r;
  vtkDataArray* labels = c->GetOutput()->GetPointData()->GetScalars();
  r.Labels.resize(labels->GetNumberOfTuples());
  for (vtkIdType v = 0; v < labels->GetNumberOfTuples(); ++v)
    r.Labels[v] = static_cast<int>(labels->GetTuple1(v));
  int whole[6];
  image->GetExtent(whole);
  for (vtkIdType i = 0; i < c->GetNumberOfExtractedRegions(); ++i)
  {
    const vtkIdType label = c->GetExtractedRegionLabels()->GetValue(i);
    r.Size[label] = c->GetExtractedRegionSizes()->GetValue(i);
    int e[6];
    c->GetExtractedRegionExtents()->GetTypedTuple(i, e);
    bool border = false;
    for (int a = 0; a < 6; ++a)
      border = border || e[a] == whole[a];
    r.OnBorder[label] = border;
  }
  return r;
}

vtkSmartPointer<vtkImageData> FromMask(const Mask& m, const int d[3])
{
  return dgtest::MakeImage(
    d[0], d[1], d[2], [&](int i, int j, int k) { return m[(std::size_t(k) * d[1] + j) * d[0] + i]; });
}
} // namespace

TEST(IslandVTKConnectivity, SameComponentsAsVTK)
{
  for (double p : { 0.3, 0.5, 0.7 })
  {
    const int d[3] = { 21, 17, 15 };
    auto image = dgtest::RandomVoxels(d[0], d[1], d[2], p, 11);
    const Mask m = ValuesOf(image);
    for (std::uint8_t value : { 0, 1 })
    {
      std::vector<std::int64_t> sizes;
      std::vector<std::uint8_t> border;
      dg::ComponentSizes(m, d, value, sizes, border);
      const Regions r = VTKRegions(image, value);
      std::vector<std::int64_t> vtkSizes;
      for (const auto& s : r.Size)
        vtkSizes.push_back(s.second);
      std::sort(sizes.begin(), sizes.end());
      std::sort(vtkSizes.begin(), vtkSizes.end());
      EXPECT_EQ(sizes, vtkSizes) << "p " << p << " value " << int(value);
      EXPECT_GT(sizes.size(), 1u);
    }
  }
}

TEST(IslandVTKConnectivity, SameResultAsVTKSizeRange)
{
  for (double p : { 0.35, 0.6 })
  {
    for (int minimumSize : { 2, 4, 9 })
    {
      SCOPED_TRACE(testing::Message() << "p " << p << " size " << minimumSize);
      const int d[3] = { 19, 16, 14 };
      auto image = dgtest::RandomVoxels(d[0], d[1], d[2], p, 5);

      // Islands: VTK keeps the regions of at least minimumSize voxels.
      const Regions kept = VTKRegions(image, 1, minimumSize);
      Mask islandsOnly(kept.Labels.size());
      for (std::size_t v = 0; v < islandsOnly.size(); ++v)
        islandsOnly[v] = kept.Labels[v] != 0;
      vtkNew<vtkDigitalIslandFilter> f;
      f->SetInputData(image);
      f->SetMinimumSize(minimumSize);
      f->FillCavitiesOff();
      f->Update();
      ASSERT_EQ(ValuesOf(f->GetOutput()), islandsOnly);
      const vtkIdType all = static_cast<vtkIdType>(VTKRegions(image, 1).Size.size());
      EXPECT_EQ(f->GetNumberOfRemovedIslands(), all - static_cast<vtkIdType>(kept.Size.size()));

      // Cavities of that result: VTK's outside regions off the border and
      // smaller than minimumSize become inside.
      const Regions outside = VTKRegions(FromMask(islandsOnly, d), 0);
      Mask expected = islandsOnly;
      vtkIdType cavities = 0;
      for (const auto& s : outside.Size)
        cavities += s.second < minimumSize && !outside.OnBorder.at(s.first);
      for (std::size_t v = 0; v < expected.size(); ++v)
      {
        const int label = outside.Labels[v];
        if (label != 0 && outside.Size.at(label) < minimumSize && !outside.OnBorder.at(label))
          expected[v] = 1;
      }
      f->FillCavitiesOn();
      f->Update();
      ASSERT_EQ(ValuesOf(f->GetOutput()), expected);
      EXPECT_EQ(f->GetNumberOfFilledCavities(), cavities);
      EXPECT_GT(f->GetNumberOfRemovedIslands() + cavities, 0);
    }
  }
}
