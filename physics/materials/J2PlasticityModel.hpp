// J2 (von Mises) elastoplasticity at finite strain, after Simo (1992) and Simo & Hughes (1998,
// Box 9.1): the multiplicative split F = F_e F_p, a Hencky (logarithmic) elastic law in the
// principal axes of the elastic left Cauchy-Green tensor b_e, and the radial return on the
// Kirchhoff stress with linear isotropic hardening. With log strains the return map is the
// small-strain one, exactly: for a proportional path it reproduces the small-strain closed form
// in the log strains (test/test_material.cpp checks this).
//
// History per particle (ParticleSet::history): b_e in the stored stress layout (xx, yy, xy, zz,
// yz, xz) and the equivalent plastic strain alpha. One step with relative deformation gradient
// f = I + G:
//   b_e^trial = f b_e^n f^T = sum_A lambda_A^2 n_A (x) n_A,   eps_A = ln lambda_A,
//   tau_A = K tr(eps) + 2 mu dev(eps)_A,   q = |dev tau|,  phi = q - sqrt(2/3) (sigma_y + H alpha),
//   phi > 0:  dgamma = phi / (2 mu + 2/3 H),  dev tau -= 2 mu dgamma nu,  eps -= dgamma nu,
//             alpha += sqrt(2/3) dgamma,   nu = dev tau / q,
//   sigma = tau / J,   b_e^{n+1} = sum_A exp(2 eps_A) n_A (x) n_A.
// In 2D (plane strain) z is a principal direction with f_zz = 1; the 3 x 3 algebra is shared.
// The tangent given to the stiffness (JFNK's preconditioner, and Assembled Newton's matrix) is
// the consistent (algorithmic) one of this return map (Simo 1992; Simo & Hughes Box 3.2 and
// ch. 9; de Souza Neto, Peric & Owen ch. 14), taken at the step's increment G from the stored
// history: the derivative of the Lie rate of tau, so that with the stiffness kernel's geometric
// term the assembled matrix is the exact Jacobian of the internal force and Assembled Newton
// converges quadratically (test_material, test_implicit, test_large_deformation).
#pragma once

#include <cmath>

#include "physics/materials/HenckyElasticity.hpp"

namespace impm {

struct J2PlasticityModel {
  double lambda, mu, yieldStress, hardening;
  static constexpr int historyCount = 7;  // b_e (6, stored layout) and alpha

  // The initial history: b_e = I, alpha = 0.
  KOKKOS_INLINE_FUNCTION static void initialHistory(double* h) { henckyInitialHistory(h); }

  // One step's trial state and return, shared by the stress update and the tangent: the
  // principal directions n (columns) of b_e^trial = f b_e^n f^T, its log strains, q^trial =
  // |dev tau^trial|, the yield function phi of the trial state against the radius
  // sqrt(2/3) (sigma_y + H alpha_n), dgamma (0 unless phi > 0), and after the return the elastic
  // log strains and the principal Kirchhoff stresses.
  struct Return {
    double n[3][3], epsTrial[3], eps[3], tau[3];
    double qTrial, phi, radius, dgamma;
  };

  template <int Dim>
  KOKKOS_INLINE_FUNCTION void returnMap(const double (&G)[Dim][Dim], const double* h, Return& r) const {
    henckyTrial<Dim>(G, h, r.n, r.epsTrial);
    for (int a = 0; a < 3; ++a) r.eps[a] = r.epsTrial[a];
    const double volumetric = r.eps[0] + r.eps[1] + r.eps[2];
    const double bulk = lambda + 2.0 * mu / 3.0;
    double dev[3], q2 = 0;
    for (int a = 0; a < 3; ++a) {
      dev[a] = 2.0 * mu * (r.eps[a] - volumetric / 3.0);
      q2 += dev[a] * dev[a];
    }
    const double q = std::sqrt(q2), root23 = 0.816496580927726;  // sqrt(2/3)
    r.qTrial = q;
    r.radius = root23 * (yieldStress + hardening * h[6]);
    r.phi = q - r.radius;
    r.dgamma = 0.0;
    if (r.phi > 0.0) {
      r.dgamma = r.phi / (2.0 * mu + 2.0 * hardening / 3.0);
      for (int a = 0; a < 3; ++a) {
        const double nu = dev[a] / q;
        dev[a] -= 2.0 * mu * r.dgamma * nu;
        r.eps[a] -= r.dgamma * nu;
      }
    }
    for (int a = 0; a < 3; ++a) r.tau[a] = bulk * volumetric + dev[a];
  }

