// Feature-line quality (issue 15's metrics, dgFeatureMetrics.h) of AT's plain
// output and of vtkSharpFeaturesFilter after it, on ground-truth shapes, for
// parameter studies. Prints one line per case and method.
//
// Usage: BenchFeatureLines [--sizes 64] [--shapes cube,cube2,octahedron,cubesphere]
//          (also cylinder, wedge, cubesphere-twin: cubesphere's volume voxel for
//          voxel, with other true circles; mixed2 ... mixed12, a box whose four
//          edges along one axis are sharp and whose other eight are rounded
//          with that radius; and issue 39's smooth and filleted
//          shapes, torus ... blobs, fillet2 ... fillet12, and rounded prisms
//          prism6r2 ... prism12r12 (edges turning by 60, 45 or 30 degrees),
//          scored as smooth shapes: lines per 1000 surfels, errors, share
//          worse than II)
//          [--noise 0,0.3] [--seeds 1,2] [--radius R] [--alpha A] [--lambda L]
//          [--islands N (default 8, vtkDigitalIslandFilter; 0 = off)] [--depth D]
//          [--min-region M] [--angle DEG] [--strong-angle DEG] [--planar-angle DEG] [--edge-angle DEG] [--beta B]
//          [--residual R] [--fit 0|1] [--passes P] [--vote-depth D]
//          [--threshold T] [--second-pass 0|1] [--curved 0|1] [--quadric 0|1] [--quadric-merge F] [--quadric-distance D]
//          [--corner-depth D] [--turn-share S] [--field-width W (0: from the noise)] [--undo-blur 0|1]
// DG_ATCACHE=DIR keeps AT's output per case in DIR and reuses it (then only
// the stage runs, and the II and AT lines are not printed): parameter
// studies of the stage alone.
// DG_PROFILE=1 also prints the errors by distance to the edges and where the
// lines lie; DG_DUMP=PREFIX writes PREFIX_surface.vtp, _lines.vtp, _atlines.vtp
// (and _oracle.vtp with DG_ORACLE: the lines between the truth's parts).
#include "dgFeatureMetrics.h"
#include "dgGroundTruth.h"
#include "vtkAmbrosioTortorelliFilter.h"
#include "vtkDigitalIslandFilter.h"
#include "vtkDigitalSurfaceFilter.h"
#include "vtkIINormalEstimator.h"
#include "vtkSharpFeaturesFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkIdList.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <sys/stat.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using V3 = Eigen::Vector3d;

std::vector<std::string> Split(const std::string& s)
{
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty())
      out.push_back(item);
  return out;
}

// Where the benchmark's shapes sit (off the grid's symmetry), and cube ∩
// sphere's half side and radius.
V3 ShapeCentre(int n)
{
  return V3::Constant(0.5 * (n - 1)) + V3(0.13, 0.07, 0.11);
}
double CubeSphereHalfSide(int n)
{
  return 0.3 * n;
}
double CubeSphereRadius(int n)
{
  return 0.38 * n;
}

std::unique_ptr<dgtest::ImplicitShape> MakeShape(const std::string& name, int n)
{
  const V3 c = ShapeCentre(n);
  if (name == "cube")
    return dgtest::MakeRotatedCube(c, 0.26 * n, 20, 30, 10);
  if (name == "cube2")
    return dgtest::MakeRotatedCube(c, 0.26 * n, 35, 10, 50);
  if (name == "cubesphere")
    return dgtest::MakeCubeSphere(c, CubeSphereHalfSide(n), CubeSphereRadius(n));
  if (name == "cubesphere-twin")
  {
    // cubesphere with each face moved to the other end of the interval of
    // positions that leave the same voxels inside (the voxel centres are the
    // integer points): the same volume, voxel for voxel, and other circles.
    const double h = CubeSphereHalfSide(n);
    std::array<double, 6> d;
    for (int a = 0; a < 3; ++a)
    {
      const double hi = c[a] + h, lo = c[a] - h; // +a face: x <= hi; -a face: x >= lo
      const double fh = hi - std::floor(hi), fl = std::ceil(lo) - lo;
      d[2 * a] = (fh < 0.5 ? std::floor(hi) + 0.98 : std::floor(hi) + 0.02) - c[a];
      d[2 * a + 1] = c[a] - (fl < 0.5 ? std::ceil(lo) - 0.98 : std::ceil(lo) - 0.02);
    }
    return dgtest::MakeCubeSphere(c, d, CubeSphereRadius(n));
  }
  if (name == "octahedron")
    return dgtest::MakeOctahedron(c, 0.42 * n);
  if (name == "cylinder")
    return dgtest::MakeCylinder(c, 0.32 * n, 0.3 * n);
  if (name == "wedge")
    return dgtest::MakeWedge(c, 0.3 * n);
  // Sharp edges that end in fillets: "mixedR", the fillets' radius R voxels.
  for (int radius = 2; radius <= 12; ++radius)
    if (name == "mixed" + std::to_string(radius))
      return dgtest::MakeMixedBox(c, V3(0.3, 0.22, 0.18) * n, radius, 20, 30, 10);
  // The smooth and filleted shapes of issue 39 (no sharp edge): scored by
  // dgtest::MeasureSmooth instead.
  return dgtest::MakeSmoothShape(name, n);
}

