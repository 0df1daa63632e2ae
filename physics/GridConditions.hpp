// Grid conditions: the grid-side physics between particle-to-grid and grid-to-particle. Each
// condition acts on a set of grid dofs (one component of one node); today's conditions prescribe
// the motion of their dofs (a fixed component is the motion 0). The integrators call the hooks
// below at fixed places in their steps, and each hook both writes the prescribed values into the
// grid fields and records the force the condition applied (its reaction):
//   explicit step:  p2g -> grid update -> afterExplicitGridUpdate -> g2p
//   implicit step:  set-up (the start velocity and acceleration written, the dofs marked not
//                   free) -> Newton on the free dofs, the prescribed increments written into the
//                   grid displacement at every residual -> the converged residual at the
//                   prescribed dofs recorded as the reaction -> g2p
// A dof named by two conditions belongs to the first (the deck refuses two different motions).
//
// Rigid walls (explicit): a wall is the plane x_axis = position with the bodies on one side. A grid
// node on or behind it that would move into it after the grid update loses that normal velocity
// (and gains nothing if it moves away: contact is one-sided), and Coulomb friction takes off at
// most `friction` times the normal velocity change from its tangential velocity (stopping it when
// that suffices); its reaction is m dv / dt. Nodes with a prescribed component keep their motion.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "physics/Constraints.hpp"

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
                 const std::vector<WallSpec>& walls = {});

  // Evaluates the conditions' time functions for the step [t, t + dt] (host; cheap). Every hook
  // below uses the step last set.
  void setStep(double t, double dt);

  // Writes `field` into columns col.. (one per dimension) of an owned grid view at every dof.
  template <class ExecSpace, class GridView>
  void write(const GridView& owned, int col, PrescribedField field) const {
    auto node = node_; auto comp = comp_; auto cond = cond_; auto values = values_;
    const int f = int(field);
    Kokkos::parallel_for(
        "grid_condition_write", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k) { owned(node(k), col + comp(k)) = values(cond(k), f * 3 + comp(k)); });
  }

  // Records each dof's reaction, forceAt(owned node, component): the force the condition applies
  // to its node (the integrator knows the balance at the dof); then sums them per condition.
  template <class ExecSpace, class ForceAtDof>
  void recordReaction(const ForceAtDof& forceAt) {
    auto node = node_; auto comp = comp_; auto force = dofForce_;
    Kokkos::parallel_for(
        "grid_condition_reaction", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k) { force(k) = forceAt(node(k), comp(k)); });
    sumReactions();
  }

  // Explicit hook, after the grid update on owned nodes: the new velocity and acceleration
  // (kin, columns velCol.. and accCol..) take the prescribed ones, and each dof's reaction is the
  // force that gives its node that acceleration, m a - F_int - F_ext + c p (mass damping c; the
  // particle sums in `sums`: mass, momentum, F_ext and F_int columns).
  template <class ExecSpace, class SumsView, class KinView>
  void afterExplicitGridUpdate(const SumsView& sums, int massCol, int momCol, int fextCol, int fintCol,
                               const KinView& kin, int velCol, int accCol, double damping) {
    write<ExecSpace>(kin, velCol, PrescribedField::EndVelocity);
    write<ExecSpace>(kin, accCol, PrescribedField::Acceleration);
    recordReaction<ExecSpace>(KOKKOS_LAMBDA(int n, int d) {
      return sums(n, massCol) * kin(n, accCol + d) - sums(n, fintCol + d) - sums(n, fextCol + d) +
             damping * sums(n, momCol + d);
    });
    if (hasWalls()) {
      wallContact<ExecSpace>(sums, massCol, kin, velCol, accCol, true);
      sumWallReactions();
    }
  }

  // The walls on a grid velocity field alone (the velocity the stress is computed from, with USF
  // and MUSL): velocity into a wall removed, friction as above; no acceleration, no reaction.
  template <class ExecSpace, class SumsView, class VelocityView>
  void enforceWalls(const SumsView& sums, int massCol, const VelocityView& vel, int velCol) const {
    if (hasWalls()) wallContact<ExecSpace>(sums, massCol, vel, velCol, -1, false);
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
  std::vector<double> reactions(const Teuchos::Comm<int>& comm) const;

  // Owned local node index and component of each dof on this rank.
  Kokkos::View<int*, DeviceType> nodes() const { return node_; }
  Kokkos::View<int*, DeviceType> components() const { return comp_; }

 private:
  void sumReactions();
  void sumWallReactions();
  // The contact of every wall node (see the file comment): kin's velocity (and acceleration, when
  // accCol >= 0) corrected; with `record`, each node's reaction m dv / dt into wallForce_.
  template <class ExecSpace, class SumsView, class KinView>
  void wallContact(const SumsView& sums, int massCol, const KinView& kin, int velCol, int accCol, bool record) const {
    auto node = wallNode_; auto wall = wallOf_; auto params = wallParams_; auto force = wallForce_;
    const int dim = dim_;
    const double dt = dt_;
    Kokkos::parallel_for(
        "wall_contact", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          const int n = node(k), w = wall(k);
          const int axis = (int)params(w, 0);
          const double side = params(w, 1), mu = params(w, 2), m = sums(n, massCol);
          double dv[3] = {0.0, 0.0, 0.0};
          const double vn = side * kin(n, velCol + axis);
          if (m > 0.0 && vn < 0.0) {
            dv[axis] = -kin(n, velCol + axis);
            double vt2 = 0.0;
            for (int d = 0; d < dim; ++d)
              if (d != axis) vt2 += kin(n, velCol + d) * kin(n, velCol + d);
            const double vt = std::sqrt(vt2), limit = -mu * vn;
            const double removed = vt <= limit ? 1.0 : limit / vt;  // the tangential fraction friction stops
            for (int d = 0; d < dim; ++d)
              if (d != axis) dv[d] = -removed * kin(n, velCol + d);
          }
          for (int d = 0; d < dim; ++d) {
            kin(n, velCol + d) += dv[d];
            if (accCol >= 0) kin(n, accCol + d) += dv[d] / dt;
            if (record) force(k, d) = m * dv[d] / dt;
          }
        });
  }
  int dim_ = 2;
  std::vector<ConstraintSpec> specs_;
  std::vector<std::string> names_;
  std::vector<std::array<bool, 3>> prescribed_;
  Kokkos::View<int*, DeviceType> node_, comp_, cond_;
  // Per condition: PrescribedField::Count x 3 components, for the step last set.
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> values_;
  Kokkos::View<double*, DeviceType> dofForce_;
  std::vector<double> localReaction_;  // 3 per condition, then 3 per wall
  // Walls: the specs, each wall node (owned local index) and its wall, per wall (axis, side,
  // friction), and each wall node's last reaction.
  std::vector<WallSpec> walls_;
  Kokkos::View<int*, DeviceType> wallNode_, wallOf_;
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> wallParams_, wallForce_;
  double dt_ = 0.0;
  std::array<bool, int(PrescribedField::Count)> zero_{};
};

}  // namespace impm
