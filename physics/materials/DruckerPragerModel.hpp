// Drucker-Prager elastoplasticity at finite strain: the Hencky elasticity and multiplicative split
// of the J2 model (physics/materials/HenckyElasticity.hpp), with a pressure-dependent cone, a
// non-associated flow through the dilatancy angle, linear cohesion hardening or softening down to
// a residual cohesion, and the return to the cone or to its apex (de Souza Neto, Peric & Owen 2008,
// section 8.3 and Box 8.5, written in the principal Kirchhoff stresses and elastic log strains).
//
// Tension is positive; p = tr(tau) / 3 and sqrt(J2) = |dev tau| / sqrt(2):
//   yield      Phi = sqrt(J2) + eta p - xi c(alpha),      c = max(c_r, c_0 + H alpha)
//   potential  Psi = sqrt(J2) + etaBar p
// with (eta, xi) from the friction angle phi and etaBar from the dilatancy angle psi by the match
// to Mohr-Coulomb the deck names (the `Cone`):
//   Plane Strain   eta = 3 tan(phi) / sqrt(9 + 12 tan^2 phi),   xi = 3 / sqrt(9 + 12 tan^2 phi)
//                  (the Mohr-Coulomb collapse load in plane strain, for associated flow)
//   Outer          eta = 6 sin(phi) / (sqrt(3) (3 - sin phi)),  xi = 6 cos(phi) / (sqrt(3) (3 - sin phi))
//                  (the compressive meridian: triaxial compression)
//   Inner          the same with 3 + sin(phi) (the extensive meridian: triaxial extension)
// The cone return (sqrt(J2) - mu dgamma >= 0):
//   dgamma = Phi^trial / (mu + K eta etaBar + xi^2 H),  dev tau = (1 - mu dgamma / sqrt(J2^trial)) dev tau^trial,
//   p = p^trial - K etaBar dgamma,  alpha += xi dgamma;
// otherwise the apex return, p = (xi / eta) c, with the plastic volumetric strain
//   dev_v = (p^trial - (xi / eta) c_n) / (K + (xi / eta) (xi / etaBar) H),  alpha += (xi / etaBar) dev_v
// (etaBar = 0: dev_v = (p^trial - (xi / eta) c_n) / K, alpha unchanged). c is piecewise linear in
// alpha, so both returns are exact in one step: a return that would soften below c_r is redone
// at c_r with H = 0. With c = 0 the apex is the stress-free state, the tension limit of a
// cohesionless soil.
//
// History per particle: b_e (6, stored layout) and alpha, as J2.
#pragma once

#include <cmath>

#include "physics/materials/HenckyElasticity.hpp"

namespace impm {

// The Mohr-Coulomb match of the cone (the deck's 'Cone').
enum class DruckerPragerCone { PlaneStrain = 0, Outer = 1, Inner = 2 };

struct DruckerPragerModel {
  double lambda, mu;
  double eta, etaBar, xi;                 // the cone's slopes (from the friction and dilatancy angles)
  double cohesion, hardening, residual;   // c_0, H (negative: softening) and c_r
  static constexpr int historyCount = 7;  // b_e (6, stored layout) and alpha

  // The slopes of the cone matched to Mohr-Coulomb with friction angle `angle` (radians): the
  // pressure slope (eta, or etaBar from the dilatancy angle) and xi.
  static void coneSlopes(DruckerPragerCone cone, double angle, double& slope, double& xi) {
    if (cone == DruckerPragerCone::PlaneStrain) {
      const double t = std::tan(angle), root = std::sqrt(9.0 + 12.0 * t * t);
      slope = 3.0 * t / root;
      xi = 3.0 / root;
    } else {
      const double s = std::sin(angle),
                   denominator = std::sqrt(3.0) * (cone == DruckerPragerCone::Outer ? 3.0 - s : 3.0 + s);
      slope = 6.0 * s / denominator;
      xi = 6.0 * std::cos(angle) / denominator;
    }
  }

