#include "core/GridDistribution.hpp"

#include <Teuchos_Array.hpp>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace impm {

GridDistribution::GridDistribution(const StructuredGrid& grid, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                   int ghostWidth)
    : GridDistribution(grid, comm, ghostWidth, RankGrid(grid, comm->getSize())) {}

GridDistribution::GridDistribution(const StructuredGrid& grid, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                   int ghostWidth, const RankGrid& ranks)
    : grid_(grid), comm_(comm), ranks_(ranks), ghostWidth_(ghostWidth) {
  if (ranks.ranks() != comm->getSize())
    throw std::logic_error("GridDistribution: a rank grid of " + std::to_string(ranks.ranks()) + " ranks for " +
                           std::to_string(comm->getSize()) + " MPI ranks");
  const int rank = comm->getRank();
  ranks_.cellBox(rank, cellLo_, cellHi_);
  const auto at = ranks_.coordsOf(rank);
  int ownedLo[3], ownedHi[3], ghostLo[3], ghostHi[3];
  for (int d = 0; d < 3; ++d) {
    const int nodes = d == 0 ? grid.nodesX() : d == 1 ? grid.nodesY() : grid.nodesZ();
    if (d == 2 && grid.dim != 3) {  // one layer of nodes
      ownedLo[d] = ghostLo[d] = 0;
      ownedHi[d] = ghostHi[d] = 1;
      continue;
    }
    const bool lastAlong = at[d] == ranks_.dims(d) - 1;
    ownedLo[d] = cellLo_[d];
    ownedHi[d] = lastAlong ? nodes : cellHi_[d];
    ghostLo[d] = std::max(0, cellLo_[d] - ghostWidth);
    ghostHi[d] = std::min(nodes, cellHi_[d] + ghostWidth + 1);
  }
  owned_ = LocalNodeIndexer::box(ownedLo[0], ownedHi[0], ownedLo[1], ownedHi[1], ownedLo[2], ownedHi[2]);
  ghosted_ = LocalNodeIndexer::box(ghostLo[0], ghostHi[0], ghostLo[1], ghostHi[1], ghostLo[2], ghostHi[2]);

  // Gids in box order (x slowest): kernels index the ghosted multivector rows with the box indexer.
  auto gidsOf = [&](const LocalNodeIndexer& ix) {
    Teuchos::Array<GO> gids;
    gids.reserve(ix.size());
    for (int i = ix.lo[0]; i < ix.end(0); ++i)
      for (int j = ix.lo[1]; j < ix.end(1); ++j)
        for (int k = ix.lo[2]; k < ix.end(2); ++k) gids.push_back(grid.nodeId(i, j, k));
    return gids;
  };
  const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
  ownedMap_ = Teuchos::rcp(new Map(invalid, gidsOf(owned_)(), 0, comm));
  ghostedMap_ = Teuchos::rcp(new Map(invalid, gidsOf(ghosted_)(), 0, comm));
  importer_ = Teuchos::rcp(new Import(ownedMap_, ghostedMap_));
}

bool GridDistribution::ownsPoint(const double* x) const {
  int c[3] = {0, 0, 0};
  for (int d = 0; d < grid_.dim; ++d) c[d] = cellIndexOf(grid_, d, x[d]);
  return ownsCell(c[0], c[1], c[2]);
}

GridFields::GridFields(const GridDistribution& dist, int accumCount, int kinCount) : importer(dist.importer()) {
  accumOwned = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), accumCount));
  kinOwned = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), kinCount));
  if (dist.comm()->getSize() == 1) {  // one rank: the ghosted map is the owned map (same gids, same order)
    accumGhosted = accumOwned;
    kinGhosted = kinOwned;
  } else {
    accumGhosted = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), accumCount));
    kinGhosted = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), kinCount));
  }
}

void GridFields::exportAccumulated() {
  if (ghostedIsOwned()) return;  // the sums are already the owned ones
  accumOwned->putScalar(0.0);
  accumOwned->doExport(*accumGhosted, *importer, Tpetra::ADD);
}

void GridFields::importKinematics() {
  if (!ghostedIsOwned()) kinGhosted->doImport(*kinOwned, *importer, Tpetra::INSERT);
}

void GridFields::importAccumulated() {
  if (!ghostedIsOwned()) accumGhosted->doImport(*accumOwned, *importer, Tpetra::INSERT);
}

}  // namespace impm
