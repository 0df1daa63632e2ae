// Initial particle states other than rest (Initial Conditions in the deck).
#pragma once

#include "core/ParticleSet.hpp"
#include "physics/ManufacturedSolution.hpp"

namespace impm {

// v_x(X, 0) = V sin(n pi (X - xMin) / L) at each particle's reference position X, v_y = 0; the
// displacement stays zero. One mode of the fixed-fixed bar (BarStandingWaveExact).
void applyStandingWaveVelocity(ParticleSet& particles, double xMin, double length, double amplitude, int mode);

// v(X, 0) of the manufactured solution at each particle's reference position; u stays zero (the
// field starts undeformed).
void applyManufacturedVelocity(ParticleSet& particles, const AxisAlignedManufactured& field);

}  // namespace impm
