// The Ambrosio-Tortorelli core without pipelines: the operators A, B, M on
// hand-checked complexes (a cube of 6 quads, a tetrahedron, an open and a
// non-manifold triangle mesh), their algebraic identities on digital
// surfaces, the assembled systems and energy against independent formulas,
// one step against a dense solve, energy descent, the three linear solvers
// against each other, and determinism across thread counts.
#include "dgATOperators.h"
#include "dgATSolver.h"
#include "dgGroundTruth.h"
#include "dgTestShapes.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <map>
#include <random>

namespace
{
struct Polygons
{
  std::int64_t NumberOfVertices = 0;
  std::vector<std::int64_t> Offsets{ 0 };
  std::vector<std::int64_t> Connectivity;
  void Add(std::initializer_list<std::int64_t> face)
  {
    for (std::int64_t v : face)
    {
      this->Connectivity.push_back(v);
    }
    this->Offsets.push_back(static_cast<std::int64_t>(this->Connectivity.size()));
  }
  std::int64_t NumberOfFaces() const { return static_cast<std::int64_t>(this->Offsets.size()) - 1; }
};

// Unit cube, vertex id = x + 2y + 4z, faces counter-clockwise from outside:
// -z, +z, -y, +y, -x, +x.
Polygons Cube()
{
  Polygons p;
  p.NumberOfVertices = 8;
  p.Add({ 0, 2, 3, 1 });
  p.Add({ 4, 5, 7, 6 });
  p.Add({ 0, 1, 5, 4 });
  p.Add({ 2, 6, 7, 3 });
  p.Add({ 0, 4, 6, 2 });
  p.Add({ 1, 3, 7, 5 });
  return p;
}

// Tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), faces oriented outward.
Polygons Tetrahedron()
{
  Polygons p;
  p.NumberOfVertices = 4;
  p.Add({ 0, 2, 1 });
  p.Add({ 0, 1, 3 });
  p.Add({ 0, 3, 2 });
  p.Add({ 1, 2, 3 });
  return p;
}

Polygons FromPolyData(vtkPolyData* pd)
{
  Polygons p;
  p.NumberOfVertices = pd->GetNumberOfPoints();
  vtkNew<vtkIdList> ids;
  auto* polys = pd->GetPolys();
  polys->InitTraversal();
  while (polys->GetNextCell(ids))
  {
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
    {
      p.Connectivity.push_back(ids->GetId(i));
    }
    p.Offsets.push_back(static_cast<std::int64_t>(p.Connectivity.size()));
  }
  return p;
}

vtkSmartPointer<vtkPolyData> Surface(vtkImageData* image)
{
  vtkNew<vtkDigitalSurfaceFilter> f;
  f->SetInputData(image);
  f->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(f->GetOutput());
  return out;
}

dg::ATComplex Build(const Polygons& p)
{
  dg::ATComplex c;
  std::string error;
  EXPECT_TRUE(c.Build(p.NumberOfVertices, p.Offsets, p.Connectivity, &error)) << error;
  return c;
}

Eigen::MatrixXd Dense(const dg::ATSparse& m)
{
  return Eigen::MatrixXd(m);
}
Eigen::MatrixXd Dense(const dg::ATSystemMatrix& m)
{
  return Eigen::MatrixXd(m);
}

// A noisy normal field per surfel: the trivial normal of a digital surface
// plus a deterministic perturbation, or a random field for abstract meshes.
Eigen::MatrixXd RandomField(std::int64_t n, int c, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> d;
  Eigen::MatrixXd g(n, c);
  for (std::int64_t i = 0; i < n; ++i)
    for (int k = 0; k < c; ++k)
      g(i, k) = d(rng);
  return g;
}

Eigen::MatrixXd TrivialNormalsPlusNoise(vtkPolyData* pd, double sigma, unsigned seed)
{
  vtkDataArray* n = pd->GetCellData()->GetNormals();
  std::mt19937 rng(seed);
  std::normal_distribution<double> d(0.0, sigma);
  Eigen::MatrixXd g(pd->GetNumberOfCells(), 3);
  for (vtkIdType c = 0; c < pd->GetNumberOfCells(); ++c)
  {
    Eigen::Vector3d x(n->GetComponent(c, 0), n->GetComponent(c, 1), n->GetComponent(c, 2));
    x += Eigen::Vector3d(d(rng), d(rng), d(rng));
    g.row(c) = x.normalized().transpose();
  }
  return g;
}

double MaxAbs(const Eigen::MatrixXd& m)
{
  return m.size() ? m.cwiseAbs().maxCoeff() : 0.0;
}
} // namespace

