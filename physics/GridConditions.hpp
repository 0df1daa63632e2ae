// Grid conditions: the grid-side physics between particle-to-grid and grid-to-particle. Each
// condition acts on a set of grid dofs (one component of one node); impm's conditions prescribe
// the motion of their dofs (a fixed component is the motion 0). The integrators call the hooks
// below at fixed places in their steps, and each hook both writes the prescribed values into the
// grid fields and records the force the condition applied (its reaction):
//   explicit step:  p2g -> [USF: onStressVelocity -> stress] -> grid update ->
//                   afterExplicitGridUpdate -> g2p [MUSL: re-map -> onStressVelocity -> stress]
//   implicit step:  set-up (the start velocity and acceleration written, the dofs marked not
//                   free) -> Newton on the free dofs, the prescribed increments written into the
//                   grid displacement and the contact penalty added to the forces
//                   (addImplicitContactForces) at every residual -> the converged residual at the
//                   prescribed dofs recorded as the reaction -> g2p
// A dof named by two conditions belongs to the first (the deck refuses two different motions).
//
// Rigid walls: a wall is the plane x_axis = position with the bodies on one side. Explicit: a grid
// node on or behind it that would move into it after the grid update loses that normal velocity
// (and gains nothing if it moves away: contact is one-sided), and Coulomb friction takes off at
// most `friction` times the normal velocity change from its tangential velocity (stopping it when
// that suffices); its reaction is m dv / dt. A wall changes only the components no constraint
// prescribes at the node (a symmetry plane's nodes still meet a wall across it), and leaves a node
// whose normal component is prescribed alone. Implicit: an active set with friction
// (physics/ImplicitWallContact.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "physics/Constraints.hpp"
#include "physics/ImplicitWallContact.hpp"
#include "physics/MultiFieldContact.hpp"

namespace impm {

// What a condition prescribes at its dofs over one step [t, t + dt], per component.
enum class PrescribedField : int {
  Increment = 0,          // the displacement over the step
  StartVelocity = 1,      // the velocity at t
  EndVelocity = 2,        // the velocity at t + dt
  Acceleration = 3,       // (end - start velocity) / dt
  StartAcceleration = 4,  // the last step's acceleration
  VelocityChange = 5,     // end - start velocity
  Zero = 6,               // 0 (marks a dof as not free)
  Count = 7
};

// A rigid wall: the plane x_axis = position, the bodies on the side `side` (+1: x_axis >= position).
struct WallSpec {
  std::string name;
  int axis = 1;
  int side = 1;
  double position = 0.0;
  double friction = 0.0;  // Coulomb coefficient (0: frictionless)
};

class GridConditions {
 public:
  GridConditions() = default;
  GridConditions(const std::vector<ConstraintSpec>& specs, const GridDistribution& dist,
                 const std::vector<WallSpec>& walls = {}, const ContactSpec& contact = {});

  // Evaluates the conditions' time functions for the step [t, t + dt] (host; cheap). Every hook
  // below uses the step last set.
  void setStep(double t, double dt);

  // Writes `field` into columns col.. (one per dimension) of an owned grid view at every dof; with
  // several velocity fields (contact), into every field's columns, field f's `stride` further on.
  template <class ExecSpace, class GridView>
  void write(const GridView& owned, int col, PrescribedField field, int stride = 0) const {
    auto node = node_;
    auto comp = comp_;
    auto cond = cond_;
    auto values = values_;
    const int f = int(field), fields = stride > 0 ? fieldCount() : 1;
    Kokkos::parallel_for(
        "grid_condition_write", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          for (int b = 0; b < fields; ++b)
            owned(node(k), col + b * stride + comp(k)) = values(cond(k), f * 3 + comp(k));
        });
  }

