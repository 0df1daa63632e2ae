// Small-strain isotropic linear elasticity in plane strain, plane stress or 3D: the stress
// increment D sym(G), the constant tangent D and the energy (1/2) sigma : D^-1 sigma. The
// constants are those of a MaterialLaw row: c11 = lambda + 2 mu (plane stress: E / (1 - nu^2)),
// c12 = lambda (plane stress: nu E / (1 - nu^2)), c33 = mu, czz (the out-of-plane sigma_zz of
// a 2D model per unit in-plane volumetric strain: lambda in plane strain, 0 in plane stress)
// and invDet = 1 / (c11^2 - c12^2).
#pragma once

#include "core/ParticleSet.hpp"

namespace impm {

struct LinearElasticModel {
  double c11, c12, c33, czz, invDet;

  // The law, written once: s = s0 + D sym(G) in the stored layout (StressLayout<Dim>), with
  // G[i][j] = d(du_i)/dx_j. in(k) reads component k of s0 and out(k, value) stores component k of
  // s; every component is computed before any is stored, so the output may be the input.
  template <int Dim, class In, class Out>
  KOKKOS_FORCEINLINE_FUNCTION void apply(const In& in, const double (&G)[Dim][Dim], const Out& out) const {
    const double a = c11, b = c12, c = c33;
    if constexpr (Dim == 2) {
      const double gxx = G[0][0], gyy = G[1][1], gamma = G[0][1] + G[1][0];  // gamma: engineering shear
      const double sxx = in(0) + a * gxx + b * gyy, syy = in(1) + b * gxx + a * gyy;
      const double sxy = in(2) + c * gamma, szz = in(3) + czz * (gxx + gyy);
      out(0, sxx);
      out(1, syy);
      out(2, sxy);
      out(3, szz);
    } else {
      const double exx = G[0][0], eyy = G[1][1], ezz = G[2][2];
      const double sxx = in(0) + a * exx + b * (eyy + ezz);
      const double syy = in(1) + a * eyy + b * (exx + ezz);
      const double szz = in(3) + a * ezz + b * (exx + eyy);
      const double sxy = in(2) + c * (G[0][1] + G[1][0]);
      const double syz = in(4) + c * (G[1][2] + G[2][1]);
      const double sxz = in(5) + c * (G[0][2] + G[2][0]);
      out(0, sxx);
      out(1, syy);
      out(2, sxy);
      out(3, szz);
      out(4, syz);
      out(5, sxz);
    }
  }

  // On arrays (the implicit trial stresses, the tangent checks). s may alias s0.
  template <int Dim>
  KOKKOS_FORCEINLINE_FUNCTION void stress(const double* s0, const double (&G)[Dim][Dim], double* s) const {
    apply<Dim>([s0](int k) { return s0[k]; }, G, [s](int k, double value) { s[k] = value; });
  }

  // On particle p's row of a stress view, in place (the explicit G2P's hot path): each component
  // is read and written as a scalar. A local copy of the row, written component by component and
  // read back as a vector by GCC's SLP code, stalled store forwarding for a fifth of the G2P.
  template <int Dim, class StressView>
  KOKKOS_FORCEINLINE_FUNCTION void updateStress(const StressView& stress, int p, const double (&G)[Dim][Dim]) const {
    apply<Dim>([&](int k) { return stress(p, k); }, G, [&](int k, double value) { stress(p, k) = value; });
  }

  // (1/2) sigma : eps with eps = D^-1 sigma (in 2D in the plane: the out-of-plane term vanishes
  // in both plane strain, eps_zz = 0, and plane stress, sigma_zz = 0).
  template <int Dim>
  KOKKOS_INLINE_FUNCTION double energyDensity(const double* s) const {
    const double a = c11, b = c12, c = c33;
    if constexpr (Dim == 2) {
      const double exx = (a * s[0] - b * s[1]) * invDet, eyy = (a * s[1] - b * s[0]) * invDet;
      return 0.5 * (s[0] * exx + s[1] * eyy + s[2] * s[2] / c);
    } else {
      // lambda = b, mu = c: eps_ii = (s_ii - lambda / (3 lambda + 2 mu) tr s) / (2 mu).
      const double trace = s[0] + s[1] + s[3];
      const double k = b / (3 * b + 2 * c);
      const double exx = (s[0] - k * trace) / (2 * c), eyy = (s[1] - k * trace) / (2 * c),
                   ezz = (s[3] - k * trace) / (2 * c);
      return 0.5 * (s[0] * exx + s[1] * eyy + s[3] * ezz + (s[2] * s[2] + s[4] * s[4] + s[5] * s[5]) / c);
    }
  }
};

// An isotropic tangent on the Voigt strains of StressLayout<Dim> (engineering shears): normal
// diagonal a, normal off-diagonal b, shear c.
template <int Dim>
KOKKOS_INLINE_FUNCTION void isotropicTangent(double a, double b, double c,
                                             double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) {
  constexpr int nv = StressLayout<Dim>::voigt;
  for (int i = 0; i < nv; ++i)
    for (int j = 0; j < nv; ++j) D[i][j] = 0.0;
  // Normal components: 0, 1 (and 3 in 3D); shears: 2 (and 4, 5).
  const int normals[3] = {0, 1, 3};
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) D[normals[i]][normals[j]] = i == j ? a : b;
  D[2][2] = c;
  if constexpr (Dim == 3) {
    D[4][4] = c;
    D[5][5] = c;
  }
}

}  // namespace impm
