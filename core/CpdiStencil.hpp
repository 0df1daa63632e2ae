// The CPDI1 stencil (Sadeghirad, Brannon & Burghardt 2011, IJNME 86): ParticleStencil<Cpdi, Dim>
// with the interface the kernels use (first[], count[], forEachNode, forEachOffset).
//
// The particle domain is the parallelogram / parallelepiped x_p + sum_i xi_i r_i, xi in [-1, 1]^Dim,
// spanned by r_i = F l0_i e_i (column i of F times the initial half size l0_i = halfSize(p, i)).
// With s^c in {-1, 1}^Dim a corner's signs and x_c = x_p + R s^c (R = [r_1 ... r_Dim]):
//   S_ip      = 2^-Dim sum_c N_i(x_c)
//   grad S_ip = 2^-Dim sum_c N_i(x_c) R^-T s^c
// N_i the linear tent. The gradient is the exact domain average of grad of the multilinear
// interpolant of the corner values (divergence theorem over the faces), the paper's closed form
// (its eq. for 2D with x1..x4 = (-,-), (+,-), (+,+), (-,+) is this one written out). Since the tents
// reproduce linear fields, sum S = 1, sum grad S = 0, sum S x_i = x_p and sum grad S x_i^T = I.
//
// The nodes are the union of the corner cells' nodes: a dense box of at most Cpdi::max_nodes_1d
// = 4 nodes per direction (corners within 3 cells). Beyond that the box keeps its first 4 nodes
// (weights are lost) and `capped` is set; the run loop stops such a run with a message naming
// the particle (Simulation::checkParticlesInReach). Grid edge: every corner is clipped to the
// grid (like uGIMP clips its domain), which keeps sum S = 1 and sum grad S = 0.
#pragma once

#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"
#include "core/SmallMatrix.hpp"

namespace impm {

template <int Dim>
struct ParticleStencil<Cpdi, Dim> {
  static_assert(Dim == 2 || Dim == 3, "impm grids are 2D or 3D");
  static constexpr int N = Cpdi::max_nodes_1d;
  static constexpr int dim = Dim;
  static constexpr int boxNodes = Dim == 2 ? N * N : N * N * N;
  int first[Dim];
  int count[Dim];
  bool capped;              // the corners' cells needed more than N nodes in some direction
  double w[boxNodes];       // weights, dense over the box: node (a, b[, c]) at a + N (b + N c)
  double g[boxNodes][Dim];  // gradient weights

  // From the particle views: position(p, d), halfSize(p, d) (the initial half sizes) and F(p, i, j).
  template <class PositionView, class SizeView, class DeformationView>
  KOKKOS_INLINE_FUNCTION ParticleStencil(const StructuredGrid& grid, const PositionView& position,
                                         const SizeView& halfSize, const DeformationView& F, int p)
      : ParticleStencil(StencilGrid(grid), position, halfSize, F, p) {}
  // The same with the inverse cell sizes computed once for the kernel (StencilGrid).
  template <class PositionView, class SizeView, class DeformationView>
  KOKKOS_INLINE_FUNCTION ParticleStencil(const StencilGrid& grid, const PositionView& position,
                                         const SizeView& halfSize, const DeformationView& F, int p) {
    double xc[Dim], r[Dim][Dim];
    for (int d = 0; d < Dim; ++d) {
      xc[d] = position(p, d);
      for (int i = 0; i < Dim; ++i) r[i][d] = F(p, d, i) * halfSize(p, i);
    }
    build(grid, xc, r);
  }
  // From coordinates (tests): centre xc[d], initial half sizes l[i], F row-major (F[Dim i + j]).
  KOKKOS_INLINE_FUNCTION
  ParticleStencil(const StructuredGrid& grid, const double* xc, const double* l, const double* F) {
    double x[Dim], r[Dim][Dim];
    for (int d = 0; d < Dim; ++d) {
      x[d] = xc[d];
      for (int i = 0; i < Dim; ++i) r[i][d] = F[Dim * d + i] * l[i];
    }
    build(StencilGrid(grid), x, r);
  }

  KOKKOS_INLINE_FUNCTION int nodes(int d) const { return count[d]; }

  template <class Fn>
  KOKKOS_INLINE_FUNCTION void forEachNode(const LocalNodeIndexer& ix, Fn&& f) const {
    if constexpr (Dim == 2) {
      for (int a = 0; a < count[0]; ++a)
        for (int b = 0; b < count[1]; ++b) {
          const int n = a + N * b;
          f(ix(first[0] + a, first[1] + b), w[n], g[n]);
        }
    } else {
      for (int a = 0; a < count[0]; ++a)
        for (int b = 0; b < count[1]; ++b)
          for (int c = 0; c < count[2]; ++c) {
            const int n = a + N * (b + N * c);
            f(ix(first[0] + a, first[1] + b, first[2] + c), w[n], g[n]);
          }
    }
  }
  template <class Fn>
  KOKKOS_INLINE_FUNCTION void forEachOffset(Fn&& f) const {
    if constexpr (Dim == 2) {
      for (int a = 0; a < count[0]; ++a)
        for (int b = 0; b < count[1]; ++b) {
          const int offset[2] = {a, b};
          const int n = a + N * b;
          f(offset, w[n], g[n]);
        }
    } else {
      for (int a = 0; a < count[0]; ++a)
        for (int b = 0; b < count[1]; ++b)
          for (int c = 0; c < count[2]; ++c) {
            const int offset[3] = {a, b, c};
            const int n = a + N * (b + N * c);
            f(offset, w[n], g[n]);
          }
    }
  }