  KOKKOS_INLINE_FUNCTION static void initialHistory(double* h) { henckyInitialHistory(h); }

  enum : int { Elastic = 0, Cone = 1, Apex = 2 };
  // One step's trial state and return, shared by the stress update and the tangent.
  struct Return {
    double n[3][3], epsTrial[3], eps[3], tau[3];
    double devTrial[3], devNorm;  // dev eps^trial and |dev eps^trial|
    double phi, scale;            // Phi^trial, and a stress scale for "on the surface" tests
    double dgamma, hEffective;    // the cone's multiplier; the slope of c(alpha) at the return
    int regime;
  };

  KOKKOS_INLINE_FUNCTION double bulk() const { return lambda + 2.0 * mu / 3.0; }

  template <int Dim>
  KOKKOS_INLINE_FUNCTION void returnMap(const double (&G)[Dim][Dim], const double* h, Return& r, double& dAlpha) const {
    henckyTrial<Dim>(G, h, r.n, r.epsTrial);
    const double K = bulk(), root2 = 1.4142135623730951;
    const double volumetric = r.epsTrial[0] + r.epsTrial[1] + r.epsTrial[2];
    double e2 = 0;
    for (int a = 0; a < 3; ++a) {
      r.devTrial[a] = r.epsTrial[a] - volumetric / 3.0;
      e2 += r.devTrial[a] * r.devTrial[a];
    }
    r.devNorm = std::sqrt(e2);
    const double sqrtJ2 = root2 * mu * r.devNorm, pTrial = K * volumetric;
    double c = cohesion + hardening * h[kHenckyInternal], H = hardening;
    if (c <= residual) {
      c = residual;
      H = 0.0;
    }
    r.phi = sqrtJ2 + eta * pTrial - xi * c;
    r.scale = sqrtJ2 + std::fabs(eta * pTrial) + xi * c;
    r.regime = Elastic;
    r.dgamma = 0.0;
    r.hEffective = H;
    dAlpha = 0.0;
    double p = pTrial, shrink = 1.0;
    if (r.phi > 0.0) {
      double dgamma = r.phi / (mu + K * eta * etaBar + xi * xi * H);
      double hCone = H;
      if (H != 0.0 && c + H * xi * dgamma < residual) {  // softens past c_r: the return at c_r
        hCone = 0.0;
        dgamma = (sqrtJ2 + eta * pTrial - xi * residual) / (mu + K * eta * etaBar);
      }
      if (sqrtJ2 - mu * dgamma >= 0.0) {
        r.regime = Cone;
        r.dgamma = dgamma;
        r.hEffective = hCone;
        shrink = sqrtJ2 > 0.0 ? 1.0 - mu * dgamma / sqrtJ2 : 0.0;
        p = pTrial - K * etaBar * dgamma;
        dAlpha = xi * dgamma;
      } else {
        r.regime = Apex;
        shrink = 0.0;
        const double beta = xi / eta;
        double dVolumetric;
        if (etaBar > 0.0) {
          const double alphaPerVolume = xi / etaBar;
          dVolumetric = (pTrial - beta * c) / (K + alphaPerVolume * beta * H);
          if (H != 0.0 && c + H * alphaPerVolume * dVolumetric < residual) {
            H = 0.0;
            dVolumetric = (pTrial - beta * residual) / K;
          }
          dAlpha = alphaPerVolume * dVolumetric;
        } else {
          H = 0.0;
          dVolumetric = (pTrial - beta * c) / K;
        }
        r.hEffective = H;
        p = pTrial - K * dVolumetric;
      }
    }
    for (int a = 0; a < 3; ++a) {
      r.tau[a] = p + 2.0 * mu * shrink * r.devTrial[a];
      r.eps[a] = shrink * r.devTrial[a] + p / (3.0 * K);
    }
  }