TEST(ATOperators, CubeMatchesHandWrittenMatrices)
{
  const dg::ATComplex c = Build(Cube());
  ASSERT_EQ(c.NumberOfVertices(), 8);
  ASSERT_EQ(c.NumberOfEdges(), 12);
  ASSERT_EQ(c.NumberOfFaces(), 6);
  const int edges[12][2] = { { 0, 1 },
    { 0, 2 },
    { 0, 4 },
    { 1, 3 },
    { 1, 5 },
    { 2, 3 },
    { 2, 6 },
    { 3, 7 },
    { 4, 5 },
    { 4, 6 },
    { 5, 7 },
    { 6, 7 } };
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(12, 8), m = Eigen::MatrixXd::Zero(12, 8);
  for (int e = 0; e < 12; ++e)
  {
    EXPECT_EQ(c.EdgeVertices[2 * e], edges[e][0]);
    EXPECT_EQ(c.EdgeVertices[2 * e + 1], edges[e][1]);
    a(e, edges[e][0]) = -1;
    a(e, edges[e][1]) = 1;
    m(e, edges[e][0]) = m(e, edges[e][1]) = 0.5;
  }
  // Worked out by hand from the face windings: +1 where the face runs
  // low -> high along the edge.
  Eigen::MatrixXd b(12, 6);
  b << -1, 0, 1, 0, 0, 0, //
    1, 0, 0, 0, -1, 0,    //
    0, 0, -1, 0, 1, 0,    //
    -1, 0, 0, 0, 0, 1,    //
    0, 0, 1, 0, 0, -1,    //
    1, 0, 0, -1, 0, 0,    //
    0, 0, 0, 1, -1, 0,    //
    0, 0, 0, -1, 0, 1,    //
    0, 1, -1, 0, 0, 0,    //
    0, -1, 0, 0, 1, 0,    //
    0, 1, 0, 0, 0, -1,    //
    0, -1, 0, 1, 0, 0;
  EXPECT_EQ(MaxAbs(Dense(c.MatrixA()) - a), 0.0);
  EXPECT_EQ(MaxAbs(Dense(c.MatrixM()) - m), 0.0);
  EXPECT_EQ(MaxAbs(Dense(c.MatrixB()) - b), 0.0);
}

TEST(ATOperators, TriangleMeshesMatchHandWrittenMatrices)
{
  {
    const dg::ATComplex c = Build(Tetrahedron());
    ASSERT_EQ(c.NumberOfEdges(), 6);
    Eigen::MatrixXd a(6, 4), b(6, 4);
    a << -1, 1, 0, 0, //
      -1, 0, 1, 0,    //
      -1, 0, 0, 1,    //
      0, -1, 1, 0,    //
      0, -1, 0, 1,    //
      0, 0, -1, 1;
    b << -1, 1, 0, 0, //
      1, 0, -1, 0,    //
      0, -1, 1, 0,    //
      -1, 0, 0, 1,    //
      0, 1, 0, -1,    //
      0, 0, -1, 1;
    EXPECT_EQ(MaxAbs(Dense(c.MatrixA()) - a), 0.0);
    EXPECT_EQ(MaxAbs(Dense(c.MatrixM()) - 0.5 * a.cwiseAbs()), 0.0);
    EXPECT_EQ(MaxAbs(Dense(c.MatrixB()) - b), 0.0);
  }
  {
    // Open square split in two triangles (boundary edges have one face),
    // plus a fin: a third triangle on the diagonal makes it non-manifold.
    Polygons p;
    p.NumberOfVertices = 5;
    p.Add({ 0, 1, 2 });
    p.Add({ 0, 2, 3 });
    p.Add({ 2, 0, 4 });
    const dg::ATComplex c = Build(p);
    // Edges: 01 02 03 04 12 23 24.
    ASSERT_EQ(c.NumberOfEdges(), 7);
    Eigen::MatrixXd b(7, 3);
    b << 1, 0, 0, //
      -1, 1, -1,  //
      0, -1, 0,   //
      0, 0, 1,    //
      1, 0, 0,    //
      0, 1, 0,    //
      0, 0, -1;
    EXPECT_EQ(MaxAbs(Dense(c.MatrixB()) - b), 0.0);
    EXPECT_EQ(c.EdgeFacePtr[2] - c.EdgeFacePtr[1], 3); // the fin edge has 3 faces
  }
}

