// The nodes a particle talks to, with tensor-product weights and gradient weights in Dim = 2
// or 3 dimensions, computed from a 1D shape-function trait (LinearMpm, UniformGimp,
// QuadraticLagrange, QuadraticBSpline or CubicBSpline). CPDI's stencil is not a tensor product: it is the
// specialisation in CpdiStencil.hpp (included at the end).
#pragma once

#include "core/ParticleSet.hpp"
#include "core/ShapeFunctions.hpp"
#include "core/StructuredGrid.hpp"

namespace impm {

// What a shape's stencil reads besides position and half size: CPDI the deformation gradient
// (CpdiStencil.hpp), the others nothing, an empty value, so that their kernels capture and load
// nothing more. Kernels build a stencil as ParticleStencil(grid, x, halfSize, deformation, p)
// with deformation = DomainDeformation<Shape, Dim>::of(particles).
struct NoDomainDeformation {};

template <class Shape, int Dim>
struct DomainDeformation {
  static NoDomainDeformation of(const ParticleSet&) { return {}; }
};

template <class Shape, int Dim = 2>
struct ParticleStencil {
  static_assert(Dim == 2 || Dim == 3, "impm grids are 2D or 3D");
  static constexpr int N = Shape::max_nodes_1d;
  static constexpr int dim = Dim;
  int first[Dim];               // first node index per direction
  int count[Dim];               // nodes per direction
  double w[Dim][N], g[Dim][N];  // 1D weights and gradient weights per direction

  // Centre and half sizes of the particle domain (clipped to the grid, see build1d) from the
  // particle views: position(p, d), halfSize(p, d).
  template <class PositionView, class SizeView>
  KOKKOS_FORCEINLINE_FUNCTION ParticleStencil(const StructuredGrid& grid, const PositionView& position,
                                              const SizeView& halfSize, int p)
      : ParticleStencil(StencilGrid(grid), position, halfSize, NoDomainDeformation{}, p) {}
  template <class PositionView, class SizeView>
  KOKKOS_FORCEINLINE_FUNCTION ParticleStencil(const StructuredGrid& grid, const PositionView& position,
                                              const SizeView& halfSize, NoDomainDeformation, int p)
      : ParticleStencil(grid, position, halfSize, p) {}
  // The same with the inverse cell sizes computed once for the kernel (StencilGrid). Written out
  // per direction (not a loop over d) so that each direction's grid constants are plain members:
  // the 2D kernels kept their speed this way.
  template <class PositionView, class SizeView>
  KOKKOS_FORCEINLINE_FUNCTION ParticleStencil(const StencilGrid& grid, const PositionView& position,
                                              const SizeView& halfSize, NoDomainDeformation, int p) {
    const double* inv = grid.inverseSpacing;
    build1d(position(p, 0), grid.x0, grid.hx, inv[0], halfSize(p, 0), grid.nx, first[0], count[0], w[0], g[0]);
    build1d(position(p, 1), grid.y0, grid.hy, inv[1], halfSize(p, 1), grid.ny, first[1], count[1], w[1], g[1]);
    if constexpr (Dim == 3)
      build1d(position(p, 2), grid.z0, grid.hz, inv[2], halfSize(p, 2), grid.nz, first[2], count[2], w[2], g[2]);
  }
  // From coordinates: (x, y) and half sizes (lx, ly) in 2D.
  KOKKOS_FORCEINLINE_FUNCTION
  ParticleStencil(const StructuredGrid& grid, double x, double y, double lx, double ly) {
    static_assert(Dim == 2, "the (x, y, lx, ly) constructor is 2D");
    build1d(x, grid.x0, grid.hx, lx, grid.nx, first[0], count[0], w[0], g[0]);
    build1d(y, grid.y0, grid.hy, ly, grid.ny, first[1], count[1], w[1], g[1]);
  }
  // In Dim dimensions: centre xc[d] and half sizes l[d].
  KOKKOS_FORCEINLINE_FUNCTION
  ParticleStencil(const StructuredGrid& grid, const double* xc, const double* l) {
    for (int d = 0; d < Dim; ++d)
      build1d(xc[d], grid.origin(d), grid.spacing(d), l[d], grid.cells(d), first[d], count[d], w[d], g[d]);
  }

  // Node count along direction d; a compile-time constant for shapes with a fixed count, so
  // that kernels' loops unroll.
  KOKKOS_FORCEINLINE_FUNCTION int nodes(int d) const { return Shape::fixed_count ? N : count[d]; }

