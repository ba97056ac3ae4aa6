#include "dgSharpFeaturesField.h"

#include <vtkSMPThreadLocal.h>
#include <vtkSMPTools.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace dg
{
namespace sharp
{
namespace
{

// Per thread: the search that last reached a face, and the part's faces
// gathered for the weights' loop.
struct Scratch
{
  std::vector<std::uint32_t> Stamp; // the search that last reached a face
  std::uint32_t Searches = 0;
  std::vector<std::uint32_t> Queue;
  // The part's faces, single precision and one array per coordinate
  // (centres relative to the part's first face), padded to whole blocks:
  // the weights' loop runs in vector registers.
  std::vector<float> X, Y, Z, DX, DY, DZ, IX, IY, IZ, IE, W, M;
};

// Lanes of the weights' loop: independent partial sums the compiler keeps
// in one vector register each.
constexpr int Lanes = 8;

// exp(-t) for t in [0, 3.125] (d^2 / 2 width^2 up to the cut at 2.5
// widths) as (exp(-t / 8))^8, the inner one by its Taylor polynomial of
// degree 6 (relative error below 3e-6): plain arithmetic, which vectorises,
// where a table lookup does not.
inline float NegativeExp(float t)
{
  const float u = -0.125f * t;
  float e = 1.0f + u * (1.0f + u * (0.5f + u * (1.0f / 6 + u * (1.0f / 24 + u * (1.0f / 120 + u * (1.0f / 720))))));
  e *= e;
  e *= e;
  return e * e;
}

// Each gathered face's weight for the face at (fx, fy, fz): the Gaussian
// (half = 1 / 2 width^2), 0 beyond the cut; M the same for the faces whose
// datum lies within 90 degrees of o, else 0. Plain arrays in and out, so
// that the loop runs in vector registers.
void Weigh(const float* __restrict X, const float* __restrict Y, const float* __restrict Z,
  const float* __restrict DX, const float* __restrict DY, const float* __restrict DZ, float fx,
  float fy, float fz, float ox, float oy, float oz, float half, float reach2, std::size_t n,
  float* __restrict W, float* __restrict M)
{
  for (std::size_t h = 0; h < n; ++h)
  {
    const float dx = X[h] - fx, dy = Y[h] - fy, dz = Z[h] - fz;
    const float d2 = dx * dx + dy * dy + dz * dz;
    // Evaluated everywhere (clamped) and then selected: a conditional call
    // would keep the loop scalar.
    const float t = d2 * half;
    const float e = NegativeExp(t < 4.0f ? t : 4.0f);
    const float w = d2 <= reach2 ? e : 0.0f;
    W[h] = w;
    M[h] = DX[h] * ox + DY[h] * oy + DZ[h] * oz >= 0.0f ? w : 0.0f;
  }
}

// out[f] = the Gaussian-weighted mean of in over the faces f's side reaches
// (dgSharpFeaturesField.h), for the faces `want` marks (every face the
// searches cover when null); the others keep out's value. extraIn, when
// given, is averaged the same way into extraOut.
void Convolve(const FieldSearches& searches, const std::vector<Vec3>& centre,
  const std::vector<Vec3>& data, double width, const std::vector<Vec3>& in, std::vector<Vec3>& out,
  const std::vector<char>* want = nullptr, const std::vector<double>* extraIn = nullptr,
  std::vector<double>* extraOut = nullptr)
{
  const std::int64_t T = static_cast<std::int64_t>(searches.Cubes.size());
  const double reach = std::min(2.5 * width, searches.Reach);
  const float reach2 = static_cast<float>(reach * reach);
  const float half = static_cast<float>(0.5 / (width * width));
  vtkSMPThreadLocal<Scratch> local;
  vtkSMPTools::For(0, T, [&](std::int64_t t0, std::int64_t t1) {
    Scratch& s = local.Local();
    for (std::int64_t t = t0; t < t1; ++t)
    {
      const FieldSearches::Cube& cube = searches.Cubes[t];
      const std::int64_t first = searches.TilePtr[t];
      const std::int64_t count = searches.TilePtr[t + 1] - first;
      const std::int64_t parts = static_cast<std::int64_t>(cube.PartStart.size()) - 1;
      for (std::int64_t p = 0; p < parts; ++p)
      {
        bool needed = false;
        for (std::int64_t j = 0; j < count && !needed; ++j)
          needed = cube.Part[j] == p && (!want || (*want)[searches.TileFaces[first + j]]);
        if (!needed)
          continue;
        // The part's faces in contiguous arrays: every face of the part reads
        // them all. The padding lies far away: zero weight.
        const std::uint32_t* members = cube.Members.data() + cube.PartStart[p];
        const std::size_t q = cube.PartStart[p + 1] - cube.PartStart[p];
        const std::size_t padded = (q + Lanes - 1) / Lanes * Lanes;
        const Vec3 origin = centre[members[0]];
        for (auto* v : { &s.X, &s.Y, &s.Z, &s.DX, &s.DY, &s.DZ, &s.IX, &s.IY, &s.IZ, &s.IE })
        {
          v->resize(v == &s.IE && !extraIn ? 0 : padded);
          if (!v->empty())
            std::fill(v->begin() + q, v->end(), 0.0f);
        }
        s.W.resize(padded); // written by Weigh for every face
        s.M.resize(padded);
        for (std::size_t h = q; h < padded; ++h)
          s.X[h] = 1e18f;
        for (std::size_t h = 0; h < q; ++h)
        {
          const std::int64_t g = members[h];
          s.X[h] = static_cast<float>(centre[g].x - origin.x);
          s.Y[h] = static_cast<float>(centre[g].y - origin.y);
          s.Z[h] = static_cast<float>(centre[g].z - origin.z);
          s.DX[h] = static_cast<float>(data[g].x);
          s.DY[h] = static_cast<float>(data[g].y);
          s.DZ[h] = static_cast<float>(data[g].z);
          s.IX[h] = static_cast<float>(in[g].x);
          s.IY[h] = static_cast<float>(in[g].y);
          s.IZ[h] = static_cast<float>(in[g].z);
        }
        if (extraIn)
          for (std::size_t h = 0; h < q; ++h)
            s.IE[h] = static_cast<float>((*extraIn)[members[h]]);
        const float *X = s.X.data(), *Y = s.Y.data(), *Z = s.Z.data();
        const float *DX = s.DX.data(), *DY = s.DY.data(), *DZ = s.DZ.data();
        const float *IX = s.IX.data(), *IY = s.IY.data(), *IZ = s.IZ.data(), *IE = s.IE.data();
        float *W = s.W.data(), *M = s.M.data();
        for (std::int64_t j = 0; j < count; ++j)
        {
          const std::int64_t f = searches.TileFaces[first + j];
          if (cube.Part[j] != p || (want && !(*want)[f]))
            continue;
          // The faces on f's side of a thin part: those whose data lie
          // within 90 degrees of f's, unless f's own datum is the odd one
          // out (a noise pit's faces, whose input points across the
          // surface), where the mean of all reached faces says where f faces.
          // One pass sums both; the odd ones out take a second.
          const float fx = static_cast<float>(centre[f].x - origin.x),
                      fy = static_cast<float>(centre[f].y - origin.y),
                      fz = static_cast<float>(centre[f].z - origin.z);
          const float ox = static_cast<float>(data[f].x), oy = static_cast<float>(data[f].y),
                      oz = static_cast<float>(data[f].z);
          float ax[Lanes] = {}, ay[Lanes] = {}, az[Lanes] = {}, sx[Lanes] = {}, sy[Lanes] = {},
                sz[Lanes] = {}, sw[Lanes] = {};
          Weigh(X, Y, Z, DX, DY, DZ, fx, fy, fz, ox, oy, oz, half, reach2, padded, W, M);
          for (std::size_t b = 0; b < padded; b += Lanes)
            for (int l = 0; l < Lanes; ++l)
            {
              const std::size_t h = b + l;
              ax[l] += DX[h] * W[h];
              ay[l] += DY[h] * W[h];
              az[l] += DZ[h] * W[h];
              sx[l] += IX[h] * M[h];
              sy[l] += IY[h] * M[h];
              sz[l] += IZ[h] * M[h];
              sw[l] += M[h];
            }
          Vec3 all, sum;
          double weights = 0, extra = 0;
          for (int l = 0; l < Lanes; ++l)
          {
            all += Vec3(ax[l], ay[l], az[l]);
            sum += Vec3(sx[l], sy[l], sz[l]);
            weights += sw[l];
          }
          if (extraIn)
          {
            float se[Lanes] = {};
            for (std::size_t b = 0; b < padded; b += Lanes)
              for (int l = 0; l < Lanes; ++l)
                se[l] += IE[b + l] * M[b + l];
            for (int l = 0; l < Lanes; ++l)
              extra += se[l];
          }
          if (data[f].Dot(all) < 0)
          {
            sum = Vec3();
            weights = extra = 0;
            for (std::size_t h = 0; h < q; ++h)
            {
              const double w = Vec3(DX[h], DY[h], DZ[h]).Dot(all) >= 0 ? W[h] : 0.0;
              sum += Vec3(IX[h], IY[h], IZ[h]) * w;
              weights += w;
              if (extraIn)
                extra += IE[h] * w;
            }
          }
          out[f] = weights > 0 ? sum * (1.0 / weights) : in[f];
          if (extraIn)
            (*extraOut)[f] = weights > 0 ? extra / weights : (*extraIn)[f];
        }
      }
    }
  });
}

// Whether searches found for `reach` serve a Gaussian that reaches `need`:
// far enough, and not so far that the weights' loop mostly reads faces
// beyond the cut.
bool Serves(const FieldSearches* searches, double need)
{
  return searches && searches->Reach >= need * (1 - 1e-12) && searches->Reach <= 2.0 * need;
}

} // namespace

void SideNeighbours::Build(const FaceGraph& graph, const std::vector<char>& crease, std::int64_t F)
{
  this->Ptr.assign(F + 1, 0);
  auto each = [&](std::int64_t f, auto&& visit) {
    for (std::int64_t j = graph.FaceEdgePtr[f]; j < graph.FaceEdgePtr[f + 1]; ++j)
    {
      const std::int64_t e = graph.FaceEdges[j];
      if (!crease[e])
        for (std::int64_t i = graph.EdgeFacePtr[e]; i < graph.EdgeFacePtr[e + 1]; ++i)
          if (graph.EdgeFaces[i] != f)
            visit(graph.EdgeFaces[i]);
    }
  };
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      std::int64_t n = 0;
      each(f, [&](std::int64_t) { ++n; });
      this->Ptr[f + 1] = n;
    }
  });
  std::partial_sum(this->Ptr.begin(), this->Ptr.end(), this->Ptr.begin());
  this->Next.resize(this->Ptr[F]);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      std::int64_t k = this->Ptr[f];
      each(f, [&](std::int64_t g) { this->Next[k++] = static_cast<std::uint32_t>(g); });
    }
  });
}

