// The sharp-features stage's output field (Filters/dgSharpFeaturesField.h)
// against brute-force references on small meshes: the twiced Gaussian
// within sides, its masked form, and the step that undoes an estimator's
// blur (docs/sharp-features.md, step 10).
#include "dgSharpFeaturesField.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <vector>

namespace
{
using dg::sharp::FaceGraph;
using dg::sharp::Vec3;

// A strip of quads over a profile in the x-z plane, extruded along y: a
// plane (z = 0, x < 0), a quarter circle of radius R (the fillet), then a
// wall (x = R, z > R). Faces' centres and true normals from the profile.
struct FilletStrip
{
  std::vector<Vec3> Centre, Normal;
  std::vector<double> Arc; // each face's arc length from the plane-fillet junction
  FaceGraph Graph;

  FilletStrip(double radius, double step, double flat, int rows)
  {
    // The profile's points by arc length s from the junction.
    std::vector<Vec3> profile;
    std::vector<double> arcs;
    const double quarter = 0.5 * M_PI * radius;
    for (double s = -flat; s <= quarter + flat + 1e-9; s += step)
    {
      arcs.push_back(s);
      if (s < 0)
        profile.emplace_back(s, 0, 0);
      else if (s <= quarter)
      {
        const double a = s / radius;
        profile.emplace_back(radius * std::sin(a), 0, radius * (1 - std::cos(a)));
      }
      else
        profile.emplace_back(radius, 0, radius + (s - quarter));
    }
    const std::int64_t P = static_cast<std::int64_t>(profile.size());
    std::vector<Vec3> points;
    for (int j = 0; j <= rows; ++j)
      for (const Vec3& p : profile)
        points.emplace_back(p.x, j * step, p.z);
    std::vector<std::int64_t> offsets{ 0 }, conn;
    for (int j = 0; j < rows; ++j)
      for (std::int64_t i = 0; i + 1 < P; ++i)
      {
        const std::int64_t a = j * P + i, b = a + 1, c = b + P, d = a + P;
        conn.insert(conn.end(), { a, b, c, d });
        offsets.push_back(static_cast<std::int64_t>(conn.size()));
        const Vec3 centre = (points[a] + points[b] + points[c] + points[d]) * 0.25;
        this->Centre.push_back(centre);
        const double s = 0.5 * (arcs[i] + arcs[i + 1]);
        this->Arc.push_back(s);
        // The solid lies above the plane and left of the wall: the normal
        // points down on the plane and along +x on the wall.
        const double a0 = std::max(0.0, std::min(0.5 * M_PI, s / radius));
        this->Normal.emplace_back(std::sin(a0), 0, -std::cos(a0));
      }
    this->Graph.Build(offsets, conn);
  }
};

double Angle(const Vec3& a, const Vec3& b)
{
  return dg::sharp::AngleDegrees(a, b);
}

// The field's Gaussian by brute force: every face within 2.5 widths (the
// strip is connected and has no crease, so every such face is reachable).
std::vector<Vec3> BruteMean(const std::vector<Vec3>& centre, const std::vector<Vec3>& in, double width)
{
  const std::size_t F = centre.size();
  std::vector<Vec3> out(F);
  for (std::size_t f = 0; f < F; ++f)
  {
    Vec3 sum;
    double weights = 0;
    for (std::size_t g = 0; g < F; ++g)
    {
      const Vec3 d = centre[g] - centre[f];
      const double d2 = d.Dot(d);
      if (d2 > 6.25 * width * width)
        continue;
      const double w = std::exp(-0.5 * d2 / (width * width));
      sum += in[g] * w;
      weights += w;
    }
    out[f] = sum * (1.0 / weights);
  }
  return out;
}

TEST(SharpFeaturesField, TwicedGaussianMatchesBruteForceAndItsMaskedForm)
{
  const FilletStrip strip(6.0, 0.5, 6.0, 12);
  const std::size_t F = strip.Centre.size();
  const std::vector<char> crease(strip.Graph.Edges.size(), 0);
  const double width = 1.5;
  std::vector<Vec3> normals;
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(
    strip.Graph, crease, strip.Centre, strip.Normal, width, normals));
  // Brute force: K d + K (d - K d).
  const std::vector<Vec3> first = BruteMean(strip.Centre, strip.Normal, width);
  std::vector<Vec3> residual(F);
  for (std::size_t f = 0; f < F; ++f)
    residual[f] = strip.Normal[f] - first[f];
  const std::vector<Vec3> second = BruteMean(strip.Centre, residual, width);
  double worst = 0;
  for (std::size_t f = 0; f < F; ++f)
    worst = std::max(worst, Angle(normals[f], (first[f] + second[f]).Unit()));
  // The stage sums in single precision with a polynomial exponential.
  EXPECT_LT(worst, 1e-3);

