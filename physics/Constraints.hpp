// Velocity / displacement constraints on grid node sets: each entry fixes one component of
// one owned node to zero.
#pragma once

#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "physics/Body.hpp"

namespace impm {

// A face of the body, or a single grid node; which components are fixed.
struct ConstraintSpec {
  std::string name;
  std::string where;  // "Face" or "Node"
  std::string face;   // x-, x+, y-, y+
  double x = 0, y = 0;
  bool fixX = false, fixY = false;
};

// Grid nodes on a face of the body (global i, j), within the body's extent along the face.
std::vector<std::pair<int, int>> faceNodes(const StructuredGrid& g, const RectangularBody& body, const std::string& face);

class NodalConstraints {
 public:
  NodalConstraints() = default;
  NodalConstraints(const std::vector<ConstraintSpec>& specs, const RectangularBody& body, const GridDistribution& dist);

  // Zero the constrained components of two-component fields stored in columns col, col+1
  // of an owned grid view (used for velocity, acceleration and displacement).
  template <class ExecSpace, class GridView>
  void apply(const GridView& owned, int col) const {
    auto node = node_; auto comp = comp_;
    Kokkos::parallel_for(
        "apply_constraints", Kokkos::RangePolicy<ExecSpace>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k) { owned(node(k), col + comp(k)) = 0.0; });
  }
  // Owned local node index and component of each constraint on this rank.
  Kokkos::View<int*, DeviceType> nodes() const { return node_; }
  Kokkos::View<int*, DeviceType> components() const { return comp_; }

 private:
  Kokkos::View<int*, DeviceType> node_, comp_;
};

}  // namespace impm
