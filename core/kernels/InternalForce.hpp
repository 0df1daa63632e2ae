// Internal force f_i = - sum_p V_p sigma_p . grad S_ip, written once: the explicit stepper
// passes the particle stresses, the implicit residual passes trial stresses.
#pragma once

#include <Kokkos_ScatterView.hpp>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"

namespace impm {

template <class ExecSpace, class Shape, class GridView, class StressView>
void accumulateInternalForce(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                             const StressView& stress, const GridView& grid, int forceCol) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  auto x = ps.x; auto hs = ps.halfSize; auto vol = ps.volume;
  Kokkos::parallel_for(
      "internal_force", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        const double V = vol(p), sxx = stress(p, 0), syy = stress(p, 1), sxy = stress(p, 2);
        for (int aI = 0; aI < st.ni; ++aI)
          for (int bJ = 0; bJ < st.nj; ++bJ) {
            const int n = ix(st.i0 + aI, st.j0 + bJ);
            const double dx = st.gradX(aI, bJ), dy = st.gradY(aI, bJ);
            out(n, forceCol) += -V * (sxx * dx + sxy * dy);
            out(n, forceCol + 1) += -V * (sxy * dx + syy * dy);
          }
      });
  GridView dest = grid;  // contribute() takes a non-const view
  Kokkos::Experimental::contribute(dest, sv);
}

}  // namespace impm
