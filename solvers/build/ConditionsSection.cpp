// Deck sections Constraints and Loads: grid conditions (fixed or prescribed motion, with their
// reactions) and external loads, with their time functions. Walls: WallsSection.cpp.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/Collective.hpp"
#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

#include <cmath>

namespace impm {

using build::kParticlePlacementDoc;
using build::onGridLine;
using build::timeFunctionKeys;
using schema::choice;
using schema::number;
using schema::positive;
using schema::positiveInt;
using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

// The time-function keys of a load or a prescribed motion (physics/TimeFunction.hpp).
void build::timeFunctionKeys(ParameterList& pl, const std::string& def, const std::string& what) {
  choice(pl, "Time Function", def, {"Step", "Sine", "Constant", "Ramp", "Table"},
         what +
             ". Step: H(t - Start Time); Sine: sin(omega t); Constant: 1; Ramp: min(max(t - Start Time, 0) / Ramp "
             "Time, 1), for quasi-static loading; Table: linear between the (t, value) pairs of Table, the end values "
             "held "
             "outside them");
  number(pl, "Ramp Time", 0.0, "duration of the rise of a Ramp (s)");
  number(pl, "Angular Frequency", 0.0, "omega of the Sine time function (rad/s)");
  number(pl, "Start Time", 0.0, "time at which a Step comes on, or a Ramp starts rising (s)");
  pl.set("Table", "", "Time Function = Table: 't0, v0; t1, v1; ...' (as Bodies/Vertices), the times increasing (s)");
}

RCP<const ParameterList> build::constraintsTemplate() {
  auto pl = rcp(new ParameterList("Constraints"));
  choice(*pl, "Where", "Face", {"Face", "Node", "Box"},
         "a face of a rectangular body, the grid node at (X, Y), or every grid node in the box X/Y Min/Max "
         "(edges included)");
  choice(*pl, "Face", "x-", {"x-", "x+", "y-", "y+", "z-", "z+"}, "face of the body (Where = Face; z-, z+ in 3D)");
  pl->set("Body", "", "the body whose face it is (Where = Face; empty: the first body)");
  number(*pl, "X", 0.0, "x of the node (Where = Node)");
  number(*pl, "Y", 0.0, "y of the node (Where = Node)");
  number(*pl, "Z", 0.0, "z of the node (Where = Node; 3D)");
  number(*pl, "X Min", 0.0, "box (Where = Box)");
  number(*pl, "X Max", 0.0, "box (Where = Box)");
  number(*pl, "Y Min", 0.0, "box (Where = Box)");
  number(*pl, "Y Max", 0.0, "box (Where = Box)");
  number(*pl, "Z Min", -1.0e300, "box (Where = Box; 3D; default: the whole grid in z)");
  number(*pl, "Z Max", 1.0e300, "box (Where = Box; 3D; default: the whole grid in z)");
  choice(*pl, "Components", "all", {"all", "x", "y", "z", "xy", "xz", "yz", "xyz"},
         "the components it prescribes (all: every component of the grid's dimension; z: 3D only)");
  choice(*pl, "Motion", "Fixed", {"Fixed", "Velocity", "Displacement"},
         "Fixed: the components stay at rest; Velocity: they move at Value X/Y/Z (m/s) times the time function; "
         "Displacement: they are displaced by Value X/Y/Z (m) times the time function from where they are at t = 0. "
         "The force the condition applies to the grid is in history.csv (<name>_reaction_<x|y|z>) and summary.yaml "
         "(Reactions)");
  number(*pl, "Value X", 0.0, "Motion = Velocity: velocity (m/s); Displacement: displacement (m); x");
  number(*pl, "Value Y", 0.0, "the same, y");
  number(*pl, "Value Z", 0.0, "the same, z (3D)");
  timeFunctionKeys(*pl, "Constant", "the factor of Value X/Y/Z over time");
  return pl;
}

RCP<const ParameterList> build::loadsTemplate() {
  auto pl = rcp(new ParameterList("Loads"));
  choice(*pl, "Type", "Face Traction",
         {"Face Traction", "Node Force", "Particle Force", "Body Force", "Manufactured Body Force"},
         "uniform traction on a face of a rectangular body (consistent nodal forces), a force on the grid "
         "node at (X, Y), a force carried by the particle nearest (X, Y), a body force m_p g "
         "(Acceleration X/Y, e.g. gravity) on the particles of Body, or the body force m_p b(X_p, t) that makes "
         "the deck's manufactured solution exact (Exact Solution/Type = Axis-Aligned Manufactured Solution; no "
         "other key: the field is the exact solution's)");
  choice(*pl, "Face", "x+", {"x-", "x+", "y-", "y+", "z-", "z+"}, "face of the body (Face Traction; z-, z+ in 3D)");
  pl->set("Body", "",
          "Face Traction: the body whose face it is (empty: the first body); Body Force: the "
          "body it acts on (empty: every body)");
  number(*pl, "Acceleration X", 0.0, "Body Force: acceleration, x (m/s^2)");
  number(*pl, "Acceleration Y", 0.0, "Body Force: acceleration, y (m/s^2)");
  number(*pl, "Acceleration Z", 0.0, "Body Force: acceleration, z (m/s^2; 3D)");
  number(*pl, "X", 0.0, "x of the point (Node Force, Particle Force)");
  number(*pl, "Y", 0.0, "y of the point (Node Force, Particle Force)");
  number(*pl, "Z", 0.0, "z of the point (Node Force, Particle Force; 3D)");
  number(*pl, "Force X", 0.0, "total force, x component (N)");
  number(*pl, "Force Y", 0.0, "total force, y component (N)");
  number(*pl, "Force Z", 0.0, "total force, z component (N; 3D)");
  timeFunctionKeys(*pl, "Step", "the factor of the force over time (the same factor scales a Body Force)");
  return pl;
}

TimeFunction Simulation::timeFunctionOf(const ParameterList& l, const std::string& key) const {
  TimeFunction f;
  const std::string tf = l.get<std::string>("Time Function");
  f.kind = tf == "Sine"       ? TimeFunction::Kind::Sine
           : tf == "Constant" ? TimeFunction::Kind::Constant
           : tf == "Ramp"     ? TimeFunction::Kind::Ramp
           : tf == "Table"    ? TimeFunction::Kind::Table
                              : TimeFunction::Kind::Step;
  f.rampTime = l.get<double>("Ramp Time");
  if (f.kind == TimeFunction::Kind::Ramp && !(f.rampTime > 0))
    throw DeckError("'" + key + "/Ramp Time' must be positive for a Ramp, got " + formatNumber(f.rampTime));
  f.omega = l.get<double>("Angular Frequency");
  f.startTime = l.get<double>("Start Time");
  if (f.kind == TimeFunction::Kind::Sine && !(f.omega > 0))
    throw DeckError("'" + key + "/Angular Frequency' must be positive for a Sine");
  const std::string table = l.get<std::string>("Table");
  if (f.kind == TimeFunction::Kind::Table) {
    try {
      f.table = parseTimeTable(table);
    } catch (const std::invalid_argument& e) {
      throw DeckError("'" + key + "/Table' = '" + table + "': " + e.what());
    }
  } else if (!table.empty()) {
    throw DeckError("'" + key + "/Table' is set but 'Time Function' is " + tf + " (Table needs Time Function = Table)");
  }
  return f;
}

// The motion of a constraint: Fixed (at rest), or a velocity or displacement of the prescribed
// components times a time function.
void Simulation::readMotion(const ParameterList& c, const std::string& key, ConstraintSpec& s) const {
  const std::string motion = c.get<std::string>("Motion");
  s.motion = motion == "Velocity"       ? ConstraintSpec::Motion::Velocity
             : motion == "Displacement" ? ConstraintSpec::Motion::Displacement
                                        : ConstraintSpec::Motion::Fixed;
  const char* names[3] = {"Value X", "Value Y", "Value Z"};
  for (int d = 0; d < 3; ++d) {
    s.value[d] = c.get<double>(names[d]);
    if (s.value[d] == 0.0) continue;
    if (s.motion == ConstraintSpec::Motion::Fixed)
      throw DeckError("'" + key + "/" + names[d] + "' = " + formatNumber(s.value[d]) +
                      " but 'Motion' is Fixed (a moving condition needs Motion = Velocity or Displacement)");
    if (!s.fixes(d) || d >= grid_.dim)
      throw DeckError("'" + key + "/" + names[d] + "' = " + formatNumber(s.value[d]) + " but 'Components' = " +
                      c.get<std::string>("Components") + " does not prescribe " + char('x' + d));
  }
  s.time = timeFunctionOf(c, key);
}

// Two conditions that name the same dof must prescribe the same motion there (the first keeps it).
void Simulation::checkConditionOverlaps(const std::vector<ConstraintSpec>& specs) const {
  std::map<std::array<int, 4>, size_t> owner;  // (i, j, k, component) -> first condition
  for (size_t c = 0; c < specs.size(); ++c) {
    const ConstraintSpec& s = specs[c];
    const std::vector<NodeIndex> nodes = constraintNodes(s, grid_);
    for (const auto& [i, j, k] : nodes)
      for (int d = 0; d < grid_.dim; ++d) {
        if (!s.fixes(d)) continue;
        const auto [it, inserted] = owner.insert({{i, j, k, d}, c});
        if (inserted || specs[it->second].sameMotion(s, d)) continue;
        const StructuredGrid& g = grid_;
        throw DeckError("'Constraints/" + specs[it->second].name + "' and 'Constraints/" + s.name +
                        "' prescribe different motions of component " + char('x' + d) + " of the grid node at " +
                        describePoint({g.nodeX(i), g.nodeY(j), g.dim == 3 ? g.nodeZ(k) : 0.0}));
      }
  }
}

std::vector<ConstraintSpec> Simulation::buildConstraints() {
  std::vector<ConstraintSpec> specs;
  const ParameterList& cl = deck_.sublist("Constraints");
  for (auto it = cl.begin(); it != cl.end(); ++it) {
    const ParameterList& c = cl.sublist(cl.name(it));
    ConstraintSpec s;
    s.name = cl.name(it);
    const std::string key = "Constraints/" + s.name;
    s.where = c.get<std::string>("Where");
    s.face = c.get<std::string>("Face");
    const Point node = pointOf(c);
    s.x = node[0];
    s.y = node[1];
    s.z = node[2];
    s.xMin = c.get<double>("X Min");
    s.xMax = c.get<double>("X Max");
    s.yMin = c.get<double>("Y Min");
    s.yMax = c.get<double>("Y Max");
    if (grid_.dim == 3) {
      s.zMin = c.get<double>("Z Min");
      s.zMax = c.get<double>("Z Max");
    }
    const std::string comp = c.get<std::string>("Components");
    const bool all = comp == "all";
    s.fixX = all || comp.find('x') != std::string::npos;
    s.fixY = all || comp.find('y') != std::string::npos;
    s.fixZ = (all && grid_.dim == 3) || comp.find('z') != std::string::npos;
    if (grid_.dim == 2 && s.fixZ)
      throw DeckError("'" + key + "/Components' = " + comp + " fixes z, which needs 'Grid/Dimension' = 3");
    if (grid_.dim == 2 && s.where == "Face" && s.face[0] == 'z')
      throw DeckError("'" + key + "/Face' = " + s.face + " needs 'Grid/Dimension' = 3");
    if (s.where == "Node") checkGridNode(key, s.x, s.y, s.z);
    if (s.where == "Face") {
      const BodySpec& b = bodyNamed(key + "/Body", c.get<std::string>("Body"));
      if (!b.rectangle)
        throw DeckError("'" + key + "': Where = Face needs a Rectangle body; 'Bodies/" + b.name + "' is not one");
      s.body = b.rect;
    }
    if (s.where == "Box") {
      if (!(s.xMax >= s.xMin && s.yMax >= s.yMin && s.zMax >= s.zMin))
        throw DeckError("'" + key + "': the box needs X Max >= X Min, Y Max >= Y Min (and Z Max >= Z Min)");
      if (boxNodes(grid_, s.xMin, s.xMax, s.yMin, s.yMax, s.zMin, s.zMax).empty())
        throw DeckError("'" + key + "': the box [" + formatNumber(s.xMin) + ", " + formatNumber(s.xMax) + "] x [" +
                        formatNumber(s.yMin) + ", " + formatNumber(s.yMax) + "] holds no grid node");
    }
    readMotion(c, key, s);
    specs.push_back(s);
  }
  checkConditionOverlaps(specs);
  return specs;
}

std::vector<LoadSpec> Simulation::buildLoads() {
  std::vector<LoadSpec> specs;
  std::vector<long long> loadParticle;
  const ParameterList& ll = deck_.sublist("Loads");
  for (auto it = ll.begin(); it != ll.end(); ++it) {
    const ParameterList& l = ll.sublist(ll.name(it));
    LoadSpec s;
    s.name = ll.name(it);
    const std::string key = "Loads/" + s.name;
    s.type = l.get<std::string>("Type");
    s.face = l.get<std::string>("Face");
    const Point point = pointOf(l);
    s.x = point[0];
    s.y = point[1];
    s.z = point[2];
    s.forceX = l.get<double>("Force X");
    s.forceY = l.get<double>("Force Y");
    s.forceZ = l.get<double>("Force Z");
    s.accelerationX = l.get<double>("Acceleration X");
    s.accelerationY = l.get<double>("Acceleration Y");
    s.accelerationZ = l.get<double>("Acceleration Z");
    if (grid_.dim == 2 && (s.forceZ != 0.0 || s.accelerationZ != 0.0))
      throw DeckError("'" + key + "/" + (s.forceZ != 0.0 ? "Force Z" : "Acceleration Z") +
                      "' is not zero: z components need 'Grid/Dimension' = 3");
    if (grid_.dim == 2 && s.type == "Face Traction" && s.face[0] == 'z')
      throw DeckError("'" + key + "/Face' = " + s.face + " needs 'Grid/Dimension' = 3");
    s.time = timeFunctionOf(l, key);
    if (s.type == "Node Force") {
      checkGridNode(key, s.x, s.y, s.z);
      checkNodeReached(key, point);
    }
    const std::string bodyName = l.get<std::string>("Body");
    if (s.type == "Face Traction") {
      const BodySpec& b = bodyNamed(key + "/Body", bodyName);
      if (!b.rectangle)
        throw DeckError("'" + key + "': a Face Traction needs a Rectangle body; 'Bodies/" + b.name + "' is not one");
      s.body = b.rect;
    }
    if (s.type == "Body Force" && !bodyName.empty())
      s.bodyIndex = (int)(&bodyNamed(key + "/Body", bodyName) - bodies_.data());
    if (s.type == "Manufactured Body Force") {
      if (!manufactured_)
        throw DeckError("'" + key +
                        "/Type' = Manufactured Body Force needs 'Exact Solution/Type' = Axis-Aligned Manufactured "
                        "Solution (the field whose forcing it is)");
      s.manufactured = *manufactured_;
      s.bodyIndex = 0;  // the manufactured solution's single body
    }
    long long particle = -1;
    if (s.type == "Particle Force") {
      Monitor m;
      nearestParticle(point, m);
      checkNearParticle("'" + key + "/Type' = Particle Force at", point, m);
      particle = m.particleId;
    }
    loadParticle.push_back(particle);
    specs.push_back(s);
  }
  if (manufactured_ &&
      std::none_of(specs.begin(), specs.end(), [](const LoadSpec& s) { return s.type == "Manufactured Body Force"; }))
    throw DeckError(
        "'Exact Solution/Type' = Axis-Aligned Manufactured Solution needs a load of 'Type' = Manufactured Body "
        "Force in Loads (without it the field is not a solution)");
  loadSpecs_ = specs;  // rebuilt for a new rank grid (load balance)
  loadParticleIds_ = loadParticle;
  loads_ = LoadSet(specs, *dist_, loadParticle, (int)bodies_.size(), shapeInfo(shape_).quadraticElements);
  loads_.locateParticles(particles_);
  return specs;
}

void Simulation::checkNodeReached(const std::string& key, const Point& point) const {
  Point node = {0, 0, 0};
  for (int d = 0; d < grid_.dim; ++d)
    node[d] = grid_.origin(d) + grid_.spacing(d) * std::lround((point[d] - grid_.origin(d)) / grid_.spacing(d));
  if (particlesReaching(node, node) == 0)
    throw DeckError(
        "'" + key + "/Type' = Node Force at " + describePoint(point) +
        ": no particle reaches this grid node at t = 0, so the force would act on no mass; put it on a node of a "
        "body, or use a Particle Force");
}

void Simulation::checkConditionsReached(const std::vector<ConstraintSpec>& specs) const {
  for (const ConstraintSpec& s : specs) {
    // (A fixed face or box is the grid's boundary wherever the bodies go later; a fixed node is
    // placed on a body, to hold it.)
    if (s.motion == ConstraintSpec::Motion::Fixed && s.where != "Node") continue;
    const std::vector<NodeIndex> nodes = constraintNodes(s, grid_);
    // (Face and box node sets are boxes of nodes: a particle reaching their bounding box reaches one of them.)
    Point lo = {1e300, 1e300, 1e300}, hi = {-1e300, -1e300, -1e300};
    for (const auto& ijk : nodes)
      for (int d = 0; d < grid_.dim; ++d) {
        const double x = grid_.origin(d) + grid_.spacing(d) * ijk[d];
        lo[d] = std::min(lo[d], x);
        hi[d] = std::max(hi[d], x);
      }
    const char* motion = s.motion == ConstraintSpec::Motion::Velocity       ? "Velocity"
                         : s.motion == ConstraintSpec::Motion::Displacement ? "Displacement"
                                                                            : "Fixed";
    if (particlesReaching(lo, hi) == 0)
      throw DeckError("'Constraints/" + s.name + "/Motion' = " + motion +
                      ": no particle reaches its grid nodes at t = 0, so it would " +
                      (s.motion == ConstraintSpec::Motion::Fixed ? "hold" : "move") +
                      " nothing; put it where a body is");
  }
}

// Particles (over all ranks) whose shape functions reach a grid node in [lo, hi] at t = 0.
long long Simulation::particlesReaching(const Point& lo, const Point& hi) const {
  // A node's shape function reaches one cell (FE Q9: one element of two cells; quadratic
  // B-splines: 1.5 cells; cubic: 2), plus the particle's half size with GIMP.
  const ShapeInfo& shape = shapeInfo(shape_);
  const double span = shape.nodeReachCells;
  const double reach[3] = {span * grid_.hx, span * grid_.hy, span * grid_.hz};
  const double domain = shape.particleDomain ? 1.0 : 0.0;
  auto px = particles_.x;
  auto hs = particles_.halfSize;
  const int dim = grid_.dim;
  const double l0 = lo[0], l1 = lo[1], l2 = lo[2], h0 = hi[0], h1 = hi[1], h2 = hi[2];
  const double r0 = reach[0], r1 = reach[1], r2 = reach[2];
  // Distance from x to the interval [a, b] along one direction.
  auto gap = [](double x, double a, double b) { return x < a ? a - x : x > b ? x - b : 0.0; };
  long long local = 0;
  Kokkos::parallel_reduce(
      "nodes_reached", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count),
      KOKKOS_LAMBDA(int p, long long& n) {
        bool near = gap(px(p, 0), l0, h0) < r0 + domain * hs(p, 0) && gap(px(p, 1), l1, h1) < r1 + domain * hs(p, 1);
        if (dim == 3) near = near && gap(px(p, 2), l2, h2) < r2 + domain * hs(p, 2);
        if (near) ++n;
      },
      local);
  long long reached = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, local, Teuchos::outArg(reached));
  return reached;
}

}  // namespace impm
