// External loads: total forces with a time function, applied as consistent nodal forces on
// a face of the body, at a grid node, or carried by the particle nearest a point.
#pragma once

#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "physics/Body.hpp"

namespace impm {

struct TimeFunction {
  enum class Kind { Step, Sine, Constant } kind = Kind::Step;
  double omega = 0.0;      // Sine: angular frequency (rad/s)
  double startTime = 0.0;  // Step: load is on for t >= startTime
  double operator()(double t) const;
};

struct LoadSpec {
  std::string name;
  std::string type;  // "Face Traction", "Node Force", "Particle Force"
  std::string face;  // for Face Traction
  double x = 0, y = 0;
  double forceX = 0, forceY = 0;  // total force (N)
  TimeFunction time;
};

class LoadSet {
 public:
  LoadSet() = default;
  // particleIndex[k]: local particle chosen for each Particle Force load (-1 if on another rank).
  LoadSet(const std::vector<LoadSpec>& specs, const RectangularBody& body, const GridDistribution& dist,
          const std::vector<int>& particleIndex);

  // Adds the nodal forces at time t into columns col, col+1 of an owned grid view.
  template <class ExecSpace, class GridView>
  void applyNodal(const GridView& owned, int col, double t) const {
    updateMagnitudes(t);
    auto node = node_; auto load = load_; auto w = weight_; auto f = nodalForce_;
    Kokkos::parallel_for(
        "nodal_loads", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          owned(node(k), col) += w(k) * f(load(k), 0);
          owned(node(k), col + 1) += w(k) * f(load(k), 1);
        });
  }
  // Particle-carried forces at time t: indices of the particles and their forces.
  Kokkos::View<int*, DeviceType> particleIndices() const { return particle_; }
  Kokkos::View<double* [2], Kokkos::LayoutRight, DeviceType> particleForces(double t) const;
  bool hasParticleForces() const { return particle_.extent(0) > 0; }

 private:
  void updateMagnitudes(double t) const;
  std::vector<LoadSpec> specs_;
  Kokkos::View<int*, DeviceType> node_, load_;
  Kokkos::View<double*, DeviceType> weight_;
  mutable Kokkos::View<double* [2], Kokkos::LayoutRight, DeviceType> nodalForce_;  // per load, at t
  Kokkos::View<int*, DeviceType> particle_;
  std::vector<int> particleLoad_;
  mutable Kokkos::View<double* [2], Kokkos::LayoutRight, DeviceType> particleForce_;
};

}  // namespace impm
