// Lazy, neighbour-only particle migration (after Cabana::Grid's particleMigrate and ExaMPM): a
// rank holds the particles of its box of cells (RankGrid), and sees `slack` cells more ghost
// nodes around it than its stencils need (GridDistribution's ghost width = stencil reach +
// slack). After a step, one count and one global reduction decide: while every particle is
// within `slack` cells of its rank's box nothing moves; once some particle is not, every
// particle outside its rank's box is packed (ParticleSet::pack), sent to the neighbouring rank
// that owns its cell (one message per neighbour: a count, then the rows), and appended there.
// Particles fixed in place (the FE reference) never migrate.
#pragma once

#include <array>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"

namespace impm {

// Moves particles to the neighbouring ranks that own their cells, when some particle is more
// than `slack` cells outside its rank's box. Collective. Returns the number of particles that
// moved (over all ranks; 0 when nothing was exchanged). Throws std::runtime_error when a particle
// went beyond the neighbouring ranks' blocks in one step.
long long migrateParticles(ParticleSet& particles, const GridDistribution& dist, int slack = 0);

// After the rank grid changed (load balance): every particle goes to the rank that owns its cell,
// wherever it is (Tpetra::Distributor: one message per pair of ranks that exchange). Collective.
// The kept particles keep their order, then the arrivals by increasing sender rank. Returns the
// number of particles that moved (over all ranks).
long long sendParticlesToOwners(ParticleSet& particles, const GridDistribution& dist);

// The particle count per cell index along each direction, summed over all ranks (the load
// balancer's histograms): counts[d][i] = particles whose cell index along d is i. Collective.
std::array<std::vector<double>, 3> particleHistograms(const ParticleSet& particles, const StructuredGrid& grid,
                                                      const Teuchos::Comm<int>& comm);

}  // namespace impm
