// Internal force f_i = - sum_p V_p sigma_p . grad S_ip, written once (scatterInternalForce):
// the explicit stepper calls it inside its fused particle-to-grid kernel with the particle
// stresses, the implicit residual with trial stresses.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/kernels/Interpolation.hpp"

namespace impm {

// One particle's contribution, for a stencil already built.
template <class Shape, class Access>
KOKKOS_INLINE_FUNCTION void scatterInternalForce(const ParticleStencil<Shape>& st, const LocalNodeIndexer& ix,
                                                 double V, double sxx, double syy, double sxy, Access& out,
                                                 int forceCol) {
  st.forEachNode(ix, [&](int n, double, double dx, double dy) {
    out(n, forceCol) += -V * (sxx * dx + sxy * dy);
    out(n, forceCol + 1) += -V * (sxy * dx + syy * dy);
  });
}

template <class ExecSpace, class Shape, class GridView, class StressView>
void accumulateInternalForce(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                             const StressView& stress, const GridView& grid, int forceCol) {
  auto vol = ps.volume;
  scatterToGrid<ExecSpace, Shape>(
      "internal_force", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st, auto& out) {
        scatterInternalForce(st, ix, vol(p), stress(p, 0), stress(p, 1), stress(p, 2), out, forceCol);
      });
}

}  // namespace impm
