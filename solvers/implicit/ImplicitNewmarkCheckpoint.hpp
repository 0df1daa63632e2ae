// ImplicitNewmark<Shape, Dim>'s part of a checkpoint: counters, step control, the kept P (per
// rank) and the FE reference's grid kinematics. Included by ImplicitNewmarkImpl.hpp.
#pragma once

#include "solvers/implicit/ImplicitNewmark.hpp"

#include <map>
#include <stdexcept>
#include <utility>
#include <string>
#include <vector>

namespace impm {

// ---- Checkpoint -------------------------------------------------------------------------------

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::saveState(NamedArrays& state) const {
  std::vector<double> scalars = {double(firstStep_), control_.carriedSubStep(), double(control_.halvings())};
  for (const auto& part : {refresh_.state(), statistics_.scalars(), control_.subStepStatistics()})
    scalars.insert(scalars.end(), part.begin(), part.end());
  state["implicit scalars"] = scalars;
  statistics_.save(state);
  // A Jacobian-free run reuses P (and its preconditioner) for later steps: kept, per rank.
  state["implicit ranks"] = {double(dist_.comm()->getSize())};
  if (jacobianFree() && !assembler_.matrix().is_null()) assembler_.save(state["node implicit P"]);
  state["implicit re-solves"] = {double(contactResolves_), double(wallResolves_)};
  if (fields_ > 1) saveContactStates(state);
  if (conditions_.hasWalls()) saveWallStates(state);
  if (opt_.fixedParticles) {
    // The grid's own v and a (owned nodes) with their global ids: per rank.
    auto k = gridKinematics_->getLocalViewHost(Tpetra::Access::ReadOnly);
    const auto map = dist_.ownedNodeMap();
    auto& gids = state["node implicit grid kinematics gids"];
    auto& values = state["node implicit grid kinematics"];
    for (size_t n = 0; n < k.extent(0); ++n) {
      gids.push_back(double(map->getGlobalElement((LO)n)));
      for (int c = 0; c < 2 * Dim; ++c) values.push_back(k(n, c));
    }
  }
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::restoreState(const NamedArrays& state) {
  const std::vector<double>& s = state.at("implicit scalars");
  if (s.size() != 17)
    throw std::runtime_error("checkpoint: 'implicit scalars' has " + std::to_string(s.size()) + " entries, not 17");
  firstStep_ = s[0] != 0;
  refresh_.restore(s[3], s[4], s[5], s[6]);
  statistics_.restoreScalars(std::vector<double>(s.begin() + 7, s.begin() + 13));
  control_.restore(s[1], s[2], std::vector<double>(s.begin() + 13, s.end()));
  statistics_.restore(state);
  const auto ranks = state.find("implicit ranks"), P = state.find("node implicit P");
  if (ranks != state.end() && P != state.end() && int(ranks->second.at(0)) == dist_.comm()->getSize())
    restoredP_ = P->second;
  const auto resolves = state.find("implicit re-solves");
  if (resolves != state.end() && resolves->second.size() == 2) {
    contactResolves_ = long(resolves->second[0]);
    wallResolves_ = long(resolves->second[1]);
  }
  if (fields_ > 1) restoreContactStates(state);
  if (conditions_.hasWalls()) restoreWallStates(state);
  if (opt_.fixedParticles) {
    const auto& gids = state.at("node implicit grid kinematics gids");
    const auto& values = state.at("node implicit grid kinematics");
    auto k = gridKinematics_->getLocalViewHost(Tpetra::Access::OverwriteAll);
    const auto map = dist_.ownedNodeMap();
    for (size_t i = 0; i < gids.size(); ++i) {
      const LO n = map->getLocalElement((GO)gids[i]);
      if (n == Teuchos::OrdinalTraits<LO>::invalid()) continue;
      for (int c = 0; c < 2 * Dim; ++c) k(n, c) = values[i * 2 * Dim + c];
    }
  }
}

// Multi-field contact: the active set (each owned node's state, slip directions and carried
// force, with its global id: per rank). A checkpoint without them (or a new decomposition's node
// the old rank did not own) starts Free with no force.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::saveContactStates(NamedArrays& state) const {
  const ContactActiveSet& set = conditions_.implicitContactSet();
  auto st = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), set.state);
  auto dir = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), set.direction);
  auto force = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), set.force);
  const auto map = dist_.ownedNodeMap();
  auto& gids = state["node implicit contact gids"];
  auto& states = state["node implicit contact states"];
  auto& directions = state["node implicit contact directions"];
  auto& forces = state["node implicit contact forces"];
  for (size_t n = 0; n < st.extent(0); ++n) {
    gids.push_back(double(map->getGlobalElement((LO)n)));
    for (size_t f = 0; f < st.extent(1); ++f) states.push_back(st(n, f));
    for (size_t c = 0; c < dir.extent(1); ++c) directions.push_back(dir(n, c));
    for (size_t c = 0; c < force.extent(1); ++c) forces.push_back(force(n, c));
  }
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::restoreContactStates(const NamedArrays& state) {
  const auto gids = state.find("node implicit contact gids");
  if (gids == state.end()) return;
  const std::vector<double>& states = state.at("node implicit contact states");
  const std::vector<double>& directions = state.at("node implicit contact directions");
  const auto forcesFound = state.find("node implicit contact forces");
  const auto map = dist_.ownedNodeMap();
  ContactActiveSet& set = conditions_.implicitContactSet();
  set.fit(map->getNodeNumElements(), fields_);
  auto st = Kokkos::create_mirror_view(set.state);
  auto dir = Kokkos::create_mirror_view(set.direction);
  auto force = Kokkos::create_mirror_view(set.force);
  Kokkos::deep_copy(st, set.state);
  Kokkos::deep_copy(dir, set.direction);
  Kokkos::deep_copy(force, set.force);
  const size_t fields = st.extent(1), width = dir.extent(1);
  const bool withForces = forcesFound != state.end();
  if (states.size() != gids->second.size() * fields || directions.size() != gids->second.size() * width ||
      (withForces && forcesFound->second.size() != gids->second.size() * width))
    throw std::runtime_error("checkpoint: the implicit contact states do not match " + std::to_string(fields) +
                             " fields");
  for (size_t i = 0; i < gids->second.size(); ++i) {
    const LO n = map->getLocalElement((GO)gids->second[i]);
    if (n == Teuchos::OrdinalTraits<LO>::invalid()) continue;
    for (size_t f = 0; f < fields; ++f) st(n, f) = int(states[i * fields + f]);
    for (size_t c = 0; c < width; ++c) dir(n, c) = directions[i * width + c];
    for (size_t c = 0; c < width && withForces; ++c) force(n, c) = forcesFound->second[i * width + c];
  }
  Kokkos::deep_copy(set.state, st);
  Kokkos::deep_copy(set.direction, dir);
  Kokkos::deep_copy(set.force, force);
}

