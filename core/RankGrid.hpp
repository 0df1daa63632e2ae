// The Cartesian grid of MPI ranks over the background grid's cells (a block decomposition, as
// Cabana::Grid's block partitioner): ranks form a p_x x p_y (x p_z) array, rank r at coordinates
// (cx, cy, cz) with r = (cx * p_y + cy) * p_z + cz, and along each direction d the cell indices are
// cut at cuts(d) = {0 = c_0 < c_1 < ... < c_p = cells}; rank (cx, cy, cz) owns the cells
// [cuts(0)[cx], cuts(0)[cx+1]) x [cuts(1)[cy], ...) x .... Cuts start balanced in cells and may
// be moved by the load balancer (tensor splits: whole planes of ranks share a cut).
// Pure bookkeeping: no MPI calls, so every rank computes the same answers.
#pragma once

#include <array>
#include <vector>

#include "core/StructuredGrid.hpp"

namespace impm {

class RankGrid {
 public:
  // `requested` ranks per direction (0: chosen here); `minCells` is the fewest cells a rank may
  // own along a direction. Throws DeckError when the ranks cannot all own cells, or when the
  // requested counts do not multiply to `nranks`.
  RankGrid(const StructuredGrid& grid, int nranks, std::array<int, 3> requested = {0, 0, 0}, int minCells = 1);

  int ranks() const { return nranks_; }
  int dims(int d) const { return dims_[d]; }
  // The cells along d: the grid's, and 1 along z in 2D.
  int cells(int d) const { return cells_[d]; }
  const std::vector<int>& cuts(int d) const { return cuts_[d]; }
  int minCells() const { return minCells_; }

  std::array<int, 3> coordsOf(int rank) const;
  int rankAt(const std::array<int, 3>& c) const { return (c[0] * dims_[1] + c[1]) * dims_[2] + c[2]; }
  // The rank owning cell (ci, cj, ck) (indices clamped to the grid).
  int ownerOfCell(int ci, int cj, int ck = 0) const;
  // The cells rank owns, [lo[d], hi[d]).
  void cellBox(int rank, int lo[3], int hi[3]) const;
  // The other ranks whose blocks touch rank's (faces, edges and corners: up to 8 in 2D, 26 in
  // 3D), in increasing rank order. The relation is symmetric.
  std::vector<int> neighbours(int rank) const;

  // New cuts along d (load balance): p_d + 1 increasing values from 0 to cells(d), every part at
  // least minCells() wide. Throws std::invalid_argument otherwise.
  void setCuts(int d, const std::vector<int>& cuts);

  bool operator==(const RankGrid& o) const { return dims_ == o.dims_ && cuts_ == o.cuts_; }

 private:
  int nranks_ = 1, minCells_ = 1;
  std::array<int, 3> dims_{{1, 1, 1}}, cells_{{1, 1, 1}};
  std::array<std::vector<int>, 3> cuts_;
};

// The cuts that split `weights` (one per cell along a direction) into `parts` contiguous parts of
// at least `minCells` cells, minimising the largest part's weight; among those, the cuts nearest
// to `current` (when it has parts + 1 entries), so that equal loads do not move boundaries.
std::vector<int> balancedCuts(const std::vector<double>& weights, int parts, int minCells,
                              const std::vector<int>& current = {});

}  // namespace impm
