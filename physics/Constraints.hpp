// Prescribed motion of grid node sets (a face, a node, a box): which components, and their
// motion (fixed, or a velocity or displacement times a time function). GridConditions applies them.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "physics/Body.hpp"
#include "physics/TimeFunction.hpp"

namespace impm {

// A face of a rectangular body, a single grid node, or every grid node in a box; which
// components are fixed.
struct ConstraintSpec {
  std::string name;
  std::string where;                                                  // "Face", "Node" or "Box"
  std::string face;                                                   // x-, x+, y-, y+ (3D: also z-, z+) (Face)
  RectangularBody body;                                               // the body whose face it is (Face)
  double x = 0, y = 0, z = 0;                                         // the node (Node)
  double xMin = 0, xMax = 0, yMin = 0, yMax = 0, zMin = 0, zMax = 0;  // the box, edges included (Box)
  bool fixX = false, fixY = false, fixZ = false;                      // the components it prescribes
  bool fixes(int d) const { return d == 0 ? fixX : d == 1 ? fixY : fixZ; }
  // Fixed: the prescribed components stay at rest. Velocity: v_d(t) = value[d] f(t).
  // Displacement: u_d(t) = value[d] f(t) from the start of the run.
  enum class Motion { Fixed, Velocity, Displacement } motion = Motion::Fixed;
  double value[3] = {0, 0, 0};
  TimeFunction time{TimeFunction::Kind::Constant, 0.0, 0.0, 0.0, {}};
  // The same motion of component d (for two conditions that share a dof).
  bool sameMotion(const ConstraintSpec& o, int d) const {
    const bool stillHere = motion == Motion::Fixed || value[d] == 0.0;
    const bool stillThere = o.motion == Motion::Fixed || o.value[d] == 0.0;
    if (stillHere || stillThere) return stillHere && stillThere;
    return motion == o.motion && value[d] == o.value[d] && time == o.time;
  }

  static ConstraintSpec onFace(const std::string& name, const RectangularBody& body, const std::string& face, bool fixX,
                               bool fixY) {
    ConstraintSpec s;
    s.name = name;
    s.where = "Face";
    s.body = body;
    s.face = face;
    s.fixX = fixX;
    s.fixY = fixY;
    return s;
  }
  static ConstraintSpec atNode(const std::string& name, double x, double y, bool fixX, bool fixY) {
    ConstraintSpec s;
    s.name = name;
    s.where = "Node";
    s.x = x;
    s.y = y;
    s.fixX = fixX;
    s.fixY = fixY;
    return s;
  }
};

using NodeIndex = std::array<int, 3>;  // global (i, j, k); k = 0 in 2D

// Grid nodes inside a box, edges included (to round-off); the z range is ignored in 2D.
std::vector<NodeIndex> boxNodes(const StructuredGrid& g, double xMin, double xMax, double yMin, double yMax,
                                double zMin = 0, double zMax = 0);

// Grid nodes on a face of the body, within the body's extent along the face.
std::vector<NodeIndex> faceNodes(const StructuredGrid& g, const RectangularBody& body, const std::string& face);

// The nodes a constraint names: its face, its box, or its node.
std::vector<NodeIndex> constraintNodes(const ConstraintSpec& s, const StructuredGrid& g);

}  // namespace impm
