#include "physics/InitialConditions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

double applyGeostaticStress(ParticleSet& particles, const Materials& materials, int body, double gravity,
                            double surfaceY, double k0) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles.x);
  auto ids = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles.body);
  auto mat = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles.material);
  auto stress = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles.stress);
  const bool withHistory = particles.hasHistory();
  auto history = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles.history);
  const int dim = particles.dim;
  const bool planeStress = materials.plane() == PlaneCondition::PlaneStress;
  double highest = -std::numeric_limits<double>::infinity();
  for (int p = 0; p < particles.count; ++p) {
    if (ids(p) != body) continue;
    const double y = x(p, 1);
    highest = std::max(highest, y);
    const int m = mat(p);
    const double vertical = -materials.density(m) * gravity * (surfaceY - y), horizontal = k0 * vertical;
    const double outOfPlane = dim == 3 || !planeStress ? horizontal : 0.0;
    for (int c = 0; c < stressComponents(dim); ++c) stress(p, c) = 0.0;
    stress(p, 0) = horizontal;
    stress(p, 1) = vertical;
    stress(p, 3) = outOfPlane;  // 2D: sigma_zz; 3D: the stored layout's zz
    if (withHistory && materials.law().hasHistory(m)) {
      // b_e = exp(2 eps_e) on the axes, eps_e = tr(tau) / (9 K) + dev(tau) / (2 mu), tau = sigma at J = 1.
      const MaterialParameters& q = materials.parameters(m);
      const double mu = q.E / (2 * (1 + q.nu)), K = q.E / (3 * (1 - 2 * q.nu));
      const double principal[3] = {horizontal, vertical, outOfPlane}, trace = horizontal + vertical + outOfPlane;
      const int slot[3] = {0, 1, 3};  // xx, yy, zz of the stored 3 x 3 layout
      for (int a = 0; a < 3; ++a)
        history(p, slot[a]) = std::exp(2.0 * (trace / (9 * K) + (principal[a] - trace / 3) / (2 * mu)));
    }
  }
  Kokkos::deep_copy(particles.stress, stress);
  if (withHistory) Kokkos::deep_copy(particles.history, history);
  return highest;
}

}  // namespace impm
