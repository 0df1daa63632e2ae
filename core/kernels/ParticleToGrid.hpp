// Particle-to-grid: mass, momentum and particle point forces, scattered into the ghosted
// grid sums through a Kokkos ScatterView (duplicated per thread on OpenMP, atomic on GPUs).
#pragma once

#include <Kokkos_ScatterView.hpp>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"
#include "core/kernels/InternalForce.hpp"

namespace impm {

// Adds m_p S_ip, m_p v_p S_ip (and m_p a_p S_ip into `accColumn` when >= 0) to `grid`.
// One particle's mass and momentum (and m a when accCol >= 0), for a stencil already built.
template <class Shape, class Access>
KOKKOS_INLINE_FUNCTION void scatterMassMomentum(const ParticleStencil<Shape>& st, const LocalNodeIndexer& ix,
                                                double mp, double vx, double vy, double ax, double ay, Access& out,
                                                int massCol, int momCol, int accCol) {
  for (int aI = 0; aI < st.countX(); ++aI)
    for (int bJ = 0; bJ < st.countY(); ++bJ) {
      const int n = ix(st.i0 + aI, st.j0 + bJ);
      const double w = mp * st.weight(aI, bJ);
      if (massCol >= 0) out(n, massCol) += w;
      out(n, momCol) += w * vx;
      out(n, momCol + 1) += w * vy;
      if (accCol >= 0) {
        out(n, accCol) += w * ax;
        out(n, accCol + 1) += w * ay;
      }
    }
}

template <class ExecSpace, class Shape, class GridView>
void particleToGridMassMomentum(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                const GridView& grid, int massCol, int momCol, int accCol = -1) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  auto x = ps.x; auto hs = ps.halfSize; auto m = ps.mass; auto v = ps.v; auto a = ps.a;
  Kokkos::parallel_for(
      "p2g", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        const double ax = accCol >= 0 ? a(p, 0) : 0.0, ay = accCol >= 0 ? a(p, 1) : 0.0;
        scatterMassMomentum(st, ix, m(p), v(p, 0), v(p, 1), ax, ay, out, massCol, momCol, accCol);
      });
  GridView dest = grid;  // contribute() takes a non-const view
  Kokkos::Experimental::contribute(dest, sv);
}

// The explicit stepper's fused transfer: mass, momentum and internal force in one pass over
// the particles (one stencil evaluation per particle).
template <class ExecSpace, class Shape, class GridView>
void particleToGridMomentumAndForce(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                    const GridView& grid, int massCol, int momCol, int forceCol) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  auto x = ps.x; auto hs = ps.halfSize; auto m = ps.mass; auto v = ps.v; auto vol = ps.volume; auto s = ps.stress;
  Kokkos::parallel_for(
      "p2g", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        scatterMassMomentum(st, ix, m(p), v(p, 0), v(p, 1), 0.0, 0.0, out, massCol, momCol, -1);
        scatterInternalForce(st, ix, vol(p), s(p, 0), s(p, 1), s(p, 2), out, forceCol);
      });
  GridView dest = grid;
  Kokkos::Experimental::contribute(dest, sv);
}

// Residual of the consistent-mass projection of the particle velocities onto the grid,
//   r_i = sum_p m_p S_ip (v_p - sum_j S_jp v_j) = p_i - M_C v,
// for grid velocities v in columns velCol, velCol+1 of `velocity`. One Jacobi correction
// v += M_L^-1 r removes the O(h^2) smoothing that the lumped projection M_L^-1 p applies to
// a velocity field every step (see ExplicitStepper).
// `particleField` is the particle field being projected (ps.v by default; ps.a for the
// implicit integrator's accelerations).
template <class ExecSpace, class Shape, class VelocityView, class GridView>
void particleToGridProjectionResidual(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                      const VelocityView& velocity, int velCol, const GridView& grid, int outCol,
                                      const ParticleSet::Vec2* particleField = nullptr) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  auto x = ps.x; auto hs = ps.halfSize; auto m = ps.mass;
  auto v = particleField ? *particleField : ps.v;
  Kokkos::parallel_for(
      "p2g_projection_residual", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        double vx = 0, vy = 0;
        for (int aI = 0; aI < st.countX(); ++aI)
          for (int bJ = 0; bJ < st.countY(); ++bJ) {
            const int n = ix(st.i0 + aI, st.j0 + bJ);
            const double w = st.weight(aI, bJ);
            vx += w * velocity(n, velCol);
            vy += w * velocity(n, velCol + 1);
          }
        const double rx = m(p) * (v(p, 0) - vx), ry = m(p) * (v(p, 1) - vy);
        for (int aI = 0; aI < st.countX(); ++aI)
          for (int bJ = 0; bJ < st.countY(); ++bJ) {
            const int n = ix(st.i0 + aI, st.j0 + bJ);
            const double w = st.weight(aI, bJ);
            out(n, outCol) += w * rx;
            out(n, outCol + 1) += w * ry;
          }
      });
  GridView dest = grid;
  Kokkos::Experimental::contribute(dest, sv);
}

