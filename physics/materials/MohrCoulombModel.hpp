// Mohr-Coulomb elastoplasticity at finite strain: the Hencky elasticity and multiplicative split of
// the J2 and Drucker-Prager models (physics/materials/HenckyElasticity.hpp), the six planes of
// Mohr-Coulomb with a non-associated flow through the dilatancy angle, an optional tension cutoff
// (Rankine planes sigma_A <= t), and linear cohesion hardening or softening down to a residual
// cohesion (de Souza Neto, Peric & Owen 2008, section 8.2 and Boxes 8.1-8.4, written in the
// principal Kirchhoff stresses and elastic log strains).
//
// Tension is positive. In the frame of the trial principal stresses sorted s_1 >= s_2 >= s_3:
//   plane (i, j)   Phi_ij = (s_i - s_j) + (s_i + s_j) sin(phi) - 2 c(alpha) cos(phi)
//                  flow   (1 + sin psi) e_i - (1 - sin psi) e_j,   alpha' = 2 cos(phi) gamma'
//   cutoff i       Phi_i = s_i - t,   flow e_i (the cutoff does not change alpha)
// with c = max(c_r, c_0 + H alpha). The main plane is (1, 3); the edges add (2, 3) (s_1 = s_2,
// triaxial extension) or (1, 2) (s_2 = s_3, triaxial compression); the apex is s_A = c cot(phi).
// phi = 0 is Tresca (c the undrained shear strength), which has no apex.
//
// Every surface is a plane in the principal stresses, so the return onto any set of active surfaces
// is one small linear solve (exact in one step, as c is piecewise linear in alpha): with the
// elastic principal stiffness De, normals a_k and flows g_k,
//   sum_l (a_k . De g_l + 4 cos^2(phi) H [k, l are Mohr-Coulomb planes]) dgamma_l = Phi_k^trial.
// The candidates are tried in a fixed order (main plane, the two edges, then the cutoff alone, with
// the main plane, with the compression edge, two cutoffs, two cutoffs and the main plane, the
// tension apex s = t, and last the apex) and the first one with dgamma >= 0 that leaves every
// surface satisfied is the return (for associated flow it is the unique closest point). The apex:
//   p = p^trial - K dv,  dv = (p^trial - c_n cot phi) / (K + H cos(phi) cot(phi) / sin(psi)),
//   alpha += dv cos(phi) / sin(psi)   (psi = 0: dv = (p^trial - c_n cot phi) / K, alpha unchanged).
// A return that would soften below c_r is redone at c_r with H = 0.
//
// History per particle: b_e (6, stored layout) and alpha, as J2 and Drucker-Prager.
#pragma once

#include <cmath>

#include "physics/materials/HenckyElasticity.hpp"

namespace impm {

struct MohrCoulombModel {
  double lambda, mu;
  double sinPhi, cosPhi, sinPsi;
  double cohesion, hardening, residual;   // c_0, H (negative: softening) and c_r
  double tension;                         // the cutoff t (> 0), or 0: none
  static constexpr int historyCount = 7;  // b_e (6, stored layout) and alpha

  KOKKOS_INLINE_FUNCTION static void initialHistory(double* h) { henckyInitialHistory(h); }

  // Surfaces of the sorted frame: the planes (i, j) = (0, 2) main, (1, 2), (0, 1), and the three
  // with i > j; then the cutoffs of s_0, s_1, s_2.
  enum : int {
    Main = 0,
    ExtensionEdge = 1,
    CompressionEdge = 2,
    Cutoff0 = 6,
    Cutoff1 = 7,
    Cutoff2 = 8,
    SurfaceCount = 9
  };
  enum : int { Elastic = 0, Planes = 1, Apex = 2 };

  struct Return {
    double n[3][3], epsTrial[3], eps[3], tau[3];
    int order[3];          // order[k]: the principal axis of the k-th largest trial stress
    int active[3], count;  // the active surfaces (Planes)
    double phiTrial[SurfaceCount], scale;
    double hEffective;  // the slope of c(alpha) at the return
    int regime;
  };

  KOKKOS_INLINE_FUNCTION double bulk() const { return lambda + 2.0 * mu / 3.0; }

