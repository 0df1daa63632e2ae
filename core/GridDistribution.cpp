#include "core/GridDistribution.hpp"

#include <Teuchos_Array.hpp>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace impm {

GridDistribution::GridDistribution(const StructuredGrid& grid,
                                   const Teuchos::RCP<const Teuchos::Comm<int>>& comm, int ghostColumns)
    : grid_(grid), comm_(comm) {
  const int nranks = comm->getSize(), rank = comm->getRank();
  if (grid.nx < nranks)
    throw std::runtime_error("the grid has " + std::to_string(grid.nx) + " cell columns for " +
                             std::to_string(nranks) + " MPI ranks; use fewer ranks or more cells in x");
  // Balanced slabs of cell columns.
  const int base = grid.nx / nranks, extra = grid.nx % nranks;
  cellBegin_ = rank * base + std::min(rank, extra);
  cellEnd_ = cellBegin_ + base + (rank < extra ? 1 : 0);

  const int ny1 = grid.nodesY(), nz1 = grid.nodesZ();
  const int ownedColEnd = (rank == nranks - 1) ? grid.nx + 1 : cellEnd_;
  owned_ = LocalNodeIndexer{cellBegin_, ownedColEnd, ny1, nz1};
  ghosted_ = LocalNodeIndexer{std::max(0, cellBegin_ - ghostColumns),
                              std::min(grid.nx + 1, cellEnd_ + ghostColumns + 1), ny1, nz1};

  auto gidsOf = [&](const LocalNodeIndexer& ix) {
    Teuchos::Array<GO> gids;
    gids.reserve(ix.size());
    for (int i = ix.colBegin; i < ix.colEnd; ++i)
      for (int j = 0; j < ny1; ++j)
        for (int k = 0; k < nz1; ++k) gids.push_back(grid.nodeId(i, j, k));
    return gids;
  };
  const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
  ownedMap_ = Teuchos::rcp(new Map(invalid, gidsOf(owned_)(), 0, comm));
  ghostedMap_ = Teuchos::rcp(new Map(invalid, gidsOf(ghosted_)(), 0, comm));
  importer_ = Teuchos::rcp(new Import(ownedMap_, ghostedMap_));
}

GridFields::GridFields(const GridDistribution& dist, int accumCount, int kinCount) : importer(dist.importer()) {
  accumOwned = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), accumCount));
  accumGhosted = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), accumCount));
  kinOwned = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), kinCount));
  kinGhosted = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), kinCount));
}

void GridFields::exportAccumulated() {
  accumOwned->putScalar(0.0);
  accumOwned->doExport(*accumGhosted, *importer, Tpetra::ADD);
}

void GridFields::importKinematics() { kinGhosted->doImport(*kinOwned, *importer, Tpetra::INSERT); }

}  // namespace impm
