// Rigid walls in the implicit step: an active set on the normal component, and Coulomb friction
// as a stick/slip set held fixed in each solve (GridConditions owns one; ImplicitNewmark drives it).
// With several velocity fields (multi-field contact) the wall acts on each body's field at a node
// on its own, as the explicit wall does: each (wall node, field) is an entry with its own set.
//
// Normal. Each step starts by holding a wall node's normal component (not an unknown: no
// displacement into the wall) where the node has mass and its start motion, v + dt a / 2, does not
// leave the wall. After a converged solve, revise() releases held components the wall pulls and
// holds free ones that moved into it, and the step is solved again until nothing changes (at most
// maxSolves() solves; the last one stands). A held component ends the step at rest: its velocity
// change is -v (FLIP particles receive the stop, as in the explicit step), and its reaction is the
// force that stops it, N = -m v / dt - F_int - F_ext.
//
// Friction (mu > 0). A held node of a frictional wall sticks or slips, and each solve holds that
// fixed, so that Newton never meets Coulomb's kink:
// - Stick: its tangential components are held too (at rest at the step's end); their reaction
//   F_t is the force that keeps it in place.
// - Slip: its tangential components are unknowns, loaded in the residual by the friction
//   -mu N s along its slip direction s, with N the normal reaction at the residual's own point
//   (addFriction()): at the converged solve the friction is exactly mu times the normal force.
// After a converged solve, revise() sticks a slipping node whose motion over the step no longer
// runs along s (the friction stopped it within the step), and lets a stuck node slip where
// |F_t| > mu N, along -F_t. The states carry over from step to step; a node the wall did not hold
// at the end of the last step starts slipping along its start velocity, or stuck if it has none.
// So a block at rest stays stuck and a sliding one slips without a solve to find out. A node whose
// slip direction turns by more than about 8 degrees (3D) counts as a change too. Friction at the
// trapezoidal rule's end of step: the residual takes it over gamma (addFriction()). Its dependence
// on u through N is in the Jacobian-free residual; the preconditioner does not see it.
#pragma once

#include <Kokkos_Core.hpp>
#include <cmath>
#include <utility>
#include <vector>

#include "core/Types.hpp"

namespace impm {

class ImplicitWallContact {
 public:
  using IntView = Kokkos::View<int*, DeviceType>;
  using Table = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>;
  // The tangential states of a held node of a frictional wall.
  static constexpr int kStick = 0, kSlip = 1;

  ImplicitWallContact() = default;
  // Per wall node: its owned node, its wall, the components the wall may change (bit d), and per
  // wall (axis, side, mu); `force` receives each wall node's reaction (summed over the fields).
  ImplicitWallContact(IntView node, IntView wall, IntView freeMask, Table params, Table force, int dim, bool frictional,
                      int fields = 1)
      : node_(node),
        wall_(wall),
        mask_(freeMask),
        params_(params),
        force_(force),
        dim_(dim),
        fields_(fields),
        frictional_(frictional),
        held_("wall_held", node.extent(0) * fields),
        decided_("wall_decided", node.extent(0) * fields),
        tangent_("wall_tangent_state", node.extent(0) * fields),
        fresh_("wall_fresh", node.extent(0) * fields),
        direction_("wall_slip_direction", node.extent(0) * fields, 3),
        friction_("wall_friction", node.extent(0) * fields, 3),
        normal_("wall_normal_force", node.extent(0) * fields),
        keptHeld_("wall_kept_held", node.extent(0) * fields),
        keptTangent_("wall_kept_tangent_state", node.extent(0) * fields),
        keptDirection_("wall_kept_slip_direction", node.extent(0) * fields, 3) {}

  bool frictional() const { return frictional_; }
  // The solves a step may take before its last one stands.
  static constexpr int maxSolves() { return 5; }

  // A new step: the normal decisions from the start motion; a node held at the end of the last
  // step keeps its tangential state, the others take one from their start motion when held. The
  // set is kept for restore() (a failed attempt's retry starts from it).
  void beginStep() const {
    Kokkos::deep_copy(keptHeld_, held_);
    Kokkos::deep_copy(keptTangent_, tangent_);
    Kokkos::deep_copy(keptDirection_, direction_);
    auto held = held_;
    auto fresh = fresh_;
    auto decided = decided_;
    Kokkos::parallel_for(
        "implicit_wall_begin_step", Kokkos::RangePolicy<>(0, held.extent(0)), KOKKOS_LAMBDA(int e) {
          fresh(e) = held(e) ? 0 : 1;
          decided(e) = 0;
        });
  }

