// The particle-grid loop skeletons, written once (after Cabana::Grid's interpolation): a kernel
// supplies only what one particle does with its stencil.
//   scatterToGrid:      p2g into a ghosted grid view through a Kokkos ScatterView (duplicated
//                       per thread on OpenMP, atomic on GPUs); body(p, stencil, access).
//   gatherFromGrid:     g2p; body(p, stencil).
// Inside a body, ParticleStencil::forEachNode(ix, f(n, w, grad)) visits the nodes. Both are
// templated on the dimension Dim (2 or 3) of the particle set.
#pragma once

#include <Kokkos_ScatterView.hpp>

#include <type_traits>
#include <utility>

#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"

namespace impm {

// The particle loops' partition: on OpenMP, Kokkos splits a range into one contiguous block of
// chunks per thread, the scatter's statically and the gather's as the start of its work stealing.
// Both use chunks of kParticleChunk particles, so that a thread's block is the same in both and a
// particle's fields stay in the cache of the thread that updates them (a mismatch moved about a
// thousand particles' lines between the two threads' caches twice per step).
constexpr int kParticleChunk = 1024;

// The g2p loops' schedule: chunks of kParticleChunk particles, stolen by a thread that has
// finished its own share. A static split into one block per thread left a thread idle for up to
// 40% of the explicit G2P when the other's half of the particles ran slower (measured on the 2D
// benchmark bar, 2 threads). A gather writes each particle on its own, so its result does not
// depend on which thread ran it; the scatter keeps the static split, which keeps a run bit-for-bit
// reproducible at a given thread count (its per-thread partial sums would otherwise change).
template <class ExecSpace>
Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>> gatherPolicy(int count) {
  return Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>(0, count, Kokkos::ChunkSize(kParticleChunk));
}
template <class ExecSpace>
Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Static>> scatterPolicy(int count) {
  return Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Static>>(0, count, Kokkos::ChunkSize(kParticleChunk));
}

// Grid passes split by node rows: every loop over a grid view's rows gives each thread the same
// contiguous block of rows. Particles are stored in cell order (x slowest, like the rows), so a
// thread's particle block touches nearly the same rows as its row block, and the grid lines it
// writes stay in its own cache. Kokkos' own fills and ScatterView reductions run over the flat
// array instead, which for the column-major Tpetra views gives a thread a block of columns over
// all nodes: on a host whose two cores do not share a cache, that cross traffic cost the 2D
// explicit G2P about 0.3 ms per step (20% at 2 threads).
//
// forEachRowBlock runs f(begin, end) over blocks of kRowBlock consecutive rows, split statically among the
// threads. Within a block the loops run down the columns (contiguous in the column-major views),
// which keeps them vectorised.
constexpr int kRowBlock = 256;
template <class ExecSpace, class F>
void forEachRowBlock(const char* label, size_t rows, const F& f) {
  const int blocks = int((rows + kRowBlock - 1) / kRowBlock);
  Kokkos::parallel_for(
      label, Kokkos::RangePolicy<ExecSpace>(0, blocks), KOKKOS_LAMBDA(int b) {
        const size_t begin = size_t(b) * kRowBlock, end = begin + kRowBlock < rows ? begin + kRowBlock : rows;
        f(begin, end);
      });
}

template <class ExecSpace, class GridView>
void zeroGridRows(const GridView& grid) {
  forEachRowBlock<ExecSpace>(
      "zero_grid_rows", grid.extent(0), KOKKOS_LAMBDA(size_t begin, size_t end) {
        for (size_t c = 0; c < grid.extent(1); ++c)
          for (size_t n = begin; n < end; ++n) grid(n, c) = 0.0;
      });
}

// The Kokkos ScatterView of a grid view, with its per-thread copies zeroed and summed by node
// rows (above) when it has copies. The sum adds the copies in Kokkos' order (dest + copy 0 +
// copy 1 ...), so results are bit for bit those of Kokkos::Experimental::contribute.
template <class GridView>
class RowScatterView : public decltype(Kokkos::Experimental::create_scatter_view(std::declval<GridView>())) {
 public:
  using Base = decltype(Kokkos::Experimental::create_scatter_view(std::declval<GridView>()));
  using ExecSpace = typename GridView::execution_space;
  static constexpr bool kDuplicated =
      std::is_same<typename Kokkos::Impl::Experimental::DefaultDuplication<ExecSpace>::type,
                   Kokkos::Experimental::ScatterDuplicated>::value &&
      std::is_same<typename GridView::array_layout, Kokkos::LayoutLeft>::value;

