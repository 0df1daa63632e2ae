// Affine particle-grid transfers: APIC (Jiang, Schroeder, Selle, Teran & Stomakhin 2015, ACM TOG
// 34(4); Jiang, Schroeder & Teran 2017, JCP 338:137) and TPIC (Nakamura, Matsumura & Mizutani
// 2023, CMAME 403:115720). Each particle carries a velocity field v_p + C_p (x - x_p)
// (ParticleSet::affine), which the particle-to-grid map evaluates at the nodes,
//   m_i v_i = sum_p m_p S_ip (v_p + C_p (x_i - x_p)),
// and the grid-to-particle map sets v_p = sum_i S_ip v_i (PIC) and
//   APIC: C_p = B_p D_p^-1,  B_p = sum_i S_ip v_i (x_i - x_p)^T,  D_p = sum_i S_ip (x_i - x_p)(x_i - x_p)^T
//   TPIC: C_p = sum_i v_i (x) grad S_ip (the grid velocity gradient at the particle).
// An affine grid velocity field comes back to the particles unchanged, v_p and C_p, and APIC
// conserves angular momentum through the round trip.
#pragma once

#include "core/ParticleStencil.hpp"
#include "core/SmallMatrix.hpp"
#include "core/StructuredGrid.hpp"

namespace impm {

// The explicit stepper's particle velocity update (Integrator/Explicit/Transfer). XPIC(m) keeps
// FLIP's kernels and replaces the old particle velocity first (solvers/XpicExtrapolation.hpp).
enum class ParticleTransfer { FlipPic, Apic, Tpic, Xpic };

inline bool carriesAffineVelocity(ParticleTransfer t) {
  return t == ParticleTransfer::Apic || t == ParticleTransfer::Tpic;
}

// How APIC's C_p = B_p D_p^-1 is computed for a shape.
//   General:  D_p summed over the stencil and inverted (GIMP, cpGIMP, CPDI).
//   Constant: D_p = inertiaFactor h_d^2 on the diagonal (B-splines inside the grid: quadratic 1/4,
//             cubic 1/3; next to the grid's edge the edge-modified functions' D_p differs).
//   Gradient: linear MPM, whose D_p is singular on a node line; there S_ip D_p^-1 (x_i - x_p) =
//             grad S_ip identically, so C_p = sum_i v_i (x) grad S_ip, TPIC's formula.
enum class ApicForm { General, Constant, Gradient };
template <class Shape>
struct ApicInertia {
  static constexpr ApicForm form = ApicForm::General;
  static constexpr double factor = 0.0;
};
template <>
struct ApicInertia<LinearMpm> {
  static constexpr ApicForm form = ApicForm::Gradient;
  static constexpr double factor = 0.0;
};
template <>
struct ApicInertia<QuadraticBSpline> {
  static constexpr ApicForm form = ApicForm::Constant;
  static constexpr double factor = 0.25;
};
template <>
struct ApicInertia<CubicBSpline> {
  static constexpr ApicForm form = ApicForm::Constant;
  static constexpr double factor = 1.0 / 3.0;
};

// The stencil's node at `offset`: its grid indices (node[2] = 0 in 2D) and r = x_i - x_p.
template <class Stencil, int Dim>
KOKKOS_INLINE_FUNCTION void stencilNode(const Stencil& st, const StructuredGrid& g, const int* offset,
                                        const double (&xp)[Dim], int (&node)[3], double (&r)[Dim]) {
  node[2] = 0;
  for (int d = 0; d < Dim; ++d) {
    node[d] = st.first[d] + offset[d];
    r[d] = g.origin(d) + node[d] * g.spacing(d) - xp[d];
  }
}

// One particle's mass and momentum m_p S_ip (v_p + C_p (x_i - x_p)) (and m_p S_ip a_p when accCol >= 0).
template <class Shape, int Dim, class Access>
KOKKOS_INLINE_FUNCTION void scatterAffineMassMomentum(const ParticleStencil<Shape, Dim>& st, const StructuredGrid& g,
                                                      const LocalNodeIndexer& ix, double mp, const double (&xp)[Dim],
                                                      const double* vp, const double (&C)[Dim][Dim], const double* ap,
                                                      Access& out, int massCol, int momCol, int accCol) {
  st.forEachOffset([&](const int* offset, double S, const double*) {
    int node[3];
    double r[Dim];
    stencilNode(st, g, offset, xp, node, r);
    const int n = ix(node[0], node[1], node[2]);
    const double w = mp * S;
    if (massCol >= 0) out(n, massCol) += w;
    for (int i = 0; i < Dim; ++i) {
      double vi = vp[i];
      for (int j = 0; j < Dim; ++j) vi += C[i][j] * r[j];
      out(n, momCol + i) += w * vi;
    }
    if (accCol >= 0)
      for (int d = 0; d < Dim; ++d) out(n, accCol + d) += w * ap[d];
  });
}

// D_p = sum_i S_ip (x_i - x_p)(x_i - x_p)^T over the stencil (nodes by offset: no grid view needed).
template <class Shape, int Dim>
KOKKOS_INLINE_FUNCTION void apicInertia(const ParticleStencil<Shape, Dim>& st, const StructuredGrid& g,
                                        const double (&xp)[Dim], double (&D)[Dim][Dim]) {
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) D[i][j] = 0.0;
  st.forEachOffset([&](const int* offset, double S, const double*) {
    int node[3];
    double r[Dim];
    stencilNode(st, g, offset, xp, node, r);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) D[i][j] += S * r[i] * r[j];
  });
}

// APIC's C = B D^-1 from B = sum_i S_ip v_i (x_i - x_p)^T and D (General form).
template <int Dim>
KOKKOS_INLINE_FUNCTION void apicAffine(const double (&B)[Dim][Dim], const double (&D)[Dim][Dim],
                                       double (&C)[Dim][Dim]) {
  double Dinv[Dim][Dim];
  inverse<Dim>(D, determinant<Dim>(D), Dinv);
  multiply<Dim>(B, Dinv, C);
}

}  // namespace impm
