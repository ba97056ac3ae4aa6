#include "dgATHalo.h"

#include <vtkCommunicator.h>
#include <vtkMultiProcessController.h>

#include <algorithm>
#include <sstream>
#include <unordered_map>

namespace dg
{
namespace
{
constexpr int IdTag = 72301, ValueTag = 72302;
static_assert(sizeof(vtkIdType) == sizeof(std::int64_t), "64-bit ids are needed");

// The directory process of a global id.
int Directory(std::int64_t gid, int processes)
{
  return static_cast<int>(((gid % processes) + processes) % processes);
}

// Pairwise exchange with one partner, deadlock-free: every process walks its
// partners in ascending order and the lower process of a pair sends first,
// so all processes meet their pairs in one global (lexicographic) order.
template<class T, class SendFn, class ReceiveFn>
void PairStep(int rank, int partner, const SendFn& send, const ReceiveFn& receive)
{
  if (rank < partner)
  {
    send();
    receive();
  }
  else
  {
    receive();
    send();
  }
}

// The owners of global ids through the directory: every process registers
// the ids it owns that others may ask for and asks for the ids it needs.
// Returns, per asked id (in `asks` order), the owner or -1; sets `conflict`
// to an id claimed by two processes.
std::vector<int> AskOwners(const ATHalo& halo,
  const std::vector<std::int64_t>& registers,
  const std::vector<std::int64_t>& asks,
  std::int64_t& conflict)
{
  const int n = halo.Processes;
  std::vector<std::vector<std::int64_t>> regOut(n), askOut(n);
  std::vector<std::vector<std::size_t>> askIndex(n);
  for (std::int64_t g : registers)
  {
    regOut[Directory(g, n)].push_back(g);
  }
  for (std::size_t i = 0; i < asks.size(); ++i)
  {
    const int d = Directory(asks[i], n);
    askOut[d].push_back(asks[i]);
    askIndex[d].push_back(i);
  }
  std::vector<std::vector<std::int64_t>> out(n);
  for (int q = 0; q < n; ++q)
  {
    out[q].push_back(static_cast<std::int64_t>(regOut[q].size()));
    out[q].insert(out[q].end(), regOut[q].begin(), regOut[q].end());
    out[q].insert(out[q].end(), askOut[q].begin(), askOut[q].end());
  }
  const auto in = halo.Exchange(out);
  std::unordered_map<std::int64_t, int> owner;
  for (int s = 0; s < n; ++s)
  {
    const std::int64_t nReg = in[s].empty() ? 0 : in[s][0];
    for (std::int64_t i = 1; i <= nReg; ++i)
    {
      const auto it = owner.emplace(in[s][i], s);
      if (!it.second && it.first->second != s)
      {
        conflict = in[s][i];
      }
    }
  }
  std::vector<std::vector<std::int64_t>> reply(n);
  for (int s = 0; s < n; ++s)
  {
    const std::int64_t nReg = in[s].empty() ? 0 : in[s][0];
    for (std::size_t i = 1 + nReg; i < in[s].size(); ++i)
    {
      const auto it = owner.find(in[s][i]);
      reply[s].push_back(it == owner.end() ? -1 : it->second);
    }
  }
  const auto answers = halo.Exchange(reply);
  std::vector<int> result(asks.size(), -1);
  for (int q = 0; q < n; ++q)
  {
    for (std::size_t i = 0; i < askIndex[q].size() && i < answers[q].size(); ++i)
    {
      result[askIndex[q][i]] = static_cast<int>(answers[q][i]);
    }
  }
  return result;
}
} // namespace

ATHalo::ATHalo(vtkMultiProcessController* controller)
  : Rank(controller->GetLocalProcessId())
  , Processes(controller->GetNumberOfProcesses())
  , Controller(controller)
{
}

std::vector<std::vector<std::int64_t>> ATHalo::Exchange(
  const std::vector<std::vector<std::int64_t>>& out) const
{
  const int n = this->Processes;
  std::vector<vtkIdType> mine(n), all(static_cast<std::size_t>(n) * n);
  for (int q = 0; q < n; ++q)
  {
    mine[q] = static_cast<vtkIdType>(out[q].size());
  }
  this->Controller->AllGather(mine.data(), all.data(), n);
  std::vector<std::vector<std::int64_t>> in(n);
  in[this->Rank] = out[this->Rank];
  for (int q = 0; q < n; ++q)
  {
    if (q == this->Rank)
    {
      continue;
    }
    const vtkIdType sendCount = mine[q], recvCount = all[static_cast<std::size_t>(q) * n + this->Rank];
    in[q].resize(recvCount);
    PairStep<std::int64_t>(
      this->Rank, q,
      [&] {
        if (sendCount > 0)
        {
          this->Controller->Send(
            reinterpret_cast<const vtkIdType*>(out[q].data()), sendCount, q, IdTag);
        }
      },
      [&] {
        if (recvCount > 0)
        {
          this->Controller->Receive(reinterpret_cast<vtkIdType*>(in[q].data()), recvCount, q, IdTag);
        }
      });
  }
  return in;
}

bool ATHalo::Build(const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity,
  const std::vector<std::int64_t>& faceIds,
  const std::vector<char>& faceGhost,
  const std::vector<std::int64_t>& pointIds,
  std::string& error)
{
  const std::int64_t nF = static_cast<std::int64_t>(faceIds.size());
  const std::int64_t nP = static_cast<std::int64_t>(pointIds.size());
  const int n = this->Processes;
  std::ostringstream problem;
  auto points = [&](std::int64_t f, auto&& body) {
    for (std::int64_t k = offsets[f]; k < offsets[f + 1]; ++k)
    {
      body(connectivity[k]);
    }
  };
  // 1. The ghost ring: ghost faces sharing a point with an owned face.
  std::vector<char> touchOwned(nP, 0), touchGhost(nP, 0), keep(nF, 0), boundary(nF, 0);
  for (std::int64_t f = 0; f < nF; ++f)
  {
    if (!faceGhost[f])
    {
      keep[f] = 1;
      points(f, [&](std::int64_t p) { touchOwned[p] = 1; });
    }
  }
  for (std::int64_t f = 0; f < nF; ++f)
  {
    if (faceGhost[f])
    {
      points(f, [&](std::int64_t p) { keep[f] |= touchOwned[p]; });
      if (keep[f])
      {
        points(f, [&](std::int64_t p) { touchGhost[p] = 1; });
      }
    }
  }
  for (std::int64_t f = 0; f < nF; ++f)
  {
    if (!faceGhost[f])
    {
      points(f, [&](std::int64_t p) { boundary[f] |= touchGhost[p]; });
    }
  }

  // 2. Owners of the ghost faces.
  std::vector<std::int64_t> registers, asks, askFaces;
  for (std::int64_t f = 0; f < nF; ++f)
  {
    if (boundary[f])
    {
      registers.push_back(faceIds[f]);
    }
    else if (faceGhost[f] && keep[f])
    {
      asks.push_back(faceIds[f]);
      askFaces.push_back(f);
    }
  }
  std::int64_t conflict = -1;
  std::vector<int> faceOwner(nF, this->Rank);
  {
    const std::vector<int> owners = AskOwners(*this, registers, asks, conflict);
    for (std::size_t i = 0; i < askFaces.size(); ++i)
    {
      faceOwner[askFaces[i]] = owners[i];
      if (owners[i] < 0)
      {
        problem << "the ghost cell with global id " << asks[i]
                << " is owned by no piece (the pieces' ghost cells do not match their owners). ";
        break;
      }
    }
  }
  if (conflict >= 0)
  {
    problem << "the cell global id " << conflict
            << " is owned (not a ghost) in two pieces: the input is not partitioned (each cell "
               "must be owned by one piece; replicated data needs one process). ";
  }

  // 3. Owners of the vertices: the lowest owner of a face around them. All
  // faces around a point of an owned face are here; the others are asked.
  std::vector<int> vertexOwner(nP, -1);
  for (std::int64_t p = 0; p < nP; ++p)
  {
    if (touchOwned[p])
    {
      vertexOwner[p] = this->Rank;
    }
  }
  for (std::int64_t f = 0; f < nF; ++f)
  {
    if (faceGhost[f] && keep[f] && faceOwner[f] >= 0)
    {
      points(f, [&](std::int64_t p) {
        if (touchOwned[p])
        {
          vertexOwner[p] = std::min(vertexOwner[p], faceOwner[f]);
        }
      });
    }
  }
  registers.clear();
  asks.clear();
  std::vector<std::int64_t> askPoints;
  {
    std::vector<char> registered(nP, 0);
    for (std::int64_t f = 0; f < nF; ++f)
    {
      if (boundary[f])
      {
        points(f, [&](std::int64_t p) {
          if (vertexOwner[p] == this->Rank && !registered[p])
          {
            registered[p] = 1;
            registers.push_back(pointIds[p]);
          }
        });
      }
    }
    for (std::int64_t p = 0; p < nP; ++p)
    {
      if (!touchOwned[p] && touchGhost[p])
      {
        asks.push_back(pointIds[p]);
        askPoints.push_back(p);
      }
    }
  }
  conflict = -1;
  {
    const std::vector<int> owners = AskOwners(*this, registers, asks, conflict);
    for (std::size_t i = 0; i < askPoints.size(); ++i)
    {
      vertexOwner[askPoints[i]] = owners[i];
      if (owners[i] < 0 && problem.str().empty())
      {
        problem << "the point with global id " << asks[i]
                << " of a ghost cell is owned by no piece (the pieces' ghost cells or point "
                   "global ids do not match). ";
      }
    }
  }
  if (conflict >= 0)
  {
    problem << "the point global id " << conflict
            << " is claimed by two pieces: point global ids are not consistent. ";
  }

  // 4. Rows: owned first, in input order.
  this->FaceRows.clear();
  this->VertexRows.clear();
  this->VertexOwner.clear();
  for (int pass = 0; pass < 2; ++pass)
  {
    for (std::int64_t f = 0; f < nF; ++f)
    {
      if (keep[f] && (faceGhost[f] != 0) == (pass == 1))
      {
        this->FaceRows.push_back(f);
      }
    }
    for (std::int64_t p = 0; p < nP; ++p)
    {
      if ((touchOwned[p] || touchGhost[p]) && (vertexOwner[p] == this->Rank) == (pass == 0))
      {
        this->VertexRows.push_back(p);
        this->VertexOwner.push_back(vertexOwner[p]);
      }
    }
    if (pass == 0)
    {
      this->OwnedFaces = static_cast<std::int64_t>(this->FaceRows.size());
      this->OwnedVertices = static_cast<std::int64_t>(this->VertexRows.size());
    }
  }

  // 5. Halo lists: every ghost row asks its owner for its value's row.
  for (Lists& l : this->Halo)
  {
    l.Partners.clear();
    l.Send.assign(n, {});
    l.Receive.assign(n, {});
  }
  std::vector<std::vector<std::int64_t>> faceAsk(n), vertexAsk(n);
  for (std::size_t r = this->OwnedFaces; r < this->FaceRows.size(); ++r)
  {
    const int o = faceOwner[this->FaceRows[r]];
    if (o >= 0 && o != this->Rank)
    {
      faceAsk[o].push_back(faceIds[this->FaceRows[r]]);
      this->Halo[0].Receive[o].push_back(static_cast<std::int64_t>(r));
    }
  }
  for (std::size_t r = this->OwnedVertices; r < this->VertexRows.size(); ++r)
  {
    const int o = this->VertexOwner[r];
    if (o >= 0 && o != this->Rank)
    {
      vertexAsk[o].push_back(pointIds[this->VertexRows[r]]);
      this->Halo[1].Receive[o].push_back(static_cast<std::int64_t>(r));
    }
  }
  std::vector<std::vector<std::int64_t>> out(n);
  for (int q = 0; q < n; ++q)
  {
    out[q].push_back(static_cast<std::int64_t>(faceAsk[q].size()));
    out[q].insert(out[q].end(), faceAsk[q].begin(), faceAsk[q].end());
    out[q].insert(out[q].end(), vertexAsk[q].begin(), vertexAsk[q].end());
  }
  const auto in = this->Exchange(out);
  std::unordered_map<std::int64_t, std::int64_t> faceRow, vertexRow;
  for (std::int64_t r = 0; r < this->OwnedFaces; ++r)
  {
    faceRow.emplace(faceIds[this->FaceRows[r]], r);
  }
  for (std::int64_t r = 0; r < this->OwnedVertices; ++r)
  {
    vertexRow.emplace(pointIds[this->VertexRows[r]], r);
  }
  for (int s = 0; s < n; ++s)
  {
    if (s == this->Rank || in[s].empty())
    {
      continue;
    }
    const std::int64_t nFaceAsks = in[s][0];
    for (std::size_t i = 1; i < in[s].size(); ++i)
    {
      const bool face = static_cast<std::int64_t>(i) <= nFaceAsks;
      const auto& rows = face ? faceRow : vertexRow;
      const auto it = rows.find(in[s][i]);
      if (it == rows.end())
      {
        if (problem.str().empty())
        {
          problem << "piece " << s << " needs the " << (face ? "cell" : "point")
                  << " with global id " << in[s][i] << ", which this piece does not own. ";
        }
        continue;
      }
      this->Halo[face ? 0 : 1].Send[s].push_back(it->second);
    }
  }
  for (Lists& l : this->Halo)
  {
    for (int q = 0; q < n; ++q)
    {
      if (!l.Send[q].empty() || !l.Receive[q].empty())
      {
        l.Partners.push_back(q);
      }
    }
  }
  error = problem.str();
  if (!error.empty())
  {
    error.pop_back();
  }
  return this->AllOk(error.empty());
}

void ATHalo::SumAll(double* values, int count) const
{
  std::vector<double> all(static_cast<std::size_t>(count) * this->Processes);
  this->Controller->AllGather(values, all.data(), count);
  for (int c = 0; c < count; ++c)
  {
    double s = 0;
    for (int r = 0; r < this->Processes; ++r)
    {
      s += all[static_cast<std::size_t>(r) * count + c];
    }
    values[c] = s;
  }
}

double ATHalo::MaxAll(double value) const
{
  double result = value;
  this->Controller->AllReduce(&value, &result, 1, vtkCommunicator::MAX_OP);
  return result;
}

bool ATHalo::AllOk(bool ok) const
{
  int mine = ok ? 1 : 0, all = 0;
  this->Controller->AllReduce(&mine, &all, 1, vtkCommunicator::MIN_OP);
  return all == 1;
}

void ATHalo::UpdateGhosts(int kind, double* x, int nc) const
{
  this->UpdateGhostsOf(kind, x, nc);
}

void ATHalo::UpdateGhosts(int kind, float* x, int nc) const
{
  this->UpdateGhostsOf(kind, x, nc);
}

template<class T>
void ATHalo::UpdateGhostsOf(int kind, T* x, int nc) const
{
  const Lists& l = this->Halo[kind];
  std::vector<T> sendBuffer, receiveBuffer;
  for (int q : l.Partners)
  {
    const auto& send = l.Send[q];
    const auto& receive = l.Receive[q];
    sendBuffer.resize(send.size() * nc);
    for (std::size_t i = 0; i < send.size(); ++i)
    {
      std::copy(x + send[i] * nc, x + (send[i] + 1) * nc, sendBuffer.data() + i * nc);
    }
    receiveBuffer.resize(receive.size() * nc);
    PairStep<T>(
      this->Rank, q,
      [&] {
        if (!sendBuffer.empty())
        {
          this->Controller->Send(sendBuffer.data(), static_cast<vtkIdType>(sendBuffer.size()), q, ValueTag);
        }
      },
      [&] {
        if (!receiveBuffer.empty())
        {
          this->Controller->Receive(
            receiveBuffer.data(), static_cast<vtkIdType>(receiveBuffer.size()), q, ValueTag);
        }
      });
    for (std::size_t i = 0; i < receive.size(); ++i)
    {
      std::copy(receiveBuffer.data() + i * nc, receiveBuffer.data() + (i + 1) * nc, x + receive[i] * nc);
    }
  }
}

std::int64_t ATHalo::HaloValues(int kind) const
{
  std::int64_t s = 0;
  for (int q : this->Halo[kind].Partners)
  {
    s += static_cast<std::int64_t>(this->Halo[kind].Send[q].size() + this->Halo[kind].Receive[q].size());
  }
  return s;
}

int ATHalo::Neighbours(int kind) const
{
  return static_cast<int>(this->Halo[kind].Partners.size());
}
} // namespace dg