  // Records each dof's reaction, forceAt(owned node, component): the force the condition applies
  // to its node (the integrator knows the balance at the dof); then sums them per condition.
  template <class ExecSpace, class ForceAtDof>
  void recordReaction(const ForceAtDof& forceAt) {
    auto node = node_;
    auto comp = comp_;
    auto force = dofForce_;
    Kokkos::parallel_for(
        "grid_condition_reaction", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k) { force(k) = forceAt(node(k), comp(k)); });
    sumReactions();
  }

  // Explicit hook, after the grid update on owned nodes: contact between the bodies' fields first;
  // then the new velocity and acceleration (kin, columns velCol.. and accCol..) take the prescribed
  // ones, and each dof's reaction is the force that gives its node that acceleration,
  // m a - F_int - F_ext + c p (mass damping c; the particle sums in `sums`: mass, momentum, F_ext,
  // F_int and volume-gradient columns), summed over the fields; then the walls. The columns of
  // field f are f * the strides of useFieldColumns further on.
  template <class ExecSpace, class SumsView, class KinView>
  void afterExplicitGridUpdate(const SumsView& sums, int massCol, int momCol, int fextCol, int fintCol, int gradCol,
                               const KinView& kin, int velCol, int accCol, double damping) {
    if (contact_.active()) {
      std::vector<double> pairForce;
      contact_.exchange<ExecSpace>(sums, massCol, gradCol, sumsStride_, kin, velCol, accCol, kinStride_, dim_, dt_,
                                   true, &pairForce);
      std::copy(pairForce.begin(), pairForce.end(), localReaction_.end() - pairForce.size());
    }
    write<ExecSpace>(kin, velCol, PrescribedField::EndVelocity, kinStride_);
    write<ExecSpace>(kin, accCol, PrescribedField::Acceleration, kinStride_);
    const int fields = fieldCount(), ss = sumsStride_, ks = kinStride_;
    recordReaction<ExecSpace>(KOKKOS_LAMBDA(int n, int d) {
      double force = 0.0;
      for (int f = 0; f < fields; ++f)
        force += sums(n, massCol + f * ss) * kin(n, accCol + f * ks + d) - sums(n, fintCol + f * ss + d) -
                 sums(n, fextCol + f * ss + d) + damping * sums(n, momCol + f * ss + d);
      return force;
    });
    if (hasWalls()) {
      wallContact<ExecSpace>(sums, massCol, ss, kin, velCol, accCol, ks, true);
      sumWallReactions();
    }
  }

  // The contact and the walls on a grid velocity field alone (the velocity the stress is computed
  // from, with USF and MUSL): velocity into a wall or another body removed, friction as above; no
  // acceleration, no reaction. The fields' columns in `vel` are velStride apart; rigid bodies move
  // with their velocity at the step's end (stepEnd) or start.
  template <class ExecSpace, class SumsView, class VelocityView>
  void enforceContact(const SumsView& sums, int massCol, int gradCol, const VelocityView& vel, int velCol,
                      int velStride, bool stepEnd) const {
    contact_.exchange<ExecSpace>(sums, massCol, gradCol, sumsStride_, vel, velCol, -1, velStride, dim_, dt_, stepEnd,
                                 nullptr);
    if (hasWalls()) wallContact<ExecSpace>(sums, massCol, sumsStride_, vel, velCol, -1, velStride, false);
  }

  // Explicit hook on the grid velocity the stress is computed from (USF: the start velocity after
  // p2g; MUSL: the end velocity of the re-mapped momentum), without reactions: the prescribed
  // velocity written (and a zero acceleration in accCol.., when accCol >= 0), then the contact and
  // the walls (enforceContact).
  template <class ExecSpace, class SumsView, class VelocityView>
  void onStressVelocity(const SumsView& sums, int massCol, int gradCol, const VelocityView& vel, int velCol, int accCol,
                        int velStride, bool stepEnd) const {
    write<ExecSpace>(vel, velCol, stepEnd ? PrescribedField::EndVelocity : PrescribedField::StartVelocity, velStride);
    if (accCol >= 0) write<ExecSpace>(vel, accCol, PrescribedField::Zero, velStride);
    enforceContact<ExecSpace>(sums, massCol, gradCol, vel, velCol, velStride, stepEnd);
  }

  // Implicit walls: an active set with Coulomb friction (physics/ImplicitWallContact.hpp), driven
  // by the implicit step; recordImplicitWallReactions sums its forces per wall.
  ImplicitWallContact& implicitWalls() { return implicitWalls_; }
  const ImplicitWallContact& implicitWalls() const { return implicitWalls_; }
  template <class ExecSpace, class ReactionAt>
  void recordImplicitWallReactions(const ReactionAt& reactionAt) {
    implicitWalls_.record<ExecSpace>(reactionAt);
    sumWallReactions();
  }

  // Implicit hook, at every residual with several fields: the contact between the bodies as a
  // penalty, augmented by the force carried from the last step (carryImplicitContactForces; zero
  // where no rigid body is). endVelocity(n, f, c) is field f's
  // trial end velocity at owned node n (component c). Each field's velocity is shifted by its
  // carried force over its penalty stiffness, v_s = v_new - lambda / (coefficient m); the contact
  // law, with the active set's states frozen (ContactActiveSet), turns the shifted velocities into
  // v*, and field f's force columns (forceCol.., forceStride apart) get
  // F = coefficient m (v* - v_s) = lambda + coefficient m (v* - v_new): the augmented Lagrangian
  // force, max(0, lambda_n + kappa g) along the normal and Coulomb's cone about it. The pair forces
  // of this call, times pairForceFactor, are what recordImplicitContactForces records.
  template <class ExecSpace, class StateView, class EndVelocity, class ForceView>
  void addImplicitContactForces(const StateView& s, int massCol, int gradCol, int stateStride,
                                const EndVelocity& endVelocity, const ForceView& f, int forceCol, int forceStride,
                                double coefficient, double pairForceFactor) {
    const int fields = fieldCount(), dim = dim_;
    trialContactVelocities<ExecSpace>(s, massCol, stateStride, endVelocity, coefficient);
    auto vel = lawVelocity_;
    auto before = trialVelocity_;
    contactSet_.mode = ContactActiveSet::Mode::Frozen;
    contact_.exchange<ExecSpace>(s, massCol, gradCol, stateStride, vel, 0, -1, dim, dim, dt_, true, &implicitPairForce_,
                                 &contactSet_);
    auto penalty = penaltyForce_;
    Kokkos::parallel_for(
        "contact_penalty_force", Kokkos::RangePolicy<ExecSpace>(0, vel.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int b = 0; b < fields; ++b) {
            const double m = s(n, b * stateStride + massCol);
            for (int c = 0; c < dim; ++c) {
              const double force = coefficient * m * (vel(n, b * dim + c) - before(n, b * dim + c));
              penalty(n, b * dim + c) = force;
              f(n, b * forceStride + forceCol + c) += force;
            }
          }
        });
    for (double& value : implicitPairForce_) value *= pairForceFactor;
  }
  // After a converged solve: each contact node's state decided anew from the trial end
  // velocities, shifted as in addImplicitContactForces (ContactActiveSet, Classify); returns this
  // rank's count of changed nodes.
  template <class ExecSpace, class StateView, class EndVelocity>
  int classifyImplicitContact(const StateView& s, int massCol, int gradCol, int stateStride,
                              const EndVelocity& endVelocity, double coefficient) {
    trialContactVelocities<ExecSpace>(s, massCol, stateStride, endVelocity, coefficient);
    contactSet_.mode = ContactActiveSet::Mode::Classify;
    return contact_.exchange<ExecSpace>(s, massCol, gradCol, stateStride, lawVelocity_, 0, -1, dim_, dim_, dt_, true,
                                        nullptr, &contactSet_);
  }
  // For the preconditioner: per owned node, -d m_a (v*_a - v_a) / d v_b of the contact law at the
  // trial end velocities (shifted as in addImplicitContactForces), with the active set's states
  // (ContactActiveSet::jacobian, Linearize). The penalty's stiffness is coefficient d v_new / d u
  // times it.
  template <class ExecSpace, class StateView, class EndVelocity>
  Kokkos::View<const double**, Kokkos::LayoutRight, DeviceType> linearizeImplicitContact(const StateView& s,
                                                                                         int massCol, int gradCol,
                                                                                         int stateStride,
                                                                                         const EndVelocity& endVelocity,
                                                                                         double coefficient) {
    trialContactVelocities<ExecSpace>(s, massCol, stateStride, endVelocity, coefficient);
    Kokkos::deep_copy(contactSet_.jacobian, 0.0);
    contactSet_.mode = ContactActiveSet::Mode::Linearize;
    contact_.exchange<ExecSpace>(s, massCol, gradCol, stateStride, lawVelocity_, 0, -1, dim_, dim_, dt_, true, nullptr,
                                 &contactSet_);
    return contactSet_.jacobian;
  }
  // The active set at the start of a step attempt, kept so that a failed attempt (StepControl
  // retries it smaller) starts again from it; and the set itself (checkpoints).
  void keepImplicitContactStates(size_t ownedNodes) {
    contactSet_.fit(ownedNodes, fieldCount());
    keptContactSet_.fit(ownedNodes, fieldCount());
    Kokkos::deep_copy(keptContactSet_.state, contactSet_.state);
    Kokkos::deep_copy(keptContactSet_.direction, contactSet_.direction);
    Kokkos::deep_copy(keptContactSet_.force, contactSet_.force);
  }
  void restoreImplicitContactStates() {
    Kokkos::deep_copy(contactSet_.state, keptContactSet_.state);
    Kokkos::deep_copy(contactSet_.direction, keptContactSet_.direction);
    Kokkos::deep_copy(contactSet_.force, keptContactSet_.force);
  }
  ContactActiveSet& implicitContactSet() { return contactSet_; }
  const ContactActiveSet& implicitContactSet() const { return contactSet_; }
  // The force of each pair of bodies on its first (3 per pair, this rank's share) at the last
  // addImplicitContactForces: the converged step's, when called after the solve.
  void recordImplicitContactForces() {
    std::copy(implicitPairForce_.begin(), implicitPairForce_.end(), localReaction_.end() - implicitPairForce_.size());
  }
  // After a converged step: the contact forces at the nodes a rigid body reaches become the
  // multipliers of the next step (the augmented Lagrangian of addImplicitContactForces), so that a
  // body pressed by a rigid one holds its load without the penalty's creep. Between deformable
  // bodies the multiplier made a soft block ring on its slab (its normal force swinging from 0.1 to
  // 2 times its weight) and slide too far near the stick threshold: those keep the plain penalty.
  template <class ExecSpace, class StateView>
  void carryImplicitContactForces(const StateView& s, int massCol, int stateStride) {
    if (!contact_.hasRigid() || penaltyForce_.extent(0) != contactSet_.force.extent(0)) return;
    const int fields = fieldCount(), dim = dim_;
    auto penalty = penaltyForce_;
    auto carried = contactSet_.force;
    auto rigid = contact_.rigidFields();
    Kokkos::parallel_for(
        "contact_carry_force", Kokkos::RangePolicy<ExecSpace>(0, carried.extent(0)), KOKKOS_LAMBDA(int n) {
          bool rigidHere = false;
          for (int b = 0; b < fields; ++b) rigidHere = rigidHere || (rigid(b) && s(n, b * stateStride + massCol) > 0.0);
          for (int b = 0; b < fields; ++b)
            for (int c = 0; c < dim; ++c) carried(n, 3 * b + c) = rigidHere ? penalty(n, b * dim + c) : 0.0;
        });
  }
  // The contact law (its checks; the implicit step's line-search default).
  const MultiFieldContact& contact() const { return contact_; }

  // Multi-field contact: the number of grid velocity fields (1 without contact), each body's
  // field, and where the integrator keeps field f: its particle sums sumsStride * f columns and its
  // kinematics kinStride * f columns after field 0's.
  int fieldCount() const { return contact_.fieldCount(); }
  Kokkos::View<const int*, DeviceType> fieldOfBody() const { return contact_.fieldOfBody(); }
  void useFieldColumns(int sumsStride, int kinStride) {
    sumsStride_ = sumsStride;
    kinStride_ = kinStride;
  }
  bool hasWalls() const { return wallNode_.extent(0) > 0 || !walls_.empty(); }

  bool empty() const { return names_.empty(); }
  // Whether `field` is zero at every dof for the step last set (a write of it can be skipped
  // where the column already holds zeros).
  bool isZero(PrescribedField field) const { return zero_[int(field)]; }
  // Conditions by name, the components each prescribes, and this rank's share of the force each
  // applied to the grid in the last step (3 per condition); reactions(comm) sums over ranks.
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::array<bool, 3>>& prescribed() const { return prescribed_; }
  // What each condition's force is: "reaction" (constraints, walls) or "contact" (a pair of
  // bodies: the force of the second on the first).
  const std::vector<std::string>& forceKinds() const { return kinds_; }
  std::vector<double> reactions(const Teuchos::Comm<int>& comm) const;
  // Takes over this rank's share of the last step's forces from the conditions this replaces (the
  // same conditions on a new rank grid: the shares still sum to the forces over the ranks).
  void keepReactionsOf(const GridConditions& previous) { localReaction_ = previous.localReaction_; }

  // Owned local node index and component of each dof on this rank.
  Kokkos::View<int*, DeviceType> nodes() const { return node_; }
  Kokkos::View<int*, DeviceType> components() const { return comp_; }

 private:
  void sumReactions();
  void sumWallReactions();
  // The contact of every wall node (see the file comment), in each field: kin's velocity (and
  // acceleration, when accCol >= 0) corrected; with `record`, each node's reaction m dv / dt
  // (summed over the fields) into wallForce_.
  template <class ExecSpace, class SumsView, class KinView>
  void wallContact(const SumsView& sums, int massCol, int sumsStride, const KinView& kin, int velCol, int accCol,
                   int kinStride, bool record) const {
    auto node = wallNode_;
    auto wall = wallOf_;
    auto params = wallParams_;
    auto force = wallForce_;
    auto free = wallFree_;
    const int dim = dim_, fields = kinStride > 0 ? fieldCount() : 1;
    const double dt = dt_;
    Kokkos::parallel_for(
        "wall_contact", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          const int n = node(k), w = wall(k), mask = free(k);
          const int axis = (int)params(w, 0);
          const double side = params(w, 1), mu = params(w, 2);
          double total[3] = {0.0, 0.0, 0.0};
          for (int f = 0; f < fields; ++f) {
            const int vel = velCol + f * kinStride;
            const double m = sums(n, massCol + f * sumsStride);
            double dv[3] = {0.0, 0.0, 0.0};
            const double vn = side * kin(n, vel + axis);
            if (m > 0.0 && vn < 0.0) {
              dv[axis] = -kin(n, vel + axis);
              double vt2 = 0.0;  // (components a constraint prescribes keep their motion)
              for (int d = 0; d < dim; ++d)
                if (d != axis && (mask >> d) & 1) vt2 += kin(n, vel + d) * kin(n, vel + d);
              const double vt = std::sqrt(vt2), limit = -mu * vn;
              const double removed = vt <= limit ? 1.0 : limit / vt;  // the tangential fraction friction stops
              for (int d = 0; d < dim; ++d)
                if (d != axis && (mask >> d) & 1) dv[d] = -removed * kin(n, vel + d);
            }
            for (int d = 0; d < dim; ++d) {
              kin(n, vel + d) += dv[d];
              if (accCol >= 0) kin(n, accCol + f * kinStride + d) += dv[d] / dt;
              total[d] += m * dv[d] / dt;
            }
          }
          if (record)
            for (int d = 0; d < dim; ++d) force(k, d) = total[d];
        });
  }
  int dim_ = 2;
  std::vector<ConstraintSpec> specs_;
  std::vector<std::string> names_;
  std::vector<std::array<bool, 3>> prescribed_;
  std::vector<std::string> kinds_;
  Kokkos::View<int*, DeviceType> node_, comp_, cond_;
  // Per condition: PrescribedField::Count x 3 components, for the step last set.
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> values_;
  Kokkos::View<double*, DeviceType> dofForce_;
  std::vector<double> localReaction_;  // 3 per condition, then 3 per wall, then 3 per contact pair
  // Walls: the specs, each wall node (owned local index) and its wall, per wall (axis, side,
  // friction), and each wall node's last reaction.
  std::vector<WallSpec> walls_;
  Kokkos::View<int*, DeviceType> wallNode_, wallOf_;
  Kokkos::View<int*, DeviceType> wallFree_;  // per wall node: bit d set when the wall may change component d
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> wallParams_, wallForce_;
  ImplicitWallContact implicitWalls_;
  MultiFieldContact contact_;
  // The implicit contact's trial end velocities, the law's answer to them, its pair forces, and
  // its active set (with the copy a step attempt started from).
  // (penaltyForce_: each field's contact force at the last residual, owned node x field x component.)
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> trialVelocity_, lawVelocity_, penaltyForce_;
  std::vector<double> implicitPairForce_;
  ContactActiveSet contactSet_, keptContactSet_;
  // Fills trialVelocity_ and lawVelocity_ (owned node x field x component) with endVelocity,
  // shifted by the carried force over the penalty stiffness coefficient m of the field.
  template <class ExecSpace, class StateView, class EndVelocity>
  void trialContactVelocities(const StateView& s, int massCol, int stateStride, const EndVelocity& endVelocity,
                              double coefficient) {
    const int fields = fieldCount(), dim = dim_;
    if (trialVelocity_.extent(0) != s.extent(0) || trialVelocity_.extent(1) != size_t(fields * dim)) {
      trialVelocity_ = decltype(trialVelocity_)("contact_trial_velocity", s.extent(0), fields * dim);
      lawVelocity_ = decltype(trialVelocity_)("contact_law_velocity", s.extent(0), fields * dim);
      penaltyForce_ = decltype(trialVelocity_)("contact_penalty_force", s.extent(0), fields * dim);
    }
    contactSet_.fit(s.extent(0), fields);
    auto vel = lawVelocity_;
    auto before = trialVelocity_;
    auto carried = contactSet_.force;
    Kokkos::parallel_for(
        "contact_trial_velocity", Kokkos::RangePolicy<ExecSpace>(0, vel.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int b = 0; b < fields; ++b) {
            const double stiffness = coefficient * s(n, b * stateStride + massCol);
            for (int c = 0; c < dim; ++c) {
              const double lambda = carried(n, 3 * b + c);
              const double vNew = endVelocity(n, b, c) - (lambda != 0.0 && stiffness > 0.0 ? lambda / stiffness : 0.0);
              vel(n, b * dim + c) = vNew;
              before(n, b * dim + c) = vNew;
            }
          }
        });
  }
  int sumsStride_ = 0, kinStride_ = 0;
  double dt_ = 0.0;
  std::array<bool, int(PrescribedField::Count)> zero_{};
};

}  // namespace impm
