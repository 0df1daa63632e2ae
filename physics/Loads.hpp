// External loads with a time function: total forces applied as consistent nodal forces on a
// face of a rectangular body (3D: box), at a grid node, or carried by the particle nearest a point; and
// body forces (an acceleration such as gravity) on the particles of one body or of all.
#pragma once

#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/ParticleStencil.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "physics/Body.hpp"
#include "physics/ManufacturedSolution.hpp"
#include "physics/TimeFunction.hpp"

namespace impm {

struct LoadSpec {
  std::string name;
  std::string type;      // "Face Traction", "Node Force", "Particle Force", "Body Force", "Manufactured Body Force"
  std::string face;      // for Face Traction
  RectangularBody body;  // the body whose face carries a Face Traction
  int bodyIndex = -1;    // Body Force, Manufactured Body Force: the body (-1: every body)
  AxisAlignedManufactured manufactured;  // Manufactured Body Force: the field whose forcing it is
  double x = 0, y = 0, z = 0;
  double forceX = 0, forceY = 0, forceZ = 0;                       // total force (N)
  double accelerationX = 0, accelerationY = 0, accelerationZ = 0;  // Body Force (m/s^2)
  double force(int d) const { return d == 0 ? forceX : d == 1 ? forceY : forceZ; }
  double acceleration(int d) const { return d == 0 ? accelerationX : d == 1 ? accelerationY : accelerationZ; }
  TimeFunction time;

  static LoadSpec faceTraction(const std::string& name, const RectangularBody& body, const std::string& face,
                               double forceX, double forceY, TimeFunction time = {}) {
    LoadSpec s;
    s.name = name;
    s.type = "Face Traction";
    s.body = body;
    s.face = face;
    s.forceX = forceX;
    s.forceY = forceY;
    s.time = time;
    return s;
  }
};

class LoadSet {
 public:
  LoadSet() = default;
  // particleIds[k]: global id of the particle carrying load k (Particle Force), -1 otherwise.
  // Call locateParticles() before stepping (and after particles migrate). quadraticElements: the
  // grid's functions are FE Q9's (face tractions then take the quadratic edge's shares).
  LoadSet(const std::vector<LoadSpec>& specs, const GridDistribution& dist, const std::vector<long long>& particleIds,
          int bodyCount, bool quadraticElements = false);
  // Finds this rank's particles of the Particle Force loads by global id.
  void locateParticles(const ParticleSet& ps);

  // Adds the nodal forces at time t into columns col.. (one per dimension) of an owned grid view.
  template <class ExecSpace, class GridView>
  void applyNodal(const GridView& owned, int col, double t) const {
    updateMagnitudes(t);
    auto node = node_;
    auto load = load_;
    auto w = weight_;
    auto f = nodalForce_;
    const int dim = dim_;
    Kokkos::parallel_for(
        "nodal_loads", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          for (int d = 0; d < dim; ++d) owned(node(k), col + d) += w(k) * f(load(k), d);
        });
  }
  // Particle-carried forces at time t: indices of the particles and their forces.
  Kokkos::View<int*, DeviceType> particleIndices() const { return particle_; }
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> particleForces(double t) const;
  bool hasParticleForces() const { return particle_.extent(0) > 0; }
  bool hasBodyForces() const { return hasBodyForces_; }
  // Body-force acceleration of each body at time t.
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> bodyAccelerations(double t) const;

  // Every particle-carried external force at time t (point forces and body forces m_p g),
  // scattered into columns col.. of a ghosted grid view.
  template <class ExecSpace, class Shape, int Dim, class GridView, class Fields = SingleField>
  void scatterParticleForces(const StructuredGrid& g, const LocalNodeIndexer& ix, const ParticleSet& ps,
                             const GridView& grid, int col, double t, const Fields& fields = Fields()) const {
    if (hasParticleForces())
      particleToGridForces<ExecSpace, Shape, Dim>(g, ix, ps, particleIndices(), particleForces(t), grid, col, fields);
    if (hasBodyForces())
      particleToGridBodyForces<ExecSpace, Shape, Dim>(g, ix, ps, bodyAccelerations(t), grid, col, fields);
    for (int l : manufacturedLoads_)
      particleToGridBodyForceField<ExecSpace, Shape, Dim>(g, ix, ps, specs_[l].manufactured, t, specs_[l].bodyIndex,
                                                          grid, col, fields);
  }

 private:
  void updateMagnitudes(double t) const;
  std::vector<LoadSpec> specs_;
  Kokkos::View<int*, DeviceType> node_, load_;
  Kokkos::View<double*, DeviceType> weight_;
  mutable Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> nodalForce_;  // per load, at t
  Kokkos::View<int*, DeviceType> particle_;                 // local indices of the carrying particles on this rank
  std::vector<int> particleLoad_;                           // their loads
  std::vector<std::pair<long long, int>> particleLoadIds_;  // (global id, load) of every Particle Force
  mutable Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> particleForce_;
  std::vector<int> bodyForceLoads_;
  std::vector<int> manufacturedLoads_;
  int bodyCount_ = 0;
  int dim_ = 2;
  bool hasBodyForces_ = false;
  mutable Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> bodyAcceleration_;
};

}  // namespace impm
