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
  double momentum[3] = {0, 0, 0};
  // sum_p m_p |v_p|: the scale against which a change of the total momentum is measured (the
  // total itself is zero for bodies colliding head-on).
  double momentumScale = 0;
  double total() const { return kinetic + strain; }
};

template <class ExecSpace, int Dim, class Law>
ParticleTotals particleTotals(const ParticleSet& ps, const Law& law, const Teuchos::Comm<int>& comm) {
  auto m = ps.mass;
  auto v = ps.v;
  auto s = ps.stress;
  auto V = ps.volume;
  auto matId = ps.material;
  auto F = FixedParticleViews<Dim>(ps).F;
  auto hist = ps.history;
  double local[6] = {0, 0, 0, 0, 0, 0};
  Kokkos::parallel_reduce(
      "particle_totals", Kokkos::RangePolicy<ExecSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, double& ke, double& se, double& px, double& py, double& pz, double& scale) {
        double speed2 = 0;
        for (int d = 0; d < Dim; ++d) speed2 += v(p, d) * v(p, d);
        ke += 0.5 * m(p) * speed2;
        double sp[StressLayout<Dim>::count];
        for (int c = 0; c < StressLayout<Dim>::count; ++c) sp[c] = s(p, c);
        double Fp[Dim][Dim];
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j) Fp[i][j] = F(p, i, j);
        double h[ParticleSet::kHistoryCount] = {};
        if (law.hasHistory(matId(p)))
          for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = hist(p, i);
        se += V(p) * law.template energyDensity<Dim>(matId(p), sp, Fp, h);
        px += m(p) * v(p, 0);
        py += m(p) * v(p, 1);
        if (Dim == 3) pz += m(p) * v(p, Dim - 1);
        scale += m(p) * std::sqrt(speed2);
      },
      local[0], local[1], local[2], local[3], local[4], local[5]);
  double global[6];
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 6, local, global);
  ParticleTotals t;
  t.kinetic = global[0];
  t.strain = global[1];
  t.momentum[0] = global[2];
  t.momentum[1] = global[3];
  t.momentum[2] = global[4];
  t.momentumScale = global[5];
  return t;
}

}  // namespace impm