bool IsSmooth(const std::string& name, int n)
{
  return dgtest::MakeSmoothShape(name, n) != nullptr;
}
// Mean unoriented error by distance to the nearest true edge (bins of 1 voxel).
std::string Profile(const dgtest::ImplicitShape& shape, vtkPolyData* surface, const char* name)
{
  const auto centres = dgtest::SurfelCenters(surface);
  vtkDataArray* n = surface->GetCellData()->GetArray(name);
  double sum[8] = { 0 };
  int count[8] = { 0 };
  int big = 0, outside = 0, flatBad = 0;
  for (std::size_t i = 0; i < centres.size(); ++i)
  {
    const double value = shape.Value(centres[i]);
    if (std::abs(value) > 2)
      continue;
    const V3 t = shape.Normal(centres[i]);
    const double d = shape.DistanceToSharpEdge(centres[i] - value * t, 9.0);
    const int b = d < 7 ? static_cast<int>(d) : 7;
    double u[3];
    n->GetTuple(i, u);
    double a = dgtest::AngleDegrees(V3(u[0], u[1], u[2]), t);
    sum[b] += std::min(a, 180 - a);
    ++count[b];
    if (b == 0)
    {
      big += std::min(a, 180 - a) > 30, outside += value > 0;
      if (std::min(a, 180 - a) > 30 && t.cwiseAbs().maxCoeff() > 0.9999)
        ++flatBad;
    }
  }
  std::string out;
  char buf[96];
  for (int b = 0; b < 8; ++b)
  {
    std::snprintf(buf, sizeof(buf), " %5.1f", count[b] ? sum[b] / count[b] : 0.0);
    out += buf;
  }
  std::snprintf(buf, sizeof(buf), " | bin0 >30deg %d/%d (true normal axis-aligned %d), outside %d", big,
    count[0], flatBad, outside);
  return out + buf;
}
vtkSmartPointer<vtkPolyData> LinesBetweenLabels(vtkPolyData* surface, const std::vector<int>& lab);

// The lines an oracle would draw: faces labelled by their true normal (one
// label per planar face of the shape, one for all curved parts), lines
// between differently labelled faces. Where the truth itself changes on the
// digital surface, so the best any labelling can do under these metrics.
vtkSmartPointer<vtkPolyData> OracleLines(const dgtest::ImplicitShape& shape, vtkPolyData* surface)
{
  const auto centres = dgtest::SurfelCenters(surface);
  std::map<std::array<long long, 3>, int> count;
  std::vector<std::array<long long, 3>> key(centres.size());
  for (std::size_t i = 0; i < centres.size(); ++i)
  {
    const V3 n = shape.Normal(centres[i]);
    key[i] = { std::llround(n.x() * 1e6), std::llround(n.y() * 1e6), std::llround(n.z() * 1e6) };
    ++count[key[i]];
  }
  std::map<std::array<long long, 3>, int> label;
  std::vector<int> lab(centres.size());
  for (std::size_t i = 0; i < centres.size(); ++i)
  {
    if (count[key[i]] < 10)
      lab[i] = -2; // curved
    else
    {
      auto it = label.emplace(key[i], static_cast<int>(label.size())).first;
      lab[i] = it->second;
    }
  }
  return LinesBetweenLabels(surface, lab);
}