  // f(n, w, grad) for every node of the stencil: n its local index in `ix`, w = S_ip and
  // grad[d] = dS_ip/dx_d. The one loop over a particle's nodes; kernels plug in the rest.
  template <class F>
  KOKKOS_FORCEINLINE_FUNCTION void forEachNode(const LocalNodeIndexer& ix, F&& f) const {
    if constexpr (Dim == 2) {
      for (int a = 0; a < nodes(0); ++a)
        for (int b = 0; b < nodes(1); ++b) {
          const double grad[2] = {g[0][a] * w[1][b], w[0][a] * g[1][b]};
          f(ix(first[0] + a, first[1] + b), w[0][a] * w[1][b], grad);
        }
    } else {
      for (int a = 0; a < nodes(0); ++a)
        for (int b = 0; b < nodes(1); ++b) {
          const double wab = w[0][a] * w[1][b], gab = g[0][a] * w[1][b], wgb = w[0][a] * g[1][b];
          for (int c = 0; c < nodes(2); ++c) {
            const double grad[3] = {gab * w[2][c], wgb * w[2][c], wab * g[2][c]};
            f(ix(first[0] + a, first[1] + b, first[2] + c), wab * w[2][c], grad);
          }
        }
    }
  }
  // The same with the stencil's own node offsets (a, b, c) instead of a grid index (assembly).
  template <class F>
  KOKKOS_FORCEINLINE_FUNCTION void forEachOffset(F&& f) const {
    if constexpr (Dim == 2) {
      for (int a = 0; a < nodes(0); ++a)
        for (int b = 0; b < nodes(1); ++b) {
          const double grad[2] = {g[0][a] * w[1][b], w[0][a] * g[1][b]};
          const int offset[2] = {a, b};
          f(offset, w[0][a] * w[1][b], grad);
        }
    } else {
      for (int a = 0; a < nodes(0); ++a)
        for (int b = 0; b < nodes(1); ++b)
          for (int c = 0; c < nodes(2); ++c) {
            const double grad[3] = {g[0][a] * w[1][b] * w[2][c], w[0][a] * g[1][b] * w[2][c],
                                    w[0][a] * w[1][b] * g[2][c]};
            const int offset[3] = {a, b, c};
            f(offset, w[0][a] * w[1][b] * w[2][c], grad);
          }
    }
  }

  // 2D accessors (tests): node (a, b) of the stencil.
  KOKKOS_FORCEINLINE_FUNCTION int countX() const { return nodes(0); }
  KOKKOS_FORCEINLINE_FUNCTION int countY() const { return nodes(1); }
  KOKKOS_FORCEINLINE_FUNCTION double weight(int a, int b) const { return w[0][a] * w[1][b]; }
  KOKKOS_FORCEINLINE_FUNCTION double gradX(int a, int b) const { return g[0][a] * w[1][b]; }
  KOKKOS_FORCEINLINE_FUNCTION double gradY(int a, int b) const { return w[0][a] * g[1][b]; }

 private:
  KOKKOS_FORCEINLINE_FUNCTION static void build1d(double x, double origin, double h, double l, int ncells, int& first,
                                                  int& count, double* w, double* gr) {
    build1d(x, origin, h, 1.0 / h, l, ncells, first, count, w, gr);
  }
  // invh = 1.0 / h.
  KOKKOS_FORCEINLINE_FUNCTION static void build1d(double x, double origin, double h, double invh, double l, int ncells,
                                                  int& first, int& count, double* w, double* gr) {
    if constexpr (HasInteriorStencil<Shape>::value) {
      if (Shape::interiorStencil((x - origin) * invh, invh, ncells, first, w, gr)) {
        count = 2;
        return;
      }
    }
    if constexpr (HasDomainStencil<Shape>::value) {
      if (Shape::domainStencil((x - origin) * invh, l * invh, invh, ncells, first, count, w, gr)) return;
    }
    if (!Shape::fixed_count) {
      // A particle domain is clipped to the grid: the grid's edge is the body's boundary. The
      // clipped domain's functions keep the partition of unity (sum w = 1, sum grad = 0), so
      // rigid motion stays strain-free and mass, force and stiffness see the same domain.
      // (Dropping the nodes beyond the edge instead would lose both: a GIMP body that fills the
      // grid then vibrates up to 3 times too fast.)
      const double end = origin + ncells * h;
      if (x - l < origin || x + l > end) {  // rare: only domains across the edge change
        const double lo = x - l > origin ? x - l : origin;
        const double hi = x + l < end ? x + l : end;
        if (!(hi > lo)) {
          first = 0;
          count = 0;
          return;
        }  // wholly outside (the run loop stops)
        x = 0.5 * (lo + hi);
        l = 0.5 * (hi - lo);
      }
    }
    Shape::range((x - origin) / h, l / h, first, count);
    if (Shape::fixed_count) {
      // Keep the full stencil inside the grid (a particle on the last grid line uses the last cell).
      if (first < 0) first = 0;
      // (ncells - count + 1 is even for the quadratic element, whose ncells is even.)
      if (first > ncells - count + 1) first = ncells - count + 1;
    } else {
      // Inside the grid a node whose function the domain only touches has zero weight: drop it.
      if (first < 0) {
        count += first;
        first = 0;
      }
      if (first + count > ncells + 1) count = ncells + 1 - first;
    }
    for (int a = 0; a < count; ++a) {
      const double r = x - (origin + (first + a) * h);
      w[a] = Shape::value(r, h, l, first + a, ncells);
      gr[a] = Shape::gradient(r, h, l, first + a, ncells);
    }
  }
};

}  // namespace impm

#include "core/CpdiStencil.hpp"
