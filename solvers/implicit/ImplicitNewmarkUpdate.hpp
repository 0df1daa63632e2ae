// ImplicitNewmark<Shape, Dim> at the end of a converged step: the grid's Newmark update, the
// stress from the converged displacement and the particle update (FLIP/PIC, XPIC, APIC, TPIC).
// Included by ImplicitNewmarkImpl.hpp.
#pragma once

#include "solvers/implicit/ImplicitNewmark.hpp"

#include "core/PhaseTimer.hpp"
#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/InternalForce.hpp"
#include "solvers/implicit/ImplicitGridColumns.hpp"

namespace impm {

// ---- The end of the step ----------------------------------------------------------------------

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::finishStep(const Vector& u) {
  PhaseTimer phase("g2p and stress update");
  recordReactions(u);
  scatterUnknowns(u);
  gridUpdate();
  dispGhosted_->doImport(*dispOwned_, *dist_.importer(), Tpetra::INSERT);
  updateParticles();
}

// Grid acceleration at t + dt and the velocity increment on the free dofs (zero elsewhere, the
// prescribed motion at the conditions' dofs); the FE reference keeps the grid's own v and a.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::gridUpdate() {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  const NewmarkConstants k(opt_.newmark, dt_);
  const double dt = k.dt, gamma = k.gamma;
  {
    auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    const int fields = fields_, ss = stateStride_, ds = dispStride_;
    Kokkos::parallel_for(
        "implicit_grid_acceleration", Kokkos::RangePolicy<Exec>(0, d.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int b = 0; b < fields; ++b) {
            const int o = b * ss, q = b * ds;
            for (int c = 0; c < Dim; ++c) {
              const bool free = s(n, o + SC::FreeX + c) > 0.5;
              const double a = s(n, o + SC::AccX + c);
              const double aNew = free ? k.newAcceleration(d(n, q + DC::UX + c), s(n, o + SC::VelX + c), a) : 0.0;
              d(n, q + DC::AnewX + c) = aNew;
              d(n, q + DC::DvX + c) = free ? k.velocityChange(a, aNew) : 0.0;
            }
          }
        });
    conditions_.template write<Exec>(d, DC::AnewX, PrescribedField::Acceleration, ds);
    conditions_.template write<Exec>(d, DC::DvX, PrescribedField::VelocityChange, ds);
    if (conditions_.hasWalls())
      conditions_.implicitWalls().template stop<Exec>(d, DC::AnewX, DC::DvX, s, SC::VelX, dt, ds, ss);
    forEachRigidDof(
        s, KOKKOS_LAMBDA(int n, int f, int c, const RigidFieldMotion& rigid) {
          d(n, f * ds + DC::AnewX + c) = rigid.acceleration(f, c);
          d(n, f * ds + DC::DvX + c) = rigid.change(f, c);
        });
  }
  if (!opt_.fixedParticles) return;
  auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto kin = gridKinematics_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
  Kokkos::parallel_for(
      "grid_newmark_update", Kokkos::RangePolicy<Exec>(0, d.extent(0)), KOKKOS_LAMBDA(int n) {
        for (int c = 0; c < Dim; ++c) {
          const double aNew = d(n, DC::AnewX + c);
          kin(n, c) = s(n, SC::FreeX + c) > 0.5
                          ? s(n, SC::VelX + c) + dt * ((1 - gamma) * s(n, SC::AccX + c) + gamma * aNew)
                          : 0.0;
          kin(n, Dim + c) = aNew;
        }
      });
  conditions_.template write<Exec>(kin, 0, PrescribedField::EndVelocity);
  conditions_.template write<Exec>(kin, Dim, PrescribedField::Acceleration);
}

