// Every shape function a deck can name ('Method/Shape Function'), with its C++ type and the facts
// the set-up needs, in one list. The builder asks the list (shapeInfo) and dispatches on types
// through it (visitShape) instead of testing the name; a new shape function is one entry here
// (and its explicit instantiations in solvers/ExplicitStepper.cpp and solvers/implicit/ImplicitNewmark<Family>.cpp).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "core/ShapeFunctions.hpp"

namespace impm {

struct ShapeInfo {
  const char* name;        // the deck's name
  bool explicitToo;        // false: implicit only (the finite-element reference)
  bool fixedParticles;     // the finite-element reference: particles are the elements' Gauss points
  bool quadraticElements;  // FE Q9 / Hex27: 2 x 2 cell elements (even cell counts, quadratic face shares)
  bool particleDomain;     // GIMP, cpGIMP, CPDI: a particle reaches nodes over its domain
  bool cornerDomains;      // CPDI: the domain's corners must stay within the grid's reach
  double nodeReachCells;   // how far a node's function reaches, in cells (particle domain excluded)
  int stencilNodes1d;      // nodes per direction a particle touches
  int minimumCells;        // cells per direction a stencil needs
  // Linear MPM: a particle that crosses a cell line alone can be inverted with USL at any time step
  // (its far nodes' tiny mass takes a huge velocity; doc/method.md, "Cell crossing").
  bool crossingInverts;
};

template <class Shape>
struct ShapeTag {
  using type = Shape;
};

namespace detail {
// (name, explicit, fixed, quadratic, domain, corners, reach, nodes, minimum cells, crossing inverts)
inline const std::vector<ShapeInfo>& shapeTable() {
  static const std::vector<ShapeInfo> table = {
      {"MPM", true, false, false, false, false, 1.0, 2, 1, true},
      {"GIMP", true, false, false, true, false, 1.0, 3, 1, false},
      {"cpGIMP", true, false, false, true, false, 1.0, 3, 1, false},
      {"CPDI", true, false, false, true, true, 1.0, 4, 1, false},
      {"B-Spline Quadratic", true, false, false, false, false, 1.5, 3, 2, false},
      {"B-Spline Cubic", true, false, false, false, false, 2.0, 4, 3, false},
      {"FE Q4", false, true, false, false, false, 1.0, 2, 1, false},
      {"FE Q9", false, true, true, false, false, 2.0, 3, 2, false},
  };
  return table;
}
}  // namespace detail

// The names, in the order of the list (for the deck's schema).
inline std::vector<std::string> shapeNames() {
  std::vector<std::string> names;
  for (const ShapeInfo& s : detail::shapeTable()) names.push_back(s.name);
  return names;
}

// The entry of the shape named `name` (std::invalid_argument for another name).
inline const ShapeInfo& shapeInfo(const std::string& name) {
  for (const ShapeInfo& s : detail::shapeTable())
    if (name == s.name) return s;
  throw std::invalid_argument("unknown shape function '" + name + "'");
}

// Calls visit(ShapeTag<Shape>{}, info) with the C++ type of the shape named `name` (FE Q4 runs the
// linear functions, FE Q9 the quadratic Lagrange ones, both with fixed particles) and returns
// what it returns.
template <class Visit>
decltype(auto) visitShape(const std::string& name, Visit&& visit) {
  const ShapeInfo& info = shapeInfo(name);
  const std::string n = info.name;
  if (n == "GIMP") return visit(ShapeTag<UniformGimp>{}, info);
  if (n == "cpGIMP") return visit(ShapeTag<ConvectedGimp>{}, info);
  if (n == "CPDI") return visit(ShapeTag<Cpdi>{}, info);
  if (n == "B-Spline Quadratic") return visit(ShapeTag<QuadraticBSpline>{}, info);
  if (n == "B-Spline Cubic") return visit(ShapeTag<CubicBSpline>{}, info);
  if (n == "FE Q9") return visit(ShapeTag<QuadraticLagrange>{}, info);
  return visit(ShapeTag<LinearMpm>{}, info);  // MPM, FE Q4
}

}  // namespace impm
