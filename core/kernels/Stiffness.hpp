// Stiffness contributions of particle-cell pairs: K_e = int B^T D B over the pair's overlap
// box. For GIMP the particle's D is spread over its domain (chi_p) and the integral is exact:
// on one cell the integrand is a polynomial of degree <= 2 in x and in y, so 2 x 2
// Gauss-Legendre points on the overlap box integrate it exactly (the seed's slide 6). For MPM
// the particle is an integration point with weight V_p.
// Local dofs of the cell (i, j): node a = di + 2 dj at (i + di, j + dj), dof 2 a + component.
#pragma once

#include "core/ParticleCellPairs.hpp"
#include "physics/LinearElastic.hpp"

namespace impm {

using PairMatrices = Kokkos::View<double* [8][8], Kokkos::LayoutRight, DeviceType>;

template <class ExecSpace>
void pairStiffness(const StructuredGrid& g, const ParticleCellPairs& pairs, const ParticleSet& ps,
                   const LinearElastic& mat, bool gimp, const PairMatrices& Ke) {
  auto P = pairs.particle; auto C = pairs.cell; auto B = pairs.box;
  auto V = ps.volume; auto hs = ps.halfSize; auto x = ps.x;
  const double c11 = mat.c11(), c12 = mat.c12(), c33 = mat.c33();
  Kokkos::parallel_for(
      "pair_stiffness", Kokkos::RangePolicy<ExecSpace>(0, pairs.count), KOKKOS_LAMBDA(int k) {
        const int p = P(k);
        const double cx = g.x0 + C(k, 0) * g.hx, cy = g.y0 + C(k, 1) * g.hy;
        double qx[2], qy[2], wq;
        int nq;
        if (gimp) {
          // Gauss points +-1/sqrt(3) on the box; weight = box area / 4 * thickness of the particle.
          const double a = B(k, 0), b = B(k, 1), c = B(k, 2), d = B(k, 3);
          const double s = 0.5773502691896257;
          qx[0] = 0.5 * (a + b) - 0.5 * (b - a) * s; qx[1] = 0.5 * (a + b) + 0.5 * (b - a) * s;
          qy[0] = 0.5 * (c + d) - 0.5 * (d - c) * s; qy[1] = 0.5 * (c + d) + 0.5 * (d - c) * s;
          const double thickness = V(p) / (4.0 * hs(p, 0) * hs(p, 1));
          wq = 0.25 * (b - a) * (d - c) * thickness;
          nq = 2;
        } else {
          qx[0] = x(p, 0); qy[0] = x(p, 1);
          wq = V(p);
          nq = 1;
        }
        for (int r = 0; r < 8; ++r)
          for (int s = 0; s < 8; ++s) Ke(k, r, s) = 0.0;
        for (int ix = 0; ix < nq; ++ix)
          for (int iy = 0; iy < nq; ++iy) {
            const double xi = (qx[ix] - cx) / g.hx, eta = (qy[iy] - cy) / g.hy;
            const double Nx[2] = {1.0 - xi, xi}, Ny[2] = {1.0 - eta, eta};
            const double dNx[2] = {-1.0 / g.hx, 1.0 / g.hx}, dNy[2] = {-1.0 / g.hy, 1.0 / g.hy};
            double gx[4], gy[4];
            for (int dj = 0; dj < 2; ++dj)
              for (int di = 0; di < 2; ++di) {
                gx[di + 2 * dj] = dNx[di] * Ny[dj];
                gy[di + 2 * dj] = Nx[di] * dNy[dj];
              }
            for (int a = 0; a < 4; ++a)
              for (int b = 0; b < 4; ++b) {
                // B_a^T D B_b for B_a = [[gx, 0], [0, gy], [gy, gx]].
                Ke(k, 2 * a, 2 * b) += wq * (c11 * gx[a] * gx[b] + c33 * gy[a] * gy[b]);
                Ke(k, 2 * a, 2 * b + 1) += wq * (c12 * gx[a] * gy[b] + c33 * gy[a] * gx[b]);
                Ke(k, 2 * a + 1, 2 * b) += wq * (c12 * gy[a] * gx[b] + c33 * gx[a] * gy[b]);
                Ke(k, 2 * a + 1, 2 * b + 1) += wq * (c11 * gy[a] * gy[b] + c33 * gx[a] * gx[b]);
              }
          }
      });
}

}  // namespace impm
