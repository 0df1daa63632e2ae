// The particle update from a displacement-gradient increment G (explicit: dt grad v; implicit:
// grad u of the step): the stress through the material law, the deformation gradient
// F <- (I + G) F and the volume V = V0 det F. Templated on the law (physics/LinearElastic.hpp
// is one): the law sees only its material id, the old stress and G. The FE reference keeps its
// Gauss points' volumes (small strain on the undeformed mesh): updateVolume = false.
#pragma once

#include "core/ParticleSet.hpp"

namespace impm {

template <class Law>
KOKKOS_INLINE_FUNCTION void updateParticleState(const ParticleSet& ps, const Law& law, int p, double dxx, double dxy,
                                                double dyx, double dyy, bool updateVolume = true) {
  double s[4] = {ps.stress(p, 0), ps.stress(p, 1), ps.stress(p, 2), ps.stress(p, 3)};
  law.stress(ps.material(p), s, dxx, dxy, dyx, dyy, s);
  for (int c = 0; c < 4; ++c) ps.stress(p, c) = s[c];
  const double f00 = ps.F(p, 0, 0), f01 = ps.F(p, 0, 1), f10 = ps.F(p, 1, 0), f11 = ps.F(p, 1, 1);
  const double n00 = (1 + dxx) * f00 + dxy * f10, n01 = (1 + dxx) * f01 + dxy * f11;
  const double n10 = dyx * f00 + (1 + dyy) * f10, n11 = dyx * f01 + (1 + dyy) * f11;
  ps.F(p, 0, 0) = n00; ps.F(p, 0, 1) = n01; ps.F(p, 1, 0) = n10; ps.F(p, 1, 1) = n11;
  if (updateVolume) ps.volume(p) = ps.volume0(p) * (n00 * n11 - n01 * n10);
}

// Every particle with G = scale * ps.gradient (explicit: grad v and dt; implicit: grad u and 1).
template <class ExecSpace, class Law>
void updateStress(const ParticleSet& ps, const Law& law, double scale, bool updateVolume = true) {
  auto L = ps.gradient;
  Kokkos::parallel_for(
      "stress_update", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        updateParticleState(ps, law, p, scale * L(p, 0, 0), scale * L(p, 0, 1), scale * L(p, 1, 0), scale * L(p, 1, 1),
                              updateVolume);
      });
}

}  // namespace impm
