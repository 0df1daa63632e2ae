// The particle-grid loop skeletons, written once (after Cabana::Grid's interpolation): a kernel
// supplies only what one particle does with its stencil.
//   scatterToGrid:      p2g into a ghosted grid view through a Kokkos ScatterView (duplicated
//                       per thread on OpenMP, atomic on GPUs); body(p, stencil, access).
//   gatherFromGrid:     g2p; body(p, stencil).
// Inside a body, ParticleStencil::forEachNode(ix, f(n, w, grad)) visits the nodes. Both are
// templated on the dimension Dim (2 or 3) of the particle set.
#pragma once

#include <Kokkos_ScatterView.hpp>

#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"

namespace impm {

template <class ExecSpace, class Shape, int Dim, class GridView, class Body>
void scatterToGrid(const char* label, const StructuredGrid& g, const ParticleSet& ps, const GridView& grid,
                   const Body& body) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  const FixedParticleViews<Dim> pv(ps);
  auto x = pv.x; auto hs = pv.halfSize;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps);
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape, Dim> st(g, x, hs, deformation, p);
        body(p, st, out);
      });
  GridView dest = grid;  // contribute() takes a non-const view
  Kokkos::Experimental::contribute(dest, sv);
}

template <class ExecSpace, class Shape, int Dim, class Body>
void gatherFromGrid(const char* label, const StructuredGrid& g, const ParticleSet& ps, const Body& body) {
  const FixedParticleViews<Dim> pv(ps);
  auto x = pv.x; auto hs = pv.halfSize;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps);
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        const ParticleStencil<Shape, Dim> st(g, x, hs, deformation, p);
        body(p, st);
      });
}

}  // namespace impm
