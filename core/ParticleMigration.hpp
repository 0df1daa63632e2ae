// Lazy, neighbour-only particle migration (after Cabana::Grid's particleMigrate): a rank holds
// the particles of its slab of cell columns; after a step, the particles whose column now
// belongs to the slab on the left or right are packed (ParticleSet::pack), sent to that
// neighbour and appended there. Nothing is communicated beyond one reduction when no particle
// has left its slab. Particles fixed in place (the FE reference) never migrate.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"

namespace impm {

// The cell column a particle at x belongs to (the rule particle creation uses too).
KOKKOS_INLINE_FUNCTION int cellColumnOf(const StructuredGrid& g, double x) {
  const double xi = (x - g.x0) / g.hx + 1e-9;
  int i = static_cast<int>(xi);
  if (xi < i) --i;
  return i < 0 ? 0 : (i > g.nx - 1 ? g.nx - 1 : i);
}

// Moves particles to the neighbouring rank whose slab holds them. Collective. Returns the number
// of particles that moved (over all ranks). Throws std::runtime_error when a particle jumped
// beyond a neighbouring slab in one step.
long long migrateParticles(ParticleSet& particles, const GridDistribution& dist);

}  // namespace impm
