// Small-strain isotropic linear elasticity in plane strain or plane stress, and the stress
// update kernel that applies it to a particle strain increment.
#pragma once

#include <cmath>
#include <string>

#include "core/ParticleSet.hpp"

namespace impm {

enum class PlaneCondition { PlaneStrain, PlaneStress };

struct LinearElastic {
  double E = 1.0, nu = 0.0, density = 1.0;
  PlaneCondition plane = PlaneCondition::PlaneStrain;

  // In-plane constants: sigma = D eps with D = [[c11, c12, 0], [c12, c11, 0], [0, 0, c33]]
  // acting on (eps_xx, eps_yy, 2 eps_xy).
  KOKKOS_INLINE_FUNCTION double c11() const {
    return plane == PlaneCondition::PlaneStrain ? E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) : E / (1 - nu * nu);
  }
  KOKKOS_INLINE_FUNCTION double c12() const {
    return plane == PlaneCondition::PlaneStrain ? E * nu / ((1 + nu) * (1 - 2 * nu)) : E * nu / (1 - nu * nu);
  }
  KOKKOS_INLINE_FUNCTION double c33() const { return E / (2 * (1 + nu)); }
  // sigma_zz per unit in-plane volumetric strain (plane strain: lambda; plane stress: 0).
  KOKKOS_INLINE_FUNCTION double czz() const {
    return plane == PlaneCondition::PlaneStrain ? E * nu / ((1 + nu) * (1 - 2 * nu)) : 0.0;
  }

  // The modulus a 1D bar of this 2D model sees: E in plane stress, E/(1 - nu^2) in plane strain.
  double barModulus() const { return plane == PlaneCondition::PlaneStress ? E : E / (1 - nu * nu); }
  // Fastest elastic wave (P wave) speed of the 2D model, for the explicit stable time step.
  double pWaveSpeed() const { return std::sqrt(c11() / density); }
  std::string planeName() const { return plane == PlaneCondition::PlaneStrain ? "plane strain" : "plane stress"; }
};

// One particle's update from a displacement-gradient increment G = scale * gradient:
// sigma <- sigma + D sym(G), F <- (I + G) F, V = V0 det F. Written once, used by the
// stress-update kernel and inside the fused grid-to-particle kernel.
struct StressIncrement {
  double c11, c12, c33, czz;
  explicit StressIncrement(const LinearElastic& m) : c11(m.c11()), c12(m.c12()), c33(m.c33()), czz(m.czz()) {}

  KOKKOS_INLINE_FUNCTION void operator()(const ParticleSet& ps, int p, double dxx, double dxy, double dyx,
                                         double dyy) const {
    const double gxy = dxy + dyx;  // engineering shear strain increment
    ps.stress(p, 0) += c11 * dxx + c12 * dyy;
    ps.stress(p, 1) += c12 * dxx + c11 * dyy;
    ps.stress(p, 2) += c33 * gxy;
    ps.stress(p, 3) += czz * (dxx + dyy);
    const double f00 = ps.F(p, 0, 0), f01 = ps.F(p, 0, 1), f10 = ps.F(p, 1, 0), f11 = ps.F(p, 1, 1);
    const double n00 = (1 + dxx) * f00 + dxy * f10, n01 = (1 + dxx) * f01 + dxy * f11;
    const double n10 = dyx * f00 + (1 + dyy) * f10, n11 = dyx * f01 + (1 + dyy) * f11;
    ps.F(p, 0, 0) = n00; ps.F(p, 0, 1) = n01; ps.F(p, 1, 0) = n10; ps.F(p, 1, 1) = n11;
    ps.volume(p) = ps.volume0(p) * (n00 * n11 - n01 * n10);
  }
};

// Applies StressIncrement to every particle with G = scale * ps.gradient (explicit: grad v, dt).
template <class ExecSpace>
void updateStress(const ParticleSet& ps, const LinearElastic& mat, double scale) {
  const StressIncrement inc(mat);
  auto L = ps.gradient;
  Kokkos::parallel_for(
      "stress_update", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        inc(ps, p, scale * L(p, 0, 0), scale * L(p, 0, 1), scale * L(p, 1, 0), scale * L(p, 1, 1));
      });
}

}  // namespace impm