  // Only the faces near the junction: the same normals there.
  std::vector<char> where(F);
  for (std::size_t f = 0; f < F; ++f)
    where[f] = std::abs(strip.Arc[f]) < 2.0;
  std::vector<Vec3> masked;
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(
    strip.Graph, crease, strip.Centre, strip.Normal, width, masked, &where, 0.5));
  double differ = 0;
  int checked = 0;
  for (std::size_t f = 0; f < F; ++f)
    if (where[f])
    {
      differ = std::max(differ, Angle(masked[f], normals[f]));
      ++checked;
    }
  EXPECT_GT(checked, 50);
  // Single-precision sums in another order (each search's own origin).
  EXPECT_LT(differ, 1e-5);

  // Searches found once for a wider Gaussian serve both forms: the same
  // normals (their parts reach farther, the weights stop at the cut).
  dg::sharp::FieldSearches searches;
  ASSERT_TRUE(dg::sharp::FindFieldSearches(strip.Graph, crease, strip.Centre, 1.5 * width, searches));
  std::vector<Vec3> shared, sharedMasked;
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(strip.Graph, crease, strip.Centre, strip.Normal,
    width, shared, nullptr, 1.0, &searches));
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(strip.Graph, crease, strip.Centre, strip.Normal,
    width, sharedMasked, &where, 0.5, &searches));
  double sharedDiffer = 0;
  for (std::size_t f = 0; f < F; ++f)
  {
    sharedDiffer = std::max(sharedDiffer, Angle(shared[f], normals[f]));
    if (where[f])
      sharedDiffer = std::max(sharedDiffer, Angle(sharedMasked[f], normals[f]));
  }
  EXPECT_LT(sharedDiffer, 1e-5);
  EXPECT_FALSE(dg::sharp::FindFieldSearches(strip.Graph, crease, strip.Centre, 0.0, searches));
}

TEST(SharpFeaturesField, TheWideFieldWhereTheLeanIsSmall)
{
  // With no lean anywhere the field is the twicing of K K, 2 K^2 d - K^4 d
  // (brute force); with a lean above WideFullDegrees it is the narrower
  // field, as without one.
  const FilletStrip strip(6.0, 0.5, 6.0, 12);
  const std::size_t F = strip.Centre.size();
  const std::vector<char> crease(strip.Graph.Edges.size(), 0);
  const double width = 1.5;
  std::vector<Vec3> k1 = BruteMean(strip.Centre, strip.Normal, width);
  std::vector<Vec3> k2 = BruteMean(strip.Centre, k1, width);
  std::vector<Vec3> k3 = BruteMean(strip.Centre, k2, width);
  std::vector<Vec3> k4 = BruteMean(strip.Centre, k3, width);
  const std::vector<double> calm(F, 0.0), leaning(F, 2 * dg::sharp::WideFullDegrees);
  std::vector<Vec3> wide, narrow, plain;
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(strip.Graph, crease, strip.Centre, strip.Normal,
    width, wide, nullptr, 1.0, nullptr, &calm));
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(strip.Graph, crease, strip.Centre, strip.Normal,
    width, narrow, nullptr, 1.0, nullptr, &leaning));
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(
    strip.Graph, crease, strip.Centre, strip.Normal, width, plain));
  double worstWide = 0, worstNarrow = 0, apart = 0;
  for (std::size_t f = 0; f < F; ++f)
  {
    worstWide = std::max(worstWide, Angle(wide[f], (k2[f] * 2.0 - k4[f]).Unit()));
    worstNarrow = std::max(worstNarrow, Angle(narrow[f], plain[f]));
    apart = std::max(apart, Angle(wide[f], plain[f]));
  }
  EXPECT_LT(worstWide, 1e-3);
  EXPECT_LT(worstNarrow, 1e-9);
  EXPECT_GT(apart, 0.1); // the two fields differ across the fillet
}

