// Particle-to-grid: mass, momentum, projection residuals, consistent-mass products, point and
// body forces, each a small body plugged into the scatterToGrid skeleton (Interpolation.hpp).
// A vector field takes Dim consecutive grid columns from the column given.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/kernels/AffineTransfer.hpp"
#include "core/kernels/FieldColumns.hpp"
#include "core/kernels/Interpolation.hpp"
#include "core/kernels/InternalForce.hpp"

namespace impm {

// One particle's mass and momentum m v (and m a when accCol >= 0), for a stencil already built.
template <class Shape, int Dim, class Access>
KOKKOS_INLINE_FUNCTION void scatterMassMomentum(const ParticleStencil<Shape, Dim>& st, const LocalNodeIndexer& ix,
                                                double mp, const double* vp, const double* ap, Access& out, int massCol,
                                                int momCol, int accCol) {
  st.forEachNode(ix, [&](int n, double S, const double*) {
    const double w = mp * S;
    if (massCol >= 0) out(n, massCol) += w;
    for (int d = 0; d < Dim; ++d) out(n, momCol + d) += w * vp[d];
    if (accCol >= 0)
      for (int d = 0; d < Dim; ++d) out(n, accCol + d) += w * ap[d];
  });
}

// One particle's contact geometry (multi-field contact, physics/MultiFieldContact.hpp): its volume
// gradient V_p grad S_ip into col.. and its mass-weighted position m_p S_ip x_p into col + Dim...
template <class Shape, int Dim, class Access>
KOKKOS_INLINE_FUNCTION void scatterContactGeometry(const ParticleStencil<Shape, Dim>& st, const LocalNodeIndexer& ix,
                                                   double V, double m, const double* x, Access& out, int col) {
  st.forEachNode(ix, [&](int n, double S, const double* grad) {
    for (int d = 0; d < Dim; ++d) {
      out(n, col + d) += V * grad[d];
      out(n, col + Dim + d) += m * S * x[d];
    }
  });
}

// particleToGridMassMomentum and, with forceCol >= 0, particleToGridMomentumAndForce for particles
// that carry an affine velocity field (APIC, TPIC; AffineTransfer.hpp): the momentum of node i is
// m_p S_ip (v_p + C_p (x_i - x_p)).
template <class ExecSpace, class Shape, int Dim, class GridView, class Fields>
void particleToGridAffineMomentum(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                  const GridView& grid, int massCol, int momCol, int accCol, int forceCol,
                                  int geometryCol, const Fields& fields) {
  const FixedParticleViews<Dim> pv(ps);
  auto m = pv.mass;
  auto v = pv.v;
  auto a = pv.a;
  auto vol = pv.volume;
  auto x = pv.x;
  auto stress = pv.stress;
  auto C = pv.affine;
  const StructuredGrid nodes = g;
  scatterToGrid<ExecSpace, Shape, Dim>(
      "p2g", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double xp[Dim], vp[Dim], ap[Dim], Cp[Dim][Dim];
        for (int i = 0; i < Dim; ++i) {
          xp[i] = x(p, i);
          vp[i] = v(p, i);
          ap[i] = accCol >= 0 ? a(p, i) : 0.0;
          for (int j = 0; j < Dim; ++j) Cp[i][j] = C(p, i, j);
        }
        const int f = fields.offset(p);
        scatterAffineMassMomentum(st, nodes, ix, m(p), xp, vp, Cp, ap, out, massCol + f, momCol + f,
                                  accCol >= 0 ? accCol + f : -1);
        if (forceCol >= 0) {
          double s[StressLayout<Dim>::count];
          loadStress<Dim>(stress, p, s);
          scatterInternalForce(st, ix, vol(p), s, out, forceCol + f);
        }
        if (Fields::multi && geometryCol >= 0) scatterContactGeometry(st, ix, vol(p), m(p), xp, out, geometryCol + f);
      });
}