  // Cauchy stress after the relative deformation gradient f = I + G, with J = det F (total);
  // `h` (b_e, alpha) is read and updated in place.
  template <int Dim>
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION void stress(const double (&G)[Dim][Dim], double J, double* h, double* s) const {
    Return r;
    double dAlpha;
    returnMap<Dim>(G, h, r, dAlpha);
    if (r.regime == Elastic) {  // keep b_e^trial's eigenvalues as they are (no log-exp round trip)
      for (int a = 0; a < 3; ++a) r.eps[a] = r.epsTrial[a];
    }
    h[kHenckyInternal] += dAlpha;
    henckyStore<Dim>(r.n, r.tau, r.eps, J, h, s);
  }

  IMPM_OUT_OF_LINE KOKKOS_FUNCTION double energyDensity(const double* h, double J) const {
    return henckyEnergyDensity(lambda, mu, h, J);
  }

  // The elastic tangent, for callers without the particle's state.
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void tangent(double J, double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    isotropicTangent<Dim>((lambda + 2 * mu) / J, lambda / J, mu / J, D);
  }

  // The consistent tangent of the step f = I + G from the history h (henckyTangent), from the
  // principal derivative a_AB = d tau_A / d eps_B^trial (de Souza Neto et al. section 8.3, in
  // principal form; n = dev eps^trial / |dev eps^trial|, A = 1 / (mu + K eta etaBar + xi^2 H)):
  //   cone:  a = 2 mu b (I - 1/3 1 (x) 1) + 2 mu (dgamma / (sqrt2 |dev eps^trial|) - mu A) n (x) n
  //              - sqrt2 mu A K (eta n (x) 1 + etaBar 1 (x) n) + K (1 - K eta etaBar A) 1 (x) 1,
  //          b = 1 - dgamma / (sqrt2 |dev eps^trial|), and tau_A - tau_B = 2 mu b x;
  //   apex:  a = K (1 - K / (K + (xi / eta) (xi / etaBar) H)) 1 (x) 1 (0 without hardening), b = 0.
  // As for J2, a trial state on the cone to within round-off (the step's start after a plastic
  // step) counts as loading, with the continuum tangent (dgamma = 0); at the apex it counts as
  // unloading (the elastic tangent), since compression, the usual next step, unloads it.
  template <int Dim>
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION void tangent(const double (&G)[Dim][Dim], double J, const double* h,
                                                double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    Return r;
    double dAlpha;
    returnMap<Dim>(G, h, r, dAlpha);
    const double K = bulk(), root2 = 1.4142135623730951;
    const bool onCone = r.phi > -1e-8 * r.scale && root2 * mu * r.devNorm > 1e-8 * r.scale;
    const int regime = r.regime != Elastic ? r.regime : onCone ? Cone : Elastic;
    double dTau[3][3], twoMuBeta = 2.0 * mu;
    if (regime == Elastic) {
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) dTau[a][b] = K + 2.0 * mu * ((a == b ? 1.0 : 0.0) - 1.0 / 3.0);
    } else if (regime == Apex) {
      const double volumetric =
          etaBar > 0.0 && r.hEffective != 0.0 ? K * (1.0 - K / (K + (xi / eta) * (xi / etaBar) * r.hEffective)) : 0.0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) dTau[a][b] = volumetric;
      twoMuBeta = 0.0;
    } else {
      const double A = 1.0 / (mu + K * eta * etaBar + xi * xi * r.hEffective);
      const double ratio = r.dgamma / (root2 * r.devNorm), beta = 1.0 - ratio;
      double n[3];
      for (int a = 0; a < 3; ++a) n[a] = r.devTrial[a] / r.devNorm;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          dTau[a][b] = 2.0 * mu * beta * ((a == b ? 1.0 : 0.0) - 1.0 / 3.0) +
                       2.0 * mu * (ratio - mu * A) * n[a] * n[b] - root2 * mu * A * K * (eta * n[a] + etaBar * n[b]) +
                       K * (1.0 - K * eta * etaBar * A);
      twoMuBeta = 2.0 * mu * beta;
    }
    henckyTangent<Dim>(r.n, r.epsTrial, r.tau, dTau, twoMuBeta, J, D);
  }
};

}  // namespace impm