  // The set as beginStep() found it.
  void restore() const {
    Kokkos::deep_copy(held_, keptHeld_);
    Kokkos::deep_copy(tangent_, keptTangent_);
    Kokkos::deep_copy(direction_, keptDirection_);
  }

  // Marks the free components of the implicit grid state s (columns freeCol..; field f's at f *
  // stride further): a held wall component is not free, any other wall component is free where the
  // node's mass exceeds cutoff.
  template <class ExecSpace, class StateView>
  void hold(const StateView& s, int massCol, int velCol, int accCol, int freeCol, double cutoff, double dt,
            int stride = 0) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto decided = decided_;
    auto mask = mask_;
    auto tangent = tangent_;
    auto fresh = fresh_;
    auto direction = direction_;
    const int dim = dim_, fields = fields_;
    const Kokkos::RangePolicy<ExecSpace> entries(0, held.extent(0));
    if (frictional_)  // tangential components: free where massive, before the walls decide
      Kokkos::parallel_for(
          "implicit_wall_tangents_free", entries, KOKKOS_LAMBDA(int e) {
            const int k = e / fields, o = e % fields * stride, n = node(k), axis = (int)params(wall(k), 0);
            if (params(wall(k), 2) <= 0.0) return;
            for (int c = 0; c < dim; ++c)
              if (c != axis && (mask(k) >> c) & 1) s(n, o + freeCol + c) = s(n, o + massCol) > cutoff ? 1.0 : 0.0;
          });
    Kokkos::parallel_for(
        "implicit_wall_hold", entries, KOKKOS_LAMBDA(int e) {
          const int k = e / fields, o = e % fields * stride, n = node(k), axis = (int)params(wall(k), 0);
          const double side = params(wall(k), 1);
          const bool massive = s(n, o + massCol) > cutoff;
          const bool hold =
              massive &&
              (decided(e) != 0 ? decided(e) > 0
                               : side * (s(n, o + velCol + axis) + 0.5 * dt * s(n, o + accCol + axis)) <= 0.0);
          held(e) = hold ? 1 : 0;
          s(n, o + freeCol + axis) = massive && !hold ? 1.0 : 0.0;
        });
    if (frictional_)  // a node held anew slips along its start velocity (sticks at rest)
      Kokkos::parallel_for(
          "implicit_wall_start_tangent", entries, KOKKOS_LAMBDA(int e) {
            if (!held(e) || !fresh(e)) return;
            fresh(e) = 0;
            const int k = e / fields, o = e % fields * stride, n = node(k), axis = (int)params(wall(k), 0);
            double v[3] = {0.0, 0.0, 0.0}, length = 0.0;
            for (int c = 0; c < dim; ++c)
              if (c != axis && (mask(k) >> c) & 1) v[c] = s(n, o + velCol + c);
            for (int c = 0; c < 3; ++c) length += v[c] * v[c];
            length = std::sqrt(length);
            tangent(e) = length > 0.0 ? kSlip : kStick;
            for (int c = 0; c < 3; ++c) direction(e, c) = length > 0.0 ? v[c] / length : 0.0;
          });
    if (frictional_)  // a stuck node's tangential components are held
      Kokkos::parallel_for(
          "implicit_wall_stick", entries, KOKKOS_LAMBDA(int e) {
            const int k = e / fields, o = e % fields * stride, axis = (int)params(wall(k), 0);
            if (!stuck(held, tangent, params, wall, e, k)) return;
            for (int c = 0; c < dim; ++c)
              if (c != axis && (mask(k) >> c) & 1) s(node(k), o + freeCol + c) = 0.0;
          });
  }