bool FindFieldSearches(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, double width, FieldSearches& searches,
  const std::vector<char>* where)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  if (!(width > 0) || F >= (std::int64_t(1) << 32))
    return false;
  // Cubes two widths wide: with the weights in vector registers the
  // searches are most of a pass's cost (octa-flower 512^3, clean: the field
  // 1.41 s with cubes one width wide, 1.06 s two, 0.99 s three); one search
  // per cube and part, not per face (fandisk 256^3 at k = 0.3, width 2.5:
  // 10.3-11.2 s with a search per face).
  const double size = 2.0 * width;
  // Each face's cube as one sortable key, 21 bits a coordinate (the
  // surface's box in cubes of at least 2 edges: 2^21 of them would be a
  // surface 4 million voxels wide).
  Vec3 lo = centre.empty() ? Vec3() : centre[0], hi = lo;
  for (const Vec3& c : centre)
  {
    lo = Vec3(std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z));
    hi = Vec3(std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z));
  }
  const double span = std::max({ hi.x - lo.x, hi.y - lo.y, hi.z - lo.z }) / size;
  if (!(span < (1 << 21) - 2))
    return false;
  auto cube = [&](double v, double origin) {
    return static_cast<std::int64_t>(std::floor(v / size) - std::floor(origin / size));
  };
  std::vector<std::pair<std::int64_t, std::int64_t>> keyed(F);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
      keyed[f] = { (cube(centre[f].x, lo.x) << 42) | (cube(centre[f].y, lo.y) << 21) |
          cube(centre[f].z, lo.z),
        f };
  });
  if (where)
    keyed.erase(std::remove_if(keyed.begin(), keyed.end(),
                  [&](const std::pair<std::int64_t, std::int64_t>& k) { return !(*where)[k.second]; }),
      keyed.end());
  std::sort(keyed.begin(), keyed.end());
  const std::int64_t N = static_cast<std::int64_t>(keyed.size());
  searches.TileFaces.resize(N);
  searches.TilePtr.clear();
  for (std::int64_t i = 0; i < N; ++i)
  {
    searches.TileFaces[i] = keyed[i].second;
    if (i == 0 || keyed[i].first != keyed[i - 1].first)
      searches.TilePtr.push_back(i);
  }
  searches.TilePtr.push_back(N);
  searches.Reach = 2.5 * width;
  const std::int64_t T = static_cast<std::int64_t>(searches.TilePtr.size()) - 1;
  searches.Cubes.assign(T, FieldSearches::Cube());
  if (!searches.Sides)
  {
    auto sides = std::make_shared<SideNeighbours>();
    sides->Build(graph, crease, F);
    searches.Sides = sides;
  }
  const std::vector<std::int64_t>& ptr = searches.Sides->Ptr;
  const std::vector<std::uint32_t>& next = searches.Sides->Next;
  const double reach = searches.Reach;
  vtkSMPThreadLocal<Scratch> local;
  vtkSMPTools::For(0, T, [&](std::int64_t t0, std::int64_t t1) {
    Scratch& s = local.Local();
    if (s.Stamp.empty())
      s.Stamp.assign(F, 0);
    for (std::int64_t t = t0; t < t1; ++t)
    {
      const std::int64_t first = searches.TilePtr[t];
      const std::int64_t count = searches.TilePtr[t + 1] - first;
      // The cube's box grown by the reach bounds what its faces can reach.
      Vec3 lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
      for (std::int64_t j = 0; j < count; ++j)
      {
        const Vec3& c = centre[searches.TileFaces[first + j]];
        lo = Vec3(std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z));
        hi = Vec3(std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z));
      }
      auto near = [&](const Vec3& c) {
        const double dx = std::max({ 0.0, lo.x - c.x, c.x - hi.x });
        const double dy = std::max({ 0.0, lo.y - c.y, c.y - hi.y });
        const double dz = std::max({ 0.0, lo.z - c.z, c.z - hi.z });
        return dx * dx + dy * dy + dz * dz <= reach * reach;
      };
      FieldSearches::Cube& cube = searches.Cubes[t];
      cube.Part.assign(count, -1);
      cube.PartStart.assign(1, 0);
      for (std::int64_t i = 0; i < count; ++i)
      {
        const std::int64_t seed = searches.TileFaces[first + i];
        if (cube.Part[i] >= 0)
          continue;
        // One part of the cube: the faces reached from seed without
        // crossing a crease (fewer parts than faces: no stamp repeats).
        const std::uint32_t stamp = ++s.Searches;
        s.Queue.assign(1, static_cast<std::uint32_t>(seed));
        s.Stamp[seed] = stamp;
        for (std::size_t h = 0; h < s.Queue.size(); ++h)
          for (std::int64_t k = ptr[s.Queue[h]]; k < ptr[s.Queue[h] + 1]; ++k)
          {
            const std::uint32_t n = next[k];
            if (s.Stamp[n] != stamp)
            {
              s.Stamp[n] = stamp;
              if (near(centre[n]))
                s.Queue.push_back(n);
            }
          }
        const std::int32_t part = static_cast<std::int32_t>(cube.PartStart.size()) - 1;
        for (std::int64_t j = i; j < count; ++j)
          if (s.Stamp[searches.TileFaces[first + j]] == stamp)
            cube.Part[j] = part;
        cube.Members.insert(cube.Members.end(), s.Queue.begin(), s.Queue.end());
        cube.PartStart.push_back(static_cast<std::uint32_t>(cube.Members.size()));
      }
      cube.Members.shrink_to_fit();
    }
  });
  return true;
}