  // Surface k: Phi_k = a . s - (cWeight c + constant); its flow g; alpha' = alphaRate gamma'.
  struct Surface {
    double a[3], g[3], cWeight, constant, alphaRate;
  };
  KOKKOS_INLINE_FUNCTION Surface surface(int k) const {
    Surface s{{0, 0, 0}, {0, 0, 0}, 0.0, 0.0, 0.0};
    if (k >= Cutoff0) {
      s.a[k - Cutoff0] = s.g[k - Cutoff0] = 1.0;
      s.constant = tension;
      return s;
    }
    const int major[6] = {0, 1, 0, 1, 2, 2}, minor[6] = {2, 2, 1, 0, 0, 1};
    s.a[major[k]] = 1.0 + sinPhi;
    s.a[minor[k]] = -(1.0 - sinPhi);
    s.g[major[k]] = 1.0 + sinPsi;
    s.g[minor[k]] = -(1.0 - sinPsi);
    s.cWeight = s.alphaRate = 2.0 * cosPhi;
    return s;
  }
  KOKKOS_INLINE_FUNCTION int surfaceCount() const { return tension > 0.0 ? SurfaceCount : Cutoff0; }
  // De v, De the principal elastic stiffness (lambda 1 (x) 1 + 2 mu I).
  KOKKOS_INLINE_FUNCTION void elastic(const double (&v)[3], double (&out)[3]) const {
    const double trace = v[0] + v[1] + v[2];
    for (int a = 0; a < 3; ++a) out[a] = lambda * trace + 2.0 * mu * v[a];
  }

  // The return onto the surfaces set[0..n) from the trial stresses at cohesion c and slope H:
  // stresses s, multipliers dgamma, the increment of alpha; Minv the inverse of the system matrix.
  KOKKOS_INLINE_FUNCTION bool solvePlanes(const int* set, int n, const double (&sTrial)[3], double c, double H,
                                          double (&s)[3], double (&dgamma)[3], double& dAlpha,
                                          double (&Minv)[3][3]) const {
    double M[3][6] = {}, rhs[3];
    for (int k = 0; k < n; ++k) {
      const Surface sk = surface(set[k]);
      rhs[k] = sk.a[0] * sTrial[0] + sk.a[1] * sTrial[1] + sk.a[2] * sTrial[2] - sk.cWeight * c - sk.constant;
      for (int l = 0; l < n; ++l) {
        const Surface sl = surface(set[l]);
        double Dg[3];
        elastic(sl.g, Dg);
        M[k][l] = sk.a[0] * Dg[0] + sk.a[1] * Dg[1] + sk.a[2] * Dg[2] + sk.cWeight * H * sl.alphaRate;
      }
      M[k][n + k] = 1.0;
    }
    // Gauss-Jordan with partial pivoting on [M | I].
    for (int col = 0; col < n; ++col) {
      int pivot = col;
      for (int r = col + 1; r < n; ++r)
        if (std::fabs(M[r][col]) > std::fabs(M[pivot][col])) pivot = r;
      if (!(std::fabs(M[pivot][col]) > 1e-14 * mu)) return false;
      for (int j = 0; j < 2 * n; ++j) {
        const double t = M[col][j];
        M[col][j] = M[pivot][j];
        M[pivot][j] = t;
      }
      const double inv = 1.0 / M[col][col];
      for (int j = 0; j < 2 * n; ++j) M[col][j] *= inv;
      for (int r = 0; r < n; ++r) {
        if (r == col) continue;
        const double f = M[r][col];
        for (int j = 0; j < 2 * n; ++j) M[r][j] -= f * M[col][j];
      }
    }
    for (int a = 0; a < 3; ++a) s[a] = sTrial[a];
    dAlpha = 0.0;
    for (int l = 0; l < n; ++l) {
      dgamma[l] = 0.0;
      for (int k = 0; k < n; ++k) {
        Minv[l][k] = M[l][n + k];
        dgamma[l] += Minv[l][k] * rhs[k];
      }
      const Surface sl = surface(set[l]);
      double Dg[3];
      elastic(sl.g, Dg);
      for (int a = 0; a < 3; ++a) s[a] -= dgamma[l] * Dg[a];
      dAlpha += sl.alphaRate * dgamma[l];
    }
    return true;
  }