  // In the residual: each slipping node's friction -mu N s added to its free tangential components
  // of the owned forces f (forceCol..; field f's at f * forceStride further), N the held normal's
  // reaction at these forces, side reactionAt(n, f, axis) (the grid state s holds the free flags,
  // field f's at f * stateStride further). The normal's stop gives the impulse N dt; the
  // trapezoidal velocity update gives gamma of the end force (the start acceleration comes from the
  // body's forces alone), so the residual takes the friction over gamma for its impulse to be
  // mu N dt. Kept per entry for record().
  template <class ExecSpace, class ReactionAt, class StateView, class ForceView>
  void addFriction(const ReactionAt& reactionAt, const StateView& s, int freeCol, const ForceView& f, int forceCol,
                   double gamma, int stateStride = 0, int forceStride = 0) const {
    if (!frictional_) return;
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto mask = mask_;
    auto tangent = tangent_;
    auto direction = direction_;
    auto friction = friction_;
    auto normal = normal_;
    const int dim = dim_, fields = fields_;
    const Kokkos::RangePolicy<ExecSpace> entries(0, held.extent(0));
    // The normal forces first: at a corner one wall's tangent is the other's normal.
    Kokkos::parallel_for(
        "implicit_wall_normal_force", entries, KOKKOS_LAMBDA(int e) {
          const int k = e / fields, axis = (int)params(wall(k), 0);
          const bool slips = held(e) && tangent(e) == kSlip && params(wall(k), 2) > 0.0;
          const double N = slips ? params(wall(k), 1) * reactionAt(node(k), e % fields, axis) : 0.0;
          normal(e) = N > 0.0 ? N : 0.0;
        });
    Kokkos::parallel_for(
        "implicit_wall_friction", entries, KOKKOS_LAMBDA(int e) {
          const int k = e / fields, o = e % fields * stateStride, q = e % fields * forceStride;
          const int n = node(k), axis = (int)params(wall(k), 0);
          const double limit = params(wall(k), 2) * normal(e);
          for (int c = 0; c < 3; ++c) {
            const bool acts =
                limit > 0.0 && c < dim && c != axis && ((mask(k) >> c) & 1) && s(n, o + freeCol + c) > 0.5;
            friction(e, c) = acts ? -limit * direction(e, c) : 0.0;
            if (acts) Kokkos::atomic_add(&f(n, q + forceCol + c), friction(e, c) / gamma);
          }
        });
  }