// Stress from the converged displacement (weights at x_p(t)), then the particle update: x += u
// (the FE reference's Gauss points keep their place and their displacement apart), v by the grid's
// own increment (Equilibrium, FLIP) or the particle's trapezoidal rule, a = a_new.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::updateParticles() {
  using DC = implicit::DisplacementColumns<Dim>;
  auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  withFields(dispStride_, [&](const auto& columns) {
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX, columns);
  });
  const DomainConvection domain = ConvectsDomain<Shape>::value ? DomainConvection(dist_.grid()) : DomainConvection();
  if (fbar_) {
    fbar_->template accumulate<Exec>(ps_, 1.0);
    updateStress<Exec, Dim>(ps_, mat_.law(), 1.0, true, domain, fbar_->correction(ps_));
  } else {
    updateStress<Exec, Dim>(ps_, mat_.law(), 1.0, /*updateVolume=*/!opt_.fixedParticles, domain);
  }
  if (opt_.transfer == ParticleTransfer::Apic) return updateAffineParticles<ParticleTransfer::Apic>();
  if (opt_.transfer == ParticleTransfer::Tpic) return updateAffineParticles<ParticleTransfer::Tpic>();
  // XPIC: v_p <- sum S v* from the step's start velocity; the update below adds the increment.
  if (xpic_)
    xpic_->replaceParticleVelocity(*stateOwned_, implicit::StateColumns<Dim>::Mass, implicit::StateColumns<Dim>::VelX,
                                   ps_, conditions_, massCutoff_, true);
  const StructuredGrid g = dist_.grid();
  const LocalNodeIndexer ix = dist_.ghostedIndexer();
  auto x = ps_.x;
  auto hs = ps_.halfSize;
  auto v = ps_.v;
  auto a = ps_.a;
  auto up = ps_.u;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps_);
  const NewmarkConstants k(opt_.newmark, dt_);
  const double c1 = k.c1, c2 = k.c2, c3 = k.c3, dt = k.dt, gamma = k.gamma;
  const bool consistent = opt_.consistentMass, fixed = opt_.fixedParticles;
  const bool gridIncrement = equilibriumAcceleration();
  withFields(dispStride_, [&](const auto& fields) {
    Kokkos::parallel_for(
        "implicit_g2p", Kokkos::RangePolicy<Exec>(0, ps_.count), KOKKOS_LAMBDA(int p) {
          const ParticleStencil<Shape, Dim> stn(g, x, hs, deformation, p);
          double u[Dim] = {}, an[Dim] = {}, dv[Dim] = {};
          const int o = fields.offset(p);
          stn.forEachNode(ix, [&](int n, double w, const double*) {
            for (int c = 0; c < Dim; ++c) {
              u[c] += w * d(n, o + DC::UX + c);
              an[c] += w * d(n, o + DC::AnewX + c);
              dv[c] += w * d(n, o + DC::DvX + c);
            }
          });
          for (int c = 0; c < Dim; ++c) {
            if (consistent) an[c] = c1 * u[c] - c2 * v(p, c) - c3 * a(p, c);  // the particle's own Newmark update
            if (fixed)
              up(p, c) += u[c];
            else
              x(p, c) += u[c];
            if (gridIncrement)
              v(p, c) += dv[c];
            else
              v(p, c) += dt * ((1 - gamma) * a(p, c) + gamma * an[c]);
            a(p, c) = an[c];
          }
        });
  });
}

// APIC and TPIC: the grid velocity at t + dt, v_i + dv_i, and a_new on every ghosted node; then
// x_p += sum S u_i, v_p = sum S v_i(t + dt), C_p from the same field, a_p = sum S a_new (weights
// at x_p(t)). The particles' own Newmark update is not used: their velocity is the grid's.
template <class Shape, int Dim>
template <ParticleTransfer Transfer>
void ImplicitNewmark<Shape, Dim>::updateAffineParticles() {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  using K = KinColumns<Dim>;
  auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  {
    auto s = stateGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto kin = endKinematics_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
    Kokkos::parallel_for(
        "implicit_end_kinematics", Kokkos::RangePolicy<Exec>(0, kin.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int c = 0; c < Dim; ++c) {
            kin(n, K::VelX + c) = s(n, SC::VelX + c) + d(n, DC::DvX + c);
            kin(n, K::AccX + c) = d(n, DC::AnewX + c);
          }
        });
  }
  auto kin = endKinematics_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const StructuredGrid g = dist_.grid();
  const LocalNodeIndexer ix = dist_.ghostedIndexer();
  const FixedParticleViews<Dim> pv(ps_);
  auto x = pv.x;
  auto v = pv.v;
  auto a = pv.a;
  auto affine = pv.affine;
  gatherFromGrid<Exec, Shape, Dim>(
      "implicit_g2p_affine", g, ps_, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st) {
        double xp[Dim], vi[Dim] = {}, ai[Dim] = {}, grad[Dim][Dim] = {}, C[Dim][Dim], u[Dim] = {};
        for (int c = 0; c < Dim; ++c) xp[c] = x(p, c);
        gatherAffineKinematics<Transfer>(st, g, ix, kin, 0, xp, vi, ai, grad, C);
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int c = 0; c < Dim; ++c) u[c] += w * d(n, DC::UX + c);
        });
        for (int c = 0; c < Dim; ++c) {
          x(p, c) += u[c];
          v(p, c) = vi[c];
          a(p, c) = ai[c];
          for (int j = 0; j < Dim; ++j) affine(p, c, j) = C[c][j];
        }
      });
}

}  // namespace impm