  // The largest violation of any surface at stresses s and cohesion c.
  KOKKOS_INLINE_FUNCTION double violation(const double (&s)[3], double c) const {
    double worst = -1e300;
    for (int k = 0; k < surfaceCount(); ++k) {
      const Surface sk = surface(k);
      const double f = sk.a[0] * s[0] + sk.a[1] * s[1] + sk.a[2] * s[2] - sk.cWeight * c - sk.constant;
      worst = f > worst ? f : worst;
    }
    return worst;
  }

  // The apex return s_A = c cot(phi) from the mean trial stress: stresses s, the increment of alpha,
  // the slope of c used and the cohesion at the end; false when the trial state lies below the
  // apex pressure, or there is no apex (phi = 0: Tresca).
  KOKKOS_INLINE_FUNCTION bool apexReturn(const double (&sTrial)[3], double c, double H, double (&s)[3], double& dAlpha,
                                         double& hUsed, double& cEnd) const {
    if (!(sinPhi > 0.0)) return false;
    const double K = bulk(), cot = cosPhi / sinPhi, pTrial = (sTrial[0] + sTrial[1] + sTrial[2]) / 3.0;
    const double alphaPerVolume = sinPsi > 0.0 ? cosPhi / sinPsi : 0.0;
    hUsed = sinPsi > 0.0 ? H : 0.0;
    cEnd = c;
    double dv = (pTrial - c * cot) / (K + hUsed * alphaPerVolume * cot);
    if (hUsed != 0.0 && c + hUsed * alphaPerVolume * dv < residual) {
      hUsed = 0.0;
      cEnd = residual;
      dv = (pTrial - residual * cot) / K;
    } else {
      cEnd = c + hUsed * alphaPerVolume * dv;
    }
    dAlpha = alphaPerVolume * dv;
    for (int a = 0; a < 3; ++a) s[a] = pTrial - K * dv;
    return dv >= 0.0;
  }

  template <int Dim>
  KOKKOS_INLINE_FUNCTION void returnMap(const double (&G)[Dim][Dim], const double* h, Return& r, double& dAlpha) const;
  // The trial state of returnMap: r's trial strains, axes and order, scale and surface values;
  // the sorted trial stresses sTrial, the cohesion c and its modulus H at the step's start.
  // Returns whether the trial state yields.
  template <int Dim>
  KOKKOS_INLINE_FUNCTION bool trialState(const double (&G)[Dim][Dim], const double* h, Return& r, double (&tauTrial)[3],
                                         double (&sTrial)[3], double& c, double& H) const;

