// Global sums over the particles (all MPI ranks): kinetic and strain energy, and linear
// momentum. The strain energy density comes from the material law (energyDensity).
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

#include <cmath>

#include "core/ParticleSet.hpp"

namespace impm {

struct ParticleTotals {
  double kinetic = 0, strain = 0;
  double momentum[2] = {0, 0};
  // sum_p m_p |v_p|: the scale against which a change of the total momentum is measured (the
  // total itself is zero for bodies colliding head-on).
  double momentumScale = 0;
  double total() const { return kinetic + strain; }
};

template <class ExecSpace, class Law>
ParticleTotals particleTotals(const ParticleSet& ps, const Law& law, const Teuchos::Comm<int>& comm) {
  auto m = ps.mass; auto v = ps.v; auto s = ps.stress; auto V = ps.volume; auto matId = ps.material;
  double local[5] = {0, 0, 0, 0, 0};
  Kokkos::parallel_reduce(
      "particle_totals", Kokkos::RangePolicy<ExecSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, double& ke, double& se, double& px, double& py, double& scale) {
        const double vx = v(p, 0), vy = v(p, 1);
        ke += 0.5 * m(p) * (vx * vx + vy * vy);
        const double sp[4] = {s(p, 0), s(p, 1), s(p, 2), s(p, 3)};
        se += V(p) * law.energyDensity(matId(p), sp);
        px += m(p) * vx;
        py += m(p) * vy;
        scale += m(p) * std::sqrt(vx * vx + vy * vy);
      },
      local[0], local[1], local[2], local[3], local[4]);
  double global[5];
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 5, local, global);
  ParticleTotals t;
  t.kinetic = global[0]; t.strain = global[1];
  t.momentum[0] = global[2]; t.momentum[1] = global[3];
  t.momentumScale = global[4];
  return t;
}

}  // namespace impm
