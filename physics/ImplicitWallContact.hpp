// Rigid walls in the implicit step: an active set on the normal component, and Coulomb friction
// as a stick/slip set with the sliding rub applied after the solve (GridConditions owns one;
// ImplicitNewmark drives it).
//
// Normal. Each step starts by holding a wall node's normal component (not an unknown: no
// displacement into the wall) where the node has mass and its start motion, v + dt a / 2, does not
// leave the wall. After a converged solve, revise() releases held components the wall pulls and
// holds free ones that moved into it, and the step is solved again until nothing changes (at most
// maxSolves() solves; the last one stands). A held component ends the step at rest: its velocity
// change is -v (FLIP particles receive the stop, as in the explicit step), and its reaction is the
// force that stops it, N = -m v / dt - F_int - F_ext.
//
// Friction (mu > 0): stick in the solve, slip after it. A held node starts the step slipping (its
// tangential components free; the first solve is frictionless). revise() makes it stick where
// friction could stop it within the step, m |v_t| <= mu N dt with v_t its tangential end
// velocity and N its normal reaction in that solve: its tangential components are then held (at
// rest at the step's end), and their reaction F_t is the force that keeps it in place; and lets
// a stuck node slip for good where |F_t| > mu N: its tangential components are unknowns again,
// loaded in the residual by the friction force mu N F_t / |F_t| of that solve (a constant load,
// so the preconditioner is unchanged), so that the nodes still stuck do not carry its share.
// Each node changes at most twice per step, so the solves end. A node that slips from the first
// solve to the last is rubbed after it as the explicit wall rubs it:
// its tangential end velocity loses at most mu N dt / m, its new acceleration follows
// (da = dv / (gamma dt)), the particles receive the velocity change (FLIP), and the force is
// m dv / dt. Newton sees no kink (stuck components are prescribed, slipping ones free); the price
// of rubbing after the solve is a split error of first order in dt, as the step's equilibrium
// sees the sliding friction only through the velocities it leaves (test_walls: a block sliding
// to a stop, 1.2% of its velocity at dt = 100 explicit steps, 0.6% at 50). The step's
// displacement is the solve's: moving a rubbed node by Newmark's beta dt / gamma dv as well
// strained the layer above a light node by order one. Within some 30% of the stick threshold the
// set does not settle in maxSolves() solves and a block creeps (user guide, limitations).
#pragma once

#include <Kokkos_Core.hpp>
#include <cmath>

#include "core/Types.hpp"

namespace impm {

class ImplicitWallContact {
 public:
  using IntView = Kokkos::View<int*, DeviceType>;
  using Table = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>;

  ImplicitWallContact() = default;
  // Per wall node: its owned node, its wall, the components the wall may change (bit d), and per
  // wall (axis, side, mu); `force` receives each wall node's reaction.
  ImplicitWallContact(IntView node, IntView wall, IntView freeMask, Table params, Table force, int dim, bool frictional)
      : node_(node),
        wall_(wall),
        mask_(freeMask),
        params_(params),
        force_(force),
        dim_(dim),
        frictional_(frictional),
        held_("wall_held", node.extent(0)),
        decided_("wall_decided", node.extent(0)),
        slip_("wall_slip", node.extent(0)),
        friction_("wall_friction", node.extent(0), 3),
        load_("wall_external_load", node.extent(0), 3) {}

  bool frictional() const { return frictional_; }
  // The solves a step may take before its last one stands.
  static constexpr int maxSolves() { return 5; }

  // A new step: every decision from the start motion, every node slipping.
  void beginStep() {
    Kokkos::deep_copy(decided_, 0);
    Kokkos::deep_copy(slip_, kSlips);
    Kokkos::deep_copy(friction_, 0.0);
  }

  // The external force F_ext (columns fextCol..) at the wall nodes before any friction (frictional
  // walls only), kept so that loadFriction() can add the friction of the nodes that slip for good.
  template <class ExecSpace, class StateView>
  void keepLoads(const StateView& s, int fextCol) const {
    if (!frictional_) return;
    auto node = node_;
    auto load = load_;
    const int dim = dim_;
    Kokkos::parallel_for(
        "implicit_wall_keep_loads", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          for (int c = 0; c < dim; ++c) load(k, c) = s(node(k), fextCol + c);
        });
  }

