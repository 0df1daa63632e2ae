// Simulation, part 5: the rank grid at run time. Load balance moves the cuts between ranks
// (tensor splits of the particle histograms, RankGrid.hpp) and rebuilds what depends on them;
// a checkpoint keeps the cuts so that a restart at the same rank count continues bit for bit.
#include "core/ParticleMigration.hpp"
#include "core/ShapeRegistry.hpp"
#include "core/RankGrid.hpp"
#include "solvers/Simulation.hpp"

namespace impm {

bool Simulation::rebalance() {
  if (comm_->getSize() == 1 || particles_.fixedPositions()) return false;
  const auto histograms = particleHistograms(particles_, grid_, *comm_);
  RankGrid next = dist_->rankGrid();
  for (int d = 0; d < grid_.dim; ++d)
    if (next.dims(d) > 1) next.setCuts(d, balancedCuts(histograms[d], next.dims(d), next.minCells(), next.cuts(d)));
  if (next == dist_->rankGrid()) return false;
  adoptRankGrid(next, true);
  return true;
}

void Simulation::adoptRankGrid(const RankGrid& ranks, bool moveParticles) {
  NamedArrays state;
  integrator_->saveState(state);
  state.erase("node implicit P");  // its rows follow the old maps: a fresh P is assembled
  integrator_.reset();             // it refers to the maps, constraints and loads replaced below
  dist_ = std::make_unique<GridDistribution>(grid_, comm_, dist_->ghostWidth(), ranks);
  if (moveParticles) sendParticlesToOwners(particles_, *dist_);
  GridConditions conditions(constraintSpecs_, *dist_, wallSpecs_, contactSpec_);
  conditions.keepReactionsOf(constraints_);  // the last step's, for a history row written after the balance
  constraints_ = std::move(conditions);
  loads_ = LoadSet(loadSpecs_, *dist_, loadParticleIds_, (int)bodies_.size(), shapeInfo(shape_).quadraticElements);
  loads_.locateParticles(particles_);
  makeIntegrator();
  integrator_->restoreState(state);
}

void Simulation::saveRankGrid(NamedArrays& state) const {
  const RankGrid& ranks = dist_->rankGrid();
  auto& s = state["decomposition cuts"];
  s = {double(ranks.ranks())};
  for (int d = 0; d < 3; ++d) {
    s.push_back(ranks.dims(d));
    for (int c : ranks.cuts(d)) s.push_back(c);
  }
}

void Simulation::restoreRankGrid(const NamedArrays& state) {
  const auto found = state.find("decomposition cuts");
  if (found == state.end() || found->second.empty() || int(found->second[0]) != comm_->getSize()) return;
  // The same rank count: this rank read its own particles, which lie in the saved cuts.
  RankGrid saved = dist_->rankGrid();
  const std::vector<double>& s = found->second;
  size_t at = 1;
  for (int d = 0; d < 3; ++d) {
    if (at >= s.size() || int(s[at]) != saved.dims(d)) {
      // Another rank grid (the deck's Decomposition changed): the deck's stands, and the
      // particles go to their ranks in it.
      sendParticlesToOwners(particles_, *dist_);
      return;
    }
    std::vector<int> cuts(s.begin() + at + 1, s.begin() + at + 2 + saved.dims(d));
    at += 2 + saved.dims(d);
    saved.setCuts(d, cuts);
  }
  if (!(saved == dist_->rankGrid())) adoptRankGrid(saved, false);
}

}  // namespace impm
