// Internal force f_i = - sum_p V_p sigma_p . grad S_ip, written once (scatterInternalForce):
// the explicit stepper calls it inside its fused particle-to-grid kernel with the particle
// stresses, the implicit residual with trial stresses.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/SmallMatrix.hpp"
#include "core/kernels/FieldColumns.hpp"
#include "core/kernels/Interpolation.hpp"

namespace impm {

// One particle's contribution, for a stencil already built; s: the stored stress components
// (StressLayout<Dim>).
template <class Shape, int Dim, class Access>
KOKKOS_FORCEINLINE_FUNCTION void scatterInternalForce(const ParticleStencil<Shape, Dim>& st, const LocalNodeIndexer& ix,
                                                      double V, const double* s, Access& out, int forceCol) {
  using SL = StressLayout<Dim>;
  st.forEachNode(ix, [&](int n, double, const double* grad) {
    for (int i = 0; i < Dim; ++i) {
      double f = 0;
      for (int j = 0; j < Dim; ++j) f += s[SL::index(i, j)] * grad[j];
      out(n, forceCol + i) += -V * f;
    }
  });
}

// The same on the domain deformed by the step's increment G (the implicit residual of a
// finite-strain material): with dF = I + G, the gradients on the deformed domain are
// dF^-T grad S and its volume is det(dF) V, so f_i = -det(dF) V sigma . dF^-T grad S_i. This
// makes the residual's derivative (the Jacobian-free product) the full current-configuration
// tangent, material and geometric.
template <class Shape, int Dim, class Access>
KOKKOS_INLINE_FUNCTION void scatterInternalForceDeformed(const ParticleStencil<Shape, Dim>& st,
                                                         const LocalNodeIndexer& ix, double V, const double* s,
                                                         const double (&G)[Dim][Dim], Access& out, int forceCol) {
  using SL = StressLayout<Dim>;
  double dF[Dim][Dim], inv[Dim][Dim];
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) dF[i][j] = (i == j ? 1.0 : 0.0) + G[i][j];
  const double J = determinant<Dim>(dF);
  inverse<Dim>(dF, J, inv);
  const double Vnew = J * V;
  st.forEachNode(ix, [&](int n, double, const double* grad) {
    double gnew[Dim];
    for (int j = 0; j < Dim; ++j) {
      double gj = 0;
      for (int k = 0; k < Dim; ++k) gj += inv[k][j] * grad[k];
      gnew[j] = gj;
    }
    for (int i = 0; i < Dim; ++i) {
      double f = 0;
      for (int j = 0; j < Dim; ++j) f += s[SL::index(i, j)] * gnew[j];
      out(n, forceCol + i) += -Vnew * f;
    }
  });
}

// The stored stress components of particle p of a stress view.
template <int Dim, class StressView>
KOKKOS_INLINE_FUNCTION void loadStress(const StressView& stress, int p, double* s) {
  for (int c = 0; c < StressLayout<Dim>::count; ++c) s[c] = stress(p, c);
}

template <class ExecSpace, class Shape, int Dim, class GridView, class StressView, class Fields = SingleField>
void accumulateInternalForce(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                             const StressView& stress, const GridView& grid, int forceCol,
                             const Fields& fields = Fields()) {
  auto vol = ps.volume;
  scatterToGrid<ExecSpace, Shape, Dim>(
      "internal_force", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double s[StressLayout<Dim>::count];
        loadStress<Dim>(stress, p, s);
        scatterInternalForce(st, ix, vol(p), s, out, forceCol + fields.offset(p));
      });
}

}  // namespace impm
