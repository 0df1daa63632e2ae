// The run loop's check on CPDI domains (after each step's migration): a domain whose corners
// need more than Cpdi::max_nodes_1d nodes in some direction (stretched or sheared across more
// than 3 cells), or whose stencil reaches beyond the box of nodes its MPI rank sees.
#pragma once

#include <Kokkos_Core.hpp>

#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"

namespace impm {

struct CpdiDomainReport {
  int tooLarge = 0, outOfReach = 0;
  long long firstId = -1;  // the lowest global id among the particles counted (this rank)
};

template <class ExecSpace, int Dim>
CpdiDomainReport checkCpdiDomains(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps) {
  const FixedParticleViews<Dim> pv(ps);
  auto x = pv.x;
  auto hs = pv.halfSize;
  const auto F = DomainDeformation<Cpdi, Dim>::of(ps);
  auto id = ps.id;
  auto outside = KOKKOS_LAMBDA(int p, bool& capped, bool& beyond) {
    const ParticleStencil<Cpdi, Dim> st(g, x, hs, F, p);
    capped = st.capped;
    beyond = false;
    for (int d = 0; d < Dim; ++d) beyond = beyond || st.first[d] < ix.lo[d] || st.first[d] + st.count[d] > ix.end(d);
  };
  CpdiDomainReport r;
  Kokkos::parallel_reduce(
      "check_cpdi_domains", Kokkos::RangePolicy<ExecSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, int& large, int& reach) {
        bool capped, beyond;
        outside(p, capped, beyond);
        large += capped;
        reach += beyond;
      },
      r.tooLarge, r.outOfReach);
  if (r.tooLarge + r.outOfReach == 0) return r;
  long long lowest = 0;
  Kokkos::parallel_reduce(
      "check_cpdi_domains_id", Kokkos::RangePolicy<ExecSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, long long& low) {
        bool capped, beyond;
        outside(p, capped, beyond);
        if ((capped || beyond) && id(p) < low) low = id(p);
      },
      Kokkos::Min<long long>(lowest));
  r.firstId = lowest;
  return r;
}

}  // namespace impm
