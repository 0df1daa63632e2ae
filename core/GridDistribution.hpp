// How the grid is spread over MPI ranks: each rank owns a slab of cell columns (all rows and
// layers), the node columns at their left edges (the last rank also the right edge of the grid), and sees a
// band of ghost node columns either side wide enough for every particle it owns.
// Grid fields live in Tpetra multivectors over these maps; one Import is built here.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>

#include "core/StructuredGrid.hpp"
#include "core/Types.hpp"

namespace impm {

class GridDistribution {
 public:
  GridDistribution(const StructuredGrid& grid, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                   int ghostColumns = 2);

  const StructuredGrid& grid() const { return grid_; }
  const Teuchos::RCP<const Teuchos::Comm<int>>& comm() const { return comm_; }

  // Cell columns this rank owns particles in: [cellColumnBegin, cellColumnEnd).
  int cellColumnBegin() const { return cellBegin_; }
  int cellColumnEnd() const { return cellEnd_; }
  bool ownsCellColumn(int i) const { return i >= cellBegin_ && i < cellEnd_; }

  Teuchos::RCP<const Map> ownedNodeMap() const { return ownedMap_; }
  Teuchos::RCP<const Map> ghostedNodeMap() const { return ghostedMap_; }
  // Owned -> ghosted (doImport, INSERT); used in reverse (doExport, ADD) for ghosted -> owned.
  Teuchos::RCP<const Import> importer() const { return importer_; }

  const LocalNodeIndexer& ownedIndexer() const { return owned_; }
  const LocalNodeIndexer& ghostedIndexer() const { return ghosted_; }

 private:
  StructuredGrid grid_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  int cellBegin_ = 0, cellEnd_ = 0;
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
// owned and a ghosted copy.
struct GridFields {
  GridFields(const GridDistribution& dist, int accumCount, int kinCount);
  Teuchos::RCP<MultiVector> accumOwned, accumGhosted;
  Teuchos::RCP<MultiVector> kinOwned, kinGhosted;
  Teuchos::RCP<const Import> importer;

  // Sum the ghosted partial sums into the owned copy (reverse-mode Import, ADD).
  void exportAccumulated();
  // Broadcast owned kinematics to the ghosted copy.
  void importKinematics();
};

}  // namespace impm