  // Cauchy stress after the relative deformation gradient f = I + G, with J = det F (total);
  // `h` (b_e, alpha) is read and updated in place.
  template <int Dim>
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION void stress(const double (&G)[Dim][Dim], double J, double* h, double* s) const {
    Return r;
    returnMap<Dim>(G, h, r);
    h[6] += 0.816496580927726 * r.dgamma;  // alpha += sqrt(2/3) dgamma
    henckyStore<Dim>(r.n, r.tau, r.eps, J, h, s);
  }

  // The elastic (Hencky) stored energy per unit current volume, from b_e.
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION double energyDensity(const double* h, double J) const {
    return henckyEnergyDensity(lambda, mu, h, J);
  }

  // The elastic tangent, for callers without the particle's state.
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void tangent(double J, double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    isotropicTangent<Dim>((lambda + 2 * mu) / J, lambda / J, mu / J, D);
  }

  // The consistent (algorithmic) spatial tangent of the step f = I + G from the history h (b_e^n,
  // alpha_n): D = c / J with c the derivative of the Lie (Truesdell) rate of tau, as the
  // neo-Hookean tangent, so that with the stiffness kernel's geometric term the matrix is the
  // exact derivative of the internal force (henckyTangent), from the principal derivative
  //   a_AB = d tau_A / d eps_B^trial = K + 2 mu beta (delta_AB - 1/3) - 2 mu gammaBar nu_A nu_B,
  //   beta = 1 - 2 mu dgamma / q^trial, gammaBar = 1 / (1 + H / (3 mu)) - 2 mu dgamma / q^trial
  //   (Simo & Hughes Box 3.2; elastic: beta = 1, gammaBar = 0), and tau_A - tau_B = 2 mu beta x.
  // A trial state on the yield surface to within round-off (the step's start, G = 0, after a
  // plastic step) counts as loading: dgamma = 0 there gives the continuum elastoplastic tangent,
  // the one-sided derivative of a step that goes on yielding.
  template <int Dim>
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION void tangent(const double (&G)[Dim][Dim], double J, const double* h,
                                                double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    Return r;
    returnMap<Dim>(G, h, r);
    const bool loading = r.phi > -1e-8 * r.radius && r.qTrial > 0.0;
    const double bulk = lambda + 2.0 * mu / 3.0;
    const double ratio = loading ? 2.0 * mu * r.dgamma / r.qTrial : 0.0;
    const double beta = 1.0 - ratio;
    const double gammaBar = loading ? 1.0 / (1.0 + hardening / (3.0 * mu)) - ratio : 0.0;
    const double volumetric = r.epsTrial[0] + r.epsTrial[1] + r.epsTrial[2];
    double nu[3];
    for (int a = 0; a < 3; ++a) nu[a] = loading ? 2.0 * mu * (r.epsTrial[a] - volumetric / 3.0) / r.qTrial : 0.0;
    double dTau[3][3];  // d tau_A / d eps_B^trial
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q)
        dTau[p][q] = bulk + 2.0 * mu * beta * ((p == q ? 1.0 : 0.0) - 1.0 / 3.0) - 2.0 * mu * gammaBar * nu[p] * nu[q];
    henckyTangent<Dim>(r.n, r.epsTrial, r.tau, dTau, 2.0 * mu * beta, J, D);
  }
};

}  // namespace impm