  RowScatterView() = default;
  explicit RowScatterView(const GridView& grid) : Base(grid) {}

  void resetRows() {
    if constexpr (kDuplicated) {
      auto copies = this->internal_view;  // (node, column, copy)
      forEachRowBlock<ExecSpace>(
          "scatter_reset_rows", copies.extent(0), KOKKOS_LAMBDA(size_t begin, size_t end) {
            for (size_t t = 0; t < copies.extent(2); ++t)
              for (size_t c = 0; c < copies.extent(1); ++c)
                for (size_t n = begin; n < end; ++n) copies(n, c, t) = 0.0;
          });
    } else {
      this->reset();
    }
  }

  void contributeRows(const GridView& dest) const {
    if constexpr (kDuplicated) {
      auto copies = this->internal_view;
      forEachRowBlock<ExecSpace>(
          "scatter_contribute_rows", dest.extent(0), KOKKOS_LAMBDA(size_t begin, size_t end) {
            for (size_t c = 0; c < dest.extent(1); ++c)
              for (size_t t = 0; t < copies.extent(2); ++t)  // copy by copy, in Kokkos' order
                for (size_t n = begin; n < end; ++n) dest(n, c) += copies(n, c, t);
          });
    } else {
      GridView target = dest;  // contribute() takes a non-const view
      Kokkos::Experimental::contribute(target, static_cast<const Base&>(*this));
    }
  }
};

// The per-thread copies that scatterToGrid accumulates into, kept between calls for each grid
// view type and re-allocated only when the grid's extents change: the explicit stepper scatters
// every step, and allocating them each time cost a fresh mapping (page faults) and a memset per
// step. Released before Kokkos finalises.
template <class GridView>
class ScatterBuffer {
 public:
  using Scatter = RowScatterView<GridView>;
  // Copies for `grid`'s extents, zeroed.
  static Scatter& zeroedFor(const GridView& grid) {
    static ScatterBuffer buffer;
    if (!buffer.view_.is_allocated() || grid.extent(0) != buffer.extent_[0] || grid.extent(1) != buffer.extent_[1]) {
      if (!buffer.releaseAtFinalize_) {
        Kokkos::push_finalize_hook([] { buffer.view_ = Scatter(); });
        buffer.releaseAtFinalize_ = true;
      }
      buffer.view_ = Scatter(grid);  // zeroed by its constructor
      buffer.extent_[0] = grid.extent(0);
      buffer.extent_[1] = grid.extent(1);
    } else {
      buffer.view_.resetRows();
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
  auto x = pv.x;
  auto hs = pv.halfSize;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps);
  const StencilGrid sg(g);
  Kokkos::parallel_for(
      label, scatterPolicy<ExecSpace>(ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape, Dim> st(sg, x, hs, deformation, p);
        body(p, st, out);
      });
  sv.contributeRows(grid);
}

template <class ExecSpace, class Shape, int Dim, class Body>
void gatherFromGrid(const char* label, const StructuredGrid& g, const ParticleSet& ps, const Body& body) {
  const FixedParticleViews<Dim> pv(ps);
  auto x = pv.x;
  auto hs = pv.halfSize;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps);
  const StencilGrid sg(g);
  Kokkos::parallel_for(
      label, gatherPolicy<ExecSpace>(ps.count), KOKKOS_LAMBDA(int p) {
        const ParticleStencil<Shape, Dim> st(sg, x, hs, deformation, p);
        body(p, st);
      });
}

}  // namespace impm