TEST(SharpFeaturesField, CreasesSeparateTheSearchesParts)
{
  // The strip cut along its fillet's middle: no face's Gaussian reads a
  // face across the cut, so the plane's side keeps the plane's normal
  // exactly and the wall's side the wall's, however close the faces are.
  const FilletStrip strip(2.0, 0.5, 6.0, 8);
  const std::size_t F = strip.Centre.size();
  const double quarter = 0.5 * M_PI * 2.0;
  std::vector<int> side(F);
  for (std::size_t f = 0; f < F; ++f)
    side[f] = strip.Arc[f] < 0.5 * quarter ? 0 : 1;
  std::vector<char> crease(strip.Graph.Edges.size(), 0);
  std::vector<Vec3> data(F);
  for (std::size_t f = 0; f < F; ++f)
    data[f] = side[f] == 0 ? Vec3(0, 0, -1) : Vec3(1, 0, 0);
  for (std::size_t e = 0; e < strip.Graph.Edges.size(); ++e)
  {
    const std::int64_t* faces = strip.Graph.EdgeFaces.data() + strip.Graph.EdgeFacePtr[e];
    const std::int64_t n = strip.Graph.EdgeFacePtr[e + 1] - strip.Graph.EdgeFacePtr[e];
    crease[e] = n == 2 && side[faces[0]] != side[faces[1]];
  }
  dg::sharp::FieldSearches searches;
  ASSERT_TRUE(dg::sharp::FindFieldSearches(strip.Graph, crease, strip.Centre, 2.0, searches));
  std::vector<Vec3> normals;
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(
    strip.Graph, crease, strip.Centre, data, 2.0, normals, nullptr, 1.0, &searches));
  double worst = 0;
  for (std::size_t f = 0; f < F; ++f)
    worst = std::max(worst, Angle(normals[f], data[f]));
  EXPECT_LT(worst, 1e-9);
  // Without the cut the two sides mix near it.
  const std::vector<char> none(strip.Graph.Edges.size(), 0);
  ASSERT_TRUE(dg::sharp::SmoothFieldWithinSides(strip.Graph, none, strip.Centre, data, 2.0, normals));
  worst = 0;
  for (std::size_t f = 0; f < F; ++f)
    worst = std::max(worst, Angle(normals[f], data[f]));
  EXPECT_GT(worst, 10.0);
}

