// Compressible neo-Hookean hyperelasticity, the form with ln J (Wallstedt & Guilkey, JCP 227,
// 2008; Simo & Hughes 1998, eq. 9.2.6 ff.):
//   W(F) = mu/2 (tr b - 3) - mu ln J + lambda/2 (ln J)^2,   b = F F^T, J = det F,
//   sigma = (mu (b - I) + lambda ln J I) / J.
// The stress is a function of F alone (no rate, no history), so it is exact for any step size.
// In 2D the model is plane strain (F_zz = 1): b_zz = 1 and sigma_zz = lambda ln J / J. The
// spatial tangent, for K = int B^T c B dv on the current configuration, is
//   c = (lambda I (x) I + 2 (mu - lambda ln J) II) / J,
// II the symmetric fourth-order identity; the geometric term sigma_jl delta_ik is added by the
// stiffness kernel.
#pragma once

#include <cmath>

#include "core/ParticleSet.hpp"
#include "core/SmallMatrix.hpp"
#include "physics/materials/LinearElasticModel.hpp"

namespace impm {

struct NeoHookeanModel {
  double lambda, mu;

  // Cauchy stress at deformation gradient F, in the stored layout.
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void stress(const double (&F)[Dim][Dim], double* s) const {
    using SL = StressLayout<Dim>;
    const double J = determinant<Dim>(F);
    const double lnJ = std::log(J), invJ = 1.0 / J;
    for (int i = 0; i < Dim; ++i)
      for (int j = i; j < Dim; ++j) {
        double b = 0;
        for (int k = 0; k < Dim; ++k) b += F[i][k] * F[j][k];
        const double identity = i == j ? 1.0 : 0.0;
        s[SL::index(i, j)] = (mu * (b - identity) + lambda * lnJ * identity) * invJ;
      }
    if constexpr (Dim == 2) s[3] = lambda * lnJ * invJ;  // plane strain: b_zz = 1
  }

  // W / J: the energy per unit current volume (the caller multiplies by the current volume).
  template <int Dim>
  KOKKOS_INLINE_FUNCTION double energyDensity(const double (&F)[Dim][Dim]) const {
    const double J = determinant<Dim>(F), lnJ = std::log(J);
    double trb = Dim == 2 ? 1.0 : 0.0;  // plane strain: F_zz = 1
    for (int i = 0; i < Dim; ++i)
      for (int k = 0; k < Dim; ++k) trb += F[i][k] * F[i][k];
    return (0.5 * mu * (trb - 3.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ) / J;
  }

  template <int Dim>
  KOKKOS_INLINE_FUNCTION void tangent(double J, double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    const double muPrime = mu - lambda * std::log(J);
    isotropicTangent<Dim>((lambda + 2 * muPrime) / J, lambda / J, muPrime / J, D);
  }
};

}  // namespace impm
