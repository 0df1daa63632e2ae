// Particle-to-grid: mass, momentum, projection residuals, consistent-mass products, point and
// body forces, each a small body plugged into the scatterToGrid skeleton (Interpolation.hpp).
#pragma once

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/kernels/Interpolation.hpp"
#include "core/kernels/InternalForce.hpp"

namespace impm {

// One particle's mass and momentum (and m a when accCol >= 0), for a stencil already built.
template <class Shape, class Access>
KOKKOS_INLINE_FUNCTION void scatterMassMomentum(const ParticleStencil<Shape>& st, const LocalNodeIndexer& ix,
                                                double mp, double vx, double vy, double ax, double ay, Access& out,
                                                int massCol, int momCol, int accCol) {
  st.forEachNode(ix, [&](int n, double S, double, double) {
    const double w = mp * S;
    if (massCol >= 0) out(n, massCol) += w;
    out(n, momCol) += w * vx;
    out(n, momCol + 1) += w * vy;
    if (accCol >= 0) {
      out(n, accCol) += w * ax;
      out(n, accCol + 1) += w * ay;
    }
  });
}

// Adds m_p S_ip, m_p v_p S_ip (and m_p a_p S_ip into accCol when >= 0) to `grid`.
template <class ExecSpace, class Shape, class GridView>
void particleToGridMassMomentum(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                const GridView& grid, int massCol, int momCol, int accCol = -1) {
  auto m = ps.mass; auto v = ps.v; auto a = ps.a;
  scatterToGrid<ExecSpace, Shape>(
      "p2g", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st, auto& out) {
        const double ax = accCol >= 0 ? a(p, 0) : 0.0, ay = accCol >= 0 ? a(p, 1) : 0.0;
        scatterMassMomentum(st, ix, m(p), v(p, 0), v(p, 1), ax, ay, out, massCol, momCol, accCol);
      });
}

// The explicit stepper's fused transfer: mass, momentum and internal force in one pass over
// the particles (one stencil evaluation per particle).
template <class ExecSpace, class Shape, class GridView>
void particleToGridMomentumAndForce(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                    const GridView& grid, int massCol, int momCol, int forceCol) {
  auto m = ps.mass; auto v = ps.v; auto vol = ps.volume; auto s = ps.stress;
  scatterToGrid<ExecSpace, Shape>(
      "p2g", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st, auto& out) {
        scatterMassMomentum(st, ix, m(p), v(p, 0), v(p, 1), 0.0, 0.0, out, massCol, momCol, -1);
        scatterInternalForce(st, ix, vol(p), s(p, 0), s(p, 1), s(p, 2), out, forceCol);
      });
}

// Residual of the consistent-mass projection of a particle field onto the grid,
//   r_i = sum_p m_p S_ip (f_p - sum_j S_jp f_j) = p_i - M_C f,
// for grid values f in columns col, col+1 of `field`. One Jacobi correction f += M_L^-1 r
// removes the O(h^2) smoothing that the lumped projection M_L^-1 p applies to a field every
// step (see solvers/ProjectionCorrection.hpp). `particleField`: ps.v or ps.a.
template <class ExecSpace, class Shape, class FieldView, class GridView>
void particleToGridProjectionResidual(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                      const FieldView& field, int col, const GridView& grid, int outCol,
                                      const ParticleSet::Vec2& particleField) {
  auto m = ps.mass; auto v = particleField;
  scatterToGrid<ExecSpace, Shape>(
      "p2g_projection_residual", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st, auto& out) {
        double fx = 0, fy = 0;
        st.forEachNode(ix, [&](int n, double w, double, double) {
          fx += w * field(n, col);
          fy += w * field(n, col + 1);
        });
        const double rx = m(p) * (v(p, 0) - fx), ry = m(p) * (v(p, 1) - fy);
        st.forEachNode(ix, [&](int n, double w, double, double) {
          out(n, outCol) += w * rx;
          out(n, outCol + 1) += w * ry;
        });
      });
}

// Consistent-mass product M_C w = sum_p m_p S_ip (sum_j S_jp w_j) for a two-component grid
// field in columns fieldCol, fieldCol+1, scattered into outCol, outCol+1.
template <class ExecSpace, class Shape, class FieldView, class GridView>
void particleToGridMassProduct(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                               const FieldView& field, int fieldCol, const GridView& grid, int outCol) {
  auto m = ps.mass;
  scatterToGrid<ExecSpace, Shape>(
      "p2g_mass_product", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st, auto& out) {
        double wx = 0, wy = 0;
        st.forEachNode(ix, [&](int n, double w, double, double) {
          wx += w * field(n, fieldCol);
          wy += w * field(n, fieldCol + 1);
        });
        scatterMassMomentum(st, ix, m(p), wx, wy, 0.0, 0.0, out, -1, outCol, -1);
      });
}

// Point forces carried by particles: force(k) * S_ip for particle index(k) (a few particles:
// atomics, not a ScatterView over the whole grid).
template <class ExecSpace, class Shape, class GridView, class IndexView, class ForceView>
void particleToGridForces(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                          const IndexView& index, const ForceView& force, const GridView& grid, int forceCol) {
  auto x = ps.x; auto hs = ps.halfSize;
  Kokkos::parallel_for(
      "p2g_point_forces", Kokkos::RangePolicy<ExecSpace>(0, index.extent(0)), KOKKOS_LAMBDA(int k) {
        const int p = index(k);
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        st.forEachNode(ix, [&](int n, double w, double, double) {
          Kokkos::atomic_add(&grid(n, forceCol), w * force(k, 0));
          Kokkos::atomic_add(&grid(n, forceCol + 1), w * force(k, 1));
        });
      });
}

// Body forces m_p g_b S_ip, with g_b the acceleration of the particle's body (gravity).
template <class ExecSpace, class Shape, class GridView, class AccelerationView>
void particleToGridBodyForces(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                              const AccelerationView& bodyAcceleration, const GridView& grid, int forceCol) {
  auto m = ps.mass; auto body = ps.body;
  scatterToGrid<ExecSpace, Shape>(
      "p2g_body_forces", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st, auto& out) {
        const double fx = m(p) * bodyAcceleration(body(p), 0), fy = m(p) * bodyAcceleration(body(p), 1);
        st.forEachNode(ix, [&](int n, double w, double, double) {
          out(n, forceCol) += w * fx;
          out(n, forceCol + 1) += w * fy;
        });
      });
}

}  // namespace impm
