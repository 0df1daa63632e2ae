// Velocity / displacement constraints on grid node sets: each entry fixes one component of
// one owned node to zero.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "physics/Body.hpp"

namespace impm {

// A face of a rectangular body, a single grid node, or every grid node in a box; which
// components are fixed.
struct ConstraintSpec {
  std::string name;
  std::string where;    // "Face", "Node" or "Box"
  std::string face;     // x-, x+, y-, y+ (3D: also z-, z+) (Face)
  RectangularBody body; // the body whose face it is (Face)
  double x = 0, y = 0, z = 0;  // the node (Node)
  double xMin = 0, xMax = 0, yMin = 0, yMax = 0, zMin = 0, zMax = 0;  // the box, edges included (Box)
  bool fixX = false, fixY = false, fixZ = false;
  bool fixes(int d) const { return d == 0 ? fixX : d == 1 ? fixY : fixZ; }

  static ConstraintSpec onFace(const std::string& name, const RectangularBody& body, const std::string& face, bool fixX,
                               bool fixY) {
    ConstraintSpec s;
    s.name = name; s.where = "Face"; s.body = body; s.face = face; s.fixX = fixX; s.fixY = fixY;
    return s;
  }
  static ConstraintSpec atNode(const std::string& name, double x, double y, bool fixX, bool fixY) {
    ConstraintSpec s;
    s.name = name; s.where = "Node"; s.x = x; s.y = y; s.fixX = fixX; s.fixY = fixY;
    return s;
  }
};

using NodeIndex = std::array<int, 3>;  // global (i, j, k); k = 0 in 2D

// Grid nodes inside a box, edges included (to round-off); the z range is ignored in 2D.
std::vector<NodeIndex> boxNodes(const StructuredGrid& g, double xMin, double xMax, double yMin, double yMax,
                                double zMin = 0, double zMax = 0);

// Grid nodes on a face of the body, within the body's extent along the face.
std::vector<NodeIndex> faceNodes(const StructuredGrid& g, const RectangularBody& body, const std::string& face);

class NodalConstraints {
 public:
  NodalConstraints() = default;
  NodalConstraints(const std::vector<ConstraintSpec>& specs, const GridDistribution& dist);

  // Zero the constrained components of vector fields stored in columns col.. (one per
  // dimension) of an owned grid view (used for velocity, acceleration and displacement).
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
