#include "dgCurvatureHalo.h"

#include "dgATHalo.h"

#include <vtkMultiProcessController.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <unordered_map>

namespace dg
{
namespace
{
std::int64_t Bits(double x)
{
  std::int64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

double Value(std::int64_t b)
{
  double x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}
} // namespace

void SumOverPieces(vtkMultiProcessController* controller, double* values, int count)
{
  ATHalo(controller).SumAll(values, count);
}

bool GatherCurvatureHalo(vtkMultiProcessController* controller, double reach, CurvatureMesh& mesh,
  std::string& error)
{
  const ATHalo halo(controller);
  const int n = halo.Processes, rank = halo.Rank;
  const std::int64_t F = static_cast<std::int64_t>(mesh.Offsets.size()) - 1;
  const bool regions = !mesh.Region.empty();
  const bool sides = !mesh.CreaseSides.empty();
  // Every piece's box of face centres (empty: +inf..-inf), and whether it
  // has regions (pieces without faces have no say).
  std::vector<double> centres(3 * F);
  std::vector<double> boxes(7 * n, 0.0);
  double* mine = &boxes[7 * rank];
  for (int a = 0; a < 3; ++a)
  {
    mine[a] = std::numeric_limits<double>::max();
    mine[3 + a] = -std::numeric_limits<double>::max();
  }
  for (std::int64_t f = 0; f < F; ++f)
  {
    const std::int64_t m = mesh.Offsets[f + 1] - mesh.Offsets[f];
    for (int a = 0; a < 3; ++a)
    {
      double c = 0;
      for (std::int64_t k = mesh.Offsets[f]; k < mesh.Offsets[f + 1]; ++k)
        c += mesh.Points[3 * mesh.Connectivity[k] + a];
      centres[3 * f + a] = c / static_cast<double>(m);
      mine[a] = std::min(mine[a], centres[3 * f + a]);
      mine[3 + a] = std::max(mine[3 + a], centres[3 * f + a]);
    }
  }
  mine[6] = F == 0 ? 0.0 : (regions ? 1.0 : 2.0) + (sides ? 2.0 : 0.0);
  // SumAll adds the zeros of the other slots: each slot is one process's.
  halo.SumAll(boxes.data(), 7 * n);
  bool withRegions = false, withoutRegions = false, withSides = false, withoutSides = false;
  for (int q = 0; q < n; ++q)
  {
    const double kind = boxes[7 * q + 6];
    withRegions = withRegions || kind == 1.0 || kind == 3.0;
    withoutRegions = withoutRegions || kind == 2.0 || kind == 4.0;
    withSides = withSides || kind > 2.0;
    withoutSides = withoutSides || kind == 1.0 || kind == 2.0;
  }
  if ((withRegions && withoutRegions) || (withSides && withoutSides))
  {
    error = withRegions && withoutRegions ? "the region array is on some pieces only"
                                          : "the crease sides array is on some pieces only";
    return false;
  }

  // Each face within reach of another piece's box goes to it: its id,
  // region, normal, then its corners (id, position).
  std::vector<std::vector<std::int64_t>> out(n);
  for (int q = 0; q < n; ++q)
  {
    const double* box = &boxes[7 * q];
    if (q == rank || box[6] == 0.0)
      continue;
    for (std::int64_t f = 0; f < mesh.OwnFaces; ++f)
    {
      bool near = true;
      for (int a = 0; a < 3 && near; ++a)
        near = centres[3 * f + a] >= box[a] - reach && centres[3 * f + a] <= box[3 + a] + reach;
      if (!near)
        continue;
      std::vector<std::int64_t>& o = out[q];
      o.push_back(mesh.FaceIds[f]);
      o.push_back(regions ? mesh.Region[f] : 0);
      o.push_back(sides ? mesh.CreaseSides[f] : 0);
      for (int a = 0; a < 3; ++a)
        o.push_back(Bits(mesh.Normals[3 * f + a]));
      o.push_back(mesh.Offsets[f + 1] - mesh.Offsets[f]);
      for (std::int64_t k = mesh.Offsets[f]; k < mesh.Offsets[f + 1]; ++k)
      {
        const std::int64_t p = mesh.Connectivity[k];
        o.push_back(mesh.PointIds[p]);
        for (int a = 0; a < 3; ++a)
          o.push_back(Bits(mesh.Points[3 * p + a]));
      }
    }
  }
  const auto in = halo.Exchange(out);

  std::unordered_map<std::int64_t, std::int64_t> pointOf;
  for (std::size_t p = 0; p < mesh.PointIds.size(); ++p)
    pointOf.emplace(mesh.PointIds[p], static_cast<std::int64_t>(p));
  for (int q = 0; q < n; ++q)
  {
    if (q == rank)
      continue;
    const std::vector<std::int64_t>& v = in[q];
    for (std::size_t i = 0; i + 7 <= v.size();)
    {
      mesh.FaceIds.push_back(v[i++]);
      const std::int64_t region = v[i++];
      if (regions)
        mesh.Region.push_back(static_cast<int>(region));
      const std::int64_t flags = v[i++];
      if (sides)
        mesh.CreaseSides.push_back(static_cast<unsigned char>(flags));
      for (int a = 0; a < 3; ++a)
        mesh.Normals.push_back(Value(v[i++]));
      const std::int64_t m = v[i++];
      for (std::int64_t c = 0; c < m; ++c)
      {
        const std::int64_t id = v[i++];
        auto it = pointOf.find(id);
        if (it == pointOf.end())
        {
          it = pointOf.emplace(id, static_cast<std::int64_t>(mesh.PointIds.size())).first;
          mesh.PointIds.push_back(id);
          for (int a = 0; a < 3; ++a)
            mesh.Points.push_back(Value(v[i + a]));
        }
        i += 3;
        mesh.Connectivity.push_back(it->second);
      }
      mesh.Offsets.push_back(static_cast<std::int64_t>(mesh.Connectivity.size()));
      mesh.Ghost.push_back(1);
    }
  }
  return true;
}
} // namespace dg