  // 2D accessors (tests): node (a, b) of the box.
  KOKKOS_INLINE_FUNCTION int countX() const { return count[0]; }
  KOKKOS_INLINE_FUNCTION int countY() const { return count[1]; }
  KOKKOS_INLINE_FUNCTION double weight(int a, int b) const { return w[a + N * b]; }
  KOKKOS_INLINE_FUNCTION double gradX(int a, int b) const { return g[a + N * b][0]; }
  KOKKOS_INLINE_FUNCTION double gradY(int a, int b) const { return g[a + N * b][1]; }

 private:
  // r[i][d]: component d of domain vector r_i. Each corner's cell and its position in the cell
  // (in cell units, from 1/h: no division per corner) give the box and the tents.
  KOKKOS_INLINE_FUNCTION void build(const StencilGrid& grid, const double (&xp)[Dim], const double (&r)[Dim][Dim]) {
    constexpr int corners = 1 << Dim;
    constexpr double scale = 1.0 / corners;
    // The corners, clipped to the grid; the cell holding each (the last cell for a corner on the
    // last grid line) and the tents (1 - xi, xi) of its position xi in that cell.
    int cell[corners][Dim];
    double tent[corners][Dim][2];
    for (int c = 0; c < corners; ++c)
      for (int d = 0; d < Dim; ++d) {
        double x = xp[d];
        for (int i = 0; i < Dim; ++i) x += ((c >> i) & 1 ? 1.0 : -1.0) * r[i][d];
        const double lo = grid.origin(d), hi = lo + grid.cells(d) * grid.spacing(d);
        const double u = ((x < lo ? lo : x > hi ? hi : x) - lo) * grid.inverseSpacing[d];
        const int k = floorToInt(u), last = grid.cells(d) - 1;
        cell[c][d] = k < 0 ? 0 : k > last ? last : k;
        tent[c][d][0] = 1.0 - (u - cell[c][d]);
        tent[c][d][1] = u - cell[c][d];
      }
    capped = false;
    for (int d = 0; d < Dim; ++d) {
      int lo = cell[0][d], hi = lo;
      for (int c = 1; c < corners; ++c) {
        lo = cell[c][d] < lo ? cell[c][d] : lo;
        hi = cell[c][d] > hi ? cell[c][d] : hi;
      }
      first[d] = lo;
      count[d] = hi - lo + 2;
      if (count[d] > N) {
        count[d] = N;
        capped = true;
      }
    }
    for (int n = 0; n < boxNodes; ++n) {
      w[n] = 0.0;
      for (int d = 0; d < Dim; ++d) g[n][d] = 0.0;
    }
    // R^-T (R's columns are the r_i): row d of R^-T s is sum_i (R^-1)_id s_i.
    double R[Dim][Dim], Rinv[Dim][Dim];
    for (int d = 0; d < Dim; ++d)
      for (int i = 0; i < Dim; ++i) R[d][i] = r[i][d];
    inverse<Dim>(R, determinant<Dim>(R), Rinv);
    for (int c = 0; c < corners; ++c) {
      double coef[Dim];  // 2^-Dim R^-T s^c
      for (int d = 0; d < Dim; ++d) {
        double v = 0.0;
        for (int i = 0; i < Dim; ++i) v += Rinv[i][d] * ((c >> i) & 1 ? 1.0 : -1.0);
        coef[d] = scale * v;
      }
      for (int k = 0; k < corners; ++k) {  // the corner cell's 2^Dim nodes
        double Nk = 1.0;
        int n = 0, stride = 1;
        bool inside = true;
        for (int d = 0; d < Dim; ++d) {
          const int bit = (k >> d) & 1, offset = cell[c][d] + bit - first[d];
          Nk *= tent[c][d][bit];
          inside = inside && offset < N;
          n += stride * offset;
          stride *= N;
        }
        if (!inside) continue;  // only when capped
        w[n] += scale * Nk;
        for (int d = 0; d < Dim; ++d) g[n][d] += Nk * coef[d];
      }
    }
  }
};

// CPDI's stencil reads F (see DomainDeformation in ParticleStencil.hpp).
template <int Dim>
struct DomainDeformation<Cpdi, Dim> {
  static typename FixedParticleViews<Dim>::Mat of(const ParticleSet& ps) {
    return typename FixedParticleViews<Dim>::Mat(ps.F.data(), ps.F.extent(0));
  }
};

}  // namespace impm
