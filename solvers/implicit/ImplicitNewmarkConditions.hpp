// ImplicitNewmark<Shape, Dim> and the grid conditions: the contact penalty between fields in the
// residual, the conditions' reactions after a converged solve, and the implicit walls' active set.
// Included by ImplicitNewmarkImpl.hpp.
#pragma once

#include "solvers/implicit/ImplicitNewmark.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>

#include "solvers/implicit/ImplicitGridColumns.hpp"
#include "solvers/implicit/TrialInternalForce.hpp"

namespace impm {

template <class Shape, int Dim>
template <class StateView, class Body>
void ImplicitNewmark<Shape, Dim>::forEachRigidDof(const StateView& state, const Body& body) const {
  using SC = implicit::StateColumns<Dim>;
  if (!conditions_.contact().hasRigid()) return;
  const auto rigid = conditions_.contact().rigidFields();
  const RigidFieldMotion motion{conditions_.contact().rigidMotion(), dt_};
  const int fields = fields_, ss = stateStride_;
  Kokkos::parallel_for(
      "implicit_rigid_fields", Kokkos::RangePolicy<Exec>(0, state.extent(0)), KOKKOS_LAMBDA(int n) {
        for (int f = 0; f < fields; ++f) {
          if (!rigid(f) || !(state(n, f * ss + SC::Mass) > 0.0)) continue;
          for (int c = 0; c < Dim; ++c) body(n, f, c, motion);
        }
      });
}

// Field b's end-of-step velocity at owned node n (component c) for the grid displacement u last
// scattered (Newmark): what the contact law sees.
template <class Shape, int Dim>
auto ImplicitNewmark<Shape, Dim>::trialEndVelocity() const {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  const NewmarkConstants k(opt_.newmark, dt_);
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const int ss = stateStride_, ds = dispStride_;
  return KOKKOS_LAMBDA(int n, int b, int c) {
    const double v = s(n, b * ss + SC::VelX + c), a = s(n, b * ss + SC::AccX + c);
    return v + k.velocityChange(a, k.newAcceleration(d(n, b * ds + DC::UX + c), v, a));
  };
}

// The contact force in the residual: a penalty on the contact law's correction of the trial state.
// At u, each field's end velocity v_new(u) (Newmark) goes through the contact law, which returns
// v* (approach removed, slip reduced by Coulomb friction, separating bodies unchanged); the force
//   F_c = alpha r m (v* - v_new) / c_v,   c_v = gamma / (beta dt) = d v_new / d u,
// acts on the field, with r = c1 + c_p^2 / h^2 (c_p the fastest pressure wave, h the smallest
// cell), a stiffness per unit mass of the node: its inertia c1 m and an estimate of its elastic
// stiffness. The same r at every node and the law's momentum balance make the forces of two bodies
// at a node equal and opposite; |F_t| <= mu |F_n| follows from the law's friction. As alpha grows
// the solution's end velocities tend to the law's (no approach); what remains is an approach of
// order 1 / alpha of the one the bodies would have without contact (the penalty's compliance).
// Each field's start acceleration comes from its own body's forces, without contact's: the end
// force carries the whole impulse. (Correcting the start accelerations by the law, as the explicit
// step corrects velocities, would make its friction act on the relative acceleration rather than
// on the slip: a block on an incline then slides 12% too far.) Frictional contact goes through the
// active set (reviseContactStates), which each solve holds fixed; the frictionless law kinks where
// bodies meet or part, and Newton takes a line search there (Backtrack, the default with contact).
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::addContactForces() {
  using SC = implicit::StateColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
  const int ss = stateStride_;
  const auto endVelocity = trialEndVelocity();
  const double coefficient = contactPenaltyCoefficient();
  // The law's pair forces are sum m dv / dt, the penalty's coefficient dt times them. Reported is
  // the impulse the contact gives over the step per unit time, gamma F_c: the trapezoidal velocity
  // update takes gamma of the end force, and the start acceleration (from the fields' own forces)
  // none of the contact's (so that F_c is twice the force that holds a body at rest).
  conditions_.template addImplicitContactForces<Exec>(s, SC::Mass, geometryCol_, ss, endVelocity, f, FC::ForceX,
                                                      forceStride_, coefficient,
                                                      coefficient * dt_ * opt_.newmark.gamma);
}

// The penalty's coefficient alpha r / c_v (see addContactForces): times a field's nodal mass, its
// stiffness against the trial end velocity.
template <class Shape, int Dim>
double ImplicitNewmark<Shape, Dim>::contactPenaltyCoefficient() const {
  const NewmarkConstants k(opt_.newmark, dt_);
  double h = dist_.grid().spacing(0);
  for (int c = 1; c < Dim; ++c) h = std::min(h, dist_.grid().spacing(c));
  const double wave = opt_.contactWaveSpeed > 0.0 ? opt_.contactWaveSpeed : mat_.maxPWaveSpeed();
  const double r = k.c1 + wave * wave / (h * h);
  return opt_.contactPenalty * r * opt_.newmark.beta * dt_ / opt_.newmark.gamma;
}

// The force that stops field b's held wall component over the step: -m v / dt - F_int - F_ext
// (the forces at the last residual's point).
template <class Shape, int Dim>
auto ImplicitNewmark<Shape, Dim>::heldWallReaction() const {
  using SC = implicit::StateColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const double dt = dt_;
  const int ss = stateStride_, fs = forceStride_;
  return KOKKOS_LAMBDA(int n, int b, int d) {
    const int o = b * ss;
    return -s(n, o + SC::Mass) * s(n, o + SC::VelX + d) / dt - f(n, b * fs + FC::ForceX + d) - s(n, o + SC::FextX + d);
  };
}

// The reaction of each grid condition: the residual of the converged step at its dofs, the
// force the condition applies so that its nodes move as prescribed. The forces at u are those of
// the last residual when it was evaluated at u (NOX's convergence check normally is), else one
// more residual evaluation provides them.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::recordReactions(const Vector& u) {
  using DC = implicit::DisplacementColumns<Dim>;
  if (conditions_.empty()) return;
  int sameHere = 0;
  if (!lastResidualPoint_.is_null() && lastResidualPoint_->getMap().get() == u.getMap().get()) {
    auto a = lastResidualPoint_->getLocalViewHost(Tpetra::Access::ReadOnly);
    auto b = u.getLocalViewHost(Tpetra::Access::ReadOnly);
    sameHere = 1;
    for (size_t k = 0; k < a.extent(0) && sameHere; ++k) sameHere = a(k, 0) == b(k, 0);
  }
  int same = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MIN, sameHere, Teuchos::outArg(same));
  if (!same) {
    Vector R(dofs_.map(), false);
    residual(u, R);
  }
  const auto atNode = newmarkResidualAtNode<Dim>(stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 NewmarkConstants(opt_.newmark, dt_), opt_.consistentMass);
  auto disp = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  if (fields_ > 1) {  // summed over the fields
    const int fields = fields_, ss = stateStride_, ds = dispStride_, fs = forceStride_;
    conditions_.template recordReaction<Exec>(KOKKOS_LAMBDA(int n, int d) {
      double sum = 0.0;
      for (int b = 0; b < fields; ++b) sum += atNode(n, d, disp(n, b * ds + DC::UX + d), b * ss, b * fs);
      return sum;
    });
    conditions_.recordImplicitContactForces();
    using SC = implicit::StateColumns<Dim>;
    conditions_.template carryImplicitContactForces<Exec>(stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                          SC::Mass, stateStride_);
  } else {
    conditions_.template recordReaction<Exec>(
        KOKKOS_LAMBDA(int n, int d) { return atNode(n, d, disp(n, DC::UX + d)); });
  }
  if (conditions_.hasWalls()) conditions_.template recordImplicitWallReactions<Exec>(heldWallReaction());
}

