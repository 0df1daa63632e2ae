#include "solvers/implicit/FreeDofMap.hpp"

#include <Teuchos_CommHelpers.hpp>

namespace impm {

template <int Dim>
bool FreeDofMap<Dim>::update(const MultiVector& stateOwned, int freeX) {
  auto s = stateOwned.getLocalViewHost(Tpetra::Access::ReadOnly);
  const auto ownedMap = stateOwned.getMap();
  std::vector<int> nodes, comps, fields;
  std::vector<GO> gids;
  for (size_t n = 0; n < s.extent(0); ++n)
    for (int f = 0; f < fields_; ++f)
      for (int d = 0; d < Dim; ++d)
        if (s(n, freeX + f * stride_ + d) > 0.5) {
          nodes.push_back((int)n);
          comps.push_back(d);
          fields.push_back(f);
          gids.push_back(gid(ownedMap->getGlobalElement((LO)n), d, f));
        }
  node_ = Kokkos::View<int*, DeviceType>("free_node", nodes.size());
  component_ = Kokkos::View<int*, DeviceType>("free_comp", comps.size());
  field_ = Kokkos::View<int*, DeviceType>("free_field", fields.size());
  auto hn = Kokkos::create_mirror_view(node_);
  auto hc = Kokkos::create_mirror_view(component_);
  auto hf = Kokkos::create_mirror_view(field_);
  for (size_t k = 0; k < nodes.size(); ++k) {
    hn(k) = nodes[k];
    hc(k) = comps[k];
    hf(k) = fields[k];
  }
  Kokkos::deep_copy(node_, hn);
  Kokkos::deep_copy(component_, hc);
  Kokkos::deep_copy(field_, hf);
  const int changedHere = (map_.is_null() || gids != gids_) ? 1 : 0;
  gids_ = std::move(gids);
  int changed = 0;
  const auto comm = ownedMap->getComm();
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, changedHere, Teuchos::outArg(changed));
  if (changed) {
    const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
    map_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(gids_), 0, comm));
    coordinates_ = Teuchos::null;
  }
  return changed != 0;
}

template <int Dim>
Teuchos::RCP<const MultiVector> FreeDofMap<Dim>::coordinates(const StructuredGrid& g) const {
  if (map_.is_null()) return Teuchos::null;
  if (!coordinates_.is_null()) return coordinates_;
  auto coords = Teuchos::rcp(new MultiVector(map_, Dim));
  auto c = coords->getLocalViewHost(Tpetra::Access::OverwriteAll);
  const long long nz = g.nodesZ(), ny = g.nodesY();
  for (size_t k = 0; k < gids_.size(); ++k) {
    const long long node = nodeOf(gids_[k]);  // node id = (i (ny + 1) + j) nodesZ + l
    const long long l = node % nz, j = (node / nz) % ny, i = node / (nz * ny);
    c(k, 0) = g.nodeX((int)i);
    if (Dim > 1) c(k, 1) = g.nodeY((int)j);
    if (Dim > 2) c(k, Dim - 1) = g.nodeZ((int)l);
  }
  coordinates_ = coords;
  return coordinates_;
}

template class FreeDofMap<2>;
template class FreeDofMap<3>;

}  // namespace impm
