// The unknowns of an implicit step: the free components of the owned nodes, numbered
// gid = Dim node + component (one Tpetra map, distributed like the nodes). With several velocity
// fields (multi-field contact) field f of a node is a node of its own, gid = Dim (f N + node) +
// component with N the grid's node count, so that field 0 keeps the single-field numbering.
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
  GO gid(GO node, int component, int field) const { return Dim * (field * nodes_ + node) + component; }
  GO nodeOf(GO dofGid) const { return (dofGid / Dim) % nodes_; }

  // Several velocity fields: field f's flags sit f * stride columns after field 0's; `nodes` is
  // the grid's node count.
  void setFields(int fields, int stride, GO nodes) {
    fields_ = fields;
    stride_ = stride;
    nodes_ = nodes;
  }
  int fields() const { return fields_; }

  // Takes the free dofs from the flags (> 1/2) in columns freeX .. freeX + Dim - 1 (of each
  // field) of the owned grid state. Collective. Returns true when the set changed on some rank; the map object is
  // kept otherwise (the Newton solver and the preconditioner key on it).
  bool update(const MultiVector& stateOwned, int freeX);

  Teuchos::RCP<const Map> map() const { return map_; }
  const std::vector<GO>& gids() const { return gids_; }
  size_t size() const { return gids_.size(); }
  // Per free dof: its owned local node, component and field.
  Kokkos::View<int*, DeviceType> node() const { return node_; }
  Kokkos::View<int*, DeviceType> component() const { return component_; }
  Kokkos::View<int*, DeviceType> field() const { return field_; }
  // Node coordinates per free dof (MueLu's near-null space); built on first request per map.
  Teuchos::RCP<const MultiVector> coordinates(const StructuredGrid& grid) const;

 private:
  Teuchos::RCP<const Map> map_;
  std::vector<GO> gids_;
  Kokkos::View<int*, DeviceType> node_, component_, field_;
  int fields_ = 1, stride_ = 0;
  GO nodes_ = GO(1) << 62;
  mutable Teuchos::RCP<MultiVector> coordinates_;
};

}  // namespace impm