// Walls: the active set (each wall node's hold, stick or slip and slip direction, with its node's
// global id and its wall: per rank). A checkpoint without it (or a node the old rank did not own)
// starts from the start motion, as a new wall node does.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::saveWallStates(NamedArrays& state) const {
  const ImplicitWallContact& walls = conditions_.implicitWalls();
  const auto map = dist_.ownedNodeMap();
  auto& keys = state["node implicit wall keys"];
  for (const auto& [node, wall] : walls.nodeWalls())
    keys.insert(keys.end(), {double(map->getGlobalElement(node)), double(wall)});
  state["node implicit wall states"] = walls.states();
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::restoreWallStates(const NamedArrays& state) {
  const auto keys = state.find("node implicit wall keys");
  if (keys == state.end()) return;
  const std::vector<double>& rows = state.at("node implicit wall states");
  const ImplicitWallContact& walls = conditions_.implicitWalls();
  const size_t width = size_t(ImplicitWallContact::kStateWidth) * walls.fieldCount();
  if (rows.size() * 2 != keys->second.size() * width)
    throw std::runtime_error("checkpoint: the implicit wall states do not match their keys");
  const auto map = dist_.ownedNodeMap();
  std::map<std::pair<GO, int>, int> index;  // (node gid, wall) -> wall node
  const auto nodeWalls = walls.nodeWalls();
  for (size_t k = 0; k < nodeWalls.size(); ++k)
    index[{map->getGlobalElement(nodeWalls[k].first), nodeWalls[k].second}] = int(k);
  std::vector<std::pair<int, const double*>> restored;
  for (size_t i = 0; 2 * i < keys->second.size(); ++i) {
    const auto found = index.find({GO(keys->second[2 * i]), int(keys->second[2 * i + 1])});
    if (found != index.end()) restored.push_back({found->second, &rows[i * width]});
  }
  walls.restoreStates(restored);
}

}  // namespace impm
