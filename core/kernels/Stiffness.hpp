// Stiffness contributions K_e = int B^T D B, assembled over blocks of grid nodes.
//
// Two ways to integrate, both as Kokkos kernels that fill one small dense matrix per entry:
//  - overlapStiffness (the seed's GIMP stiffness, slide 6): one entry per particle-cell pair.
//    The particle's D is spread over its domain (chi_p) and the integral is exact: on one cell
//    the integrand is a polynomial of degree <= 2 in x and in y, so 2 x 2 Gauss-Legendre
//    points on the overlap box integrate it exactly. Block = the cell's 2 x 2 nodes.
//  - stencilStiffness: one entry per particle, V_p B_p^T D B_p with B_p from the particle's
//    stencil gradients. For MPM and the FE modes the particle is an integration point (point
//    gradients; the FE reference's particles are Gauss points with their weights as volumes);
//    for GIMP it uses the averaged gradients and is then the exact derivative of the GIMP
//    internal force (the seed's integrated stiffness is not). Block = the stencil's nodes.
// Local dof of block node (a, b): 2 (a + blockNodesX b) + component.
#pragma once

#include "core/ParticleCellPairs.hpp"
#include "core/ParticleStencil.hpp"

namespace impm {

// Per entry: the block's first node (i, j) and its dense matrix over the block's dofs.
struct BlockMatrices {
  int count = 0;
  int blockNodesX = 2, blockNodesY = 2;  // nodes per direction of a block
  Kokkos::View<int* [2], Kokkos::LayoutRight, DeviceType> origin;
  Kokkos::View<double***, Kokkos::LayoutRight, DeviceType> K;
  int dofs() const { return 2 * blockNodesX * blockNodesY; }
};

namespace detail {
// K(k) += w B^T D B for node gradients (gx, gy) of the block's nodes (nn of them), with the
// material tangent D on (eps_xx, eps_yy, 2 eps_xy).
template <class KView>
KOKKOS_INLINE_FUNCTION void addBtDB(const KView& K, int k, int nn, const double* gx, const double* gy, double w,
                                    const double D[3][3]) {
  for (int a = 0; a < nn; ++a) {
    // D B_a for B_a = [[gx, 0], [0, gy], [gy, gx]]: columns for the a's x and y dofs.
    double DBx[3], DBy[3];
    for (int r = 0; r < 3; ++r) {
      DBx[r] = D[r][0] * gx[a] + D[r][2] * gy[a];
      DBy[r] = D[r][1] * gy[a] + D[r][2] * gx[a];
    }
    for (int b = 0; b < nn; ++b) {
      // B_b^T (D B_a): rows for b's x and y dofs. K is symmetric for a symmetric D.
      K(k, 2 * b, 2 * a) += w * (gx[b] * DBx[0] + gy[b] * DBx[2]);
      K(k, 2 * b, 2 * a + 1) += w * (gx[b] * DBy[0] + gy[b] * DBy[2]);
      K(k, 2 * b + 1, 2 * a) += w * (gy[b] * DBx[1] + gx[b] * DBx[2]);
      K(k, 2 * b + 1, 2 * a + 1) += w * (gy[b] * DBy[1] + gx[b] * DBy[2]);
    }
  }
}
}  // namespace detail

template <class ExecSpace, class Law>
BlockMatrices overlapStiffness(const StructuredGrid& g, const ParticleCellPairs& pairs, const ParticleSet& ps,
                               const Law& law) {
  BlockMatrices out;
  out.count = pairs.count;
  out.blockNodesX = out.blockNodesY = 2;
  out.origin = pairs.cell;
  out.K = Kokkos::View<double***, Kokkos::LayoutRight, DeviceType>("overlap_stiffness", pairs.count, 8, 8);
  auto P = pairs.particle; auto C = pairs.cell; auto B = pairs.box;
  auto V = ps.volume; auto hs = ps.halfSize; auto matId = ps.material; auto x = ps.x;
  auto K = out.K;
  Kokkos::parallel_for(
      "overlap_stiffness", Kokkos::RangePolicy<ExecSpace>(0, pairs.count), KOKKOS_LAMBDA(int k) {
        const int p = P(k);
        const double cx = g.x0 + C(k, 0) * g.hx, cy = g.y0 + C(k, 1) * g.hy;
        // Gauss points +-1/sqrt(3) on the box; weight = box area / 4 * thickness of the particle.
        const double a = B(k, 0), b = B(k, 1), c = B(k, 2), d = B(k, 3);
        const double s = 0.5773502691896257;
        const double qx[2] = {0.5 * (a + b) - 0.5 * (b - a) * s, 0.5 * (a + b) + 0.5 * (b - a) * s};
        const double qy[2] = {0.5 * (c + d) - 0.5 * (d - c) * s, 0.5 * (c + d) + 0.5 * (d - c) * s};
        // The particle's volume over its domain clipped to the grid (the boxes are clipped too,
        // as the stencils are; see ParticleStencil::build1d).
        const double clippedWidth = detail::minOf(x(p, 0) + hs(p, 0), g.xMax()) - detail::maxOf(x(p, 0) - hs(p, 0), g.x0);
        const double clippedHeight = detail::minOf(x(p, 1) + hs(p, 1), g.yMax()) - detail::maxOf(x(p, 1) - hs(p, 1), g.y0);
        const double thickness = V(p) / (clippedWidth * clippedHeight);
        const double wq = 0.25 * (b - a) * (d - c) * thickness;
        double D[3][3];
        law.tangent(matId(p), D);
        for (int ix = 0; ix < 2; ++ix)
          for (int iy = 0; iy < 2; ++iy) {
            const double xi = (qx[ix] - cx) / g.hx, eta = (qy[iy] - cy) / g.hy;
            const double Nx[2] = {1.0 - xi, xi}, Ny[2] = {1.0 - eta, eta};
            const double dNx[2] = {-1.0 / g.hx, 1.0 / g.hx}, dNy[2] = {-1.0 / g.hy, 1.0 / g.hy};
            double gx[4], gy[4];
            for (int dj = 0; dj < 2; ++dj)
              for (int di = 0; di < 2; ++di) {
                gx[di + 2 * dj] = dNx[di] * Ny[dj];
                gy[di + 2 * dj] = Nx[di] * dNy[dj];
              }
            detail::addBtDB(K, k, 4, gx, gy, wq, D);
          }
      });
  return out;
}

// Blocks are Shape::max_nodes_1d nodes wide (fewer on a grid with fewer node lines); a stencil
// shorter than that (GIMP near a cell line) sits inside the block, which is shifted to stay
// inside the grid. With massFactor c > 0
// the block also gets c times the particle's consistent mass, c m_p S_ap S_bp per component.
template <class ExecSpace, class Shape, class Law>
BlockMatrices stencilStiffness(const StructuredGrid& g, const ParticleSet& ps, const Law& law,
                               double massFactor = 0.0) {
  constexpr int bn = Shape::max_nodes_1d;
  const int bnx = bn < g.nx + 1 ? bn : g.nx + 1, bny = bn < g.ny + 1 ? bn : g.ny + 1;
  const int nd = 2 * bnx * bny;
  BlockMatrices out;
  out.count = ps.count;
  out.blockNodesX = bnx;
  out.blockNodesY = bny;
  out.origin = decltype(out.origin)("stencil_block_origin", ps.count);
  out.K = Kokkos::View<double***, Kokkos::LayoutRight, DeviceType>("stencil_stiffness", ps.count, nd, nd);
  auto O = out.origin; auto K = out.K;
  auto x = ps.x; auto hs = ps.halfSize; auto V = ps.volume; auto m = ps.mass; auto matId = ps.material;
  Kokkos::parallel_for(
      "stencil_stiffness", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        const int bi = st.i0 < g.nx + 1 - bnx ? st.i0 : g.nx + 1 - bnx;
        const int bj = st.j0 < g.ny + 1 - bny ? st.j0 : g.ny + 1 - bny;
        O(p, 0) = bi;
        O(p, 1) = bj;
        double gx[bn * bn], gy[bn * bn], w[bn * bn];
        for (int n = 0; n < bn * bn; ++n) gx[n] = gy[n] = w[n] = 0.0;
        for (int a = 0; a < st.countX(); ++a)
          for (int b = 0; b < st.countY(); ++b) {
            const int n = (st.i0 + a - bi) + bnx * (st.j0 + b - bj);
            gx[n] = st.gradX(a, b);
            gy[n] = st.gradY(a, b);
            w[n] = st.weight(a, b);
          }
        for (int r = 0; r < nd; ++r)
          for (int c = 0; c < nd; ++c) K(p, r, c) = 0.0;
        double D[3][3];
        law.tangent(matId(p), D);
        detail::addBtDB(K, p, bnx * bny, gx, gy, V(p), D);
        if (massFactor > 0.0)
          for (int a = 0; a < bnx * bny; ++a)
            for (int b = 0; b < bnx * bny; ++b)
              for (int c = 0; c < 2; ++c) K(p, 2 * a + c, 2 * b + c) += massFactor * m(p) * w[a] * w[b];
      });
  return out;
}

}  // namespace impm
