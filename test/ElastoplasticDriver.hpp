// Test helpers for the finite-strain elastoplastic models (J2, Drucker-Prager, Mohr-Coulomb): a
// one-particle driver through a sequence of deformation gradients, the check of a consistent
// tangent against central differences of the Lie rate of the Kirchhoff stress, and element tests
// under mixed control (axial strain stepped, lateral stress held).
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/Materials.hpp"

namespace impm_test {

using namespace impm;

// Drives one particle of material 0 through the deformation gradients F_1 ... F_N (increments
// f = F_{k+1} F_k^-1 from F_0 = I) and returns the Cauchy stress, the history and J.
template <int Dim>
struct ElastoplasticDriver {
  MaterialLaw law;
  double h[ParticleSet::kHistoryCount];
  double s[StressLayout<Dim>::count] = {};
  double F[Dim][Dim];
  explicit ElastoplasticDriver(const MaterialLaw& l) : law(l) {
    law.initialHistory(0, h);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) F[i][j] = i == j ? 1.0 : 0.0;
  }
  void stepTo(const double (&Fnew)[Dim][Dim]) {
    double inv[Dim][Dim], f[Dim][Dim], G[Dim][Dim];
    inverse<Dim>(F, determinant<Dim>(F), inv);
    multiply<Dim>(Fnew, inv, f);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) G[i][j] = f[i][j] - (i == j ? 1.0 : 0.0);
    law.template stress<Dim>(0, s, G, Fnew, h, s);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) F[i][j] = Fnew[i][j];
  }
};

// tau = J sigma after the increment f = I + G from the driver's state (its history is not changed).
template <int Dim>
void kirchhoffAfter(const ElastoplasticDriver<Dim>& d, const double (&G)[Dim][Dim], double* tau) {
  double h[ParticleSet::kHistoryCount], s[StressLayout<Dim>::count], f[Dim][Dim], F[Dim][Dim];
  for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = d.h[i];
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) f[i][j] = (i == j ? 1.0 : 0.0) + G[i][j];
  multiply<Dim>(f, d.F, F);
  d.law.template stress<Dim>(0, d.s, G, F, h, s);
  const double J = determinant<Dim>(F);
  for (int c = 0; c < StressLayout<Dim>::count; ++c) tau[c] = J * s[c];
}

// The tangent D of the increment G from the driver's state against central differences of the
// Lie rate of tau: perturbing f to (I + e L) f, (tau(+e) - tau(-e)) / 2e - (L tau + tau L^T)
// must be J D sym(L) for symmetric L (one per Voigt strain), and zero for skew L (objectivity:
// the kernel's D sees only sym(L)). Returns the worst mismatch over mu; `plastic` tells whether
// the increment yields, and `fromElastic` the largest |D - D_elastic| / mu.
template <int Dim>
double tangentMismatch(const ElastoplasticDriver<Dim>& d, const double (&G)[Dim][Dim], double mu, bool& plastic,
                       double& fromElastic) {
  using SL = StressLayout<Dim>;
  double f[Dim][Dim], F[Dim][Dim], tau[SL::count];
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) f[i][j] = (i == j ? 1.0 : 0.0) + G[i][j];
  multiply<Dim>(f, d.F, F);
  const double J = determinant<Dim>(F);
  double D[SL::voigt][SL::voigt], De[SL::voigt][SL::voigt];
  d.law.template tangent<Dim>(0, G, J, d.h, D);
  d.law.template tangent<Dim>(0, J, De);
  kirchhoffAfter(d, G, tau);
  {
    double h[ParticleSet::kHistoryCount], s[SL::count];
    for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = d.h[i];
    d.law.template stress<Dim>(0, d.s, G, F, h, s);
    plastic = h[kHenckyInternal] > d.h[kHenckyInternal];
  }
  fromElastic = 0;
  for (int r = 0; r < SL::voigt; ++r)
    for (int v = 0; v < SL::voigt; ++v) fromElastic = std::max(fromElastic, J * std::abs(D[r][v] - De[r][v]) / mu);
  const double e = 1e-6;
  double worst = 0;
  // Directions: the Voigt strains (symmetric), then the skew ones (i < j).
  for (int v = 0; v < SL::voigt + Dim * (Dim - 1) / 2; ++v) {
    double L[Dim][Dim] = {};
    const bool symmetric = v < SL::voigt;
    if (symmetric) {
      const int i = SL::first(v), j = SL::second(v);
      if (i == j)
        L[i][i] = 1.0;
      else
        L[i][j] = L[j][i] = 0.5;
    } else {
      const int w = v - SL::voigt, i = w == 2 ? 1 : 0, j = w == 0 ? 1 : 2;
      L[i][j] = 0.5;
      L[j][i] = -0.5;
    }
    double Gp[Dim][Dim], Gm[Dim][Dim], tp[SL::count], tm[SL::count];
    for (int a = 0; a < Dim; ++a)
      for (int b = 0; b < Dim; ++b) {
        double lf = 0;
        for (int k = 0; k < Dim; ++k) lf += L[a][k] * f[k][b];
        Gp[a][b] = f[a][b] + e * lf - (a == b ? 1.0 : 0.0);
        Gm[a][b] = f[a][b] - e * lf - (a == b ? 1.0 : 0.0);
      }
    kirchhoffAfter(d, Gp, tp);
    kirchhoffAfter(d, Gm, tm);
    for (int r = 0; r < SL::voigt; ++r) {
      const int a = SL::first(r), b = SL::second(r);
      double convected = 0;  // (L tau + tau L^T)_ab
      for (int k = 0; k < Dim; ++k) convected += L[a][k] * tau[SL::index(k, b)] + tau[SL::index(a, k)] * L[b][k];
      const double lie = (tp[r] - tm[r]) / (2 * e) - convected;
      worst = std::max(worst, std::abs(lie - (symmetric ? J * D[r][v] : 0.0)) / mu);
    }
  }
  return worst;
}

