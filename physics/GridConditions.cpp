#include "physics/GridConditions.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace impm {

GridConditions::GridConditions(const std::vector<ConstraintSpec>& specs, const GridDistribution& dist,
                               const std::vector<WallSpec>& walls, const ContactSpec& contact)
    : dim_(dist.grid().dim), specs_(specs), walls_(walls) {
  if (contact.enabled()) {
    const StructuredGrid& grid = dist.grid();
    const double spacing[3] = {grid.spacing(0), grid.spacing(1), grid.dim == 3 ? grid.spacing(2) : 1.0};
    contact_ = MultiFieldContact(contact, spacing);
  }
  const StructuredGrid& g = dist.grid();
  const LocalNodeIndexer& owned = dist.ownedIndexer();
  std::vector<int> nodes, comps, conds;
  std::set<std::pair<int, int>> taken;  // (owned node, component): a dof belongs to its first condition
  for (size_t c = 0; c < specs.size(); ++c) {
    const ConstraintSpec& s = specs[c];
    names_.push_back(s.name);
    kinds_.push_back("reaction");
    prescribed_.push_back({s.fixes(0), s.fixes(1), g.dim == 3 && s.fixes(2)});
    for (auto [i, j, k] : constraintNodes(s, g)) {
      if (!owned.contains(i, j, k)) continue;
      for (int d = 0; d < g.dim; ++d)
        if (s.fixes(d) && taken.insert({owned(i, j, k), d}).second) {
          nodes.push_back(owned(i, j, k));
          comps.push_back(d);
          conds.push_back((int)c);
        }
    }
  }
  auto toDevice = [](const std::vector<int>& v, const std::string& label) {
    Kokkos::View<int*, DeviceType> out(label, v.size());
    auto h = Kokkos::create_mirror_view(out);
    for (size_t k = 0; k < v.size(); ++k) h(k) = v[k];
    Kokkos::deep_copy(out, h);
    return out;
  };
  node_ = toDevice(nodes, "condition_nodes");
  comp_ = toDevice(comps, "condition_components");
  cond_ = toDevice(conds, "condition_of_dof");
  values_ = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>("condition_values", specs.size(),
                                                                    int(PrescribedField::Count) * 3);
  dofForce_ = Kokkos::View<double*, DeviceType>("condition_dof_force", nodes.size());
  localReaction_.assign(3 * (specs.size() + walls.size() + contact_.pairCount()), 0.0);

  // Walls: every owned node on or behind the plane (to round-off), acting on the components no
  // constraint prescribes there (a node whose normal component is prescribed keeps its motion).
  std::map<int, int> prescribedMask;  // owned node -> bit d set when component d is prescribed
  for (const auto& [n, d] : taken) prescribedMask[n] |= 1 << d;
  std::vector<int> wallNodes, wallOf, wallFree;
  wallParams_ = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>("wall_parameters", walls.size(), 3);
  auto hp = Kokkos::create_mirror_view(wallParams_);
  for (size_t w = 0; w < walls.size(); ++w) {
    const WallSpec& wall = walls[w];
    names_.push_back(wall.name);
    kinds_.push_back("reaction");
    prescribed_.push_back({true, true, g.dim == 3});
    hp(w, 0) = wall.axis;
    hp(w, 1) = wall.side;
    hp(w, 2) = wall.friction;
    const double tolerance = 1e-9 * g.spacing(wall.axis);
    for (int i = owned.lo[0]; i < owned.end(0); ++i)
      for (int j = owned.lo[1]; j < owned.end(1); ++j)
        for (int k = owned.lo[2]; k < owned.end(2); ++k) {
          const int ijk[3] = {i, j, k};
          const double x = g.origin(wall.axis) + g.spacing(wall.axis) * ijk[wall.axis];
          const auto found = prescribedMask.find(owned(i, j, k));
          const int held = found == prescribedMask.end() ? 0 : found->second;
          if (wall.side * (x - wall.position) > tolerance || (held >> wall.axis) & 1) continue;
          wallNodes.push_back(owned(i, j, k));
          wallOf.push_back((int)w);
          wallFree.push_back(~held & 7);
        }
  }
  Kokkos::deep_copy(wallParams_, hp);
  for (int pair = 0; pair < contact_.pairCount(); ++pair) {
    names_.push_back(contact.pairNames[pair]);
    kinds_.push_back("contact");
    prescribed_.push_back({true, true, g.dim == 3});
  }
  wallNode_ = toDevice(wallNodes, "wall_nodes");
  wallOf_ = toDevice(wallOf, "wall_of_node");
  wallFree_ = toDevice(wallFree, "wall_free_components");
  wallForce_ = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>("wall_node_force", wallNodes.size(), 3);
  const bool frictional = std::any_of(walls.begin(), walls.end(), [](const WallSpec& w) { return w.friction > 0.0; });
  implicitWalls_ = ImplicitWallContact(wallNode_, wallOf_, wallFree_, wallParams_, wallForce_, g.dim, frictional,
                                       std::max(1, fieldCount()));
}