TEST(SharpFeaturesField, UndoingTheBlurRestoresTheFilletJunction)
{
  // An estimator that averages the true normals over a ball leans them
  // towards the fillet next to the junction; one step against a Gaussian
  // of the same spread takes most of that lean out, and leaves the flat
  // part far from the fillet as it was.
  const FilletStrip strip(6.0, 0.5, 10.0, 10);
  const std::size_t F = strip.Centre.size();
  const std::vector<char> crease(strip.Graph.Edges.size(), 0);
  const double sigma = 1.5;
  std::vector<Vec3> blurred = BruteMean(strip.Centre, strip.Normal, sigma);
  for (Vec3& b : blurred)
    b = b.Unit();
  std::vector<Vec3> undone;
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(
    strip.Graph, crease, strip.Centre, blurred, sigma, 1.0, undone));
  double before = 0, after = 0, far = 0;
  int junction = 0;
  for (std::size_t f = 0; f < F; ++f)
  {
    if (std::abs(strip.Arc[f]) < 2.0)
    {
      before += Angle(blurred[f], strip.Normal[f]);
      after += Angle(undone[f], strip.Normal[f]);
      ++junction;
    }
    // Beyond twice the cut (2 x 2.5 sigma): no blurred datum in reach.
    if (strip.Arc[f] < -7.5)
      far = std::max(far, Angle(undone[f], strip.Normal[f]));
  }
  ASSERT_GT(junction, 50);
  before /= junction;
  after /= junction;
  std::printf("junction: blurred %.3f deg, undone %.3f deg; flat far away %.2e deg\n", before,
    after, far);
  EXPECT_GT(before, 0.5); // the blur is there to undo
  EXPECT_LT(after, 0.5 * before); // measured 0.41
  EXPECT_LT(far, 1e-6);

  // A mask keeps the unmarked faces' data; gain 0 changes nothing.
  std::vector<char> where(F, 0);
  std::vector<Vec3> masked, none;
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(
    strip.Graph, crease, strip.Centre, blurred, sigma, 1.0, masked, &where));
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(
    strip.Graph, crease, strip.Centre, blurred, sigma, 0.0, none));
  for (std::size_t f = 0; f < F; ++f)
  {
    EXPECT_LT(Angle(masked[f], blurred[f]), 1e-12);
    EXPECT_LT(Angle(none[f], blurred[f]), 1e-9);
  }
  EXPECT_FALSE(dg::sharp::UndoBlurWithinSides(
    strip.Graph, crease, strip.Centre, blurred, 0.0, 1.0, none));

  // The gate (a Gaussian of 2 sigma over the correction) keeps the step at
  // the junction, where the blur's lean is systematic.
  std::vector<Vec3> gated;
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(
    strip.Graph, crease, strip.Centre, blurred, sigma, 1.0, gated, nullptr, nullptr, 2.0));
  double gatedJunction = 0;
  for (std::size_t f = 0; f < F; ++f)
    if (std::abs(strip.Arc[f]) < 2.0)
      gatedJunction += Angle(gated[f], strip.Normal[f]);
  gatedJunction /= junction;
  std::printf("junction with the gate: %.3f deg\n", gatedJunction);
  EXPECT_LT(gatedJunction, 0.6 * before);
}

TEST(SharpFeaturesField, TheGateLeavesTheDigitisationWiggleAlone)
{
  // A plane whose normals wiggle by 1 degree with a period of 4 edges (a
  // staircase's wiggle, which no blur made): the step without the gate
  // doubles the wiggle's short part; with the gate the averaged correction
  // stays under its start and the data come back unchanged.
  const FilletStrip strip(6.0, 0.5, 30.0, 30);
  const std::size_t F = strip.Centre.size();
  const std::vector<char> crease(strip.Graph.Edges.size(), 0);
  std::vector<char> plane(F);
  std::vector<Vec3> wiggle(F);
  const double amplitude = M_PI / 180;
  for (std::size_t f = 0; f < F; ++f)
  {
    const Vec3& c = strip.Centre[f];
    const double a = amplitude * std::sin(2 * M_PI * c.x / 4.0) * std::cos(2 * M_PI * c.y / 4.0);
    wiggle[f] = Vec3(std::sin(a), 0, -std::cos(a));
    plane[f] = strip.Arc[f] < -12.0; // beyond the reach of the fillet
  }
  std::vector<Vec3> plain, gated;
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(
    strip.Graph, crease, strip.Centre, wiggle, 1.5, 1.0, plain, &plane));
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(
    strip.Graph, crease, strip.Centre, wiggle, 1.5, 1.0, gated, &plane, nullptr, 2.0));
  const Vec3 down(0, 0, -1);
  double before = 0, without = 0, with = 0;
  int n = 0;
  for (std::size_t f = 0; f < F; ++f)
    if (plane[f] && strip.Centre[f].y > 6 && strip.Centre[f].y < 9)
    {
      before += Angle(wiggle[f], down);
      without += Angle(plain[f], down);
      with += Angle(gated[f], down);
      ++n;
    }
  ASSERT_GT(n, 50);
  std::printf("wiggle %.3f deg: step %.3f deg, gated step %.3f deg\n", before / n, without / n, with / n);
  EXPECT_GT(without, 1.3 * before);
  EXPECT_LT(with, 1.01 * before);
}

