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

#include "core/ParticleSet.hpp"
#include "core/SmallMatrix.hpp"
#include "physics/materials/LinearElasticModel.hpp"

namespace impm {

// Eigen-decomposition of a symmetric 3 x 3 matrix A = V diag(w) V^T by cyclic Jacobi rotations
// (quadratically convergent; a few sweeps reach round-off). A is overwritten.
KOKKOS_INLINE_FUNCTION void symmetricEigen3(double (&A)[3][3], double (&w)[3], double (&V)[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) V[i][j] = i == j ? 1.0 : 0.0;
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = A[0][1] * A[0][1] + A[0][2] * A[0][2] + A[1][2] * A[1][2];
    const double diag = A[0][0] * A[0][0] + A[1][1] * A[1][1] + A[2][2] * A[2][2];
    if (off <= 1e-32 * diag || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (A[p][q] == 0.0) continue;
        const double theta = 0.5 * (A[q][q] - A[p][p]) / A[p][q];
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A <- A J
          const double akp = A[k][p], akq = A[k][q];
          A[k][p] = c * akp - s * akq;
          A[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // A <- J^T A
          const double apk = A[p][k], aqk = A[q][k];
          A[p][k] = c * apk - s * aqk;
          A[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {  // V <- V J
          const double vkp = V[k][p], vkq = V[k][q];
          V[k][p] = c * vkp - s * vkq;
          V[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int i = 0; i < 3; ++i) w[i] = A[i][i];
}

// The return map is long (an eigen-decomposition, logs and exps): kept out of line, so that the
// kernels that can call it (g2p with the stress update, the implicit residual) do not carry its
// code on the linear-elastic path. (Measured: no difference beyond the 5% run-to-run noise.)
#if defined(__GNUC__) && !defined(__CUDA_ARCH__)
#define IMPM_OUT_OF_LINE __attribute__((noinline))
#else
#define IMPM_OUT_OF_LINE
#endif

struct J2PlasticityModel {
  double lambda, mu, yieldStress, hardening;
  static constexpr int historyCount = 7;  // b_e (6, stored layout) and alpha

  // The initial history: b_e = I, alpha = 0.
  KOKKOS_INLINE_FUNCTION static void initialHistory(double* h) {
    h[0] = 1; h[1] = 1; h[2] = 0; h[3] = 1; h[4] = 0; h[5] = 0; h[6] = 0;
  }

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
    using SL3 = StressLayout<3>;
    double f[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) f[i][j] += G[i][j];
    double be[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) be[i][j] = h[SL3::index(i, j)];
    double fbe[3][3], trial[3][3];
    multiply<3>(f, be, fbe);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double t = 0;
        for (int k = 0; k < 3; ++k) t += fbe[i][k] * f[j][k];
        trial[i][j] = t;
      }
    double b[3];
    symmetricEigen3(trial, b, r.n);
    for (int a = 0; a < 3; ++a) r.eps[a] = r.epsTrial[a] = 0.5 * std::log(b[a]);
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
    using SL3 = StressLayout<3>;
    Return r;
    returnMap<Dim>(G, h, r);
    h[6] += 0.816496580927726 * r.dgamma;  // alpha += sqrt(2/3) dgamma
    const double invJ = 1.0 / J;
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        double sij = 0, bij = 0;
        for (int a = 0; a < 3; ++a) {
          sij += r.tau[a] * r.n[i][a] * r.n[j][a];
          bij += std::exp(2.0 * r.eps[a]) * r.n[i][a] * r.n[j][a];
        }
        h[SL3::index(i, j)] = bij;
        if (i < Dim && j < Dim) s[StressLayout<Dim>::index(i, j)] = sij * invJ;
      }
    if constexpr (Dim == 2) {  // sigma_zz: z is principal (f_zz = 1, b_e xz = yz = 0)
      double szz = 0;
      for (int a = 0; a < 3; ++a) szz += r.tau[a] * r.n[2][a] * r.n[2][a];
      s[3] = szz * invJ;
    }
  }

  // The elastic (Hencky) stored energy per unit current volume, from b_e.
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION double energyDensity(const double* h, double J) const {
    using SL3 = StressLayout<3>;
    double be[3][3], b[3], n[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) be[i][j] = h[SL3::index(i, j)];
    symmetricEigen3(be, b, n);
    double eps[3], volumetric = 0;
    for (int a = 0; a < 3; ++a) {
      eps[a] = 0.5 * std::log(b[a]);
      volumetric += eps[a];
    }
    double dev2 = 0;
    for (int a = 0; a < 3; ++a) dev2 += (eps[a] - volumetric / 3.0) * (eps[a] - volumetric / 3.0);
    const double bulk = lambda + 2.0 * mu / 3.0;
    return (mu * dev2 + 0.5 * bulk * volumetric * volumetric) / J;
  }

  // The elastic tangent, for callers without the particle's state.
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void tangent(double J, double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    isotropicTangent<Dim>((lambda + 2 * mu) / J, lambda / J, mu / J, D);
  }

  // The consistent (algorithmic) spatial tangent of the step f = I + G from the history h (b_e^n,
  // alpha_n): D = c / J with c the derivative of the Lie (Truesdell) rate of tau, as the
  // neo-Hookean tangent, so that with the stiffness kernel's geometric term the matrix is the
  // exact derivative of the internal force. tau is an isotropic function of b_e^trial; in its
  // principal frame, for a symmetric rate d (db^trial = d b + b d):
  //   normal:  c_AABB = a_AB - 2 tau_A delta_AB,   a_AB = d tau_A / d eps_B^trial
  //            = K + 2 mu beta (delta_AB - 1/3) - 2 mu gammaBar nu_A nu_B,
  //            beta = 1 - 2 mu dgamma / q^trial, gammaBar = 1 / (1 + H / (3 mu)) - 2 mu dgamma / q^trial
  //            (Simo & Hughes Box 3.2; elastic: beta = 1, gammaBar = 0);
  //   shear:   (c : d)_AB = (2 mu beta x coth x - tau_A - tau_B) d_AB,  x = eps_A^trial - eps_B^trial,
  //            from (tau_A - tau_B) / (b_A - b_B) (b_A + b_B) with tau_A - tau_B = 2 mu beta x
  //            (smooth as b_A -> b_B: x coth x -> 1).
  // A trial state on the yield surface to within round-off (the step's start, G = 0, after a
  // plastic step) counts as loading: dgamma = 0 there gives the continuum elastoplastic tangent,
  // the one-sided derivative of a step that goes on yielding.
  template <int Dim>
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION void tangent(const double (&G)[Dim][Dim], double J, const double* h,
                                                double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    using SL = StressLayout<Dim>;
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
    double normal[3][3], shear[3][3];  // principal frame: c_AABB, and the factors of d_AB (A != B)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        normal[a][b] = bulk + 2.0 * mu * beta * ((a == b ? 1.0 : 0.0) - 1.0 / 3.0) - 2.0 * mu * gammaBar * nu[a] * nu[b] -
                       (a == b ? 2.0 * r.tau[a] : 0.0);
        const double x = r.epsTrial[a] - r.epsTrial[b];
        const double xCothX = std::fabs(x) < 1e-6 ? 1.0 + x * x / 3.0 : x / std::tanh(x);
        shear[a][b] = 2.0 * mu * beta * xCothX - r.tau[a] - r.tau[b];
      }
    const double invJ = 1.0 / J;
    for (int v = 0; v < SL::voigt; ++v) {
      // The unit rate of Voigt strain v (engineering shear: d_kl = d_lk = 1/2) in the principal frame.
      const int k = SL::first(v), l = SL::second(v);
      double dp[3][3];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) dp[a][b] = 0.5 * (r.n[k][a] * r.n[l][b] + r.n[l][a] * r.n[k][b]);
      double op[3][3];  // (c : d) in the principal frame
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          if (a == b) {
            op[a][a] = 0;
            for (int e = 0; e < 3; ++e) op[a][a] += normal[a][e] * dp[e][e];
          } else {
            op[a][b] = shear[a][b] * dp[a][b];
          }
        }
      for (int w = 0; w < SL::voigt; ++w) {
        const int i = SL::first(w), j = SL::second(w);
        double cij = 0;
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) cij += r.n[i][a] * op[a][b] * r.n[j][b];
        D[w][v] = cij * invJ;
      }
    }
  }
};

}  // namespace impm
