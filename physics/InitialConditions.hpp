// Initial particle states other than rest (Initial Conditions in the deck).
#pragma once

#include "core/ParticleSet.hpp"

namespace impm {

// v_x(X, 0) = V sin(n pi (X - xMin) / L) at each particle's reference position X, v_y = 0; the
// displacement stays zero. One mode of the fixed-fixed bar (BarStandingWaveExact).
void applyStandingWaveVelocity(ParticleSet& particles, double xMin, double length, double amplitude, int mode);

}  // namespace impm
