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

// sigma_p <- sigma_p + D * sym(scale * gradient_p); F_p <- (I + scale * gradient_p) F_p and
// V_p = V0_p det F_p. Explicit: gradient = grad v, scale = dt.
template <class ExecSpace>
void updateStress(const ParticleSet& ps, const LinearElastic& mat, double scale) {
  auto L = ps.gradient; auto s = ps.stress; auto F = ps.F; auto V = ps.volume; auto V0 = ps.volume0;
  const double c11 = mat.c11(), c12 = mat.c12(), c33 = mat.c33(), czz = mat.czz();
  Kokkos::parallel_for(
      "stress_update", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        const double dxx = scale * L(p, 0, 0), dxy = scale * L(p, 0, 1);
        const double dyx = scale * L(p, 1, 0), dyy = scale * L(p, 1, 1);
        const double gxy = dxy + dyx;  // engineering shear strain increment
        s(p, 0) += c11 * dxx + c12 * dyy;
        s(p, 1) += c12 * dxx + c11 * dyy;
        s(p, 2) += c33 * gxy;
        s(p, 3) += czz * (dxx + dyy);
        const double f00 = F(p, 0, 0), f01 = F(p, 0, 1), f10 = F(p, 1, 0), f11 = F(p, 1, 1);
        F(p, 0, 0) = (1 + dxx) * f00 + dxy * f10;
        F(p, 0, 1) = (1 + dxx) * f01 + dxy * f11;
        F(p, 1, 0) = dyx * f00 + (1 + dyy) * f10;
        F(p, 1, 1) = dyx * f01 + (1 + dyy) * f11;
        V(p) = V0(p) * (F(p, 0, 0) * F(p, 1, 1) - F(p, 0, 1) * F(p, 1, 0));
      });
}

}  // namespace impm
