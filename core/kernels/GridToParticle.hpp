// Grid-to-particle: interpolation of grid fields and of their gradients to particles.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/kernels/Interpolation.hpp"
#include "core/kernels/StressUpdate.hpp"

namespace impm {

// Explicit update. From the ghosted grid kinematics (new velocity v_i and the acceleration
// a_i = (v_i - v_i^old)/dt) it sets
//   v_p <- flip (v_p + dt sum S a_i) + (1 - flip) sum S v_i,   a_p = sum S a_i,
//   gradient_p = sum grad S (x) v_i  (for the stress update),  x_p <- x_p + dt sum S v_i.
// The weights are those of the particle position at the start of the step.
// With `updateStressNow` (USL), the stress update with dt * gradient_p through `law` runs in
// the same pass.
template <class ExecSpace, class Shape, class Law, class GridView>
void gridToParticleExplicit(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                            const GridView& kinematics, double dt, double flip, bool movePositions,
                            const Law& law, bool updateStressNow) {
  auto x = ps.x; auto v = ps.v; auto a = ps.a; auto L = ps.gradient;
  gatherFromGrid<ExecSpace, Shape>("g2p", g, ps, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st) {
    double vx = 0, vy = 0, ax = 0, ay = 0, l00 = 0, l01 = 0, l10 = 0, l11 = 0;
    st.forEachNode(ix, [&](int n, double w, double dx, double dy) {
      const double gvx = kinematics(n, kin::VelX), gvy = kinematics(n, kin::VelY);
      vx += w * gvx; vy += w * gvy;
      ax += w * kinematics(n, kin::AccX); ay += w * kinematics(n, kin::AccY);
      l00 += gvx * dx; l01 += gvx * dy; l10 += gvy * dx; l11 += gvy * dy;
    });
    v(p, 0) = flip * (v(p, 0) + dt * ax) + (1.0 - flip) * vx;
    v(p, 1) = flip * (v(p, 1) + dt * ay) + (1.0 - flip) * vy;
    a(p, 0) = ax; a(p, 1) = ay;
    if (updateStressNow) updateParticleState(ps, law, p, dt * l00, dt * l01, dt * l10, dt * l11);
    else { L(p, 0, 0) = l00; L(p, 0, 1) = l01; L(p, 1, 0) = l10; L(p, 1, 1) = l11; }
    if (movePositions) {
      x(p, 0) += dt * vx;
      x(p, 1) += dt * vy;
    }
  });
}

// gradient_p = sum_i grad S_ip (x) w_i for a two-component grid field in columns col, col+1.
template <class ExecSpace, class Shape, class GridView>
void gridGradientAtParticles(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                             const GridView& field, int col) {
  auto L = ps.gradient;
  gatherFromGrid<ExecSpace, Shape>("grid_gradient", g, ps, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st) {
    double l00 = 0, l01 = 0, l10 = 0, l11 = 0;
    st.forEachNode(ix, [&](int n, double, double dx, double dy) {
      const double wx = field(n, col), wy = field(n, col + 1);
      l00 += wx * dx; l01 += wx * dy; l10 += wy * dx; l11 += wy * dy;
    });
    L(p, 0, 0) = l00; L(p, 0, 1) = l01; L(p, 1, 0) = l10; L(p, 1, 1) = l11;
  });
}

// target_p = (accumulate ? target_p : 0) + scale * sum_i S_ip w_i for a two-component grid
// field w in columns col, col+1. MUSL/USF move particles with it (target x, scale dt); the
// implicit integrator hands the initial grid acceleration to the particles (target a).
template <class ExecSpace, class Shape, class GridView>
void interpolateToParticles(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                            const GridView& field, int col, const ParticleSet::Vec2& target, double scale,
                            bool accumulate) {
  gatherFromGrid<ExecSpace, Shape>(
      "interpolate_to_particles", g, ps, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape>& st) {
        double wx = 0, wy = 0;
        st.forEachNode(ix, [&](int n, double w, double, double) {
          wx += w * field(n, col); wy += w * field(n, col + 1);
        });
        target(p, 0) = (accumulate ? target(p, 0) : 0.0) + scale * wx;
        target(p, 1) = (accumulate ? target(p, 1) : 0.0) + scale * wy;
      });
}

}  // namespace impm