  // After a converged solve (owned displacement d at uCol..; field f's at f * stride further;
  // reactionAt(n, f, d) a held component's reaction): the number of entries this rank changes
  // (released, held, stuck, slipping or turned) for the next solve. An entry held again after a
  // release in the same step stays held, so that its normal changes at most twice a step.
  template <class ExecSpace, class DispView, class ReactionAt>
  int revise(const DispView& d, int uCol, const ReactionAt& reactionAt, double tolerance, int stride = 0) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto decided = decided_;
    auto mask = mask_;
    auto tangent = tangent_;
    auto direction = direction_;
    const int dim = dim_, fields = fields_;
    int changes = 0;
    Kokkos::parallel_reduce(
        "implicit_wall_revise", Kokkos::RangePolicy<ExecSpace>(0, held.extent(0)),
        KOKKOS_LAMBDA(int e, int& count) {
          const int k = e / fields, f = e % fields, o = f * stride, n = node(k), axis = (int)params(wall(k), 0);
          const double side = params(wall(k), 1), mu = params(wall(k), 2);
          if (held(e) && decided(e) != 2 && side * reactionAt(n, f, axis) < 0.0) {  // the wall pulls: let go
            decided(e) = -1;
            ++count;
          } else if (!held(e) && side * d(n, o + uCol + axis) < -tolerance) {  // into the wall: hold
            decided(e) = decided(e) < 0 ? 2 : 1;
            ++count;
          } else if (held(e) && mu > 0.0) {
            double t[3] = {0.0, 0.0, 0.0}, t2 = 0.0;  // a stuck node's F_t, a slipping one's motion u_t
            for (int c = 0; c < dim; ++c)
              if (c != axis && (mask(k) >> c) & 1) {
                t[c] = tangent(e) == kStick ? reactionAt(n, f, c) : d(n, o + uCol + c);
                t2 += t[c] * t[c];
              }
            const double length = std::sqrt(t2), limit = mu * side * reactionAt(n, f, axis);
            if (tangent(e) == kStick) {
              if (length > limit) {  // holding takes more than mu N: slip along -F_t
                tangent(e) = kSlip;
                for (int c = 0; c < 3; ++c) direction(e, c) = -t[c] / length;
                ++count;
              }
            } else {
              double along = 0.0;
              for (int c = 0; c < dim; ++c) along += t[c] * direction(e, c);
              if (!(along > 0.0)) {  // friction stopped it within the step
                tangent(e) = kStick;
                ++count;
              } else if (along < 0.99 * length) {  // slips on, its direction turned
                for (int c = 0; c < 3; ++c) direction(e, c) = t[c] / length;
                ++count;
              }
            }
          }
        },
        changes);
    return changes;
  }

  // After the last solve: each wall node's force, summed over its fields: the held components'
  // reactions (reactionAt(n, f, c)), a stuck entry's tangential ones too, and a slipping entry's
  // friction at the last residual (addFriction()).
  template <class ExecSpace, class ReactionAt>
  void record(const ReactionAt& reactionAt) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto force = force_;
    auto mask = mask_;
    auto tangent = tangent_;
    auto friction = friction_;
    const int dim = dim_, fields = fields_;
    const bool frictional = frictional_;
    Kokkos::parallel_for(
        "implicit_wall_reaction", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          const int n = node(k), axis = (int)params(wall(k), 0);
          for (int c = 0; c < 3; ++c) force(k, c) = 0.0;
          for (int f = 0; f < fields; ++f) {
            const int e = k * fields + f;
            const bool stuckNode = stuck(held, tangent, params, wall, e, k);
            const bool slips = frictional && held(e) && !stuckNode && params(wall(k), 2) > 0.0;
            for (int c = 0; c < 3; ++c) {
              const bool heldComponent = held(e) && (c == axis || (stuckNode && c < dim && ((mask(k) >> c) & 1)));
              force(k, c) += heldComponent ? reactionAt(n, f, c) : slips ? friction(e, c) : 0.0;
            }
          }
        });
  }

  // The held components' end of step: at rest (velocity change -v, acceleration -v / dt), a stuck
  // entry's tangential ones too (field f's columns at f * dispStride and f * stateStride further).
  template <class ExecSpace, class DispView, class StateView>
  void stop(const DispView& d, int anewCol, int dvCol, const StateView& s, int velCol, double dt, int dispStride = 0,
            int stateStride = 0) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto mask = mask_;
    auto tangent = tangent_;
    const int dim = dim_, fields = fields_;
    Kokkos::parallel_for(
        "implicit_wall_stop", Kokkos::RangePolicy<ExecSpace>(0, held.extent(0)), KOKKOS_LAMBDA(int e) {
          if (!held(e)) return;
          const int k = e / fields, q = e % fields * dispStride, o = e % fields * stateStride;
          const int n = node(k), axis = (int)params(wall(k), 0);
          const bool stuckNode = stuck(held, tangent, params, wall, e, k);
          for (int c = 0; c < dim; ++c)
            if (c == axis || (stuckNode && ((mask(k) >> c) & 1))) {
              d(n, q + dvCol + c) = -s(n, o + velCol + c);
              d(n, q + anewCol + c) = -s(n, o + velCol + c) / dt;
            }
        });
  }

  // Each wall node's (owned node, wall), on the host.
  std::vector<std::pair<int, int>> nodeWalls() const {
    auto node = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), node_);
    auto wall = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), wall_);
    std::vector<std::pair<int, int>> pairs;
    for (size_t k = 0; k < node.extent(0); ++k) pairs.push_back({node(k), wall(k)});
    return pairs;
  }
  int fieldCount() const { return fields_; }
  // The set a checkpoint keeps, per wall node (in the order of nodeWalls()) and field: held at the
  // end of the step, the tangential state and the slip direction (3).
  static constexpr int kStateWidth = 5;
  std::vector<double> states() const {
    auto held = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), held_);
    auto tangent = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tangent_);
    auto direction = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), direction_);
    std::vector<double> rows;
    for (size_t e = 0; e < held.extent(0); ++e) {
      rows.insert(rows.end(), {double(held(e)), double(tangent(e))});
      for (int c = 0; c < 3; ++c) rows.push_back(direction(e, c));
    }
    return rows;
  }
  // Restores the rows of states() given as (wall node, its fieldCount() x kStateWidth values).
  void restoreStates(const std::vector<std::pair<int, const double*>>& rows) const {
    auto held = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), held_);
    auto tangent = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tangent_);
    auto direction = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), direction_);
    for (const auto& [k, row] : rows)
      for (int f = 0; f < fields_; ++f) {
        const int e = k * fields_ + f;
        const double* r = row + f * kStateWidth;
        held(e) = int(r[0]);
        tangent(e) = int(r[1]);
        for (int c = 0; c < 3; ++c) direction(e, c) = r[2 + c];
      }
    Kokkos::deep_copy(held_, held);
    Kokkos::deep_copy(tangent_, tangent);
    Kokkos::deep_copy(direction_, direction);
  }

 private:
  // Entry e (wall node k) of a frictional wall: held and stuck.
  KOKKOS_INLINE_FUNCTION static bool stuck(const IntView& held, const IntView& tangent, const Table& params,
                                           const IntView& wall, int e, int k) {
    return held(e) && tangent(e) == kStick && params(wall(k), 2) > 0.0;
  }

  IntView node_, wall_, mask_;
  Table params_, force_;
  int dim_ = 2, fields_ = 1;
  bool frictional_ = false;
  // Per entry (wall node k, field f at k * fields + f): held in this solve (1); the step's decision
  // from an earlier solve (1 hold, -1 release, 2 held again for good, 0 by the start motion); the
  // tangential state and slip direction, and whether they are still to be taken from the start
  // motion (not held at the end of the last step); the friction and the normal force of a
  // slipping entry at the last residual; the set at the step's start.
  IntView held_, decided_, tangent_, fresh_;
  Table direction_, friction_;
  Kokkos::View<double*, DeviceType> normal_;
  IntView keptHeld_, keptTangent_;
  Table keptDirection_;
};

}  // namespace impm
