// The particle-cell pairs: for every particle, each grid cell its domain overlaps, with the
// overlap box. GIMP integrals over a particle's domain (weights, and the implicit stiffness
// K = sum_p D_p int_{Omega_p} B^T B) are sums over these boxes, on each of which the
// integrand is a polynomial that separates in x and y. For MPM a particle is a point: one
// pair, a degenerate box, in the cell that contains it.
#pragma once

#include "core/ParticleSet.hpp"
#include "core/ShapeFunctions.hpp"
#include "core/StructuredGrid.hpp"

namespace impm {

struct ParticleCellPairs {
  int count = 0;
  Kokkos::View<int*, DeviceType> particle;                         // particle of each pair
  Kokkos::View<int* [2], Kokkos::LayoutRight, DeviceType> cell;    // cell (i, j)
  Kokkos::View<double* [4], Kokkos::LayoutRight, DeviceType> box;  // xlo, xhi, ylo, yhi
};

namespace detail {
KOKKOS_INLINE_FUNCTION double maxOf(double a, double b) { return a > b ? a : b; }
KOKKOS_INLINE_FUNCTION double minOf(double a, double b) { return a < b ? a : b; }
// Cells [first, last] covered by [lo, hi] in one direction, clamped to the grid. A domain edge
// on a grid line does not overlap the next cell.
KOKKOS_INLINE_FUNCTION void cellSpan(double lo, double hi, double origin, double h, int n, int& first, int& last) {
  first = floorToInt((lo - origin) / h);
  last = floorToInt((hi - origin) / h);
  if (last > first && origin + last * h >= hi) --last;
  first = first < 0 ? 0 : (first > n - 1 ? n - 1 : first);
  last = last < 0 ? 0 : (last > n - 1 ? n - 1 : last);
}
}  // namespace detail

template <class ExecSpace>
ParticleCellPairs buildParticleCellPairs(const StructuredGrid& g, const ParticleSet& ps, bool pointParticles) {
  auto x = ps.x;
  auto hs = ps.halfSize;
  using detail::cellSpan;
  using detail::maxOf;
  using detail::minOf;
  Kokkos::View<int*, DeviceType> offsets("pair_offsets", ps.count + 1);
  Kokkos::parallel_for(
      "pair_count", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        const double lx = pointParticles ? 0.0 : hs(p, 0), ly = pointParticles ? 0.0 : hs(p, 1);
        int i0, i1, j0, j1;
        cellSpan(x(p, 0) - lx, x(p, 0) + lx, g.x0, g.hx, g.nx, i0, i1);
        cellSpan(x(p, 1) - ly, x(p, 1) + ly, g.y0, g.hy, g.ny, j0, j1);
        offsets(p + 1) = (i1 - i0 + 1) * (j1 - j0 + 1);
      });
  int total = 0;
  Kokkos::parallel_scan(
      "pair_offsets", Kokkos::RangePolicy<ExecSpace>(0, ps.count + 1),
      KOKKOS_LAMBDA(int p, int& sum, bool final) {
        const int c = offsets(p);
        sum += c;
        if (final) offsets(p) = sum;
      },
      total);
  ParticleCellPairs pairs;
  pairs.count = total;
  pairs.particle = Kokkos::View<int*, DeviceType>("pair_particle", total);
  pairs.cell = decltype(pairs.cell)("pair_cell", total);
  pairs.box = decltype(pairs.box)("pair_box", total);
  auto P = pairs.particle;
  auto C = pairs.cell;
  auto B = pairs.box;
  Kokkos::parallel_for(
      "pair_fill", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        const double lx = pointParticles ? 0.0 : hs(p, 0), ly = pointParticles ? 0.0 : hs(p, 1);
        int i0, i1, j0, j1;
        cellSpan(x(p, 0) - lx, x(p, 0) + lx, g.x0, g.hx, g.nx, i0, i1);
        cellSpan(x(p, 1) - ly, x(p, 1) + ly, g.y0, g.hy, g.ny, j0, j1);
        int k = offsets(p);  // after the scan: the first pair of particle p
        for (int i = i0; i <= i1; ++i)
          for (int j = j0; j <= j1; ++j, ++k) {
            P(k) = p;
            C(k, 0) = i;
            C(k, 1) = j;
            const double cx0 = g.x0 + i * g.hx, cy0 = g.y0 + j * g.hy;
            B(k, 0) = maxOf(x(p, 0) - lx, cx0);
            B(k, 1) = minOf(x(p, 0) + lx, cx0 + g.hx);
            B(k, 2) = maxOf(x(p, 1) - ly, cy0);
            B(k, 3) = minOf(x(p, 1) + ly, cy0 + g.hy);
          }
      });
  return pairs;
}

}  // namespace impm