// Consistent-mass product M_C w = sum_p m_p S_ip (sum_j S_jp w_j) for a two-component grid
// field in columns fieldCol, fieldCol+1, scattered into outCol, outCol+1.
template <class ExecSpace, class Shape, class FieldView, class GridView>
void particleToGridMassProduct(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                               const FieldView& field, int fieldCol, const GridView& grid, int outCol) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  auto x = ps.x; auto hs = ps.halfSize; auto m = ps.mass;
  Kokkos::parallel_for(
      "p2g_mass_product", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        double wx = 0, wy = 0;
        for (int aI = 0; aI < st.countX(); ++aI)
          for (int bJ = 0; bJ < st.countY(); ++bJ) {
            const int n = ix(st.i0 + aI, st.j0 + bJ);
            wx += st.weight(aI, bJ) * field(n, fieldCol);
            wy += st.weight(aI, bJ) * field(n, fieldCol + 1);
          }
        scatterMassMomentum(st, ix, m(p), wx, wy, 0.0, 0.0, out, -1, outCol, -1);
      });
  GridView dest = grid;
  Kokkos::Experimental::contribute(dest, sv);
}

// Point forces carried by particles: force(k) * S_ip for particle index(k).
template <class ExecSpace, class Shape, class GridView, class IndexView, class ForceView>
void particleToGridForces(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                          const IndexView& index, const ForceView& force, const GridView& grid, int forceCol) {
  auto x = ps.x; auto hs = ps.halfSize;
  Kokkos::parallel_for(
      "p2g_point_forces", Kokkos::RangePolicy<ExecSpace>(0, index.extent(0)), KOKKOS_LAMBDA(int k) {
        const int p = index(k);
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        for (int aI = 0; aI < st.countX(); ++aI)
          for (int bJ = 0; bJ < st.countY(); ++bJ) {
            const int n = ix(st.i0 + aI, st.j0 + bJ);
            const double w = st.weight(aI, bJ);
            Kokkos::atomic_add(&grid(n, forceCol), w * force(k, 0));
            Kokkos::atomic_add(&grid(n, forceCol + 1), w * force(k, 1));
          }
      });
}

// Body forces m_p g_b S_ip, with g_b the acceleration of the particle's body (gravity).
template <class ExecSpace, class Shape, class GridView, class AccelerationView>
void particleToGridBodyForces(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                              const AccelerationView& bodyAcceleration, const GridView& grid, int forceCol) {
  auto sv = Kokkos::Experimental::create_scatter_view(grid);
  auto x = ps.x; auto hs = ps.halfSize; auto m = ps.mass; auto body = ps.body;
  Kokkos::parallel_for(
      "p2g_body_forces", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        auto out = sv.access();
        const ParticleStencil<Shape> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
        const double fx = m(p) * bodyAcceleration(body(p), 0), fy = m(p) * bodyAcceleration(body(p), 1);
        for (int aI = 0; aI < st.countX(); ++aI)
          for (int bJ = 0; bJ < st.countY(); ++bJ) {
            const int n = ix(st.i0 + aI, st.j0 + bJ);
            const double w = st.weight(aI, bJ);
            out(n, forceCol) += w * fx;
            out(n, forceCol + 1) += w * fy;
          }
      });
  GridView dest = grid;
  Kokkos::Experimental::contribute(dest, sv);
}

}  // namespace impm
