// Internal force f_i = - sum_p V_p sigma_p . grad S_ip, written once (scatterInternalForce):
// the explicit stepper calls it inside its fused particle-to-grid kernel with the particle
// stresses, the implicit residual calls accumulateInternalForce with trial stresses.
#pragma once

#include <Kokkos_ScatterView.hpp>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"

namespace impm {

// One particle's contribution, for a stencil already built.
template <class Shape, class Access>
KOKKOS_INLINE_FUNCTION void scatterInternalForce(const ParticleStencil<Shape>& st, const LocalNodeIndexer& ix,
                                                 double V, double sxx, double syy, double sxy, Access& out,
                                                 int forceCol) {
  for (int aI = 0; aI < st.countX(); ++aI)
    for (int bJ = 0; bJ < st.countY(); ++bJ) {
      const int n = ix(st.i0 + aI, st.j0 + bJ);
      const double dx = st.gradX(aI, bJ), dy = st.gradY(aI, bJ);
      out(n, forceCol) += -V * (sxx * dx + sxy * dy);
      out(n, forceCol + 1) += -V * (sxy * dx + syy * dy);
    }
}

template <class ExecSpace, class Shape, class GridView, class StressView>
void accumulateInternalForce(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                             const StressView& stress, const GridView& grid, int forceCol) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  auto x = ps.x; auto hs = ps.halfSize; auto vol = ps.volume;
  Kokkos::parallel_for(
      "internal_force", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        scatterInternalForce(st, ix, vol(p), stress(p, 0), stress(p, 1), stress(p, 2), out, forceCol);
      });
  GridView dest = grid;  // contribute() takes a non-const view
  Kokkos::Experimental::contribute(dest, sv);
}

}  // namespace impm