// Cube-sphere labelled by a model that knows the sphere exactly but each
// disc's plane only as its digital surface shows it: every position of the
// plane between two voxel centres gives the same volume, and the model takes
// the plane at the faces' layer (the middle of that interval). Each face
// takes the part whose constraint is the most violated (the nearest part of
// a convex intersection) and that part's normal: the best a labelling can do
// without knowing where in its voxel the plane lies.
vtkSmartPointer<vtkPolyData> LayerOracle(int n, vtkPolyData* surface, bool atLayer)
{
  const V3 c = ShapeCentre(n);
  const double h = CubeSphereHalfSide(n), R = CubeSphereRadius(n);
  double off[6];
  for (int a = 0; a < 3; ++a)
  {
    off[2 * a] = atLayer ? std::floor(c[a] + h) + 0.5 - c[a] : h;
    off[2 * a + 1] = atLayer ? c[a] - (std::ceil(c[a] - h) - 0.5) : h;
  }
  const auto centres = dgtest::SurfelCenters(surface);
  std::vector<int> lab(centres.size());
  vtkNew<vtkDoubleArray> normals;
  normals->SetName("OracleNormals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(static_cast<vtkIdType>(centres.size()));
  for (std::size_t i = 0; i < centres.size(); ++i)
  {
    const V3 q = centres[i] - c;
    int best = 6;
    double value = q.norm() - R;
    V3 nrm = q.normalized();
    for (int k = 0; k < 6; ++k)
    {
      const double sgn = (k % 2) ? -1.0 : 1.0;
      const double val = sgn * q[k / 2] - off[k];
      if (val > value)
      {
        value = val, best = k;
        nrm = sgn * V3::Unit(k / 2);
      }
    }
    lab[i] = best;
    normals->SetTuple3(static_cast<vtkIdType>(i), nrm.x(), nrm.y(), nrm.z());
  }
  surface->GetCellData()->AddArray(normals);
  return LinesBetweenLabels(surface, lab);
}

vtkSmartPointer<vtkPolyData> LinesBetweenLabels(vtkPolyData* surface, const std::vector<int>& lab)
{
  std::map<std::pair<vtkIdType, vtkIdType>, std::vector<vtkIdType>> edgeFaces;
  vtkCellArray* polys = surface->GetPolys();
  vtkNew<vtkIdList> ids;
  vtkIdType f = 0;
  for (polys->InitTraversal(); polys->GetNextCell(ids); ++f)
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      vtkIdType a = ids->GetId(k), b = ids->GetId((k + 1) % ids->GetNumberOfIds());
      edgeFaces[{ std::min(a, b), std::max(a, b) }].push_back(f);
    }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(surface->GetPoints());
  vtkNew<vtkCellArray> lines;
  for (const auto& ef : edgeFaces)
  {
    bool differ = false;
    for (vtkIdType x : ef.second)
      for (vtkIdType y : ef.second)
        differ |= lab[x] != lab[y];
    if (differ)
    {
      vtkIdType pts[2] = { ef.first.first, ef.first.second };
      lines->InsertNextCell(2, pts);
    }
  }
  out->SetLines(lines);
  return out;
}
} // namespace

// DG_DUMP=PREFIX: the stage's surface and lines (and AT's lines) as .vtp.
void Dump(vtkSharpFeaturesFilter* sharp, vtkAmbrosioTortorelliFilter* at, const dgtest::ImplicitShape& shape)
{
  const char* dump = std::getenv("DG_DUMP");
  if (!dump)
    return;
  vtkNew<vtkPolyData> surface;
  surface->ShallowCopy(sharp->GetOutput(0));
  vtkNew<vtkDoubleArray> truth;
  truth->SetName("TrueNormals");
  truth->SetNumberOfComponents(3);
  // The distance to the nearest true sharp edge (capped at 10 voxels).
  vtkNew<vtkDoubleArray> edgeDistance;
  edgeDistance->SetName("SharpEdgeDistance");
  for (const V3& x : dgtest::SurfelCenters(surface))
  {
    const V3 t = shape.Normal(x);
    truth->InsertNextTuple3(t.x(), t.y(), t.z());
    edgeDistance->InsertNextValue(std::min(10.0, shape.DistanceToSharpEdge(x, 10.0)));
  }
  surface->GetCellData()->AddArray(truth);
  surface->GetCellData()->AddArray(edgeDistance);
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetInputData(surface);
  w->SetFileName((std::string(dump) + "_surface.vtp").c_str());
  w->Write();
  w->SetInputData(sharp->GetOutput(1));
  w->SetFileName((std::string(dump) + "_lines.vtp").c_str());
  w->Write();
  if (at)
  {
    w->SetInputData(at->GetOutput(1));
    w->SetFileName((std::string(dump) + "_atlines.vtp").c_str());
    w->Write();
  }
}