  // Cauchy stress after the relative deformation gradient f = I + G, with J = det F (total);
  // `h` (b_e, alpha) is read and updated in place.
  template <int Dim>
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION void stress(const double (&G)[Dim][Dim], double J, double* h, double* s) const {
    Return r;
    double dAlpha;
    returnMap<Dim>(G, h, r, dAlpha);
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

  template <int Dim>
  IMPM_OUT_OF_LINE KOKKOS_FUNCTION void tangent(const double (&G)[Dim][Dim], double J, const double* h,
                                                double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const;
};

template <int Dim>
KOKKOS_INLINE_FUNCTION bool MohrCoulombModel::trialState(const double (&G)[Dim][Dim], const double* h, Return& r,
                                                         double (&tauTrial)[3], double (&sTrial)[3], double& c,
                                                         double& H) const {
  henckyTrial<Dim>(G, h, r.n, r.epsTrial);
  elastic(r.epsTrial, tauTrial);
  // Sort the principal axes by trial stress, largest first.
  int o[3] = {0, 1, 2};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2 - i; ++j)
      if (tauTrial[o[j + 1]] > tauTrial[o[j]]) {
        const int t = o[j];
        o[j] = o[j + 1];
        o[j + 1] = t;
      }
  for (int k = 0; k < 3; ++k) {
    r.order[k] = o[k];
    sTrial[k] = tauTrial[o[k]];
  }
  c = cohesion + hardening * h[kHenckyInternal];
  H = hardening;
  if (c <= residual) {
    c = residual;
    H = 0.0;
  }
  r.scale = std::fabs(sTrial[0]) + std::fabs(sTrial[2]) + 2.0 * c * cosPhi + (tension > 0.0 ? tension : 0.0);
  bool yields = false;
  for (int k = 0; k < SurfaceCount; ++k) {
    const Surface sk = surface(k);
    r.phiTrial[k] = k < surfaceCount()
                        ? sk.a[0] * sTrial[0] + sk.a[1] * sTrial[1] + sk.a[2] * sTrial[2] - sk.cWeight * c - sk.constant
                        : -1e300;
    yields = yields || r.phiTrial[k] > 0.0;
  }
  return yields;
}

// The trial state, the candidates in order, and the elastic log strains of the returned stresses.
template <int Dim>
KOKKOS_INLINE_FUNCTION void MohrCoulombModel::returnMap(const double (&G)[Dim][Dim], const double* h, Return& r,
                                                        double& dAlpha) const {
  double tauTrial[3], sTrial[3], c, H;
  const bool yields = trialState<Dim>(G, h, r, tauTrial, sTrial, c, H);
  const int* o = r.order;
  r.regime = Elastic;
  r.count = 0;
  r.hEffective = H;
  dAlpha = 0.0;
  if (!yields) {
    for (int a = 0; a < 3; ++a) {
      r.tau[a] = tauTrial[a];
      r.eps[a] = r.epsTrial[a];  // keep b_e^trial's eigenvalues as they are (no log-exp round trip)
    }
    return;
  }
  // The candidates (-1: the apex, last: with softening a cutoff and the softened apex may both
  // hold, and the cutoff, which leaves c alone, is taken), the first admissible one wins; else the
  // least violating one.
  constexpr int kCandidates = 10;
  const int sets[kCandidates][3] = {{Main},
                                    {Main, ExtensionEdge},
                                    {Main, CompressionEdge},
                                    {Cutoff0},
                                    {Cutoff0, Main},
                                    {Cutoff0, Main, CompressionEdge},
                                    {Cutoff0, Cutoff1},
                                    {Cutoff0, Cutoff1, Main},
                                    {Cutoff0, Cutoff1, Cutoff2},
                                    {-1}};
  const int sizes[kCandidates] = {1, 2, 2, 1, 2, 3, 2, 3, 3, 1};
  const double tolerance = 1e-10 * r.scale;
  double best[3] = {sTrial[0], sTrial[1], sTrial[2]}, bestViolation = 1e300, bestAlpha = 0.0, bestH = H;
  int bestCandidate = -1;
  for (int q = 0; q < kCandidates && bestViolation > tolerance; ++q) {
    if (!(tension > 0.0) && sets[q][0] >= Cutoff0) continue;
    double s[3], dgamma[3] = {0, 0, 0}, Minv[3][3], da = 0.0, hUsed = H, cEnd;
    double shortfall = 0.0;  // of the multipliers below zero, in stress
    if (sets[q][0] < 0) {
      if (!apexReturn(sTrial, c, H, s, da, hUsed, cEnd)) continue;
    } else {
      if (!solvePlanes(sets[q], sizes[q], sTrial, c, H, s, dgamma, da, Minv)) continue;
      cEnd = c + H * da;
      if (H != 0.0 && cEnd < residual) {
        hUsed = 0.0;
        cEnd = residual;
        if (!solvePlanes(sets[q], sizes[q], sTrial, residual, 0.0, s, dgamma, da, Minv)) continue;
      }
      for (int l = 0; l < sizes[q]; ++l) shortfall = std::fmax(shortfall, -2.0 * mu * dgamma[l]);
    }
    const double v = std::fmax(violation(s, cEnd), shortfall);
    if (v < bestViolation) {
      bestViolation = v;
      bestCandidate = q;
      bestAlpha = da;
      bestH = hUsed;
      for (int a = 0; a < 3; ++a) best[a] = s[a];
    }
  }
  dAlpha = bestAlpha;
  r.hEffective = bestH;
  if (bestCandidate >= 0 && sets[bestCandidate][0] < 0) {
    r.regime = Apex;
  } else if (bestCandidate >= 0) {
    r.regime = Planes;
    r.count = sizes[bestCandidate];
    for (int l = 0; l < r.count; ++l) r.active[l] = sets[bestCandidate][l];
  }
  const double K = bulk(), p = (best[0] + best[1] + best[2]) / 3.0;
  for (int k = 0; k < 3; ++k) {
    r.tau[o[k]] = best[k];
    r.eps[o[k]] = (best[k] - p) / (2.0 * mu) + p / (3.0 * K);
  }
}

// The consistent tangent of the step f = I + G from the history h (henckyTangent), from the
// principal derivative d tau / d eps^trial in the sorted frame:
//   planes:  De - (De g_l) Minv_lk (De a_k)^T over the active surfaces (the same system matrix);
//   apex:    K (1 - K / (K + H cos(phi) cot(phi) / sin(psi))) 1 (x) 1 (0 without hardening).
// As for Drucker-Prager, a trial state on the surfaces to within round-off (the step's start after
// a plastic step) counts as loading with the continuum tangent of the largest candidate set whose
// surfaces all hold it; at the apex it counts as unloading.
template <int Dim>
KOKKOS_FUNCTION void MohrCoulombModel::tangent(const double (&G)[Dim][Dim], double J, const double* h,
                                               double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
  Return r;
  double dAlpha;
  returnMap<Dim>(G, h, r, dAlpha);
  // On the surfaces within round-off: the largest candidate set that holds the state; at either
  // apex (every plane, or every cutoff, holds it) the elastic tangent.
  const auto holds = [&](int k) { return r.phiTrial[k] > -1e-8 * r.scale; };
  const bool atApex = (holds(Main) && holds(ExtensionEdge) && holds(CompressionEdge)) ||
                      (holds(Cutoff0) && holds(Cutoff1) && holds(Cutoff2));
  if (r.regime == Elastic && !atApex) {
    const int sets[8][3] = {{Main},
                            {Main, ExtensionEdge},
                            {Main, CompressionEdge},
                            {Cutoff0},
                            {Cutoff0, Main},
                            {Cutoff0, Main, CompressionEdge},
                            {Cutoff0, Cutoff1},
                            {Cutoff0, Cutoff1, Main}};
    const int sizes[8] = {1, 2, 2, 1, 2, 3, 2, 3};
    for (int q = 0; q < 8; ++q) {
      bool all = sizes[q] > r.count;
      for (int l = 0; l < sizes[q] && all; ++l) all = holds(sets[q][l]);
      if (!all) continue;
      r.count = sizes[q];
      for (int l = 0; l < r.count; ++l) r.active[l] = sets[q][l];
    }
    if (r.count > 0) r.regime = Planes;
  }
  const double K = bulk();
  double sorted[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) sorted[a][b] = lambda + (a == b ? 2.0 * mu : 0.0);
  if (r.regime == Apex) {
    const double volumetric = sinPsi > 0.0 && r.hEffective != 0.0
                                  ? K * (1.0 - K / (K + r.hEffective * (cosPhi / sinPsi) * (cosPhi / sinPhi)))
                                  : 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) sorted[a][b] = volumetric;
  } else if (r.regime == Planes) {
    double sTrial[3], s[3], dgamma[3], Minv[3][3], da;
    for (int k = 0; k < 3; ++k) sTrial[k] = 0.0;
    solvePlanes(r.active, r.count, sTrial, 0.0, r.hEffective, s, dgamma, da, Minv);
    double Dg[3][3], Da[3][3];
    for (int l = 0; l < r.count; ++l) {
      const Surface sl = surface(r.active[l]);
      elastic(sl.g, Dg[l]);
      elastic(sl.a, Da[l]);
    }
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int l = 0; l < r.count; ++l)
          for (int k = 0; k < r.count; ++k) sorted[a][b] -= Dg[l][a] * Minv[l][k] * Da[k][b];
  }
  double dTau[3][3], ratio[3][3];
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) dTau[r.order[a]][r.order[b]] = sorted[a][b];
  // (tau_A - tau_B) / (eps_A^trial - eps_B^trial), its limit d tau_A/d eps_A - d tau_A/d eps_B
  // for equal trial strains.
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double x = r.epsTrial[a] - r.epsTrial[b];
      ratio[a][b] = std::fabs(x) > 1e-7 ? (r.tau[a] - r.tau[b]) / x : dTau[a][a] - dTau[a][b];
    }
  henckyTangent<Dim>(r.n, r.epsTrial, r.tau, dTau, ratio, J, D);
}

}  // namespace impm
