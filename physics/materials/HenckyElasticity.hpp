// The Hencky (logarithmic) elasticity shared by the finite-strain elastoplastic models (J2,
// Drucker-Prager, Mohr-Coulomb): the multiplicative split F = F_e F_p with the elastic left Cauchy-Green tensor
// b_e as the particle's history, the principal Kirchhoff stresses tau_A = K tr(eps) + 2 mu
// dev(eps)_A of the elastic log strains eps_A = ln lambda_A, and the return maps written in those
// principal axes, where they are the small-strain ones exactly (Simo 1992; Simo & Hughes 1998,
// ch. 9; de Souza Neto, Peric & Owen 2008, ch. 14).
//
// The helpers are forced inline into each model's out-of-line stress and tangent (inlined, the
// trial state keeps its arrays in registers: J2 runs 8% faster in impm_bench_explicit --case j2-2d
// than with henckyTrial called out of line).
//
// History layout (ParticleSet::history): b_e in the stored stress layout (xx, yy, xy, zz, yz, xz),
// then the model's internal variable (the equivalent plastic strain) at kHenckyInternal.
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

constexpr int kHenckyInternal = 6;  // the history slot after b_e

// The initial history: b_e = I, internal variable 0.
KOKKOS_INLINE_FUNCTION void henckyInitialHistory(double* h) {
  h[0] = 1;
  h[1] = 1;
  h[2] = 0;
  h[3] = 1;
  h[4] = 0;
  h[5] = 0;
  h[6] = 0;
}

// The trial state of the step f = I + G from b_e^n (in h): the principal directions n (columns)
// of b_e^trial = f b_e^n f^T and its log strains eps_A = ln lambda_A.
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION void henckyTrial(const double (&G)[Dim][Dim], const double* h, double (&n)[3][3],
                                             double (&eps)[3]) {
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
  symmetricEigen3(trial, b, n);
  for (int a = 0; a < 3; ++a) eps[a] = 0.5 * std::log(b[a]);
}

// After the return: b_e^{n+1} = sum_A exp(2 eps_A) n_A (x) n_A into h, and the Cauchy stress
// sigma = tau / J (tau = sum_A tau_A n_A (x) n_A) into s, in the stored layout.
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION void henckyStore(const double (&n)[3][3], const double (&tau)[3], const double (&eps)[3],
                                             double J, double* h, double* s) {
  using SL3 = StressLayout<3>;
  const double invJ = 1.0 / J;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      double sij = 0, bij = 0;
      for (int a = 0; a < 3; ++a) {
        sij += tau[a] * n[i][a] * n[j][a];
        bij += std::exp(2.0 * eps[a]) * n[i][a] * n[j][a];
      }
      h[SL3::index(i, j)] = bij;
      if (i < Dim && j < Dim) s[StressLayout<Dim>::index(i, j)] = sij * invJ;
    }
  if constexpr (Dim == 2) {  // sigma_zz: z is principal (f_zz = 1, b_e xz = yz = 0)
    double szz = 0;
    for (int a = 0; a < 3; ++a) szz += tau[a] * n[2][a] * n[2][a];
    s[3] = szz * invJ;
  }
}

// The elastic (Hencky) stored energy per unit current volume, from b_e.
KOKKOS_INLINE_FUNCTION double henckyEnergyDensity(double lambda, double mu, const double* h, double J) {
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

// The spatial tangent D = c / J of a return map written in the principal axes of b_e^trial, from
// its principal parts: c is the derivative of the Lie (Truesdell) rate of tau, so that with the
// stiffness kernel's geometric term the matrix is the exact derivative of the internal force.
// For a symmetric rate d (db^trial = d b + b d), in the principal frame:
//   normal:  c_AABB = a_AB - 2 tau_A delta_AB,   a_AB = d tau_A / d eps_B^trial (the model's);
//   shear:   (c : d)_AB = (r_AB x coth x - tau_A - tau_B) d_AB,  x = eps_A^trial - eps_B^trial,
//            from (tau_A - tau_B) / (b_A - b_B) (b_A + b_B) with r_AB = (tau_A - tau_B) / x
//            (smooth as b_A -> b_B: x coth x -> 1). J2 and Drucker-Prager have one ratio for
//            every pair (tau_A - tau_B = twoMuBeta x); Mohr-Coulomb gives each pair its own.
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION void henckyTangent(const double (&n)[3][3], const double (&epsTrial)[3],
                                               const double (&tau)[3], const double (&a)[3][3],
                                               const double (&ratio)[3][3], double J,
                                               double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) {
  using SL = StressLayout<Dim>;
  double normal[3][3], shear[3][3];  // principal frame: c_AABB, and the factors of d_AB (A != B)
  for (int p = 0; p < 3; ++p)
    for (int q = 0; q < 3; ++q) {
      normal[p][q] = a[p][q] - (p == q ? 2.0 * tau[p] : 0.0);
      const double x = epsTrial[p] - epsTrial[q];
      const double xCothX = std::fabs(x) < 1e-6 ? 1.0 + x * x / 3.0 : x / std::tanh(x);
      shear[p][q] = ratio[p][q] * xCothX - tau[p] - tau[q];
    }
  const double invJ = 1.0 / J;
  for (int v = 0; v < SL::voigt; ++v) {
    // The unit rate of Voigt strain v (engineering shear: d_kl = d_lk = 1/2) in the principal frame.
    const int k = SL::first(v), l = SL::second(v);
    double dp[3][3];
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) dp[p][q] = 0.5 * (n[k][p] * n[l][q] + n[l][p] * n[k][q]);
    double op[3][3];  // (c : d) in the principal frame
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) {
        if (p == q) {
          op[p][p] = 0;
          for (int e = 0; e < 3; ++e) op[p][p] += normal[p][e] * dp[e][e];
        } else {
          op[p][q] = shear[p][q] * dp[p][q];
        }
      }
    for (int w = 0; w < SL::voigt; ++w) {
      const int i = SL::first(w), j = SL::second(w);
      double cij = 0;
      for (int p = 0; p < 3; ++p)
        for (int q = 0; q < 3; ++q) cij += n[i][p] * op[p][q] * n[j][q];
      D[w][v] = cij * invJ;
    }
  }
}

// The same with one ratio for every pair: tau_A - tau_B = twoMuBeta (eps_A^trial - eps_B^trial).
template <int Dim>
KOKKOS_FORCEINLINE_FUNCTION void henckyTangent(const double (&n)[3][3], const double (&epsTrial)[3],
                                               const double (&tau)[3], const double (&a)[3][3], double twoMuBeta,
                                               double J,
                                               double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) {
  const double ratio[3][3] = {
      {twoMuBeta, twoMuBeta, twoMuBeta}, {twoMuBeta, twoMuBeta, twoMuBeta}, {twoMuBeta, twoMuBeta, twoMuBeta}};
  henckyTangent<Dim>(n, epsTrial, tau, a, ratio, J, D);
}

}  // namespace impm