// Multi-field contact: after a converged solve, each contact node's state (free, stick, slip) from
// the trial end velocities at u (collective); true when any changed, and the step is to be solved
// again with the new set (ContactActiveSet). The residual of each solve is smooth in u: Newton does
// not meet Coulomb's kink, which the classification between solves settles instead.
template <class Shape, int Dim>
bool ImplicitNewmark<Shape, Dim>::reviseContactStates(const Vector& u) {
  using SC = implicit::StateColumns<Dim>;
  Vector R(dofs_.map(), false);
  residual(u, R);  // u in the grid displacement
  int local = 0;
  {
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    local = conditions_.template classifyImplicitContact<Exec>(s, SC::Mass, geometryCol_, stateStride_,
                                                               trialEndVelocity(), contactPenaltyCoefficient());
  }
  int changes = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_SUM, local, Teuchos::outArg(changes));
  if (changes > 0) PCurrent_ = false;  // P carries the set's stiffness (contactStiffness)
  return changes > 0;
}

// Implicit walls: after a converged solve, the components to release or hold (collective); when
// any changed, the free dofs follow and the step is to be solved again.
template <class Shape, int Dim>
bool ImplicitNewmark<Shape, Dim>::reviseWallContacts(const Vector& u) {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  Vector R(dofs_.map(), false);
  residual(u, R);  // the forces at u, and u in the grid displacement
  const double tolerance = 1e-9 * dist_.grid().spacing(0);
  const ImplicitWallContact& walls = conditions_.implicitWalls();
  int local = 0;
  {
    const auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    local = walls.template revise<Exec>(d, DC::UX, heldWallReaction(), tolerance, dispStride_);
  }
  int changes = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_SUM, local, Teuchos::outArg(changes));
  if (changes == 0) return false;
  {
    auto st = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    walls.template hold<Exec>(st, SC::Mass, SC::VelX, SC::AccX, SC::FreeX, massCutoff_, dt_, stateStride_);
  }
  stateGhosted_->doImport(*stateOwned_, *dist_.importer(), Tpetra::INSERT);
  PCurrent_ = false;
  if (dofs_.update(*stateOwned_, SC::FreeX)) assembler_.forgetMatrix();
  return true;
}

}  // namespace impm