// Adds m_p S_ip, m_p v_p S_ip (and m_p a_p S_ip into accCol when >= 0; with several fields, the
// contact geometry into geometryCol.. when >= 0) to `grid`, in the columns of each particle's field.
// With `affine`, the particles' affine velocity too (particleToGridAffineMomentum).
template <class ExecSpace, class Shape, int Dim, class GridView, class Fields = SingleField>
void particleToGridMassMomentum(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                const GridView& grid, int massCol, int momCol, int accCol = -1, int geometryCol = -1,
                                const Fields& fields = Fields(), bool affine = false) {
  if (affine) {
    particleToGridAffineMomentum<ExecSpace, Shape, Dim>(g, ix, ps, grid, massCol, momCol, accCol, -1, geometryCol,
                                                        fields);
    return;
  }
  const FixedParticleViews<Dim> pv(ps);
  auto m = pv.mass;
  auto v = pv.v;
  auto a = pv.a;
  auto vol = pv.volume;
  auto x = pv.x;
  scatterToGrid<ExecSpace, Shape, Dim>(
      "p2g", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double vp[Dim], ap[Dim];
        for (int d = 0; d < Dim; ++d) {
          vp[d] = v(p, d);
          ap[d] = accCol >= 0 ? a(p, d) : 0.0;
        }
        const int f = fields.offset(p);
        scatterMassMomentum(st, ix, m(p), vp, ap, out, massCol + f, momCol + f, accCol >= 0 ? accCol + f : -1);
        if (Fields::multi && geometryCol >= 0) {
          double xp[Dim];
          for (int d = 0; d < Dim; ++d) xp[d] = x(p, d);
          scatterContactGeometry(st, ix, vol(p), m(p), xp, out, geometryCol + f);
        }
      });
}

// The explicit stepper's fused transfer: mass, momentum and internal force in one pass over
// the particles (one stencil evaluation per particle); the contact geometry too when geometryCol >= 0.
// With `affine`, the particles' affine velocity too (particleToGridAffineMomentum).
template <class ExecSpace, class Shape, int Dim, class GridView, class Fields = SingleField>
void particleToGridMomentumAndForce(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                    const GridView& grid, int massCol, int momCol, int forceCol, int geometryCol = -1,
                                    const Fields& fields = Fields(), bool affine = false) {
  if (affine) {
    particleToGridAffineMomentum<ExecSpace, Shape, Dim>(g, ix, ps, grid, massCol, momCol, -1, forceCol, geometryCol,
                                                        fields);
    return;
  }
  const FixedParticleViews<Dim> pv(ps);
  auto m = pv.mass;
  auto v = pv.v;
  auto vol = pv.volume;
  auto stress = pv.stress;
  auto x = pv.x;
  scatterToGrid<ExecSpace, Shape, Dim>(
      "p2g", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double vp[Dim], s[StressLayout<Dim>::count];
        for (int d = 0; d < Dim; ++d) vp[d] = v(p, d);
        loadStress<Dim>(stress, p, s);
        const int f = fields.offset(p);
        scatterMassMomentum(st, ix, m(p), vp, vp, out, massCol + f, momCol + f, -1);
        scatterInternalForce(st, ix, vol(p), s, out, forceCol + f);
        if (Fields::multi && geometryCol >= 0) {
          double xp[Dim];
          for (int d = 0; d < Dim; ++d) xp[d] = x(p, d);
          scatterContactGeometry(st, ix, vol(p), m(p), xp, out, geometryCol + f);
        }
      });
}

// Residual of the consistent-mass projection of a particle field onto the grid,
//   r_i = sum_p m_p S_ip (f_p - sum_j S_jp f_j) = p_i - M_C f,
// for grid values f in columns col.. of `field`. One Jacobi correction f += M_L^-1 r
// removes the O(h^2) smoothing that the lumped projection M_L^-1 p applies to a field every
// step (see solvers/ProjectionCorrection.hpp). `particleField`: ps.v or ps.a.
template <class ExecSpace, class Shape, int Dim, class FieldView, class GridView>
void particleToGridProjectionResidual(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                      const FieldView& field, int col, const GridView& grid, int outCol,
                                      const ParticleSet::Vec& particleField) {
  auto m = ps.mass;
  auto v = FixedParticleViews<Dim>::vec(particleField);
  scatterToGrid<ExecSpace, Shape, Dim>(
      "p2g_projection_residual", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double f[Dim] = {};
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int d = 0; d < Dim; ++d) f[d] += w * field(n, col + d);
        });
        double r[Dim];
        for (int d = 0; d < Dim; ++d) r[d] = m(p) * (v(p, d) - f[d]);
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int d = 0; d < Dim; ++d) out(n, outCol + d) += w * r[d];
        });
      });
}

