// Grid-to-particle: interpolation of grid fields and of their gradients to particles. Vector
// fields take Dim consecutive grid columns.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/kernels/AffineTransfer.hpp"
#include "core/kernels/FieldColumns.hpp"
#include "core/kernels/Interpolation.hpp"
#include "core/kernels/StressUpdate.hpp"

namespace impm {

// The node sums of the explicit grid-to-particle map for particles with an affine velocity
// (AffineTransfer.hpp): vi = sum S v_i, ai = sum S a_i, grad = sum v_i (x) grad S, and C_p.
template <ParticleTransfer Transfer, class Shape, int Dim, class GridView>
KOKKOS_INLINE_FUNCTION void gatherAffineKinematics(const ParticleStencil<Shape, Dim>& st, const StructuredGrid& g,
                                                   const LocalNodeIndexer& ix, const GridView& kinematics, int f,
                                                   const double (&xp)[Dim], double (&vi)[Dim], double (&ai)[Dim],
                                                   double (&grad)[Dim][Dim], double (&C)[Dim][Dim]) {
  using K = KinColumns<Dim>;
  using Inertia = ApicInertia<Shape>;
  constexpr bool gradientForm = Transfer == ParticleTransfer::Tpic || Inertia::form == ApicForm::Gradient;
  constexpr bool summedInertia = !gradientForm && Inertia::form == ApicForm::General;
  [[maybe_unused]] double B[Dim][Dim] = {}, D[Dim][Dim] = {};
  st.forEachOffset([&](const int* offset, double w, const double* dw) {
    int node[3];
    double r[Dim];
    stencilNode(st, g, offset, xp, node, r);
    const int n = ix(node[0], node[1], node[2]);
    for (int i = 0; i < Dim; ++i) {
      const double gv = kinematics(n, f + K::VelX + i);
      vi[i] += w * gv;
      ai[i] += w * kinematics(n, f + K::AccX + i);
      for (int j = 0; j < Dim; ++j) {
        grad[i][j] += gv * dw[j];
        if constexpr (!gradientForm) B[i][j] += w * gv * r[j];
        if constexpr (summedInertia) D[i][j] += w * r[i] * r[j];
      }
    }
  });
  if constexpr (gradientForm) {
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) C[i][j] = grad[i][j];
  } else if constexpr (Inertia::form == ApicForm::Constant) {
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) C[i][j] = B[i][j] / (Inertia::factor * g.spacing(j) * g.spacing(j));
  } else {
    apicAffine<Dim>(B, D, C);
  }
}

// Explicit update. From the ghosted grid kinematics (new velocity v_i and the acceleration
// a_i = (v_i - v_i^old)/dt) it sets
//   v_p <- flip (v_p + dt sum S a_i) + (1 - flip) sum S v_i,   a_p = sum S a_i,
//   gradient_p = sum grad S (x) v_i  (for the stress update),  x_p <- x_p + dt sum S v_i.
// With an affine transfer (APIC, TPIC) v_p <- sum S v_i and C_p from the grid velocity
// (AffineTransfer.hpp); `flip` is not used.
// The weights are those of the particle position at the start of the step.
// With `updateStressNow` (USL), the stress update with dt * gradient_p through `law` runs in
// the same pass. Each particle reads its own field's columns (`fields`).
template <ParticleTransfer Transfer, class ExecSpace, class Shape, int Dim, class Law, class GridView, class Fields>
void gridToParticleExplicitWith(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                                const GridView& kinematics, double dt, double flip, bool movePositions, const Law& law,
                                bool updateStressNow, const Fields& fields) {
  using K = KinColumns<Dim>;
  const FixedParticleViews<Dim> pv(ps);
  auto x = pv.x;
  auto v = pv.v;
  auto a = pv.a;
  auto L = pv.gradient;
  auto affine = pv.affine;
  const DomainConvection domain = ConvectsDomain<Shape>::value ? DomainConvection(g) : DomainConvection();
  const StructuredGrid nodes = g;
  gatherFromGrid<ExecSpace, Shape, Dim>(
      "g2p", g, ps, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st) {
        double vi[Dim] = {}, ai[Dim] = {}, grad[Dim][Dim] = {};
        const int f = fields.offset(p);
        if constexpr (Transfer == ParticleTransfer::FlipPic) {
          st.forEachNode(ix, [&](int n, double w, const double* dw) {
            for (int i = 0; i < Dim; ++i) {
              const double gv = kinematics(n, f + K::VelX + i);
              vi[i] += w * gv;
              ai[i] += w * kinematics(n, f + K::AccX + i);
              for (int j = 0; j < Dim; ++j) grad[i][j] += gv * dw[j];
            }
          });
          for (int i = 0; i < Dim; ++i) {
            v(p, i) = flip * (v(p, i) + dt * ai[i]) + (1.0 - flip) * vi[i];
            a(p, i) = ai[i];
          }
        } else {
          double xp[Dim], C[Dim][Dim];
          for (int i = 0; i < Dim; ++i) xp[i] = x(p, i);
          gatherAffineKinematics<Transfer>(st, nodes, ix, kinematics, f, xp, vi, ai, grad, C);
          for (int i = 0; i < Dim; ++i) {
            v(p, i) = vi[i];
            a(p, i) = ai[i];
            for (int j = 0; j < Dim; ++j) affine(p, i, j) = C[i][j];
          }
        }
        if (updateStressNow) {
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) grad[i][j] *= dt;
          updateParticleState<Dim>(pv, law, p, grad, true, domain);
        } else {
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) L(p, i, j) = grad[i][j];
        }
        if (movePositions)
          for (int i = 0; i < Dim; ++i) x(p, i) += dt * vi[i];
      });
}

