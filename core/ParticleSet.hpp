// Material points as Kokkos Views (structure of arrays), on the node's memory space.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

#include "core/Types.hpp"

namespace impm {

struct ParticleSet {
  using Vec2 = Kokkos::View<double* [2], Kokkos::LayoutRight, DeviceType>;
  using Mat2 = Kokkos::View<double* [2][2], Kokkos::LayoutRight, DeviceType>;
  using Scal = Kokkos::View<double*, DeviceType>;
  using Stress = Kokkos::View<double* [4], Kokkos::LayoutRight, DeviceType>;  // xx, yy, xy, zz

  int count = 0;
  Vec2 x;          // current position
  Vec2 x0;         // reference position (displacement u = x - x0)
  Vec2 v;          // velocity
  Vec2 a;          // acceleration (implicit Newmark and output)
  Vec2 halfSize;   // half size of the particle domain (GIMP); uGIMP keeps it fixed
  Scal mass;
  Scal volume0;    // reference volume
  Scal volume;     // current volume, volume0 * det F
  Stress stress;   // Cauchy stress
  Mat2 F;          // deformation gradient
  Mat2 gradient;   // scratch: gradient of a grid field at the particle (velocity or displacement)
  // Displacement of particles that do not move (the FE reference's Gauss points); empty
  // otherwise, where the displacement is x - x0.
  Vec2 u;

  bool fixedPositions() const { return u.extent(0) > 0; }

  ParticleSet() = default;
  explicit ParticleSet(int n) : count(n) {
    x = Vec2("x", n); x0 = Vec2("x0", n); v = Vec2("v", n); a = Vec2("a", n);
    halfSize = Vec2("halfSize", n);
    mass = Scal("mass", n); volume0 = Scal("volume0", n); volume = Scal("volume", n);
    stress = Stress("stress", n); F = Mat2("F", n); gradient = Mat2("gradient", n);
    auto Fv = F;
    Kokkos::parallel_for("init_F", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int p) {
      Fv(p, 0, 0) = 1.0; Fv(p, 1, 1) = 1.0; Fv(p, 0, 1) = 0.0; Fv(p, 1, 0) = 0.0;
    });
  }

  // Bytes held per particle by the views above.
  static constexpr size_t bytesPerParticle() {
    return sizeof(double) * (2 * 5 + 3 + 4 + 4 + 4);
  }
};

// The heaviest particle's mass over all ranks (the reference for void grid nodes).
inline double heaviestParticleMass(const ParticleSet& ps, const Teuchos::Comm<int>& comm) {
  double local = 0.0, global = 0.0;
  auto m = ps.mass;
  Kokkos::parallel_reduce(
      "heaviest_particle", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, double& mx) { mx = m(p) > mx ? m(p) : mx; }, Kokkos::Max<double>(local));
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, local, Teuchos::outArg(global));
  return global;
}

}  // namespace impm
