#include "physics/InitialConditions.hpp"

#include <cmath>

namespace impm {

void applyStandingWaveVelocity(ParticleSet& particles, double xMin, double length, double amplitude, int mode) {
  const double k = mode * std::acos(-1.0) / length;
  auto x0 = particles.x0;
  auto v = particles.v;
  Kokkos::parallel_for(
      "standing_wave_velocity", Kokkos::RangePolicy<ExecutionSpace>(0, particles.count), KOKKOS_LAMBDA(int p) {
        v(p, 0) = amplitude * std::sin(k * (x0(p, 0) - xMin));
        for (int d = 1; d < (int)v.extent(1); ++d) v(p, d) = 0.0;
      });
  Kokkos::fence();
}

void applyManufacturedVelocity(ParticleSet& particles, const AxisAlignedManufactured& field) {
  auto x0 = particles.x0;
  auto v = particles.v;
  const int dim = particles.dim;
  Kokkos::parallel_for(
      "manufactured_velocity", Kokkos::RangePolicy<ExecutionSpace>(0, particles.count), KOKKOS_LAMBDA(int p) {
        double X[3] = {0, 0, 0};
        for (int d = 0; d < dim; ++d) X[d] = x0(p, d);
        for (int d = 0; d < dim; ++d) v(p, d) = field.velocity(X, 0.0, d);
      });
  Kokkos::fence();
}

}  // namespace impm