template <class ExecSpace, class Shape, int Dim, class Law, class GridView, class Fields = SingleField>
void gridToParticleExplicit(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                            const GridView& kinematics, double dt, double flip, bool movePositions, const Law& law,
                            bool updateStressNow, const Fields& fields = Fields(),
                            ParticleTransfer transfer = ParticleTransfer::FlipPic) {
  if (transfer == ParticleTransfer::Apic)
    gridToParticleExplicitWith<ParticleTransfer::Apic, ExecSpace, Shape, Dim>(
        g, ix, ps, kinematics, dt, flip, movePositions, law, updateStressNow, fields);
  else if (transfer == ParticleTransfer::Tpic)
    gridToParticleExplicitWith<ParticleTransfer::Tpic, ExecSpace, Shape, Dim>(
        g, ix, ps, kinematics, dt, flip, movePositions, law, updateStressNow, fields);
  else
    gridToParticleExplicitWith<ParticleTransfer::FlipPic, ExecSpace, Shape, Dim>(
        g, ix, ps, kinematics, dt, flip, movePositions, law, updateStressNow, fields);
}

// gradient_p = sum_i grad S_ip (x) w_i for a grid vector field in columns col...
template <class ExecSpace, class Shape, int Dim, class GridView, class Fields = SingleField>
void gridGradientAtParticles(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                             const GridView& field, int col, const Fields& fields = Fields()) {
  auto L = FixedParticleViews<Dim>(ps).gradient;
  gatherFromGrid<ExecSpace, Shape, Dim>(
      "grid_gradient", g, ps, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st) {
        double grad[Dim][Dim] = {};
        const int c = col + fields.offset(p);
        st.forEachNode(ix, [&](int n, double, const double* dw) {
          for (int i = 0; i < Dim; ++i) {
            const double wi = field(n, c + i);
            for (int j = 0; j < Dim; ++j) grad[i][j] += wi * dw[j];
          }
        });
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j) L(p, i, j) = grad[i][j];
      });
}

// target_p = (accumulate ? target_p : 0) + scale * sum_i S_ip w_i for a grid vector field in
// columns col... MUSL moves the particles with the re-mapped velocity this way, and the
// implicit integrator hands the initial grid acceleration to the particles (target a).
template <class ExecSpace, class Shape, int Dim, class GridView, class Fields = SingleField>
void interpolateToParticles(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                            const GridView& field, int col, const ParticleSet::Vec& target, double scale,
                            bool accumulate, const Fields& fields = Fields()) {
  auto tgt = FixedParticleViews<Dim>::vec(target);
  gatherFromGrid<ExecSpace, Shape, Dim>(
      "interpolate_to_particles", g, ps, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st) {
        double wp[Dim] = {};
        const int c = col + fields.offset(p);
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int d = 0; d < Dim; ++d) wp[d] += w * field(n, c + d);
        });
        for (int d = 0; d < Dim; ++d) tgt(p, d) = (accumulate ? tgt(p, d) : 0.0) + scale * wp[d];
      });
}

}  // namespace impm