// Consistent-mass product M_C w = sum_p m_p S_ip (sum_j S_jp w_j) for a grid vector field in
// columns fieldCol.., scattered into outCol...
template <class ExecSpace, class Shape, int Dim, class FieldView, class GridView>
void particleToGridMassProduct(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                               const FieldView& field, int fieldCol, const GridView& grid, int outCol) {
  auto m = ps.mass;
  scatterToGrid<ExecSpace, Shape, Dim>(
      "p2g_mass_product", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double wp[Dim] = {};
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int d = 0; d < Dim; ++d) wp[d] += w * field(n, fieldCol + d);
        });
        scatterMassMomentum(st, ix, m(p), wp, wp, out, -1, outCol, -1);
      });
}

// Point forces carried by particles: force(k) * S_ip for particle index(k). Few particles carry
// them, so one ordered loop adds them all: atomics from several threads added the forces of two
// loaded particles that share a node in whichever order the threads came, and the last bits of
// the load changed from run to run (at 2 threads a cantilever's two-particle tip load made Newton
// converge in one run and fail in the next).
template <class ExecSpace, class Shape, int Dim, class GridView, class IndexView, class ForceView,
          class Fields = SingleField>
void particleToGridForces(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                          const IndexView& index, const ForceView& force, const GridView& grid, int forceCol,
                          const Fields& fields = Fields()) {
  const FixedParticleViews<Dim> pv(ps);
  auto x = pv.x;
  auto hs = pv.halfSize;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps);
  const int count = index.extent(0);
  if (count == 0) return;
  Kokkos::parallel_for(
      "p2g_point_forces", Kokkos::RangePolicy<ExecSpace>(0, 1), KOKKOS_LAMBDA(int) {
        for (int k = 0; k < count; ++k) {
          const int p = index(k);
          const ParticleStencil<Shape, Dim> st(g, x, hs, deformation, p);
          const int col = forceCol + fields.offset(p);
          st.forEachNode(ix, [&](int n, double w, const double*) {
            for (int d = 0; d < Dim; ++d) grid(n, col + d) += w * force(k, d);
          });
        }
      });
}

// Body forces m_p g_b S_ip, with g_b the acceleration of the particle's body (gravity).
template <class ExecSpace, class Shape, int Dim, class GridView, class AccelerationView, class Fields = SingleField>
void particleToGridBodyForces(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                              const AccelerationView& bodyAcceleration, const GridView& grid, int forceCol,
                              const Fields& fields = Fields()) {
  auto m = ps.mass;
  auto body = ps.body;
  scatterToGrid<ExecSpace, Shape, Dim>(
      "p2g_body_forces", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double f[Dim];
        for (int d = 0; d < Dim; ++d) f[d] = m(p) * bodyAcceleration(body(p), d);
        const int col = forceCol + fields.offset(p);
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int d = 0; d < Dim; ++d) out(n, col + d) += w * f[d];
        });
      });
}

// Body forces that vary over the body: m_p b(X_p, t) S_ip for the particles of body `bodyIndex`
// (-1: every body), b a device functor of the reference position X_p and the time with
// bodyForce(X, t, d) (a manufactured solution's forcing, physics/ManufacturedSolution.hpp).
template <class ExecSpace, class Shape, int Dim, class Field, class GridView, class Fields = SingleField>
void particleToGridBodyForceField(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                  const Field& field, double t, int bodyIndex, const GridView& grid, int forceCol,
                                  const Fields& fields = Fields()) {
  auto m = ps.mass;
  auto body = ps.body;
  auto x0 = ps.x0;
  scatterToGrid<ExecSpace, Shape, Dim>(
      "p2g_body_force_field", g, ps, grid, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        if (bodyIndex >= 0 && body(p) != bodyIndex) return;
        double X[3] = {0, 0, 0}, f[Dim];
        for (int d = 0; d < Dim; ++d) X[d] = x0(p, d);
        for (int d = 0; d < Dim; ++d) f[d] = m(p) * field.bodyForce(X, t, d);
        const int col = forceCol + fields.offset(p);
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int d = 0; d < Dim; ++d) out(n, col + d) += w * f[d];
        });
      });
}

}  // namespace impm
