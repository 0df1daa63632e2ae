// Initial particle states other than rest (Initial Conditions in the deck).
#pragma once

#include "core/ParticleSet.hpp"
#include "physics/Materials.hpp"
#include "physics/ManufacturedSolution.hpp"

namespace impm {

// v_x(X, 0) = V sin(n pi (X - xMin) / L) at each particle's reference position X, v_y = 0; the
// displacement stays zero. One mode of the fixed-fixed bar (BarStandingWaveExact).
void applyStandingWaveVelocity(ParticleSet& particles, double xMin, double length, double amplitude, int mode);

// v(X, 0) of the manufactured solution at each particle's reference position; u stays zero (the
// field starts undeformed).
void applyManufacturedVelocity(ParticleSet& particles, const AxisAlignedManufactured& field);

// The geostatic stress of the particles of body `body` (ParticleSet::body): the vertical stress of
// the overburden, sigma_yy = -rho g (surfaceY - y) (compression negative), and the horizontal
// ones k0 times it (plane stress: sigma_zz = 0), with rho the particle's material density and g
// > 0 the gravity along -y. For the finite-strain elastoplastic models (history: b_e), b_e holds
// the elastic log strains of that stress (the body starts at F = I, stressed); the linear law
// takes the stress as its initial state. Returns the largest y of the body's particles on this
// rank (-inf without any), for the caller's check against surfaceY.
double applyGeostaticStress(ParticleSet& particles, const Materials& materials, int body, double gravity,
                            double surfaceY, double k0);

}  // namespace impm