TEST(SharpFeaturesField, AnAveragedCorrectionUndoesTheBlurUnderNoise)
{
  // The fillet strip's blurred normals, turned by a random tilt (noise no
  // blur made). The raw step adds the noise's own correction to the data
  // where the noise opens the gate; the correction averaged over three
  // passes of the gate's Gaussian keeps most of the blur's lean at the
  // junction and leaves the plane far from it as it was.
  const FilletStrip strip(6.0, 0.5, 20.0, 40);
  const std::size_t F = strip.Centre.size();
  const std::vector<char> crease(strip.Graph.Edges.size(), 0);
  const double sigma = 1.5;
  std::vector<Vec3> noisy = BruteMean(strip.Centre, strip.Normal, sigma);
  std::uint64_t state = 12345;
  auto uniform = [&state]() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;
  };
  // Noise correlated over a few faces, as AT's is: independent tilts of 30
  // degrees RMS per axis averaged by a Gaussian of 1 (2 faces).
  const double tilt = 30 * M_PI / 180 * std::sqrt(12.0);
  std::vector<Vec3> tilts(F);
  for (Vec3& t : tilts)
    t = Vec3(tilt * uniform(), tilt * uniform(), tilt * uniform());
  const std::vector<Vec3> correlated = BruteMean(strip.Centre, tilts, 1.0);
  for (std::size_t f = 0; f < F; ++f)
    noisy[f] = (noisy[f].Unit() + correlated[f]).Unit();
  std::vector<Vec3> off, raw, averaged;
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(strip.Graph, crease, strip.Centre, noisy, sigma, 0.0,
    off, nullptr, nullptr, 2.0));
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(strip.Graph, crease, strip.Centre, noisy, sigma, 1.0,
    raw, nullptr, nullptr, 2.0));
  ASSERT_TRUE(dg::sharp::UndoBlurWithinSides(strip.Graph, crease, strip.Centre, noisy, sigma, 1.0,
    averaged, nullptr, nullptr, 2.0, nullptr, 1.0, 1.0));
  // Each result smoothed as the field smooths its data (a Gaussian of the
  // gate's width), against the truth.
  std::vector<Vec3> fieldOff = BruteMean(strip.Centre, off, 2.0),
                    fieldRaw = BruteMean(strip.Centre, raw, 2.0),
                    fieldAveraged = BruteMean(strip.Centre, averaged, 2.0);
  double junction[3] = { 0, 0, 0 }, plane[3] = { 0, 0, 0 };
  int nj = 0, np = 0;
  for (std::size_t f = 0; f < F; ++f)
  {
    const Vec3* r[3] = { &fieldOff[f], &fieldRaw[f], &fieldAveraged[f] };
    const bool inside = strip.Centre[f].y > 6 && strip.Centre[f].y < 14;
    if (inside && std::abs(strip.Arc[f]) < 2.0)
    {
      for (int k = 0; k < 3; ++k)
        junction[k] += Angle(*r[k], strip.Normal[f]);
      ++nj;
    }
    if (inside && strip.Arc[f] < -12.0)
    {
      for (int k = 0; k < 3; ++k)
        plane[k] += Angle(*r[k], strip.Normal[f]);
      ++np;
    }
  }
  ASSERT_GT(nj, 50);
  ASSERT_GT(np, 50);
  for (int k = 0; k < 3; ++k)
  {
    junction[k] /= nj;
    plane[k] /= np;
  }
  std::printf("junction: off %.3f, raw %.3f, averaged %.3f deg; plane: off %.3f, raw %.3f, "
              "averaged %.3f deg\n",
    junction[0], junction[1], junction[2], plane[0], plane[1], plane[2]);
  // Measured: junction 5.09 / 4.29 / 4.65, plane 1.72 / 2.03 / 1.72.
  EXPECT_LT(junction[2], 0.95 * junction[0]); // the lean undone
  EXPECT_LT(plane[2], 1.01 * plane[0]);       // the noise not amplified
  EXPECT_LT(plane[2], 0.93 * plane[1]);       // as the raw step amplifies it
}

} // namespace
