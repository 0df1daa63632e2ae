// Kinetic and strain energy of the particles (summed over MPI ranks). The strain energy
// density of linear elasticity is (1/2) sigma : eps with eps = D^-1 sigma in the plane (the
// out-of-plane term vanishes in both plane strain and plane stress).
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

#include "physics/LinearElastic.hpp"

namespace impm {

struct Energies {
  double kinetic = 0, strain = 0;
  double total() const { return kinetic + strain; }
};

template <class ExecSpace>
Energies particleEnergies(const ParticleSet& ps, const LinearElastic& mat, const Teuchos::Comm<int>& comm) {
  const double c11 = mat.c11(), c12 = mat.c12(), c33 = mat.c33();
  const double det = c11 * c11 - c12 * c12;  // inverse of the 2x2 normal block
  auto m = ps.mass; auto v = ps.v; auto s = ps.stress; auto V = ps.volume;
  double local[2] = {0, 0};
  Kokkos::parallel_reduce(
      "particle_energies", Kokkos::RangePolicy<ExecSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, double& ke, double& se) {
        ke += 0.5 * m(p) * (v(p, 0) * v(p, 0) + v(p, 1) * v(p, 1));
        const double exx = (c11 * s(p, 0) - c12 * s(p, 1)) / det;
        const double eyy = (c11 * s(p, 1) - c12 * s(p, 0)) / det;
        const double gxy = s(p, 2) / c33;
        se += 0.5 * V(p) * (s(p, 0) * exx + s(p, 1) * eyy + s(p, 2) * gxy);
      },
      local[0], local[1]);
  double global[2];
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 2, local, global);
  return Energies{global[0], global[1]};
}

}  // namespace impm
