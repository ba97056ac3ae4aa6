// The distributed Ambrosio-Tortorelli solve's communication (docs/distributed.md):
// who owns which face and vertex of a piece, the halo of ghost rows each
// process reads from its neighbours, and the collective operations of the
// solver (dgATSolver.h, ATDistribution) over VTK's vtkMultiProcessController.
//
// A piece is given as its polygons with their cell global ids and ghost
// flags (owned cells are not ghosts) and its points' global ids. Ghost
// polygons that share no point with an owned one are dropped. A vertex is
// owned by the lowest process that owns a polygon around it. Owners are
// found through a directory (global id modulo the number of processes), so
// no process needs to know the partition. Every process must call Build and
// then the solver's operations collectively.
#ifndef dgATHalo_h
#define dgATHalo_h

#include "dgATSolver.h"

#include <cstdint>
#include <string>
#include <vector>

class vtkMultiProcessController;

namespace dg
{
class ATHalo : public ATDistribution
{
public:
  explicit ATHalo(vtkMultiProcessController* controller);

  /// offsets/connectivity: the piece's polygons on its point ids. Returns
  /// false on every process when any of them failed (`error` is set where
  /// the problem was seen).
  bool Build(const std::vector<std::int64_t>& offsets,
    const std::vector<std::int64_t>& connectivity,
    const std::vector<std::int64_t>& faceIds,
    const std::vector<char>& faceGhost,
    const std::vector<std::int64_t>& pointIds,
    std::string& error);

  /// Local rows: input polygon / point of each row, owned rows first.
  std::vector<std::int64_t> FaceRows, VertexRows;
  /// Owning process of each vertex row.
  std::vector<int> VertexOwner;
  std::int64_t OwnedFaces = 0, OwnedVertices = 0;
  int Rank = 0, Processes = 1;

  void SumAll(double* values, int count) const override;
  double MaxAll(double value) const override;
  bool AllOk(bool ok) const override;
  void UpdateGhosts(int kind, double* x, int nc) const override;
  void UpdateGhosts(int kind, float* x, int nc) const override;
  std::int64_t Owned(int kind) const override { return kind == 0 ? this->OwnedFaces : this->OwnedVertices; }

  /// Values exchanged per halo update of one column, both kinds (for the
  /// benchmark's bytes per CG iteration).
  std::int64_t HaloValues(int kind) const;
  int Neighbours(int kind) const;

  /// Sends out[q] to process q and returns what every process sent here
  /// (received[q] from q; received[Rank] = out[Rank]).
  std::vector<std::vector<std::int64_t>> Exchange(
    const std::vector<std::vector<std::int64_t>>& out) const;

private:
  template<class T>
  void UpdateGhostsOf(int kind, T* x, int nc) const;
  vtkMultiProcessController* Controller;
  // Per kind: for each partner process (ascending), the rows sent to it and
  // the ghost rows filled from it.
  struct Lists
  {
    std::vector<int> Partners;
    std::vector<std::vector<std::int64_t>> Send, Receive;
  };
  Lists Halo[2];
};
} // namespace dg

#endif