bool UndoBlurWithinSides(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& data, double width, double gain,
  std::vector<Vec3>& normals, const std::vector<char>* where, const FieldSearches* shared,
  double gateWidth, std::vector<double>* leanDegrees, double gateScale, double averaged)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  if (!(width > 0))
    return false;
  const double widest = std::max(width, gateWidth);
  FieldSearches own;
  if (!shared || shared->Reach < 2.5 * widest * (1 - 1e-12) || !Serves(shared, 2.5 * width))
  {
    if (shared)
      own.Sides = shared->Sides;
    if (!FindFieldSearches(graph, crease, centre, widest, own, where))
      return false;
    shared = &own;
  }
  std::vector<Vec3> blurred(data), correction(F);
  Convolve(*shared, centre, data, width, data, blurred, where);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
      correction[f] = !where || (*where)[f] ? data[f] - blurred[f].Unit() : Vec3();
  });
  // The gate: the correction averaged over the gate's Gaussian is the
  // blur's systematic lean; the digitisation's wiggle averages out.
  std::vector<Vec3> lean;
  if (gateWidth > 0)
  {
    lean.assign(F, Vec3());
    Convolve(*shared, centre, data, gateWidth, correction, lean, where);
  }
  // Under noise the correction itself is mostly noise, which the step
  // would add to the data: its average over three passes of the gate's
  // Gaussian (about 1.7 gate widths) keeps the blur's lean, which varies
  // over the estimator's ball, and drops the noise, which does not
  // (docs/sharp-features.md, step 10).
  averaged = lean.empty() ? 0.0 : std::max(0.0, std::min(1.0, averaged));
  if (averaged > 0)
  {
    std::vector<Vec3> once(F), twice(F);
    Convolve(*shared, centre, data, gateWidth, lean, once, where);
    Convolve(*shared, centre, data, gateWidth, once, twice, where);
    vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
      for (std::int64_t f = begin; f < end; ++f)
        correction[f] = correction[f] * (1 - averaged) + twice[f] * averaged;
    });
  }
  const double raise = 1 + AveragedGateRaise * averaged;
  const double none = raise * gateScale * GateStartDegrees * M_PI / 180,
               all = raise * gateScale * GateFullDegrees * M_PI / 180;
  if (leanDegrees)
  {
    leanDegrees->assign(F, 0.0);
    for (std::int64_t f = 0; f < static_cast<std::int64_t>(lean.size()); ++f)
      (*leanDegrees)[f] = lean[f].Norm() * 180 / M_PI / gateScale;
  }
  normals.resize(F);
  vtkSMPTools::For(0, F, [&](std::int64_t begin, std::int64_t end) {
    for (std::int64_t f = begin; f < end; ++f)
    {
      const double open = lean.empty()
        ? 1.0
        : std::max(0.0, std::min(1.0, (lean[f].Norm() - none) / (all - none)));
      const Vec3 d = data[f] + correction[f] * (gain * open);
      normals[f] = (!where || (*where)[f]) && d.Norm() > 0 ? d.Unit() : data[f];
    }
  });
  return true;
}