int main(int argc, char* argv[])
{
  std::vector<int> sizes = { 64 };
  std::vector<std::string> shapes = { "cube", "cube2", "octahedron", "cubesphere" };
  std::vector<double> noise = { 0, 0.3 };
  std::vector<int> seeds = { 1 };
  double radius = 4, alpha = 0.05, lambda = 0.005, angle = 15, strongAngle = 30, planarAngle = 6,
         quadricMerge = 3, quadricDistance = 3;
  int depth = 5, minRegion = 30;
  double threshold = 0.5, edgeAngle = 10;
  int islands = 8, passes = 2, voteDepth = 2, fit = 1, curved = 1, quadric = 1;
  double beta = 0.2, residual = 0.3, cornerDepth = 0.6, turnShare = 0.5, fieldWidth = 0;
  int undoBlur = 1;
  bool secondPass = false;
  for (int a = 1; a + 1 < argc; a += 2)
  {
    const std::string k = argv[a], v = argv[a + 1];
    if (k == "--sizes")
    {
      sizes.clear();
      for (auto& s : Split(v))
        sizes.push_back(std::stoi(s));
    }
    else if (k == "--shapes")
      shapes = Split(v);
    else if (k == "--noise")
    {
      noise.clear();
      for (auto& s : Split(v))
        noise.push_back(std::stod(s));
    }
    else if (k == "--seeds")
    {
      seeds.clear();
      for (auto& s : Split(v))
        seeds.push_back(std::stoi(s));
    }
    else if (k == "--radius")
      radius = std::stod(v);
    else if (k == "--alpha")
      alpha = std::stod(v);
    else if (k == "--lambda")
      lambda = std::stod(v);
    else if (k == "--depth")
      depth = std::stoi(v);
    else if (k == "--min-region")
      minRegion = std::stoi(v);
    else if (k == "--beta")
      beta = std::stod(v);
    else if (k == "--residual")
      residual = std::stod(v);
    else if (k == "--fit")
      fit = std::stoi(v);
    else if (k == "--curved")
      curved = std::stoi(v);
    else if (k == "--quadric")
      quadric = std::stoi(v);
    else if (k == "--quadric-merge")
      quadricMerge = std::stod(v);
    else if (k == "--quadric-distance")
      quadricDistance = std::stod(v);
    else if (k == "--second-pass")
      secondPass = std::stoi(v) != 0;
    else if (k == "--passes")
      passes = std::stoi(v);
    else if (k == "--vote-depth")
      voteDepth = std::stoi(v);
    else if (k == "--islands")
      islands = std::stoi(v);
    else if (k == "--edge-angle")
      edgeAngle = std::stod(v);
    else if (k == "--threshold")
      threshold = std::stod(v);
    else if (k == "--angle")
      angle = std::stod(v);
    else if (k == "--strong-angle")
      strongAngle = std::stod(v);
    else if (k == "--planar-angle")
      planarAngle = std::stod(v);
    else if (k == "--corner-depth")
      cornerDepth = std::stod(v);
    else if (k == "--turn-share")
      turnShare = std::stod(v);
    else if (k == "--field-width")
      fieldWidth = std::stod(v);
    else if (k == "--undo-blur")
      undoBlur = std::stoi(v);
    else
    {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  if (!std::getenv("VTK_SMP_BACKEND_IN_USE"))
    vtkSMPTools::SetBackend("STDThread");
  // The stage's parameters, the same on cached and fresh AT output.
  auto configure = [&](vtkSharpFeaturesFilter* sharp) {
    sharp->SetSearchDepth(depth);
    sharp->SetSmoothingPasses(passes);
    sharp->SetSmoothingDepth(voteDepth);
    sharp->SetRegionEdgeAngle(edgeAngle);
    sharp->SetFeatureThreshold(threshold);
    sharp->SetMinimumRegionSize(minRegion);
    sharp->SetMinimumFeatureAngle(angle);
    sharp->SetStrongFeatureAngle(strongAngle);
    sharp->SetPlanarRegionAngle(planarAngle);
    sharp->SetFitPlanes(fit != 0);
    sharp->SetCurvedSides(curved != 0);
    sharp->SetQuadricSides(quadric != 0);
    sharp->SetQuadricMergeFactor(quadricMerge);
    sharp->SetQuadricMergeDistance(quadricDistance);
    sharp->SetFitResidual(residual);
    sharp->SetReferenceWeight(beta);
    sharp->SetInputRadius(radius);
    sharp->SetCornerDepth(cornerDepth);
    sharp->SetMinimumTurnShare(turnShare);
    sharp->SetFieldWidth(fieldWidth);
    sharp->SetUndoInputBlur(undoBlur != 0);
  };
  for (int n : sizes)
    for (const auto& name : shapes)
    {
      auto shape = MakeShape(name, n);
      if (!shape)
      {
        std::fprintf(stderr, "unknown shape %s\n", name.c_str());
        return 2;
      }
      if (name == "cubesphere-twin")
      {
        const auto original = MakeShape("cubesphere", n);
        auto a = dgtest::Digitize(*original, n);
        auto b = dgtest::Digitize(*shape, n);
        const auto* pa = static_cast<const unsigned char*>(a->GetScalarPointer());
        const auto* pb = static_cast<const unsigned char*>(b->GetScalarPointer());
        long long differ = 0;
        for (vtkIdType i = 0; i < a->GetNumberOfPoints(); ++i)
          differ += pa[i] != pb[i];
        const auto& ea = original->SharpEdges();
        double sum = 0;
        const auto samples = shape->SharpEdgeSamples(0.25);
        for (const auto& x : samples)
          sum += ea.Distance(x, 10);
        // Any normal field's errors against the two truths add up to at least
        // the angle between them, face by face: max(error A, error B) within
        // one voxel of the edges >= sum of those angles / (|S_A| + |S_B|).
        vtkNew<vtkDigitalSurfaceFilter> ds;
        ds->SetInputData(a);
        ds->Update();
        double angles = 0;
        long long inA = 0, inB = 0;
        auto near = [](const dgtest::ImplicitShape& sh, const V3& x) {
          const double value = sh.Value(x);
          return std::abs(value) <= 2.0 &&
            sh.DistanceToSharpEdge(x - value * sh.Normal(x), 4.0) <= 1.0;
        };
        for (const V3& x : dgtest::SurfelCenters(ds->GetOutput()))
        {
          const bool a1 = near(*original, x), b1 = near(*shape, x);
          inA += a1, inB += b1;
          if (a1 && b1)
          {
            const double ang = dgtest::AngleDegrees(original->Normal(x), shape->Normal(x));
            angles += std::min(ang, 180.0 - ang);
          }
        }
        std::printf("cubesphere-twin %d: %lld voxels differ from cubesphere's volume; its circles lie %.2f "
                    "voxels from cubesphere's on average (so no line set has offset below %.2f on both); "
                    "no normal field has an error within 1 voxel of the edges below %.2f deg on both\n",
          n, differ, samples.empty() ? 0.0 : sum / samples.size(),
          samples.empty() ? 0.0 : 0.5 * sum / samples.size(), angles / std::max(1LL, inA + inB));
      }
      for (double k : noise)
        for (std::size_t si = 0; si < (k == 0 ? 1 : seeds.size()); ++si)
        {
          const auto t0 = std::chrono::steady_clock::now();
          std::string cached;
          if (const char* dir = std::getenv("DG_ATCACHE"))
          {
            char key[160];
            std::snprintf(key, sizeof(key), "/%s_%d_%.2f_%d_r%g_a%g_l%g_i%d.vtp", name.c_str(), n, k,
              seeds[si], radius, alpha, lambda, islands);
            cached = std::string(dir) + key;
          }
          struct stat st;
          if (!cached.empty() && stat(cached.c_str(), &st) == 0)
          {
            vtkNew<vtkXMLPolyDataReader> rd;
            rd->SetFileName(cached.c_str());
            rd->Update();
            vtkNew<vtkSharpFeaturesFilter> sharp;
            sharp->SetInputData(rd->GetOutput());
            configure(sharp);
            sharp->Update();
            if (IsSmooth(name, n))
            {
              const auto m = dgtest::MeasureSmooth(
                *shape, sharp->GetOutput(0), "SharpNormals", "IINormals", sharp->GetOutput(1));
              std::printf("%-10s %4d k %.1f s %d | sharp %s | cached\n", name.c_str(), n, k, seeds[si],
                m.Describe().c_str());
              Dump(sharp, nullptr, *shape);
              std::fflush(stdout);
              continue;
            }
            const auto mS = dgtest::MeasureFeatures(
              *shape, sharp->GetOutput(0), "SharpNormals", sharp->GetOutput(1));
            std::printf("%-10s %4d k %.1f s %d | sharp %s | band %lld unassigned %lld regions %d | cached\n",
              name.c_str(), n, k, seeds[si], mS.Describe().c_str(),
              static_cast<long long>(sharp->GetNumberOfBandFaces()),
              static_cast<long long>(sharp->GetNumberOfUnassignedFaces()), sharp->GetNumberOfRegions());
            Dump(sharp, nullptr, *shape);
            if (std::getenv("DG_PROFILE"))
              std::printf("   profile by edge distance 0..7+: sharp%s\n",
                Profile(*shape, sharp->GetOutput(0), "SharpNormals").c_str());
            std::fflush(stdout);
            continue;
          }
          vtkSmartPointer<vtkImageData> image = dgtest::NoisyDigitize(*shape, n, k, seeds[si]);
          if (islands > 1)
          {
            vtkNew<vtkDigitalIslandFilter> isl;
            isl->SetInputData(image);
            isl->SetMinimumSize(islands);
            isl->Update();
            image = isl->GetOutput();
          }
          vtkNew<vtkDigitalSurfaceFilter> surf;
          surf->SetInputData(image);
          vtkNew<vtkIINormalEstimator> ii;
          ii->SetInputConnection(surf->GetOutputPort());
          ii->SetSourceData(image);
          ii->SetRadius(radius);
          vtkNew<vtkAmbrosioTortorelliFilter> at;
          at->SetInputConnection(ii->GetOutputPort());
          at->SetAlpha(alpha);
          at->SetLambda(lambda);
          vtkNew<vtkSharpFeaturesFilter> sharp;
          sharp->SetInputConnection(at->GetOutputPort());
          configure(sharp);
          sharp->Update();
          if (!cached.empty())
          {
            vtkNew<vtkXMLPolyDataWriter> w;
            w->SetInputData(at->GetOutput(0));
            w->SetFileName(cached.c_str());
            w->SetDataModeToBinary();
            w->Write();
          }
          const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          if (IsSmooth(name, n))
          {
            const auto mA = dgtest::MeasureSmooth(
              *shape, at->GetOutput(0), "ATNormals", "IINormals", at->GetOutput(1));
            const auto m = dgtest::MeasureSmooth(
              *shape, sharp->GetOutput(0), "SharpNormals", "IINormals", sharp->GetOutput(1));
            std::printf("%-10s %4d k %.1f s %d | AT    %s\n", name.c_str(), n, k, seeds[si],
              mA.Describe().c_str());
            std::printf("%-10s %4d k %.1f s %d | sharp %s | %.1f s\n", name.c_str(), n, k, seeds[si],
              m.Describe().c_str(), s);
            Dump(sharp, at, *shape);
            std::fflush(stdout);
            continue;
          }
          const auto mAT = dgtest::MeasureFeatures(*shape, at->GetOutput(0), "ATNormals", at->GetOutput(1));
          const auto mII = dgtest::MeasureFeatures(*shape, ii->GetOutput(), "IINormals", nullptr);
          const auto mS = dgtest::MeasureFeatures(
            *shape, sharp->GetOutput(0), "SharpNormals", sharp->GetOutput(1));
          if (secondPass)
          {
            // AT again, fed with the side normals (an input that does not blur
            // across the edges), then the sharp stage again.
            vtkNew<vtkAmbrosioTortorelliFilter> at2;
            at2->SetInputConnection(sharp->GetOutputPort());
            at2->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, "SharpNormals");
            at2->SetAlpha(alpha);
            at2->SetLambda(lambda);
            vtkNew<vtkSharpFeaturesFilter> sharp2;
            sharp2->SetInputConnection(at2->GetOutputPort());
            sharp2->Update();
            const auto m2 = dgtest::MeasureFeatures(*shape, at2->GetOutput(0), "ATNormals", at2->GetOutput(1));
            const auto m3 = dgtest::MeasureFeatures(
              *shape, sharp2->GetOutput(0), "SharpNormals", sharp2->GetOutput(1));
            std::printf("%-10s %4d k %.1f s %d | AT2   %s\n", name.c_str(), n, k, seeds[si], m2.Describe().c_str());
            std::printf("%-10s %4d k %.1f s %d | sharp2 %s\n", name.c_str(), n, k, seeds[si], m3.Describe().c_str());
          }
          std::printf("%-10s %4d k %.1f s %d | II   err mean %.2f <1 %.2f <3 %.2f\n", name.c_str(), n, k,
            seeds[si], mII.MeanError, mII.Error1, mII.Error3);
          if (std::getenv("DG_ORACLE"))
          {
            auto oracleLines = OracleLines(*shape, surf->GetOutput());
            const auto mO = dgtest::MeasureFeatures(*shape, surf->GetOutput(), "Normals", oracleLines);
            if (const char* dump = std::getenv("DG_DUMP"))
            {
              vtkNew<vtkXMLPolyDataWriter> w;
              w->SetInputData(oracleLines);
              w->SetFileName((std::string(dump) + "_oracle.vtp").c_str());
              w->Write();
            }
            std::printf("%-10s %4d k %.1f s %d | oracle %s\n", name.c_str(), n, k, seeds[si],
              mO.Describe().c_str());
            if (name.rfind("cubesphere", 0) == 0)
              for (bool layer : { false, true })
              {
                vtkNew<vtkPolyData> copy;
                copy->DeepCopy(surf->GetOutput());
                auto lines = LayerOracle(n, copy, layer);
                const auto mL = dgtest::MeasureFeatures(*shape, copy, "OracleNormals", lines);
                std::printf("%-10s %4d k %.1f s %d | %s %s\n", name.c_str(), n, k, seeds[si],
                  layer ? "layer-oracle" : "model-oracle", mL.Describe().c_str());
              }
          }
          std::printf("%-10s %4d k %.1f s %d | AT    %s\n", name.c_str(), n, k, seeds[si],
            mAT.Describe().c_str());
          std::printf("%-10s %4d k %.1f s %d | sharp %s | band %lld unassigned %lld regions %d | %.1f s\n",
            name.c_str(), n, k, seeds[si], mS.Describe().c_str(),
            static_cast<long long>(sharp->GetNumberOfBandFaces()),
            static_cast<long long>(sharp->GetNumberOfUnassignedFaces()), sharp->GetNumberOfRegions(), s);
          Dump(sharp, at, *shape);
          if (std::getenv("DG_PROFILE"))
          {
            vtkPolyData* l = sharp->GetOutput(1);
            int h[5] = { 0 };
            for (vtkIdType c = 0; c < l->GetNumberOfCells(); ++c)
            {
              double a[3], b[3];
              vtkIdType npts;
              const vtkIdType* pts;
              l->GetCellPoints(c, npts, pts);
              l->GetPoint(pts[0], a);
              l->GetPoint(pts[1], b);
              const double d = shape->DistanceToSharpEdge(
                V3((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2), 20);
              ++h[d <= 1.5 ? 0 : d <= 3 ? 1 : d <= 6 ? 2 : d <= 12 ? 3 : 4];
            }
            std::printf("   sharp lines by edge distance <=1.5 %d, <=3 %d, <=6 %d, <=12 %d, more %d\n", h[0],
              h[1], h[2], h[3], h[4]);
          }
          if (std::getenv("DG_PROFILE"))
            std::printf("   profile by edge distance 0..7+: II%s\n   AT%s\n   sharp%s\n",
              Profile(*shape, ii->GetOutput(), "IINormals").c_str(),
              Profile(*shape, at->GetOutput(0), "ATNormals").c_str(),
              Profile(*shape, sharp->GetOutput(0), "SharpNormals").c_str());
          std::fflush(stdout);
        }
    }
  return 0;
}
