// The DICOM series geometry apart from GDCM (Applications/dgDicomGeometry.h):
// slices given in any order along an oblique normal come back sorted with
// the true step, and every way a series fails to be one volume (sheared or
// non-unit cosines, two orientations, two slices at one position, a missing
// slice, a gantry tilt, missing tags) is refused with its reason.
#include "dgDicomGeometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace
{
std::string Tag(const std::vector<double>& v)
{
  std::string s;
  char buf[40];
  for (std::size_t i = 0; i < v.size(); ++i)
  {
    std::snprintf(buf, sizeof buf, "%.10g", v[i]);
    s += (i ? "\\" : "") + std::string(buf);
  }
  return s;
}

// Slices of an oblique stack: rows along (cos a, sin a, 0), columns along
// (0, 0, -1) tilted, the normal their cross product; slice k at origin +
// (k * step + shift[k]) * normal + across[k].
struct Stack
{
  double A = 0.6, Step = 2.5;
  std::vector<double> Shift, Across;
  std::vector<dg::DicomSliceTags> Tags(const std::vector<int>& order) const
  {
    const double r[3] = { std::cos(A), std::sin(A), 0 };
    const double c[3] = { 0, 0, -1 };
    const double n[3] = { r[1] * c[2] - r[2] * c[1], r[2] * c[0] - r[0] * c[2], r[0] * c[1] - r[1] * c[0] };
    std::vector<dg::DicomSliceTags> tags;
    for (int k : order)
    {
      const double t = k * Step + (k < static_cast<int>(Shift.size()) ? Shift[k] : 0);
      const double x = k < static_cast<int>(Across.size()) ? Across[k] : 0;
      const std::vector<double> p = { -100 + t * n[0] + x * r[0], 20 + t * n[1] + x * r[1], 5 + t * n[2] };
      tags.push_back({ "dir/s" + std::to_string(k) + ".dcm", Tag(p), Tag({ r[0], r[1], r[2], c[0], c[1], c[2] }),
        Tag({ 0.8, 0.6 }) });
    }
    return tags;
  }
};

std::string Refused(const std::vector<dg::DicomSliceTags>& tags)
{
  dg::DicomStack stack;
  std::string error;
  if (!dg::OrderDicomSlices(tags, stack, error))
    return error;
  double step = 0;
  if (!dg::UniformDicomStep(stack, step, error))
    return error;
  return "";
}
} // namespace

TEST(DicomGeometry, ObliqueStackInAnyOrder)
{
  const Stack s;
  dg::DicomStack stack;
  std::string error;
  ASSERT_TRUE(dg::OrderDicomSlices(s.Tags({ 3, 0, 4, 1, 2 }), stack, error)) << error;
  ASSERT_EQ(stack.Files.size(), 5u);
  for (int k = 0; k < 5; ++k)
    EXPECT_EQ(stack.Files[k], "dir/s" + std::to_string(k) + ".dcm");
  double step = 0;
  ASSERT_TRUE(dg::UniformDicomStep(stack, step, error)) << error;
  EXPECT_NEAR(step, s.Step, 1e-7); // the tags hold 10 significant digits
  EXPECT_NEAR(stack.PixelSpacing[0], 0.8, 1e-12);
  EXPECT_NEAR(stack.PixelSpacing[1], 0.6, 1e-12);
  EXPECT_NEAR(stack.Normal[0] * stack.Row[0] + stack.Normal[1] * stack.Row[1] + stack.Normal[2] * stack.Row[2], 0, 1e-12);
}

TEST(DicomGeometry, RefusesWhatIsNotOneVolume)
{
  Stack s;
  EXPECT_EQ(Refused(s.Tags({ 0, 1, 2 })), "");
  s.Shift = { 0, 0, 0, 1.5 }; // slice 3 sits where 3.6 would: a missing slice between
  EXPECT_NE(Refused(s.Tags({ 0, 1, 2, 3 })).find("non-uniform slice spacing"), std::string::npos);
  s.Shift = {};
  s.Across = { 0, 0.5, 1.0 }; // each slice shifted across the normal
  EXPECT_NE(Refused(s.Tags({ 0, 1, 2 })).find("gantry tilt"), std::string::npos);
  s.Across = {};
  auto tags = s.Tags({ 0, 1, 2 });
  tags[2].Position = tags[1].Position;
  EXPECT_NE(Refused(tags).find("same position"), std::string::npos);
  tags = s.Tags({ 0, 1 });
  tags[1].Orientation = Tag({ 1, 0, 0, 0, 1, 0 });
  EXPECT_NE(Refused(tags).find("another ImageOrientationPatient"), std::string::npos);
  tags = s.Tags({ 0 });
  tags[0].Orientation = Tag({ 1, 0, 0, 0.2, 1, 0 });
  EXPECT_NE(Refused(tags).find("not made of unit vectors"), std::string::npos);
  tags[0].Orientation = Tag({ 1, 0, 0, 0.1, 0.994987437, 0 });
  EXPECT_NE(Refused(tags).find("sheared"), std::string::npos);
  tags = s.Tags({ 0 });
  tags[0].PixelSpacing = "";
  EXPECT_NE(Refused(tags).find("PixelSpacing"), std::string::npos);
  tags = s.Tags({ 0 });
  tags[0].Position = "1\\nan\\2";
  EXPECT_NE(Refused(tags).find("ImagePositionPatient"), std::string::npos);
}