void GridConditions::sumWallReactions() {
  auto force = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), wallForce_);
  auto wall = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), wallOf_);
  const size_t first = 3 * specs_.size();
  std::fill(localReaction_.begin() + first, localReaction_.begin() + first + 3 * walls_.size(), 0.0);
  for (size_t k = 0; k < force.extent(0); ++k)
    for (int d = 0; d < 3; ++d) localReaction_[first + 3 * wall(k) + d] += force(k, d);
}

void GridConditions::setStep(double t, double dt) {
  dt_ = dt;
  contact_.setStep(t, dt);
  auto h = Kokkos::create_mirror_view(values_);
  zero_.fill(true);
  for (size_t c = 0; c < specs_.size(); ++c) {
    const ConstraintSpec& s = specs_[c];
    for (int d = 0; d < 3; ++d) {
      double field[int(PrescribedField::Count)] = {};
      if (s.motion == ConstraintSpec::Motion::Velocity && s.value[d] != 0.0) {
        auto v = [&](double tau) { return s.value[d] * s.time(tau); };
        const double start = v(t), end = v(t + dt), before = v(t - dt);
        field[int(PrescribedField::Increment)] = 0.5 * dt * (start + end);
        field[int(PrescribedField::StartVelocity)] = start;
        field[int(PrescribedField::EndVelocity)] = end;
        field[int(PrescribedField::StartAcceleration)] = (start - before) / dt;
      } else if (s.motion == ConstraintSpec::Motion::Displacement && s.value[d] != 0.0) {
        auto u = [&](double tau) { return s.value[d] * s.time(tau); };
        const double u0 = u(t), u1 = u(t + dt), um1 = u(t - dt), um2 = u(t - 2 * dt);
        const double start = (u0 - um1) / dt, end = (u1 - u0) / dt;
        field[int(PrescribedField::Increment)] = u1 - u0;
        field[int(PrescribedField::StartVelocity)] = start;
        field[int(PrescribedField::EndVelocity)] = end;
        field[int(PrescribedField::StartAcceleration)] = (start - (um1 - um2) / dt) / dt;
      }
      field[int(PrescribedField::VelocityChange)] =
          field[int(PrescribedField::EndVelocity)] - field[int(PrescribedField::StartVelocity)];
      field[int(PrescribedField::Acceleration)] = field[int(PrescribedField::VelocityChange)] / dt;
      for (int f = 0; f < int(PrescribedField::Count); ++f) {
        h(c, f * 3 + d) = field[f];
        zero_[f] = zero_[f] && field[f] == 0.0;
      }
    }
  }
  Kokkos::deep_copy(values_, h);
}

void GridConditions::sumReactions() {
  auto force = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dofForce_);
  auto comp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), comp_);
  auto cond = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cond_);
  std::fill(localReaction_.begin(), localReaction_.begin() + 3 * specs_.size(), 0.0);
  for (size_t k = 0; k < force.extent(0); ++k) localReaction_[3 * cond(k) + comp(k)] += force(k);
}

std::vector<double> GridConditions::reactions(const Teuchos::Comm<int>& comm) const {
  std::vector<double> global(localReaction_.size(), 0.0);
  if (!global.empty())
    Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, (int)global.size(), localReaction_.data(), global.data());
  return global;
}

}  // namespace impm
