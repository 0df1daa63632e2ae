// Simulation, part 4: checkpoints and restart (solvers/Checkpoint.hpp has the files' format).
#include <Kokkos_Core.hpp>

#include "core/ParticleMigration.hpp"
#include "solvers/Checkpoint.hpp"
#include "solvers/Simulation.hpp"

namespace impm {

void Simulation::writeCheckpointAt(int step, const RunResult& r, const History& history) const {
  CheckpointContent c;
  c.step = step;
  c.time = step * dt_;
  const int n = particles_.count;
  ParticleSet::Ids all("checkpoint_indices", n);
  Kokkos::parallel_for(
      "iota", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int p) { all(p) = p; });
  c.particles = ParticleSet::Packed(Kokkos::view_alloc(Kokkos::WithoutInitializing, "checkpoint_rows"), n,
                                    particles_.packedWidth());
  particles_.pack(all, c.particles);
  Kokkos::fence();
  integrator_->saveState(c.state);
  saveRankGrid(c.state);
  history.saveState(r, c.state);
  writeCheckpoint(outputDir_, deck_, c, comm_);
}

void Simulation::restartFrom(const std::string& dir) {
  // At another rank count, a particle goes to the rank that owns its cell (the rule of particle
  // creation and migration).
  auto mine = [&](const double* x) { return dist_->ownsPoint(x); };
  CheckpointContent c = readCheckpoint(dir, deck_, particles_.packedWidth(), particles_.dim, mine, comm_);
  if (c.step > steps_)
    throw CheckpointError("--restart '" + dir + "': the checkpoint is of step " + std::to_string(c.step) +
                          ", beyond this deck's 'Integrator/Number of Steps' = " + std::to_string(steps_));
  // Output may differ from the run that wrote it, but energy columns cannot start half-way.
  if (energyHistory_ && c.state["history kinetic"].size() != c.state["history time"].size())
    throw CheckpointError("--restart '" + dir +
                          "': the run that wrote the checkpoint recorded no energy and momentum; "
                          "set 'Output/Energy And Momentum' to false, as it was there");
  // In place of the deck's initial particles (the views keep their kind: FE reference u, history).
  particles_.count = 0;
  particles_.unpackAppend(c.particles);
  Kokkos::fence();
  restoreRankGrid(c.state);  // load-balanced cuts: the particles read are those of the cuts saved
  loads_.locateParticles(particles_);
  integrator_->restoreState(c.state);
  restartStep_ = c.step;
  restartState_ = std::move(c.state);
  restarted_ = true;
}

}  // namespace impm
