// The particle-grid loop skeletons, written once (after Cabana::Grid's interpolation): a kernel
// supplies only what one particle does with its stencil.
//   scatterToGrid:      p2g into a ghosted grid view through a Kokkos ScatterView (duplicated
//                       per thread on OpenMP, atomic on GPUs); body(p, stencil, access).
//   gatherFromGrid:     g2p; body(p, stencil).
// Inside a body, ParticleStencil::forEachNode(ix, f(n, w, grad)) visits the nodes. Both are
// templated on the dimension Dim (2 or 3) of the particle set.
#pragma once

#include <Kokkos_ScatterView.hpp>

#include <utility>

#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"

namespace impm {

// The g2p loops' schedule: chunks of 1024 particles, stolen by a thread that has finished its own
// share. A static split into one block per thread left a thread idle for up to 40% of the
// explicit G2P when the other's half of the particles ran slower (measured on the 2D benchmark
// bar, 2 threads). A gather writes each particle on its own, so its result does not depend on
// which thread ran it; the scatter keeps the static split, which keeps a run bit-for-bit
// reproducible at a given thread count (its per-thread partial sums would otherwise change).
template <class ExecSpace>
Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>> gatherPolicy(int count) {
  return Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(0, count, Kokkos::ChunkSize(1024));
}

// The per-thread copies that scatterToGrid accumulates into, kept between calls for each grid
// view type and re-allocated only when the grid's extents change: the explicit stepper scatters
// every step, and allocating them each time cost a fresh mapping (page faults) and a memset per
// step. Released before Kokkos finalises.
template <class GridView>
class ScatterBuffer {
 public:
  using Scatter = decltype(Kokkos::Experimental::create_scatter_view(std::declval<GridView>()));
  // Copies for `grid`'s extents, zeroed.
  static Scatter& zeroedFor(const GridView& grid) {
    static ScatterBuffer buffer;
    if (!buffer.view_.is_allocated() || grid.extent(0) != buffer.extent_[0] || grid.extent(1) != buffer.extent_[1]) {
      if (!buffer.releaseAtFinalize_) {
        Kokkos::push_finalize_hook([] { buffer.view_ = Scatter(); });
        buffer.releaseAtFinalize_ = true;
      }
      buffer.view_ = Kokkos::Experimental::create_scatter_view(grid);  // zeroed by its constructor
      buffer.extent_[0] = grid.extent(0);
      buffer.extent_[1] = grid.extent(1);
    } else {
      buffer.view_.reset();
    }
    return buffer.view_;
  }

 private:
  Scatter view_;
  size_t extent_[2] = {0, 0};
  bool releaseAtFinalize_ = false;
};

template <class ExecSpace, class Shape, int Dim, class GridView, class Body>
void scatterToGrid(const char* label, const StructuredGrid& g, const ParticleSet& ps, const GridView& grid,
                   const Body& body) {
  static_assert(GridView::rank == 2, "scatterToGrid: a grid view is nodes x columns");
  auto sv = ScatterBuffer<GridView>::zeroedFor(grid);
  const FixedParticleViews<Dim> pv(ps);
  auto x = pv.x; auto hs = pv.halfSize;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps);
  const StencilGrid sg(g);
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape, Dim> st(sg, x, hs, deformation, p);
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
  const StencilGrid sg(g);
  Kokkos::parallel_for(
      label, gatherPolicy<ExecSpace>(ps.count), KOKKOS_LAMBDA(int p) {
        const ParticleStencil<Shape, Dim> st(sg, x, hs, deformation, p);
        body(p, st);
      });
}

}  // namespace impm
