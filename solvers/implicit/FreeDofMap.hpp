// The unknowns of an implicit step: the free components of the owned nodes, numbered
// gid = Dim node + component (one Tpetra map, distributed like the nodes).
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>
#include <vector>

#include "core/StructuredGrid.hpp"
#include "core/Types.hpp"

namespace impm {

template <int Dim>
class FreeDofMap {
 public:
  static GO gid(GO node, int component) { return Dim * node + component; }
  static GO nodeOf(GO dofGid) { return dofGid / Dim; }

  // Takes the free dofs from the flags (> 1/2) in columns freeX .. freeX + Dim - 1 of the owned
  // grid state. Collective. Returns true when the set changed on some rank; the map object is
  // kept otherwise (the Newton solver and the preconditioner key on it).
  bool update(const MultiVector& stateOwned, int freeX);

  Teuchos::RCP<const Map> map() const { return map_; }
  const std::vector<GO>& gids() const { return gids_; }
  size_t size() const { return gids_.size(); }
  // Per free dof: its owned local node and component.
  Kokkos::View<int*, DeviceType> node() const { return node_; }
  Kokkos::View<int*, DeviceType> component() const { return component_; }
  // Node coordinates per free dof (MueLu's near-null space); built on first request per map.
  Teuchos::RCP<const MultiVector> coordinates(const StructuredGrid& grid) const;

 private:
  Teuchos::RCP<const Map> map_;
  std::vector<GO> gids_;
  Kokkos::View<int*, DeviceType> node_, component_;
  mutable Teuchos::RCP<MultiVector> coordinates_;
};

}  // namespace impm
