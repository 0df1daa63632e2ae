// Deck section Walls: rigid planes on grid lines that the bodies cannot cross, with Coulomb
// friction and their reactions (physics/GridConditions.hpp, physics/ImplicitWallContact.hpp).
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <cmath>

#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

namespace impm {

using build::onGridLine;
using schema::choice;
using schema::number;
using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

RCP<const ParameterList> build::wallsTemplate() {
  auto pl = rcp(new ParameterList("Walls"));
  choice(*pl, "Normal", "y+", {"x+", "x-", "y+", "y-", "z+", "z-"},
         "the direction from the wall into the bodies: y+ is a floor under them, x- a wall on their right (z+, z- "
         "in 3D). Contact is one-sided: a grid node on or behind the wall loses the velocity that would take it "
         "into the wall and keeps the velocity that takes it away. Implicit: an active set (a held node's normal "
         "component is not an unknown; with friction a stuck node's tangential ones neither; see the user guide)");
  number(*pl, "Position", 0.0, "the wall's coordinate along its normal axis (m; on a grid line inside the grid)");
  number(*pl, "Friction", 0.0,
         "Coulomb friction coefficient mu >= 0 between the wall and the bodies: a node in contact loses at most mu "
         "times its normal velocity change from its tangential velocity (implicit: slips under the force mu N where "
         "holding it would take more; 0: frictionless). The force the wall "
         "applies to the grid is in history.csv (<name>_reaction_<x|y|z>) and summary.yaml (Reactions)");
  return pl;
}

// The rigid walls: a normal along the grid's axes, the plane on a grid line inside the grid, a
// friction coefficient of at least zero; material points (not the finite-element reference).
std::vector<WallSpec> Simulation::buildWalls() const {
  std::vector<WallSpec> walls;
  const ParameterList& ws = deck_.sublist("Walls");
  for (auto it = ws.begin(); it != ws.end(); ++it) {
    const std::string name = ws.name(it), key = "Walls/" + name;
    const ParameterList& w = ws.sublist(name);
    const bool implicit = deck_.sublist("Integrator").get<std::string>("Type") != "Explicit";
    if (implicit && shapeInfo(shape_).fixedParticles)
      throw DeckError("'" + key + "': rigid walls need material points; 'Method/Shape Function' = " + shape_ +
                      " is a finite-element reference without walls");
    WallSpec spec;
    spec.name = name;
    const std::string normal = w.get<std::string>("Normal");
    spec.axis = normal[0] - 'x';
    spec.side = normal[1] == '+' ? 1 : -1;
    if (spec.axis >= grid_.dim) throw DeckError("'" + key + "/Normal' = " + normal + " needs 'Grid/Dimension' = 3");
    spec.position = w.get<double>("Position");
    const double o = grid_.origin(spec.axis), h = grid_.spacing(spec.axis);
    const int cells = spec.axis == 0 ? grid_.nx : spec.axis == 1 ? grid_.ny : grid_.nz;
    if (!onGridLine(spec.position, o, h) || spec.position < o - 1e-9 * h || spec.position > o + cells * h + 1e-9 * h)
      throw DeckError("'" + key + "/Position' = " + formatNumber(spec.position) +
                      " is not on a grid line inside the grid (" + std::string(1, char('x' + spec.axis)) + " = " +
                      formatNumber(o) + " + k " + formatNumber(h) + ", k = 0.." + std::to_string(cells) + ")");
    spec.friction = w.get<double>("Friction");
    if (!(spec.friction >= 0) || !std::isfinite(spec.friction))
      throw DeckError("'" + key + "/Friction' must be a finite coefficient >= 0, got " + formatNumber(spec.friction));
    walls.push_back(spec);
  }
  return walls;
}

// Every particle starts on the bodies' side of every wall (over all ranks).
void Simulation::checkParticlesBesideWalls(const std::vector<WallSpec>& walls) const {
  for (const WallSpec& w : walls) {
    auto x = particles_.x;
    const int axis = w.axis;
    const double side = w.side, position = w.position, tolerance = 1e-9 * grid_.spacing(w.axis);
    long long behind = 0, total = 0;
    Kokkos::parallel_reduce(
        "particles_behind_wall", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count),
        KOKKOS_LAMBDA(int p, long long& n) { n += side * (x(p, axis) - position) < -tolerance ? 1 : 0; }, behind);
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, behind, Teuchos::outArg(total));
    if (total > 0)
      throw DeckError("'Walls/" + w.name + "': " + std::to_string(total) + " particles start behind the wall (" +
                      std::string(1, char('x' + axis)) + (w.side > 0 ? " < " : " > ") + formatNumber(position) +
                      "); the bodies must lie on the side its Normal points to");
  }
}

}  // namespace impm
