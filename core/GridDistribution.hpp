// How the grid is spread over MPI ranks: a Cartesian block decomposition (RankGrid). Each rank owns
// a box of cells, the nodes at their lower edges along each direction (the last block along a
// direction also the grid's upper edge), and sees a band of `ghostWidth` ghost nodes around its box
// on every side, wide enough for the stencils of every particle it owns.
// Grid fields live in Tpetra multivectors over these maps; one Import is built here.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include "core/RankGrid.hpp"
#include "core/StructuredGrid.hpp"
#include "core/Types.hpp"

namespace impm {

class GridDistribution {
 public:
  // The rank grid impm chooses for this grid and rank count (RankGrid with nothing requested).
  GridDistribution(const StructuredGrid& grid, const Teuchos::RCP<const Teuchos::Comm<int>>& comm, int ghostWidth = 2);
  GridDistribution(const StructuredGrid& grid, const Teuchos::RCP<const Teuchos::Comm<int>>& comm, int ghostWidth,
                   const RankGrid& ranks);

  const StructuredGrid& grid() const { return grid_; }
  const Teuchos::RCP<const Teuchos::Comm<int>>& comm() const { return comm_; }

  const RankGrid& rankGrid() const { return ranks_; }
  int ghostWidth() const { return ghostWidth_; }
  // The cells this rank owns particles in: [cellBegin(d), cellEnd(d)) along direction d.
  int cellBegin(int d) const { return cellLo_[d]; }
  int cellEnd(int d) const { return cellHi_[d]; }
  bool ownsCell(int ci, int cj, int ck = 0) const {
    return ci >= cellLo_[0] && ci < cellHi_[0] && cj >= cellLo_[1] && cj < cellHi_[1] && ck >= cellLo_[2] &&
           ck < cellHi_[2];
  }
  // Whether this rank owns the cell holding a point (coordinates x[0..dim)).
  bool ownsPoint(const double* x) const;

  Teuchos::RCP<const Map> ownedNodeMap() const { return ownedMap_; }
  Teuchos::RCP<const Map> ghostedNodeMap() const { return ghostedMap_; }
  // Owned -> ghosted (doImport, INSERT); used in reverse (doExport, ADD) for ghosted -> owned.
  Teuchos::RCP<const Import> importer() const { return importer_; }

  const LocalNodeIndexer& ownedIndexer() const { return owned_; }
  const LocalNodeIndexer& ghostedIndexer() const { return ghosted_; }

 private:
  StructuredGrid grid_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  RankGrid ranks_;
  int ghostWidth_ = 2;
  int cellLo_[3] = {0, 0, 0}, cellHi_[3] = {1, 1, 1};
  LocalNodeIndexer owned_, ghosted_;
  Teuchos::RCP<const Map> ownedMap_, ghostedMap_;
  Teuchos::RCP<const Import> importer_;
};

// Columns of the explicit grid multivectors in Dim dimensions: a vector field takes Dim
// consecutive columns, named by its first (X) one.
template <int Dim>
struct AccumColumns {  // particle-to-grid sums
  static constexpr int Mass = 0, MomX = 1, FextX = 1 + Dim, FintX = 1 + 2 * Dim, Count = 1 + 3 * Dim;
};
template <int Dim>
struct KinColumns {  // grid kinematics after the grid update
  static constexpr int VelX = 0, AccX = Dim, Count = 2 * Dim;
};

// The grid multivectors of one integrator: particle-to-grid sums and kinematics, each as an
// owned and a ghosted copy. On one MPI rank the ghosted map is the owned map, and each ghosted
// multivector is the owned one itself: the Import and Export between them would be copies of
// the whole grid per step, done by Tpetra on the master thread, which handed every grid line
// to the other thread through the caches (see exportAccumulated).
struct GridFields {
  GridFields(const GridDistribution& dist, int accumCount, int kinCount);
  Teuchos::RCP<MultiVector> accumOwned, accumGhosted;
  Teuchos::RCP<MultiVector> kinOwned, kinGhosted;
  Teuchos::RCP<const Import> importer;

  // Sum the ghosted partial sums into the owned copy (reverse-mode Import, ADD).
  void exportAccumulated();
  // Broadcast owned kinematics to the ghosted copy.
  void importKinematics();
  // Broadcast the owned sums to the ghosted copy.
  void importAccumulated();
  // True when the ghosted multivectors are the owned ones (one rank).
  bool ghostedIsOwned() const { return accumGhosted == accumOwned; }
};

}  // namespace impm