bool SmoothFieldWithinSides(const FaceGraph& graph, const std::vector<char>& crease,
  const std::vector<Vec3>& centre, const std::vector<Vec3>& data, double width,
  std::vector<Vec3>& normals, const std::vector<char>* where, double edge,
  const FieldSearches* shared, const std::vector<double>* leanDegrees)
{
  const std::int64_t F = static_cast<std::int64_t>(centre.size());
  if (!(width > 0))
    return false;
  // With a mask, the first pass covers the masked faces and every face a
  // few reaches of steps around them: the second pass at a masked face
  // reads the first's residual within its reach. (A face the search
  // reaches by a longer walk has no residual: its correction is left out.)
  FieldSearches own;
  if (shared)
    own.Sides = shared->Sides;
  if (!own.Sides)
  {
    auto sides = std::make_shared<SideNeighbours>();
    sides->Build(graph, crease, F);
    own.Sides = sides;
  }
  std::vector<char> around;
  if (where)
  {
    const std::vector<std::int64_t>& ptr = own.Sides->Ptr;
    const std::vector<std::uint32_t>& next = own.Sides->Next;
    around = *where;
    std::vector<std::int64_t> front, grown;
    for (std::int64_t f = 0; f < F; ++f)
      if (around[f])
        front.push_back(f);
    const int depth = static_cast<int>(std::ceil(3.0 * width / std::max(1e-12, edge))) + 2;
    for (int d = 0; d < depth && !front.empty(); ++d)
    {
      grown.clear();
      for (std::int64_t f : front)
        for (std::int64_t k = ptr[f]; k < ptr[f + 1]; ++k)
          if (!around[next[k]])
          {
            around[next[k]] = 1;
            grown.push_back(next[k]);
          }
      front.swap(grown);
    }
  }
  if (!Serves(shared, 2.5 * width))
  {
    if (!FindFieldSearches(graph, crease, centre, width, own, where ? &around : nullptr))
      return false;
    shared = &own;
  }
  std::vector<Vec3> first(data), residual(F), second(F);
  Convolve(*shared, centre, data, width, data, first, where ? &around : nullptr);
  for (std::int64_t f = 0; f < F; ++f)
    residual[f] = data[f] - first[f];
  Convolve(*shared, centre, data, width, residual, second, where);
  std::vector<Vec3> wide;
  std::vector<double> leanAround;
  if (leanDegrees && !where)
  {
    // The same twicing with K K as the Gaussian (a Gaussian about sqrt 2
    // times as wide): 2 K^2 d - K^4 d, from K^2 d = first - second and two
    // more passes; the first of them also averages the lean.
    std::vector<Vec3> k2(F), k3(F);
    wide.resize(F);
    leanAround.resize(F);
    for (std::int64_t f = 0; f < F; ++f)
      k2[f] = first[f] - second[f];
    Convolve(*shared, centre, data, width, k2, k3, nullptr, leanDegrees, &leanAround);
    Convolve(*shared, centre, data, width, k3, wide, nullptr);
    for (std::int64_t f = 0; f < F; ++f)
      wide[f] = k2[f] * 2.0 - wide[f];
  }
  normals.resize(F);
  for (std::int64_t f = 0; f < F; ++f)
  {
    Vec3 u = first[f] + second[f];
    if (!wide.empty())
    {
      const double t = std::max(0.0,
        std::min(1.0, (leanAround[f] - WideStartDegrees) / (WideFullDegrees - WideStartDegrees)));
      u = u.Unit() * t + wide[f].Unit() * (1 - t);
    }
    normals[f] = u.Norm() > 0 ? u.Unit() : data[f];
  }
  return true;
}

} // namespace sharp
} // namespace dg