  // F_ext at the wall nodes = the kept loads + the friction of the nodes that slip for good.
  template <class ExecSpace, class StateView>
  void loadFriction(const StateView& s, int fextCol) const {
    if (!frictional_) return;
    auto node = node_;
    auto load = load_;
    auto friction = friction_;
    const int dim = dim_;
    Kokkos::parallel_for(
        "implicit_wall_reset_loads", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          for (int c = 0; c < dim; ++c) s(node(k), fextCol + c) = load(k, c);
        });
    Kokkos::parallel_for(
        "implicit_wall_friction_loads", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          for (int c = 0; c < dim; ++c)
            if (friction(k, c) != 0.0) Kokkos::atomic_add(&s(node(k), fextCol + c), friction(k, c));
        });
  }

  // Marks the free components of the implicit grid state s (columns freeCol..): a held wall
  // component is not free, any other wall component is free where the node's mass exceeds cutoff.
  template <class ExecSpace, class StateView>
  void hold(const StateView& s, int massCol, int velCol, int accCol, int freeCol, double cutoff, double dt) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto decided = decided_;
    auto mask = mask_;
    auto slip = slip_;
    const int dim = dim_;
    if (frictional_)  // tangential components: free where massive, before the walls decide
      Kokkos::parallel_for(
          "implicit_wall_tangents_free", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
            const int n = node(k), axis = (int)params(wall(k), 0);
            if (params(wall(k), 2) <= 0.0) return;
            for (int c = 0; c < dim; ++c)
              if (c != axis && (mask(k) >> c) & 1) s(n, freeCol + c) = s(n, massCol) > cutoff ? 1.0 : 0.0;
          });
    Kokkos::parallel_for(
        "implicit_wall_hold", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          const int n = node(k), axis = (int)params(wall(k), 0);
          const double side = params(wall(k), 1);
          const bool massive = s(n, massCol) > cutoff;
          const bool hold =
              massive &&
              (decided(k) != 0 ? decided(k) > 0 : side * (s(n, velCol + axis) + 0.5 * dt * s(n, accCol + axis)) <= 0.0);
          held(k) = hold ? 1 : 0;
          s(n, freeCol + axis) = massive && !hold ? 1.0 : 0.0;
        });
    if (frictional_)  // a stuck node's tangential components are held
      Kokkos::parallel_for(
          "implicit_wall_stick", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
            if (!stuck(held, slip, params, wall, k)) return;
            const int axis = (int)params(wall(k), 0);
            for (int c = 0; c < dim; ++c)
              if (c != axis && (mask(k) >> c) & 1) s(node(k), freeCol + c) = 0.0;
          });
  }

  // After a converged solve (owned displacement d at uCol.., the grid state s with the mass at
  // massCol, reactionAt(n, d) a held component's reaction, endVelocityAt(n, d) a free one's
  // velocity at the step's end): the number of wall nodes this rank changes (released, held,
  // stuck or slipping) for the next solve.
  template <class ExecSpace, class DispView, class StateView, class ReactionAt, class EndVelocityAt>
  int revise(const DispView& d, int uCol, const StateView& s, int massCol, const ReactionAt& reactionAt,
             const EndVelocityAt& endVelocityAt, double dt, double tolerance) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto decided = decided_;
    auto mask = mask_;
    auto slip = slip_;
    auto friction = friction_;
    const int dim = dim_;
    int changes = 0;
    Kokkos::parallel_reduce(
        "implicit_wall_revise", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k, int& count) {
          const int n = node(k), axis = (int)params(wall(k), 0);
          const double side = params(wall(k), 1);
          if (held(k) && side * reactionAt(n, axis) < 0.0) {  // the wall pulls: let go
            decided(k) = -1;
            ++count;
          } else if (!held(k) && side * d(n, uCol + axis) < -tolerance) {  // into the wall: hold
            decided(k) = 1;
            ++count;
          } else if (held(k) && params(wall(k), 2) > 0.0 && slip(k) != kSlipsForGood) {
            const double limit = params(wall(k), 2) * side * reactionAt(n, axis);  // mu N
            double t2 = 0.0;  // |F_t|^2 of a stuck node, |m v_t / dt|^2 of a slipping one
            for (int c = 0; c < dim; ++c)
              if (c != axis && (mask(k) >> c) & 1) {
                const double f = slip(k) == kStuck ? reactionAt(n, c) : s(n, massCol) * endVelocityAt(n, c) / dt;
                t2 += f * f;
              }
            if (slip(k) == kStuck && t2 > limit * limit) {  // holding takes more than mu N
              slip(k) = kSlipsForGood;
              const double ratio = limit / std::sqrt(t2);
              for (int c = 0; c < dim; ++c)
                if (c != axis && (mask(k) >> c) & 1) friction(k, c) = ratio * reactionAt(n, c);
              ++count;
            } else if (slip(k) == kSlips && t2 <= limit * limit) {  // friction stops it
              slip(k) = kStuck;
              ++count;
            }
          }
        },
        changes);
    return changes;
  }

  // After the last solve: the held components' reactions, a stuck node's tangential ones too (a
  // slipping node's friction is rub()'s).
  template <class ExecSpace, class ReactionAt>
  void record(const ReactionAt& reactionAt) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto force = force_;
    auto mask = mask_;
    auto slip = slip_;
    auto friction = friction_;
    const int dim = dim_;
    Kokkos::parallel_for(
        "implicit_wall_reaction", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          const int n = node(k), axis = (int)params(wall(k), 0);
          const bool stuckNode = stuck(held, slip, params, wall, k);
          for (int c = 0; c < 3; ++c) {
            const bool heldComponent = held(k) && (c == axis || (stuckNode && c < dim && ((mask(k) >> c) & 1)));
            force(k, c) = heldComponent ? reactionAt(n, c) : held(k) && slip(k) == kSlipsForGood ? friction(k, c) : 0.0;
          }
        });
  }

  // The held components' end of step: at rest (velocity change -v, acceleration -v / dt), a stuck
  // node's tangential ones too.
  template <class ExecSpace, class DispView, class StateView>
  void stop(const DispView& d, int anewCol, int dvCol, const StateView& s, int velCol, double dt) const {
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto mask = mask_;
    auto slip = slip_;
    const int dim = dim_;
    Kokkos::parallel_for(
        "implicit_wall_stop", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          if (!held(k)) return;
          const int n = node(k), axis = (int)params(wall(k), 0);
          const bool stuckNode = stuck(held, slip, params, wall, k);
          for (int c = 0; c < dim; ++c)
            if (c == axis || (stuckNode && ((mask(k) >> c) & 1))) {
              d(n, dvCol + c) = -s(n, velCol + c);
              d(n, anewCol + c) = -s(n, velCol + c) / dt;
            }
        });
  }

  // Friction on the end-of-step motion of the nodes that slipped in every solve (see the file comment): the new
  // acceleration (anewCol..) and velocity change (dvCol..) in d, the start velocity and mass in s, reactionAt(n, axis)
  // the held normal reaction N; each node's friction force goes into its tangential reaction.
  template <class ExecSpace, class DispView, class StateView, class ReactionAt>
  void rub(const DispView& d, int anewCol, int dvCol, const StateView& s, int massCol, int velCol,
           const ReactionAt& reactionAt, double dt, double gamma) const {
    if (!frictional_) return;
    auto node = node_;
    auto wall = wall_;
    auto params = params_;
    auto held = held_;
    auto force = force_;
    auto mask = mask_;
    auto slip = slip_;
    const int dim = dim_;
    Kokkos::parallel_for(
        "implicit_wall_friction", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          const int n = node(k), axis = (int)params(wall(k), 0);
          const double side = params(wall(k), 1), mu = params(wall(k), 2), m = s(n, massCol);
          const double normal = side * reactionAt(n, axis);
          if (!held(k) || slip(k) != kSlips || mu <= 0.0 || !(normal > 0.0) || !(m > 0.0)) return;
          double vt2 = 0.0;
          for (int c = 0; c < dim; ++c)
            if (c != axis && (mask(k) >> c) & 1) {
              const double v = s(n, velCol + c) + d(n, dvCol + c);
              vt2 += v * v;
            }
          const double vt = std::sqrt(vt2), limit = mu * normal * dt / m;
          if (vt == 0.0) return;
          const double removed = vt <= limit ? 1.0 : limit / vt;  // the fraction of v_t friction takes
          for (int c = 0; c < dim; ++c)
            if (c != axis && (mask(k) >> c) & 1) {
              const double dv = -removed * (s(n, velCol + c) + d(n, dvCol + c));
              d(n, dvCol + c) += dv;
              d(n, anewCol + c) += dv / (gamma * dt);

              force(k, c) += m * dv / dt;
            }
        });
  }

 private:
  // A held node of a frictional wall that does not slip.
  KOKKOS_INLINE_FUNCTION static bool stuck(const IntView& held, const IntView& slip, const Table& params,
                                           const IntView& wall, int k) {
    return held(k) && slip(k) == kStuck && params(wall(k), 2) > 0.0;
  }
  // The tangential states of a held node of a frictional wall.
  static constexpr int kSlips = 0, kStuck = 1, kSlipsForGood = 2;

  IntView node_, wall_, mask_;
  Table params_, force_;
  int dim_ = 2;
  bool frictional_ = false;
  // Per wall node: held in this solve (1); the step's decision from an earlier solve (1 hold, -1
  // release, 0 by the start motion); the tangential state in this step; the friction force of a
  // node that slips for good; F_ext before friction.
  IntView held_, decided_, slip_;
  Table friction_, load_;
};

}  // namespace impm