// Element tests under mixed stress-strain control (compression positive in the results).

// The deformation gradient of principal log strains: axial (last axis) and lateral (the others).
template <int Dim>
void principalStretch(double axial, double lateral, double (&F)[Dim][Dim]) {
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) F[i][j] = i != j ? 0.0 : std::exp(i == Dim - 1 ? axial : lateral);
}

// Kirchhoff stress component (i, i) of the driver's state.
template <int Dim>
double kirchhoff(const ElastoplasticDriver<Dim>& d, int i) {
  return determinant<Dim>(d.F) * d.s[StressLayout<Dim>::index(i, i)];
}

// Mixed control: the axial log strain is stepped; the lateral log strain (x, and y in 3D) is
// found by Newton (derivative by differences) so that the lateral Kirchhoff stress is -sigma3.
template <int Dim>
double stepHoldingConfinement(ElastoplasticDriver<Dim>& d, double axial, double lateral, double sigma3) {
  auto lateralStress = [&](double e) {
    ElastoplasticDriver<Dim> trial = d;
    double F[Dim][Dim];
    principalStretch<Dim>(axial, e, F);
    trial.stepTo(F);
    return kirchhoff(trial, 0) + sigma3;
  };
  for (int it = 0; it < 30; ++it) {
    const double g = lateralStress(lateral);
    if (std::abs(g) < 1e-10 * sigma3) break;
    const double de = 1e-9, slope = (lateralStress(lateral + de) - g) / de;
    lateral -= g / slope;
  }
  double F[Dim][Dim];
  principalStretch<Dim>(axial, lateral, F);
  d.stepTo(F);
  return lateral;
}

struct ElementTest {
  double strength, dilatancy;  // sigma_1 (compression positive) and d(eps_v) / d(eps_axial), both at the end
  double alpha;
};

// Isotropic compression to sigma3 (elastic), then the axial log strain stepped by `axialEnd` in
// `steps` (negative: compression; positive: extension) with the lateral stress held.
template <int Dim>
ElementTest compress(const Materials& materials, double sigma3, double axialEnd, int steps) {
  ElastoplasticDriver<Dim> d(materials.law());
  const double mu = materials.c33(0), K = materials.c12(0) + 2 * mu / 3;
  // Plane strain: the in-plane isotropic state is not isotropic in 3D; Newton on the lateral
  // strain finds it (its first step).
  double axial = -sigma3 / (3 * K), lateral = axial;
  if (Dim == 3) {
    double F[Dim][Dim];
    principalStretch<Dim>(axial, lateral, F);
    d.stepTo(F);
  }
  double volumePrevious = 0, axialPrevious = 0;
  for (int k = 1; k <= steps; ++k) {
    volumePrevious = axial + (Dim - 1) * lateral;
    axialPrevious = axial;
    axial = -sigma3 / (3 * K) + axialEnd * k / steps;
    lateral = stepHoldingConfinement<Dim>(d, axial, lateral, sigma3);
  }
  const double volume = axial + (Dim - 1) * lateral;
  return {-kirchhoff(d, Dim - 1), (volume - volumePrevious) / (axial - axialPrevious), d.h[kHenckyInternal]};
}

}  // namespace impm_test
