// The nodes a particle talks to, with tensor-product weights and gradient weights,
// computed from a 1D shape-function trait (LinearMpm, UniformGimp or QuadraticLagrange).
#pragma once

#include "core/ShapeFunctions.hpp"
#include "core/StructuredGrid.hpp"

namespace impm {

template <class Shape>
struct ParticleStencil {
  static constexpr int N = Shape::max_nodes_1d;
  int i0 = 0, j0 = 0, ni = 0, nj = 0;
  double wx[N], gx[N], wy[N], gy[N];

  // (x, y): particle centre; (lx, ly): half sizes of its domain (clipped to the grid, see build1d).
  KOKKOS_INLINE_FUNCTION
  ParticleStencil(const StructuredGrid& g, double x, double y, double lx, double ly) {
    build1d(x, g.x0, g.hx, lx, g.nx, i0, ni, wx, gx);
    build1d(y, g.y0, g.hy, ly, g.ny, j0, nj, wy, gy);
  }

  // Node counts per direction; compile-time constants for shapes with a fixed count, so that
  // kernels' loops unroll.
  KOKKOS_INLINE_FUNCTION int countX() const { return Shape::fixed_count ? N : ni; }
  KOKKOS_INLINE_FUNCTION int countY() const { return Shape::fixed_count ? N : nj; }

  // f(n, w, dwdx, dwdy) for every node of the stencil: n its local index in `ix`, w = S_ip and
  // (dwdx, dwdy) = grad S_ip. The one loop over a particle's nodes; kernels plug in the rest.
  template <class F>
  KOKKOS_INLINE_FUNCTION void forEachNode(const LocalNodeIndexer& ix, F&& f) const {
    for (int a = 0; a < countX(); ++a)
      for (int b = 0; b < countY(); ++b) f(ix(i0 + a, j0 + b), weight(a, b), gradX(a, b), gradY(a, b));
  }

  KOKKOS_INLINE_FUNCTION double weight(int a, int b) const { return wx[a] * wy[b]; }
  KOKKOS_INLINE_FUNCTION double gradX(int a, int b) const { return gx[a] * wy[b]; }
  KOKKOS_INLINE_FUNCTION double gradY(int a, int b) const { return wx[a] * gy[b]; }

 private:
  KOKKOS_INLINE_FUNCTION static void build1d(double x, double origin, double h, double l, int ncells,
                                             int& first, int& count, double* w, double* gr) {
    if (!Shape::fixed_count) {
      // A particle domain is clipped to the grid: the grid's edge is the body's boundary. The
      // clipped domain's functions keep the partition of unity (sum w = 1, sum grad = 0), so
      // rigid motion stays strain-free and mass, force and stiffness see the same domain.
      // (Dropping the nodes beyond the edge instead lost both, and a GIMP body that filled the
      // grid vibrated up to 3 times too fast; issue 12.)
      const double end = origin + ncells * h;
      if (x - l < origin || x + l > end) {  // rare: only domains across the edge change
        const double lo = x - l > origin ? x - l : origin;
        const double hi = x + l < end ? x + l : end;
        if (!(hi > lo)) { first = 0; count = 0; return; }  // wholly outside (the run loop stops)
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
      if (first < 0) { count += first; first = 0; }
      if (first + count > ncells + 1) count = ncells + 1 - first;
    }
    for (int a = 0; a < count; ++a) {
      const double r = x - (origin + (first + a) * h);
      w[a] = Shape::value(r, h, l, first + a);
      gr[a] = Shape::gradient(r, h, l, first + a);
    }
  }
};

}  // namespace impm