TEST(ATOperators, BadComplexIsRejected)
{
  dg::ATComplex c;
  std::string error;
  Polygons p;
  p.NumberOfVertices = 3;
  p.Add({ 0, 1, 5 });
  EXPECT_FALSE(c.Build(p.NumberOfVertices, p.Offsets, p.Connectivity, &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
  Polygons q;
  q.NumberOfVertices = 3;
  q.Add({ 1, 1, 1 });
  EXPECT_FALSE(c.Build(q.NumberOfVertices, q.Offsets, q.Connectivity, &error));
  EXPECT_NE(error.find("degenerate"), std::string::npos) << error;
}

TEST(ATOperators, AlgebraicIdentitiesOnDigitalSurfaces)
{
  auto ball = Surface(dgtest::Ball(14, 5.3));
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(8.1, 7.9, 8.2), 4.5, 20, 30, 10);
  auto rotated = Surface(dgtest::Digitize(*cube, 17));
  for (vtkPolyData* pd : { ball.Get(), rotated.Get() })
  {
    const Polygons p = FromPolyData(pd);
    const dg::ATComplex c = Build(p);
    const dg::ATSparse a = c.MatrixA(), b = c.MatrixB();
    // Closed manifold (genus 0 here): V - E + F = 2.
    EXPECT_EQ(c.NumberOfVertices() - c.NumberOfEdges() + c.NumberOfFaces(), 2);

    // A^T A is the graph Laplacian of the edges found independently.
    std::map<std::pair<vtkIdType, vtkIdType>, int> edgeSet;
    for (std::int64_t f = 0; f < p.NumberOfFaces(); ++f)
      for (std::int64_t k = p.Offsets[f]; k < p.Offsets[f + 1]; ++k)
      {
        const std::int64_t u = p.Connectivity[k];
        const std::int64_t w = p.Connectivity[k + 1 < p.Offsets[f + 1] ? k + 1 : p.Offsets[f]];
        edgeSet[{ std::min(u, w), std::max(u, w) }] = 1;
      }
    ASSERT_EQ(static_cast<std::int64_t>(edgeSet.size()), c.NumberOfEdges());
    const int n = static_cast<int>(c.NumberOfVertices());
    Eigen::SparseMatrix<double> lap(n, n);
    std::vector<Eigen::Triplet<double>> t;
    for (const auto& e : edgeSet)
    {
      const int i = static_cast<int>(e.first.first), j = static_cast<int>(e.first.second);
      t.emplace_back(i, j, -1.0);
      t.emplace_back(j, i, -1.0);
      t.emplace_back(i, i, 1.0);
      t.emplace_back(j, j, 1.0);
    }
    lap.setFromTriplets(t.begin(), t.end());
    Eigen::SparseMatrix<double> ata = Eigen::SparseMatrix<double>(a.transpose()) * a;
    EXPECT_EQ((ata - lap).norm(), 0.0);

    // Constant fields: A 1 = 0; B 1 = 0 on a closed oriented manifold (the
    // two faces of an edge cross it in opposite directions); and d1 d0 = 0,
    // i.e. B^T A = 0: the circulation of a gradient edge field around every
    // face vanishes, by orientation.
    EXPECT_EQ((a * Eigen::VectorXd::Ones(a.cols())).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ((b * Eigen::VectorXd::Ones(b.cols())).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ((Eigen::SparseMatrix<double>(b.transpose()) * a).norm(), 0.0);
    // Every edge has two faces with opposite signs, or four (a digitised
    // rotated cube has the odd non-manifold linel) of which two enter and
    // two leave.
    for (std::int64_t e = 0; e < c.NumberOfEdges(); ++e)
    {
      const auto n = c.EdgeFacePtr[e + 1] - c.EdgeFacePtr[e];
      ASSERT_TRUE(n == 2 || n == 4) << n;
      int sum = 0;
      for (auto i = c.EdgeFacePtr[e]; i < c.EdgeFacePtr[e + 1]; ++i)
      {
        ASSERT_EQ(std::abs(c.EdgeFaceSigns[i]), 1);
        sum += c.EdgeFaceSigns[i];
      }
      ASSERT_EQ(sum, 0);
    }
  }
}

TEST(ATOperators, NonManifoldDigitalSurface)
{
  // Two voxels touching along an edge only: that linel has four quads, and
  // B still sums to zero there (two enter, two leave).
  auto image = dgtest::MakeImage(4,
    4,
    3,
    [](int i, int j, int k)
    { return (k == 1 && ((i == 1 && j == 1) || (i == 2 && j == 2))) ? 1.0 : 0.0; });
  auto pd = Surface(image);
  const dg::ATComplex c = Build(FromPolyData(pd));
  EXPECT_EQ(c.NumberOfFaces(), 12);
  int four = 0;
  for (std::int64_t e = 0; e < c.NumberOfEdges(); ++e)
  {
    const auto n = c.EdgeFacePtr[e + 1] - c.EdgeFacePtr[e];
    four += n == 4;
    int sum = 0;
    for (auto i = c.EdgeFacePtr[e]; i < c.EdgeFacePtr[e + 1]; ++i)
    {
      sum += c.EdgeFaceSigns[i];
    }
    EXPECT_EQ(sum, 0);
  }
  EXPECT_EQ(four, 1);
}

TEST(ATOperators, SystemsAndEnergyMatchOperatorFormulas)
{
  auto pd = Surface(dgtest::Ball(10, 3.4));
  const Polygons p = FromPolyData(pd);
  const dg::ATComplex c = Build(p);
  dg::ATParameters params;
  params.Alpha = 0.07;
  params.Lambda = 0.02;
  dg::ATSolver s(c, params);
  const Eigen::MatrixXd g = TrivialNormalsPlusNoise(pd, 0.3, 3);
  s.Initialize(g);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unif(0.0, 1.0);
  for (std::int64_t i = 0; i < s.V().size(); ++i)
  {
    s.V()[i] = unif(rng);
  }
  s.U() = g + 0.2 * RandomField(g.rows(), 3, 12);
  const double eps = 0.7;
  const Eigen::MatrixXd a = Dense(c.MatrixA()), b = Dense(c.MatrixB()), m = Dense(c.MatrixM());
  const Eigen::VectorXd& v = s.V();
  const Eigen::MatrixXd& u = s.U();
  const Eigen::VectorXd mv = m * v;
  const Eigen::MatrixXd bu = b * u;

  // The systems of docs/method.md section 4, from dense operators.
  s.AssembleU();
  s.AssembleV(eps);
  const Eigen::MatrixXd ku = params.Alpha * Eigen::MatrixXd::Identity(g.rows(), g.rows()) +
                             b.transpose() * mv.cwiseAbs2().asDiagonal() * b;
  const Eigen::VectorXd q = bu.cwiseAbs2().rowwise().sum();
  const Eigen::MatrixXd kv =
    params.Lambda / (4 * eps) * Eigen::MatrixXd::Identity(v.size(), v.size()) +
    params.Lambda * eps * a.transpose() * a + m.transpose() * q.asDiagonal() * m;
  EXPECT_LT(MaxAbs(Dense(s.UMatrix()) - ku), 1e-13);
  EXPECT_LT(MaxAbs(Dense(s.VMatrix()) - kv), 1e-13);

  // Energy: operators vs the solver's per-edge sums vs a brute force over
  // the polygons' sides (each manifold edge seen twice, once per face).
  const double fromOperators =
    params.Alpha * (u - g).squaredNorm() + (mv.asDiagonal() * bu).squaredNorm() +
    params.Lambda * eps * (a * v).squaredNorm() +
    params.Lambda / (4 * eps) * (Eigen::VectorXd::Ones(v.size()) - v).squaredNorm();
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::pair<std::int64_t, int>>> sides;
  for (std::int64_t f = 0; f < p.NumberOfFaces(); ++f)
    for (std::int64_t k = p.Offsets[f]; k < p.Offsets[f + 1]; ++k)
    {
      const std::int64_t x = p.Connectivity[k];
      const std::int64_t y = p.Connectivity[k + 1 < p.Offsets[f + 1] ? k + 1 : p.Offsets[f]];
      sides[{ std::min(x, y), std::max(x, y) }].push_back({ f, x < y ? 1 : -1 });
    }
  double brute = 0;
  for (std::int64_t f = 0; f < g.rows(); ++f)
  {
    brute += params.Alpha * (u.row(f) - g.row(f)).squaredNorm();
  }
  for (const auto& e : sides)
  {
    const double va = v[e.first.first], vb = v[e.first.second];
    ASSERT_EQ(e.second.size(), 2u);
    // The face that crosses the edge low -> high minus the other one.
    const auto& s0 = e.second[0].second > 0 ? e.second[0] : e.second[1];
    const auto& s1 = e.second[0].second > 0 ? e.second[1] : e.second[0];
    const double jump2 = (u.row(s0.first) - u.row(s1.first)).squaredNorm();
    brute += 0.25 * (va + vb) * (va + vb) * jump2 + params.Lambda * eps * (vb - va) * (vb - va);
  }
  for (std::int64_t i = 0; i < v.size(); ++i)
  {
    brute += params.Lambda / (4 * eps) * (1 - v[i]) * (1 - v[i]);
  }
  EXPECT_NEAR(s.Energy(eps), fromOperators, 1e-10 * fromOperators);
  EXPECT_NEAR(s.Energy(eps), brute, 1e-10 * brute);
}

TEST(ATOperators, OneStepEqualsDenseSolve)
{
  auto pd = Surface(dgtest::Ball(8, 2.6));
  const dg::ATComplex c = Build(FromPolyData(pd));
  const Eigen::MatrixXd g = TrivialNormalsPlusNoise(pd, 0.4, 5);
  for (auto solver : { dg::ATLinearSolver::ConjugateGradient,
         dg::ATLinearSolver::SimplicialLDLT,
         dg::ATLinearSolver::Cholmod,
         dg::ATLinearSolver::ConjugateGradientIC })
  {
    if (solver == dg::ATLinearSolver::Cholmod && !dg::CholmodAvailable())
    {
      continue;
    }
    dg::ATParameters params;
    params.Solver = solver;
    params.CGTolerance = 1e-13;
    dg::ATSolver s(c, params);
    s.Initialize(g);
    const double eps = 1.0;
    // Start from a non-trivial v so that the u-matrix is not alpha I + L.
    for (std::int64_t i = 0; i < s.V().size(); ++i)
    {
      s.V()[i] = 0.3 + 0.7 * std::abs(std::sin(1.7 * i));
    }
    const Eigen::MatrixXd a = Dense(c.MatrixA()), b = Dense(c.MatrixB()), m = Dense(c.MatrixM());
    const Eigen::VectorXd mv = m * s.V();
    const Eigen::MatrixXd ku = params.Alpha * Eigen::MatrixXd::Identity(g.rows(), g.rows()) +
                               b.transpose() * mv.cwiseAbs2().asDiagonal() * b;
    const Eigen::MatrixXd uRef = ku.ldlt().solve(params.Alpha * g);
    ASSERT_TRUE(s.StepU()) << dg::ATLinearSolverName(solver);
    EXPECT_LT(MaxAbs(s.U() - uRef), 1e-10) << dg::ATLinearSolverName(solver);

    const Eigen::VectorXd q = (b * s.U()).cwiseAbs2().rowwise().sum();
    const int n = static_cast<int>(s.V().size());
    const Eigen::MatrixXd kv = params.Lambda / (4 * eps) * Eigen::MatrixXd::Identity(n, n) +
                               params.Lambda * eps * a.transpose() * a +
                               m.transpose() * q.asDiagonal() * m;
    const Eigen::VectorXd vRef =
      kv.ldlt().solve(Eigen::VectorXd::Constant(n, params.Lambda / (4 * eps)));
    ASSERT_TRUE(s.StepV(eps)) << dg::ATLinearSolverName(solver);
    EXPECT_LT(MaxAbs(s.V() - vRef), 1e-10) << dg::ATLinearSolverName(solver);
    EXPECT_TRUE(s.Warnings().empty());
  }
}

// The CG solvers fix the column count at compile time for 1 and 3 columns
// and take any other count at run time: that path must solve as exactly.
TEST(ATOperators, StepUWithOtherColumnCountsEqualsDenseSolve)
{
  auto pd = Surface(dgtest::Ball(8, 2.6));
  const dg::ATComplex c = Build(FromPolyData(pd));
  const Eigen::MatrixXd b = Dense(c.MatrixB()), m = Dense(c.MatrixM());
  for (int nc : { 2, 5, 17 })
  {
    const Eigen::MatrixXd g = RandomField(c.NumberOfFaces(), nc, 40 + nc);
    for (auto solver :
      { dg::ATLinearSolver::ConjugateGradient, dg::ATLinearSolver::ConjugateGradientIC })
    {
      dg::ATParameters params;
      params.Solver = solver;
      params.CGTolerance = 1e-13;
      params.Normalize = false;
      dg::ATSolver s(c, params);
      s.Initialize(g);
      for (std::int64_t i = 0; i < s.V().size(); ++i)
      {
        s.V()[i] = 0.3 + 0.7 * std::abs(std::sin(1.3 * i));
      }
      const Eigen::VectorXd mv = m * s.V();
      const Eigen::MatrixXd ku = params.Alpha * Eigen::MatrixXd::Identity(g.rows(), g.rows()) +
                                 b.transpose() * mv.cwiseAbs2().asDiagonal() * b;
      const Eigen::MatrixXd uRef = ku.ldlt().solve(params.Alpha * g);
      ASSERT_TRUE(s.StepU()) << dg::ATLinearSolverName(solver) << ", " << nc << " columns";
      EXPECT_LT(MaxAbs(s.U() - uRef), 1e-10)
        << dg::ATLinearSolverName(solver) << ", " << nc << " columns";
    }
  }
}

TEST(ATOperators, EnergyDecreasesWithinEachLevel)
{
  std::vector<vtkSmartPointer<vtkPolyData>> shapes;
  shapes.push_back(Surface(dgtest::Ball(20, 7.3)));
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(12.1, 11.9, 12.2), 7, 20, 30, 10);
  shapes.push_back(Surface(dgtest::Digitize(*cube, 25)));
  auto cs = dgtest::MakeCubeSphere(Eigen::Vector3d(12.1, 11.9, 12.2), 8, 10);
  shapes.push_back(Surface(dgtest::Digitize(*cs, 25)));
  for (auto solver : { dg::ATLinearSolver::SimplicialLDLT,
         dg::ATLinearSolver::ConjugateGradient,
         dg::ATLinearSolver::ConjugateGradientIC })
  {
    for (std::size_t k = 0; k < shapes.size(); ++k)
    {
      const dg::ATComplex c = Build(FromPolyData(shapes[k]));
      const Eigen::MatrixXd g = TrivialNormalsPlusNoise(shapes[k], 0.2, 7 + k);
      dg::ATParameters params;
      params.Solver = solver;
      dg::ATSolver s(c, params);
      s.Initialize(g);
      int checked = 0;
      for (double eps : { 2.0, 1.0, 0.5, 0.25 })
      {
        double previous = s.Energy(eps);
        for (int it = 0; it < 6; ++it)
        {
          ASSERT_TRUE(s.StepU());
          const double afterU = s.Energy(eps);
          ASSERT_TRUE(s.StepV(eps));
          const double afterV = s.Energy(eps);
          // Each block step minimises exactly (up to the solver's accuracy).
          EXPECT_LE(afterU, previous * (1 + 1e-10)) << "shape " << k << " eps " << eps;
          EXPECT_LE(afterV, afterU * (1 + 1e-10)) << "shape " << k << " eps " << eps;
          previous = afterV;
          ++checked;
        }
      }
      EXPECT_EQ(checked, 24);
    }
  }
}

// A rotated cube 33^3 with trivial normals plus noise: small, with real
// edges for AT to find.
static std::pair<dg::ATComplex, Eigen::MatrixXd> NoisyRotatedCube33()
{
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(16.1, 15.9, 16.2), 10, 20, 30, 10);
  auto pd = Surface(dgtest::Digitize(*cube, 33));
  return { Build(FromPolyData(pd)), TrivialNormalsPlusNoise(pd, 0.2, 9) };
}

TEST(ATOperators, SolversAgreeAndRunIsDeterministic)
{
  const auto shape = NoisyRotatedCube33();
  const dg::ATComplex& c = shape.first;
  const Eigen::MatrixXd& g = shape.second;
  auto run = [&](dg::ATLinearSolver solver, int threads)
  {
    vtkSMPTools::Initialize(threads);
    dg::ATParameters params;
    params.Solver = solver;
    // Converged far past the default (TestATAccuracyBudget covers that one):
    // the solvers must then agree to 1e-6.
    params.CGTolerance = 1e-8;
    auto s = std::make_unique<dg::ATSolver>(c, params);
    EXPECT_TRUE(s->Run(g));
    EXPECT_TRUE(s->Warnings().empty());
    return s;
  };
  auto ldlt = run(dg::ATLinearSolver::SimplicialLDLT, 2);
  auto cg2 = run(dg::ATLinearSolver::ConjugateGradient, 2);
  auto cg1 = run(dg::ATLinearSolver::ConjugateGradient, 1);
  auto ic2 = run(dg::ATLinearSolver::ConjugateGradientIC, 2);
  auto ic1 = run(dg::ATLinearSolver::ConjugateGradientIC, 1);
  vtkSMPTools::Initialize(2);
  auto rel = [](const Eigen::MatrixXd& x, const Eigen::MatrixXd& ref)
  { return MaxAbs(x - ref) / MaxAbs(ref); };
  EXPECT_LT(rel(cg2->U(), ldlt->U()), 1e-6);
  EXPECT_LT(rel(cg2->V(), ldlt->V()), 1e-6);
  EXPECT_LT(rel(ic2->U(), ldlt->U()), 1e-6);
  EXPECT_LT(rel(ic2->V(), ldlt->V()), 1e-6);
  // IC(0) needs fewer iterations than Jacobi on the same systems.
  EXPECT_LT(ic2->Statistics().CGIterations, cg2->Statistics().CGIterations);
  if (dg::CholmodAvailable())
  {
    auto chol = run(dg::ATLinearSolver::Cholmod, 2);
    EXPECT_LT(rel(chol->U(), ldlt->U()), 1e-9);
    EXPECT_LT(rel(chol->V(), ldlt->V()), 1e-9);
  }
  // Bitwise identical whatever the thread count.
  EXPECT_EQ(MaxAbs(cg1->U() - cg2->U()), 0.0);
  EXPECT_EQ(MaxAbs(cg1->V() - cg2->V()), 0.0);
  EXPECT_EQ(MaxAbs(ic1->U() - ic2->U()), 0.0);
  EXPECT_EQ(MaxAbs(ic1->V() - ic2->V()), 0.0);
  // The run did find the cube's edges: some v well below 1/2.
  EXPECT_LT(ldlt->V().minCoeff(), 0.2);
  // Unit-length u after the run.
  EXPECT_LT((ldlt->U().rowwise().norm().array() - 1).abs().maxCoeff(), 1e-12);
}

TEST(ATOperators, LooserEarlyLevelsSaveIterationsWithinTheBudget)
{
  // CGToleranceEarlyFactor: 1 is the default run bit for bit; 6 loosens the
  // levels before the last, takes fewer CG iterations, and stays within the
  // accuracy budget of the exact solve with the same schedule (v within
  // 1e-3, normals within 0.05 degrees).
  const auto shape = NoisyRotatedCube33();
  const dg::ATComplex& c = shape.first;
  const Eigen::MatrixXd& g = shape.second;
  auto run = [&](dg::ATLinearSolver solver, double factor)
  {
    dg::ATParameters params;
    params.Solver = solver;
    params.CGToleranceEarlyFactor = factor;
    auto s = std::make_unique<dg::ATSolver>(c, params);
    EXPECT_TRUE(s->Run(g));
    return s;
  };
  auto byDefault = std::make_unique<dg::ATSolver>(c, dg::ATParameters());
  ASSERT_TRUE(byDefault->Run(g));
  auto one = run(dg::ATLinearSolver::ConjugateGradientIC, 1.0);
  auto six = run(dg::ATLinearSolver::ConjugateGradientIC, 6.0);
  auto exact = run(dg::ATLinearSolver::SimplicialLDLT, 1.0);
  EXPECT_EQ(MaxAbs(one->U() - byDefault->U()), 0.0);
  EXPECT_EQ(MaxAbs(one->V() - byDefault->V()), 0.0);
  EXPECT_EQ(one->Statistics().CGIterations, byDefault->Statistics().CGIterations);
  EXPECT_LT(six->Statistics().CGIterations, one->Statistics().CGIterations);
  EXPECT_EQ(six->Statistics().Iterations, exact->Statistics().Iterations);
  EXPECT_LT(MaxAbs(six->V() - exact->V()), 1e-3);
  double worst = 0;
  for (Eigen::Index f = 0; f < six->U().rows(); ++f)
  {
    const Eigen::Vector3d a = six->U().row(f).transpose(), b = exact->U().row(f).transpose();
    const double dot = a.dot(b) / (a.norm() * b.norm());
    worst = std::max(worst, std::acos(std::min(1.0, dot)) * 180.0 / M_PI);
  }
  EXPECT_LT(worst, 0.05);
  std::cout << "early factor 6: CG iterations " << six->Statistics().CGIterations << " against "
            << one->Statistics().CGIterations << ", max |dv| " << MaxAbs(six->V() - exact->V())
            << ", max angle " << worst << " deg" << std::endl;
}

TEST(ATOperators, TakingThePatternsGivesTheSameRunAndOnlyOnce)
{
  // A solver that takes the complex's patterns (what the filter does, to
  // hold them once) gives bitwise the copying solver's result; a second
  // solver on that complex fails with a message instead of a wrong run.
  auto cube = dgtest::MakeRotatedCube(Eigen::Vector3d(12.1, 11.9, 12.2), 7, 20, 30, 10);
  auto pd = Surface(dgtest::Digitize(*cube, 25));
  dg::ATComplex c = Build(FromPolyData(pd));
  const Eigen::MatrixXd g = TrivialNormalsPlusNoise(pd, 0.2, 3);
  dg::ATSolver copying(c, dg::ATParameters());
  ASSERT_TRUE(copying.Run(g));
  ASSERT_TRUE(c.HasSystemPatterns());
  dg::ATSolver taking(c, dg::ATParameters(), dg::ATSolver::TakePatterns);
  EXPECT_FALSE(c.HasSystemPatterns());
  ASSERT_TRUE(taking.Run(g));
  EXPECT_EQ(MaxAbs(taking.U() - copying.U()), 0.0);
  EXPECT_EQ(MaxAbs(taking.V() - copying.V()), 0.0);
  dg::ATSolver late(c, dg::ATParameters());
  EXPECT_FALSE(late.Run(g));
  EXPECT_NE(late.Error().find("taken"), std::string::npos) << late.Error();
}

TEST(ATOperators, InvalidParametersAreReported)
{
  const dg::ATComplex c = Build(Cube());
  const Eigen::MatrixXd g = RandomField(6, 3, 1);
  auto check = [&](auto change, const char* word)
  {
    dg::ATParameters p;
    change(p);
    EXPECT_NE(p.Check().find(word), std::string::npos) << p.Check();
    dg::ATSolver s(c, p);
    EXPECT_FALSE(s.Run(g));
    EXPECT_FALSE(s.Error().empty());
  };
  check([](dg::ATParameters& p) { p.Alpha = 0; }, "Alpha");
  check([](dg::ATParameters& p) { p.Lambda = -1; }, "Lambda");
  check([](dg::ATParameters& p) { p.EpsilonEnd = 4; }, "EpsilonStart");
  check([](dg::ATParameters& p) { p.EpsilonEnd = 0; }, "EpsilonEnd");
  check([](dg::ATParameters& p) { p.EpsilonRatio = 1; }, "EpsilonRatio");
  check([](dg::ATParameters& p) { p.MaximumIterations = 0; }, "MaximumIterations");
  check([](dg::ATParameters& p) { p.CGToleranceEarlyFactor = 0.5; }, "CGToleranceEarlyFactor");
  EXPECT_TRUE(dg::ATParameters().Check().empty());
}

// A linear solve that cannot meet its tolerance (one CG iteration allowed)
// must not stop the run nor corrupt it, and must say so. Jacobi CG works on
// a copy and keeps the previous values; IC CG solves in place (no copy of u:
// 24 bytes per face) and keeps its last iterate, whose error in the A-norm
// is no larger than the warm start's (CG minimises it over a space that
// contains the warm start).
TEST(ATOperators, FailedSolvesWarnAndKeepPreviousValuesOrABetterIterate)
{
  auto pd = Surface(dgtest::Ball(12, 4.3));
  const dg::ATComplex c = Build(FromPolyData(pd));
  const Eigen::MatrixXd g = TrivialNormalsPlusNoise(pd, 0.3, 3);
  for (auto solver :
    { dg::ATLinearSolver::ConjugateGradient, dg::ATLinearSolver::ConjugateGradientIC })
  {
    dg::ATParameters params;
    params.Solver = solver;
    params.CGTolerance = 1e-14;
    params.CGMaximumIterations = 1;
    dg::ATSolver s(c, params);
    ASSERT_TRUE(s.Run(g)) << s.Error();
    EXPECT_EQ(s.Statistics().FailedSolves, 2 * s.Statistics().Iterations);
    ASSERT_FALSE(s.Warnings().empty());
    EXPECT_NE(s.Warnings().front().find("linear solve failed"), std::string::npos)
      << s.Warnings().front();
    EXPECT_TRUE(s.U().allFinite());
    EXPECT_TRUE(s.V().allFinite());
    if (solver == dg::ATLinearSolver::ConjugateGradient)
    {
      EXPECT_EQ((s.V().array() - 1.0).abs().maxCoeff(), 0.0);
      Eigen::MatrixXd gn = g;
      gn.rowwise().normalize();
      EXPECT_LT(MaxAbs(s.U() - gn), 1e-15);
      continue;
    }
    // One failed step of each kind, against the exact solutions.
    dg::ATSolver one(c, params);
    one.Initialize(g);
    const double eps = 0.5;
    one.V() = Eigen::VectorXd::Constant(one.V().size(), 0.7);
    const Eigen::MatrixXd a = Dense(one.UMatrix());
    const Eigen::MatrixXd uExact = a.ldlt().solve(params.Alpha * g);
    EXPECT_FALSE(one.StepU());
    for (int col = 0; col < 3; ++col)
    {
      const Eigen::VectorXd e0 = g.col(col) - uExact.col(col);
      const Eigen::VectorXd e1 = one.U().col(col) - uExact.col(col);
      EXPECT_LE(e1.dot(a * e1), e0.dot(a * e0)) << "u column " << col;
      EXPECT_GT(MaxAbs(one.U().col(col) - g.col(col)), 0.0) << "the iterate moved";
    }
    const Eigen::VectorXd v0 = one.V();
    one.AssembleV(eps);
    const Eigen::MatrixXd av = Dense(one.VMatrix());
    const Eigen::VectorXd vExact =
      av.ldlt().solve(Eigen::VectorXd::Constant(v0.size(), params.Lambda / (4 * eps)));
    EXPECT_FALSE(one.StepV(eps));
    const Eigen::VectorXd f0 = v0 - vExact, f1 = one.V() - vExact;
    EXPECT_LE(f1.dot(av * f1), f0.dot(av * f0));
    EXPECT_GT(MaxAbs(one.V() - v0), 0.0);
  }
}

// The u right-hand sides can read g in the caller's array (interleaved, as
// a VTK array holds it) instead of a copy: the same bits; a source that is
// not the field given to Run is not used.
TEST(ATOperators, FieldSourceGivesTheSameRunAndIsCheckedAgainstTheField)
{
  auto pd = Surface(dgtest::Ball(12, 4.3));
  const dg::ATComplex c = Build(FromPolyData(pd));
  const Eigen::MatrixXd g = TrivialNormalsPlusNoise(pd, 0.3, 5);
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> interleaved = g;
  dg::ATSolver copying(c);
  ASSERT_TRUE(copying.Run(g)) << copying.Error();
  EXPECT_FALSE(copying.UsesFieldSource());
  dg::ATSolver reading(c);
  reading.SetFieldSource(interleaved.data(), 3, 1);
  ASSERT_TRUE(reading.Run(g)) << reading.Error();
  EXPECT_TRUE(reading.UsesFieldSource());
  EXPECT_EQ(MaxAbs(reading.U() - copying.U()), 0.0);
  EXPECT_EQ((reading.V() - copying.V()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(reading.Statistics().CGIterations, copying.Statistics().CGIterations);
  EXPECT_NEAR(reading.Energy(0.25), copying.Energy(0.25), 1e-12 * std::abs(copying.Energy(0.25)));

  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> other = interleaved;
  other(other.rows() / 2, 1) += 1e-9;
  dg::ATSolver wrong(c);
  wrong.SetFieldSource(other.data(), 3, 1);
  ASSERT_TRUE(wrong.Run(g)) << wrong.Error();
  EXPECT_FALSE(wrong.UsesFieldSource());
  EXPECT_EQ(MaxAbs(wrong.U() - copying.U()), 0.0);
}

// IC CG on a mesh with two vertices of degree 300 (the apexes of a double
// cone, numbered after their neighbours, so rows far longer than a digital
// surface's): the same result as LDL^T.
TEST(ATOperators, ICWithAVertexOfHighDegreeMatchesLDLT)
{
  const int rim = 300;
  Polygons p;
  p.NumberOfVertices = rim + 2; // rim 0..rim-1, apexes rim (top) and rim+1
  for (int i = 0; i < rim; ++i)
  {
    const int j = (i + 1) % rim;
    p.Add({ i, j, rim });
    p.Add({ j, i, rim + 1 });
  }
  const dg::ATComplex c = Build(p);
  Eigen::MatrixXd g(2 * rim, 3);
  for (int i = 0; i < rim; ++i)
  {
    const double a = 2 * M_PI * (i + 0.5) / rim, s = (i / 50) % 2 ? 0.6 : 0.2;
    g.row(2 * i) << std::cos(a), std::sin(a), s;
    g.row(2 * i + 1) << std::cos(a), std::sin(a), -s;
  }
  g.rowwise().normalize();
  dg::ATParameters ic, ldlt;
  ic.CGTolerance = 1e-10;
  ldlt.Solver = dg::ATLinearSolver::SimplicialLDLT;
  dg::ATSolver a(c, ic), b(c, ldlt);
  ASSERT_TRUE(a.Run(g)) << a.Error();
  ASSERT_TRUE(b.Run(g)) << b.Error();
  EXPECT_TRUE(a.Warnings().empty());
  EXPECT_LT(MaxAbs(a.U() - b.U()), 1e-7);
  EXPECT_LT((a.V() - b.V()).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT(b.V().minCoeff(), 0.5); // the test has features to find
}
