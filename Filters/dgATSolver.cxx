#include "dgATSolver.h"

#include "dgHugePages.h"

#include "dgATBlocks.h"
#include "dgATLinearSystems.h"

#include <vtkSMPTools.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace dg
{
namespace
{
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point t0)
{
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
} // namespace

const char* ATLinearSolverName(ATLinearSolver s)
{
  switch (s)
  {
    case ATLinearSolver::SimplicialLDLT:
      return "SimplicialLDLT";
    case ATLinearSolver::Cholmod:
      return "Cholmod";
    case ATLinearSolver::ConjugateGradientIC:
      return "ConjugateGradientIC";
    case ATLinearSolver::ConjugateGradient:
    default:
      return "ConjugateGradient";
  }
}

std::string ATParameters::Check() const
{
  std::ostringstream s;
  // Written as !(x > 0) so that NaN is rejected too.
  if (!(this->Alpha > 0))
  {
    s << "Alpha must be > 0 (got " << this->Alpha << "). ";
  }
  if (!(this->Lambda > 0))
  {
    s << "Lambda must be > 0 (got " << this->Lambda << "). ";
  }
  if (!(this->EpsilonEnd > 0))
  {
    s << "EpsilonEnd must be > 0 (got " << this->EpsilonEnd << "). ";
  }
  if (!(this->EpsilonStart >= this->EpsilonEnd) || !std::isfinite(this->EpsilonStart))
  {
    s << "EpsilonStart (" << this->EpsilonStart << ") must be finite and >= EpsilonEnd ("
      << this->EpsilonEnd << "). ";
  }
  if (!(this->EpsilonRatio > 1))
  {
    s << "EpsilonRatio must be > 1 (got " << this->EpsilonRatio << "). ";
  }
  if (this->MaximumIterations < 1)
  {
    s << "MaximumIterations must be >= 1 (got " << this->MaximumIterations << "). ";
  }
  if (!(this->Tolerance >= 0))
  {
    s << "Tolerance must be >= 0 (got " << this->Tolerance << "). ";
  }
  if (!(this->CGTolerance > 0) || this->CGMaximumIterations < 1)
  {
    s << "CGTolerance must be > 0 and CGMaximumIterations >= 1. ";
  }
  if (!(this->CGToleranceVFactor > 0) || !std::isfinite(this->CGToleranceVFactor))
  {
    s << "CGToleranceVFactor must be finite and > 0 (got " << this->CGToleranceVFactor << "). ";
  }
  if (!(this->CGToleranceEarlyFactor >= 1) || !std::isfinite(this->CGToleranceEarlyFactor))
  {
    s << "CGToleranceEarlyFactor must be finite and >= 1 (got " << this->CGToleranceEarlyFactor
      << "). ";
  }
  std::string r = s.str();
  if (!r.empty())
  {
    r.pop_back();
  }
  return r;
}

ATSolver::ATSolver(const ATComplex& complex, const ATParameters& parameters)
  : Complex(complex)
  , Params(parameters)
  , UP(complex.UPattern)
  , VP(complex.VPattern)
{
}

ATSolver::ATSolver(ATComplex& complex, const ATParameters& parameters, TakePatternsTag)
  : Complex(complex)
  , Params(parameters)
{
  this->UP = std::move(complex.UPattern);
  this->VP = std::move(complex.VPattern);
  complex.UPattern = ATPattern();
  complex.VPattern = ATPattern();
}

ATSolver::~ATSolver() = default;

void ATSolver::Initialize(const Eigen::MatrixXd& field)
{
  this->u = field;
  this->InitializeFromU();
}

void ATSolver::Initialize(Eigen::MatrixXd&& field)
{
  this->u = std::move(field);
  this->InitializeFromU();
}

// u = g on entry. The solver keeps g for the u right-hand sides alpha g
// (read in place, ATRhs): a copy of u, unless the caller's array holds the
// same values (SetFieldSource).
void ATSolver::InitializeFromU()
{
  bool source = this->FieldSource != nullptr;
  for (Eigen::Index c = 0; source && c < this->u.cols(); ++c)
  {
    for (Eigen::Index f = 0; source && f < this->u.rows(); ++f)
    {
      source = this->FieldSource[f * this->FieldRowStride + c * this->FieldColumnStride] ==
        this->u(f, c);
    }
  }
  if (source)
  {
    Eigen::MatrixXd().swap(this->G);
  }
  else
  {
    this->G.resize(this->u.rows(), this->u.cols()); // not touched yet: advised first
    AdviseHugePages(this->G.data(), static_cast<std::size_t>(this->G.size()) * sizeof(double));
    this->G = this->u;
  }
  const Eigen::Index nv = this->Complex.NumberOfVertices();
  if (this->v.size() != nv)
  {
    this->v.resize(nv);
    AdviseHugePages(this->v.data(), static_cast<std::size_t>(nv) * sizeof(double));
  }
  this->v.setOnes();
  this->LastVChange = 0;
}

// One array for the assembly's per-edge values, then the IC factorisation's
// pivots, and during a v-step the previous v beside them (never needed at
// the same time), sized once.
double* ATSolver::EdgeScratch()
{
  const std::size_t n = static_cast<std::size_t>(std::max({ this->Complex.NumberOfEdges(),
    this->Complex.NumberOfFaces(), 2 * this->Complex.NumberOfVertices() }));
  if (this->EdgeWork.size() != n)
  {
    std::vector<double>().swap(this->EdgeWork);
    ResizeHuge(this->EdgeWork, n);
  }
  return this->EdgeWork.data();
}

double ATSolver::GValue(std::int64_t f, std::int64_t c) const
{
  return this->G.size() ? this->G(f, c)
                        : this->FieldSource[f * this->FieldRowStride + c * this->FieldColumnStride];
}

ATRhs ATSolver::URhs() const
{
  ATRhs b;
  b.Rows = this->u.rows();
  b.Columns = this->u.cols();
  if (this->G.size())
  {
    b.Data = this->G.data();
    b.RowStride = 1;
    b.ColumnStride = this->G.rows();
  }
  else
  {
    b.Data = this->FieldSource;
    b.RowStride = this->FieldRowStride;
    b.ColumnStride = this->FieldColumnStride;
  }
  b.Scale = this->Params.Alpha;
  b.RowScale = this->Metric ? this->Metric->FaceArea.data() : nullptr;
  return b;
}

void ATSolver::RecoverG(Eigen::MatrixXd& out) const
{
  for (Eigen::Index c = 0; c < out.cols(); ++c)
  {
    for (Eigen::Index f = 0; f < out.rows(); ++f)
    {
      out(f, c) = this->GValue(f, c);
    }
  }
}

double* ATSolver::SystemValues()
{
  const std::size_t n =
    static_cast<std::size_t>(std::max(this->UP.NonZeros(), this->VP.NonZeros()));
  if (this->Values.size() != n)
  {
    AssignHuge(this->Values, n, 0.0);
  }
  return this->Values.data();
}

ATSystemMatrix ATSolver::UMatrix()
{
  if (this->ValuesHold != 0)
  {
    this->AssembleU();
  }
  return ATSystemMatrix(this->UP.View(this->Values.data()));
}

ATSystemMatrix ATSolver::VMatrix()
{
  if (this->ValuesHold != 1)
  {
    this->AssembleV(this->VAssemblyEpsilon > 0 ? this->VAssemblyEpsilon : this->Params.EpsilonEnd);
  }
  return ATSystemMatrix(this->VP.View(this->Values.data()));
}

void ATSolver::AssembleU()
{
  const ATComplex& K = this->Complex;
  const std::int64_t ne = K.NumberOfEdges(), nf = K.NumberOfFaces();
  // w(e) = ((M v)_e)^2, the weight of edge e in B^T diag(Mv)^2 B.
  double* w = this->EdgeScratch();
  const double* ratio = this->Metric ? this->Metric->EdgeRatio.data() : nullptr;
  const double* faceArea = this->Metric ? this->Metric->FaceArea.data() : nullptr;
  ForBlocks(ne,
    [&](std::int64_t, std::int64_t e0, std::int64_t e1)
    {
      for (std::int64_t e = e0; e < e1; ++e)
      {
        const double m =
          0.5 * (this->v[K.EdgeVertices[2 * e]] + this->v[K.EdgeVertices[2 * e + 1]]);
        w[e] = ratio ? ratio[e] * (m * m) : m * m;
      }
    });
  const int* outer = this->UP.Outer.data();
  const int* inner = this->UP.Inner.data();
  double* val = this->SystemValues();
  this->ValuesHold = 0;
  const double alpha = this->Params.Alpha;
  // Entry (f, g) = sum over the interior edges e shared by f and g, in
  // ascending order, of s_f(e) s_g(e) w(e), then alpha (or alpha |f|) on the
  // diagonal: walking f's edges ascending adds the terms in that order, as
  // the per-non-zero map that this replaced did (bitwise the same values;
  // the coefficients are exact small integers, so c * w is exact).
  static constexpr double sign[2] = { 1.0, -1.0 };
  ForBlocks(nf,
    [&](std::int64_t, std::int64_t f0, std::int64_t f1)
    {
      for (std::int64_t f = f0; f < f1; ++f)
      {
        const int r0 = outer[f], r1 = outer[f + 1];
        std::fill(val + r0, val + r1, 0.0);
        int d = r0; // the diagonal's position: branch-free count (rows are short)
        for (int k = r0; k < r1; ++k)
        {
          d += inner[k] < f;
        }
        for (int j = K.FaceEdgePtr[f]; j < K.FaceEdgePtr[f + 1]; ++j)
        {
          const unsigned char code = K.FaceEdgeCode[j];
          if (code == ATComplex::FaceEdgeBoundary)
          {
            continue; // boundary edge: no jump (dgATOperators.h)
          }
          const int e = K.FaceEdges[j];
          const double we = w[e];
          if (code != ATComplex::FaceEdgeGeneral)
          {
            // Two faces, signs +-1: s_f^2 = 1 on the diagonal, s_f s_g at g.
            val[d] += we;
            // The product of two random signs: a table, not a branch.
            val[r0 + (code & 15)] += sign[((code >> 4) ^ (code >> 5)) & 1] * we;
            continue;
          }
          const int i0 = K.EdgeFacePtr[e], i1 = K.EdgeFacePtr[e + 1];
          signed char sf = 0; // f's sign on e
          for (int i = i0; i < i1; ++i)
          {
            sf = K.EdgeFaces[i] == f ? K.EdgeFaceSigns[i] : sf;
          }
          // The edge's faces and the row's columns are both ascending.
          int k = r0;
          for (int i = i0; i < i1; ++i)
          {
            while (inner[k] != K.EdgeFaces[i])
            {
              ++k;
            }
            const auto coef = static_cast<signed char>(sf * K.EdgeFaceSigns[i]);
            val[k] += static_cast<double>(coef) * we;
          }
        }
        val[d] += faceArea ? alpha * faceArea[f] : alpha;
      }
    });
}

void ATSolver::AssembleV(double epsilon)
{
  const ATComplex& K = this->Complex;
  const std::int64_t ne = K.NumberOfEdges(), nv = K.NumberOfVertices();
  const int nc = static_cast<int>(this->u.cols());
  // q(e) = sum_i ((B u_i)_e)^2: the squared jump of u across edge e.
  double* q = this->EdgeScratch();
  const double* ratio = this->Metric ? this->Metric->EdgeRatio.data() : nullptr;
  const double* vertexArea = this->Metric ? this->Metric->VertexArea.data() : nullptr;
  ForBlocks(ne,
    [&](std::int64_t, std::int64_t e0, std::int64_t e1)
    {
      for (std::int64_t e = e0; e < e1; ++e)
      {
        double s = 0;
        // Boundary edges carry no jump (dgATOperators.h).
        for (int c = 0; c < nc && K.EdgeFacePtr[e + 1] - K.EdgeFacePtr[e] > 1; ++c)
        {
          double d = 0;
          for (std::int64_t i = K.EdgeFacePtr[e]; i < K.EdgeFacePtr[e + 1]; ++i)
          {
            d += K.EdgeFaceSigns[i] * this->u(K.EdgeFaces[i], c);
          }
          s += d * d;
        }
        q[e] = ratio ? ratio[e] * s : s;
      }
    });
  const double lambda = this->Params.Lambda;
  const double diagConst = lambda / (4 * epsilon), lapl = lambda * epsilon;
  const int* outer = this->VP.Outer.data();
  const int* inner = this->VP.Inner.data();
  double* val = this->SystemValues();
  this->ValuesHold = 1;
  this->VAssemblyEpsilon = epsilon;
  ForBlocks(nv,
    [&](std::int64_t, std::int64_t a0, std::int64_t a1)
    {
      for (std::int64_t a = a0; a < a1; ++a)
      {
        // Row a's off-diagonal entries are a's edges in order (dgATOperators.h).
        int j = K.VertexEdgePtr[a];
        for (int k = outer[a]; k < outer[a + 1]; ++k)
        {
          if (inner[k] != a)
          {
            const int e = K.VertexEdges[j++];
            val[k] = (ratio ? -lapl / ratio[e] : -lapl) + 0.25 * q[e];
          }
          else if (!ratio)
          {
            double s = 0;
            for (int i = K.VertexEdgePtr[a]; i < K.VertexEdgePtr[a + 1]; ++i)
            {
              s += q[K.VertexEdges[i]];
            }
            val[k] = diagConst + lapl * (K.VertexEdgePtr[a + 1] - K.VertexEdgePtr[a]) + 0.25 * s;
          }
          else
          {
            // The world metric: dual area, Laplacian weights |e*| / |e|.
            double s = 0, l = 0;
            for (int i = K.VertexEdgePtr[a]; i < K.VertexEdgePtr[a + 1]; ++i)
            {
              s += q[K.VertexEdges[i]];
              l += 1.0 / ratio[K.VertexEdges[i]];
            }
            val[k] = diagConst * vertexArea[a] + lapl * l + 0.25 * s;
          }
        }
      }
    });
}

bool ATSolver::SolveSystem(ATLinearSystem& system,
  const ATSystemView& m,
  const ATRhs& b,
  ATColumns x,
  const char* name,
  const std::function<void()>& restore,
  std::pair<double*, std::size_t> factorScratch)
{
  auto t0 = Clock::now();
  // Every process takes the same branches: a local failure fails them all.
  auto agree = [this](bool ok) { return this->Distribution ? this->Distribution->AllOk(ok) : ok; };
  if (!system.Analyzed)
  {
    system.Analyzed = agree(system.Analyze(m));
    this->Stats.Analysis += Seconds(t0);
    if (!system.Analyzed)
    {
      this->WarningList.push_back(std::string("symbolic analysis of the ") + name + " failed");
      ++this->Stats.FailedSolves;
      return false;
    }
    t0 = Clock::now();
  }
  system.SetFactorScratch(factorScratch.first, factorScratch.second);
  const bool factored = agree(system.Factorize(m));
  system.SetFactorScratch(nullptr, 0);
  this->Stats.Factorization += Seconds(t0);
  t0 = Clock::now();
  const std::int64_t it0 = system.Iterations;
  const bool solved = factored && system.Solve(m, b, x);
  this->Stats.Solve += Seconds(t0);
  this->Stats.CGIterations += system.Iterations - it0;
  if (!solved)
  {
    std::ostringstream s;
    // A non-finite iterate (an in-place solver that broke down) is
    // replaced by the values before the step; every process agrees.
    const bool finite = agree(x.allFinite());
    if (!finite)
    {
      restore();
    }
    s << "the " << name << " linear solve failed ("
      << (factored ? "no convergence or non-finite result" : "factorisation failed") << "); "
      << (finite ? "the step keeps what the solver left (its last iterate, or the previous values)"
                 : "the values before the step are kept");
    this->WarningList.push_back(s.str());
    ++this->Stats.FailedSolves;
    return false;
  }
  return true;
}

void ATSolver::MakeSystems()
{
  if (this->USystem && this->VSystem)
  {
    return;
  }
  this->USystem = this->Distribution
    ? MakeICSystem(this->Params.CGTolerance, this->Params.CGMaximumIterations, this->Distribution,
        0, this->Params.CGSinglePrecision)
    : MakeATLinearSystem(this->Params);
  ATParameters vParams = this->Params;
  vParams.CGTolerance *= this->Params.CGToleranceVFactor;
  this->VSystem = this->Distribution
    ? MakeICSystem(this->Params.CGTolerance * this->Params.CGToleranceVFactor,
        this->Params.CGMaximumIterations, this->Distribution, 1, this->Params.CGSinglePrecision)
    : MakeATLinearSystem(vParams);
  // The two steps alternate, so one set of CG work vectors serves both.
  if (this->USystem && this->VSystem)
  {
    this->VSystem->ShareWork(*this->USystem);
  }
}

bool ATSolver::StepU()
{
  this->MakeSystems();
  this->USystem->SetTolerance(this->Params.CGTolerance * this->ToleranceFactor);
  auto t0 = Clock::now();
  this->AssembleU();
  this->Stats.Assembly += Seconds(t0);
  const std::int64_t it0 = this->Stats.CGIterations;
  const double solve0 = this->Stats.Solve;
  // CG solves in place, so there is no copy of u to go back to: the
  // restore takes g.
  const bool ok = this->SolveSystem(*this->USystem, this->UP.View(this->Values.data()),
    this->URhs(), this->u, "u-step", [this]() { this->RecoverG(this->u); },
    { this->EdgeScratch(), this->EdgeWork.size() });
  this->Stats.CGIterationsU += this->Stats.CGIterations - it0;
  this->Stats.SolveU += this->Stats.Solve - solve0;
  return ok;
}

bool ATSolver::StepV(double epsilon)
{
  this->MakeSystems();
  this->VSystem->SetTolerance(
    this->Params.CGTolerance * this->Params.CGToleranceVFactor * this->ToleranceFactor);
  auto t0 = Clock::now();
  this->AssembleV(epsilon);
  this->Stats.Assembly += Seconds(t0);
  // The assembly is done with the per-edge values: the scratch now holds
  // the previous v (for the stopping rule, and to go back to), and v is
  // solved in place. The right-hand side lambda / (4 eps) (times the
  // vertex areas) is read as it is needed.
  const Eigen::Index nv = this->v.size();
  Eigen::Map<Eigen::VectorXd> previous(this->EdgeScratch(), nv);
  previous = this->v;
  ATRhs rhs;
  rhs.Rows = nv;
  rhs.Columns = 1;
  rhs.Scale = this->Params.Lambda / (4 * epsilon);
  rhs.RowScale = this->Metric ? this->Metric->VertexArea.data() : nullptr;
  const bool ok = this->SolveSystem(*this->VSystem, this->VP.View(this->Values.data()), rhs,
    this->v, "v-step", [&]() { this->v = previous; },
    { this->EdgeWork.data() + nv, this->EdgeWork.size() - nv });
  // The stopping rule's max |v - v_prev| over the owned rows, taken here
  // where both are at hand (Run kept a copy of v for it: 8 bytes a vertex).
  this->LastVChange = 0;
  if (ok)
  {
    const std::int64_t owned = this->Distribution ? this->Distribution->Owned(1) : nv;
    if (owned > 0)
    {
      this->LastVChange = (this->v.head(owned) - previous.head(owned)).lpNorm<Eigen::Infinity>();
    }
  }
  return ok;
}

void ATSolver::Memory(ATMemoryParts& parts) const
{
  auto dense = [](const Eigen::MatrixXd& m) { return static_cast<std::size_t>(m.size()) * sizeof(double); };
  parts.emplace_back("solver: u", dense(this->u));
  parts.emplace_back(this->G.size() ? "solver: g (for the u right-hand sides alpha g)"
                                     : "solver: g (read from the caller's array)",
    dense(this->G));
  parts.emplace_back("solver: v", static_cast<std::size_t>(this->v.size()) * sizeof(double));
  parts.emplace_back("solver: per-edge work (v-step: the previous v)",
    this->EdgeWork.capacity() * sizeof(double));
  parts.emplace_back("solver: u pattern (indices)", this->UP.Bytes());
  parts.emplace_back("solver: v pattern (indices)", this->VP.Bytes());
  parts.emplace_back("solver: matrix values (one buffer, u and v in turn)",
    this->Values.capacity() * sizeof(double));
  if (this->USystem)
  {
    this->USystem->Memory(parts, "u solver");
  }
  if (this->VSystem)
  {
    this->VSystem->Memory(parts, "v solver");
  }
}

double ATSolver::Energy(double epsilon) const
{
  const ATComplex& K = this->Complex;
  const std::int64_t nf = K.NumberOfFaces(), ne = K.NumberOfEdges(), nv = K.NumberOfVertices();
  const int nc = static_cast<int>(this->u.cols());
  const double lambda = this->Params.Lambda;
  double total = 0;
  {
    const std::int64_t nb = NumberOfBlocks(nf);
    std::vector<double> part(nb);
    ForBlocks(nf,
      [&](std::int64_t b, std::int64_t f0, std::int64_t f1)
      {
        double s = 0;
        for (std::int64_t f = f0; f < f1; ++f)
        {
          const double w = this->Metric ? this->Metric->FaceArea[f] : 1.0;
          for (int c = 0; c < nc; ++c)
          {
            const double d = this->u(f, c) - this->GValue(f, c);
            s += w * d * d;
          }
        }
        part[b] = s;
      });
    double s;
    ReduceBlocks(part, nb, 1, &s);
    total += this->Params.Alpha * s;
  }
  {
    const std::int64_t nb = NumberOfBlocks(ne);
    std::vector<double> part(nb);
    ForBlocks(ne,
      [&](std::int64_t b, std::int64_t e0, std::int64_t e1)
      {
        double s = 0;
        for (std::int64_t e = e0; e < e1; ++e)
        {
          const double va = this->v[K.EdgeVertices[2 * e]], vb = this->v[K.EdgeVertices[2 * e + 1]];
          const double m = 0.5 * (va + vb);
          const double r = this->Metric ? this->Metric->EdgeRatio[e] : 1.0;
          for (int c = 0; c < nc && K.EdgeFacePtr[e + 1] - K.EdgeFacePtr[e] > 1; ++c)
          {
            double d = 0;
            for (std::int64_t i = K.EdgeFacePtr[e]; i < K.EdgeFacePtr[e + 1]; ++i)
            {
              d += K.EdgeFaceSigns[i] * this->u(K.EdgeFaces[i], c);
            }
            s += r * m * m * d * d;
          }
          s += lambda * epsilon * (vb - va) * (vb - va) / r;
        }
        part[b] = s;
      });
    double s;
    ReduceBlocks(part, nb, 1, &s);
    total += s;
  }
  {
    const std::int64_t nb = NumberOfBlocks(nv);
    std::vector<double> part(nb);
    ForBlocks(nv,
      [&](std::int64_t b, std::int64_t a0, std::int64_t a1)
      {
        double s = 0;
        for (std::int64_t a = a0; a < a1; ++a)
        {
          const double d = (1 - this->v[a]) * (1 - this->v[a]);
          s += this->Metric ? this->Metric->VertexArea[a] * d : d;
        }
        part[b] = s;
      });
    double s;
    ReduceBlocks(part, nb, 1, &s);
    total += lambda / (4 * epsilon) * s;
  }
  return total;
}

void ATSolver::NormalizeU()
{
  ForBlocks(this->u.rows(),
    [&](std::int64_t, std::int64_t f0, std::int64_t f1)
    {
      for (std::int64_t f = f0; f < f1; ++f)
      {
        const double n = this->u.row(f).norm();
        if (n > 0)
        {
          this->u.row(f) /= n;
        }
      }
    });
}

bool ATSolver::Prepare(const Eigen::MatrixXd& field)
{
  this->Stats = ATStatistics();
  this->WarningList.clear();
  this->ErrorText = this->Params.Check();
  if (!this->ErrorText.empty())
  {
    return false;
  }
  if (this->UP.N != this->Complex.NumberOfFaces() || this->UP.Outer.empty() ||
    this->VP.N != this->Complex.NumberOfVertices() || this->VP.Outer.empty())
  {
    this->ErrorText = "the complex's system patterns were taken by another solver";
    return false;
  }
  if (this->Metric &&
    (static_cast<std::int64_t>(this->Metric->FaceArea.size()) != this->Complex.NumberOfFaces() ||
      static_cast<std::int64_t>(this->Metric->EdgeRatio.size()) != this->Complex.NumberOfEdges() ||
      static_cast<std::int64_t>(this->Metric->VertexArea.size()) != this->Complex.NumberOfVertices()))
  {
    this->ErrorText = "the metric does not match the complex";
    return false;
  }
  if (field.rows() != this->Complex.NumberOfFaces() || field.cols() < 1)
  {
    this->ErrorText = "the field has " + std::to_string(field.rows()) + " rows for " +
                      std::to_string(this->Complex.NumberOfFaces()) + " faces";
    return false;
  }
  if (this->Distribution && this->Params.Solver != ATLinearSolver::ConjugateGradientIC)
  {
    this->ErrorText = std::string("a distributed solve runs ConjugateGradientIC only (got ") +
      ATLinearSolverName(this->Params.Solver) + ")";
    return false;
  }
  if (this->Params.Solver == ATLinearSolver::Cholmod && !CholmodAvailable())
  {
    this->WarningList.push_back("CHOLMOD is not available in this build: using SimplicialLDLT");
    this->Params.Solver = ATLinearSolver::SimplicialLDLT;
  }
  this->USystem.reset();
  this->VSystem.reset();
  return true;
}

bool ATSolver::Run(const Eigen::MatrixXd& field, const ATProgressCallback& progress)
{
  if (!this->Prepare(field))
  {
    return false;
  }
  this->Initialize(field);
  return this->Schedule(progress);
}

bool ATSolver::Run(Eigen::MatrixXd&& field, const ATProgressCallback& progress)
{
  if (!this->Prepare(field))
  {
    return false;
  }
  this->Initialize(std::move(field));
  return this->Schedule(progress);
}

bool ATSolver::Schedule(const ATProgressCallback& progress)
{
  // The schedule eps_1, eps_1 / r, ... down to eps_2 (a relative slack so
  // that 2 -> 0.25 by 2 or 1 -> 0.1 by 10 include their last level).
  std::vector<double> levels;
  for (double eps = this->Params.EpsilonStart;
       eps >= this->Params.EpsilonEnd * (1 - 1e-9) && levels.size() < 1000;
       eps /= this->Params.EpsilonRatio)
  {
    levels.push_back(eps);
  }
  const double steps = static_cast<double>(levels.size()) * this->Params.MaximumIterations;
  for (std::size_t l = 0; l < levels.size(); ++l)
  {
    ++this->Stats.Levels;
    // Looser solves on the levels before the last: sqrt(F) times looser per
    // level away from the last, at most F (the level just before the last
    // gets sqrt(F): one level of steps does not always solve away F, two
    // do). Only while v still moves by far more than the stopping rule's
    // tolerance: near it, a solve's error would decide whether the level
    // stops, and so change the schedule.
    const double early = std::min(this->Params.CGToleranceEarlyFactor,
      std::pow(std::sqrt(this->Params.CGToleranceEarlyFactor),
        static_cast<double>(levels.size() - 1 - l)));
    double change = std::numeric_limits<double>::infinity();
    for (int it = 0; it < this->Params.MaximumIterations; ++it)
    {
      this->ToleranceFactor = change > 10 * this->Params.Tolerance ? early : 1.0;
      this->StepU();
      this->StepV(levels[l]);
      ++this->Stats.Iterations;
      change = this->LastVChange;
      if (this->Distribution)
      {
        change = this->Distribution->MaxAll(change);
      }
      if (progress &&
          !progress((static_cast<double>(l) * this->Params.MaximumIterations + it + 1) / steps))
      {
        return false;
      }
      if (change < this->Params.Tolerance)
      {
        break;
      }
    }
  }
  if (this->Params.Normalize)
  {
    this->NormalizeU();
  }
  return true;
}

} // namespace dg
