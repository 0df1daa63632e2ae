// Deck sections Grid, Method and Decomposition: the structured grid, the shape function and how
// the ranks split the grid.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/Collective.hpp"
#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

#include <cmath>

#include "core/RankGrid.hpp"

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

void addGridSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist("Grid", false, "structured background grid");
  p.set("Dimension", 2,
        "2 (plane strain or plane stress, with Thickness) or 3 (Origin Z, Cells Z, Cell Size Z; "
        "no Plane Condition or Thickness)");
  number(p, "Origin X", 0.0, "x of the lower-left corner");
  number(p, "Origin Y", 0.0, "y of the lower-left corner");
  number(p, "Origin Z", 0.0, "z of the lower corner (3D)");
  p.set("Cells X", 10, "number of cells in x");
  p.set("Cells Y", 1, "number of cells in y");
  p.set("Cells Z", 1, "number of cells in z (3D)");
  number(p, "Cell Size X", 1.0, "cell size in x (m)");
  number(p, "Cell Size Y", 1.0, "cell size in y (m)");
  number(p, "Cell Size Z", 1.0, "cell size in z (m; 3D)");
  choice(p, "Plane Condition", "Plane Strain", {"Plane Strain", "Plane Stress"},
         "2D idealisation; a bar in plane stress has modulus E, in plane strain E/(1 - nu^2)");
  number(p, "Thickness", 1.0, "out-of-plane thickness b (m; 2D)");
}

void addMethodSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist("Method", false, "spatial discretisation");
  choice(
      p, "Shape Function", "MPM", shapeNames(),
      "MPM: linear tent at particle points; GIMP: uniform GIMP; cpGIMP: GIMP with the particle domain "
      "stretched by the diagonal of F (capped at half a cell), for large deformation; CPDI: CPDI1 (Sadeghirad et al. "
      "2011), the domain a parallelogram / parallelepiped carried by the full F, weights averaged over its corners "
      "(corners within 3 cells per direction); B-Spline Quadratic: C1 "
      "quadratic B-splines at particle points (3 nodes per direction, Steffen et al.'s boundary splines at the "
      "grid edge; at least 2 cells per direction); B-Spline Cubic: C2 cubic B-splines at particle points (4 nodes "
      "per direction, Steffen et al.'s modified edge splines; at least 3 cells per direction); FE Q4 / FE Q9: the "
      "finite-element "
      "reference on the same kernels, particles fixed at the Gauss points (Q4: bilinear, 2 x 2 per cell; "
      "Q9: biquadratic Lagrange elements of 2 x 2 cells, 3 x 3 points; Cells X and Y even), implicit "
      "only, Rectangle bodies only; Particles Per Cell is not used. In 3D FE Q4 is the trilinear Hex8 "
      "(2 x 2 x 2 points per cell) and FE Q9 the triquadratic Hex27 (3 x 3 x 3 per element of 2 x 2 x 2 cells)");
  choice(p, "Volumetric Locking", "None", {"None", "F-bar"},
         "None: each particle's own deformation; F-bar: each particle's volume change over a step is that of its cell "
         "(the volume-weighted mean of det dF over the cell's particles of the same material, Coombs et al. 2018), "
         "its isochoric part its own, against the volumetric locking of isochoric plastic flow (J2, Drucker-Prager "
         "at zero dilatancy) and near-incompressible elasticity. Explicit and implicit (Jacobian-Free Newton), "
         "plane strain and 3D, material points only");
}

void addDecompositionSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist(
      "Decomposition", false, "how MPI ranks split the grid: a Cartesian grid of ranks, each owning a box of cells");
  p.set("Ranks X", 0,
        "ranks along x (0: impm chooses every direction left 0, the factorisation of the rank count with the fewest "
        "nodes on rank boundaries); Ranks X x Ranks Y (x Ranks Z) must equal the rank count when all are given");
  p.set("Ranks Y", 0, "ranks along y (0: chosen by impm)");
  p.set("Ranks Z", 0, "ranks along z, 3D only (0: chosen by impm)");
  p.set("Migration Slack Cells", 1,
        "particles migrate lazily: a rank's ghost band is this many cells wider than its stencils need, and "
        "particles are exchanged with neighbouring ranks only once one of them is further than this from its "
        "rank's cells (0: after every step in which a particle changed rank)");
  p.set("Load Balance Interval", 0,
        "steps between load-balance checks (0: never; also at the start when positive): when the largest rank's "
        "particle count exceeds 'Load Balance Threshold' times the mean, the cuts between ranks move along each "
        "direction to equalise the particles per plane of ranks (tensor splits), and particles, grid maps and the "
        "integrator follow. The imbalance is in summary.yaml (Decomposition)");
  p.set("Load Balance Threshold", 1.1, "rebalance only above this max / mean particles per rank (>= 1)");
}

void Simulation::readGrid() {
  const ParameterList& g = deck_.sublist("Grid");
  grid_.dim = g.get<int>("Dimension");
  if (grid_.dim != 2 && grid_.dim != 3)
    throw DeckError("'Grid/Dimension' must be 2 or 3, got " + std::to_string(grid_.dim));
  if (grid_.dim == 3) {
    grid_.z0 = g.get<double>("Origin Z");
    grid_.nz = positiveInt(g, "Grid", "Cells Z");
    grid_.hz = positive(g, "Grid", "Cell Size Z");
  }
  grid_.x0 = g.get<double>("Origin X");
  grid_.y0 = g.get<double>("Origin Y");
  grid_.nx = positiveInt(g, "Grid", "Cells X");
  grid_.ny = positiveInt(g, "Grid", "Cells Y");
  grid_.hx = positive(g, "Grid", "Cell Size X");
  grid_.hy = positive(g, "Grid", "Cell Size Y");
  thickness_ = positive(g, "Grid", "Thickness");
}

void Simulation::readMethod() {
  shape_ = deck_.sublist("Method").get<std::string>("Shape Function");
  settings_.shapeFunction = shape_;
  const ShapeInfo& shape = shapeInfo(shape_);  // (the schema admits only the registry's names)
  if (shape.fixedParticles) placement_ = shape.quadraticElements ? Placement::GaussQ9 : Placement::GaussQ4;
  fbar_ = deck_.sublist("Method").get<std::string>("Volumetric Locking") == "F-bar";
  if (fbar_ && shape.fixedParticles)
    throw DeckError("'Method/Volumetric Locking' = F-bar is for material points; 'Method/Shape Function' = " + shape_ +
                    " is the finite-element reference");
  if (fbar_ && grid_.dim == 2 && deck_.sublist("Grid").get<std::string>("Plane Condition") == "Plane Stress")
    throw DeckError(
        "'Method/Volumetric Locking' = F-bar is for plane strain and 3D; 'Grid/Plane Condition' = Plane Stress "
        "has no volumetric locking to control");
}

// The rank grid and the grid distribution (Decomposition).
void Simulation::distribute() {
  // A CPDI domain's corners may lie in 3 cells per direction: its stencil reaches 2 cells beyond
  // the particle's own (Cpdi::max_nodes_1d), one cell more than the other shapes. The migration
  // slack widens the ghost band so that particles may stray that far before they migrate.
  const ParameterList& dec = deck_.sublist("Decomposition");
  migrationSlack_ = dec.get<int>("Migration Slack Cells");
  if (migrationSlack_ < 0)
    throw DeckError("'Decomposition/Migration Slack Cells' must be 0 or positive, got " +
                    std::to_string(migrationSlack_));
  const int reach = shapeInfo(shape_).cornerDomains ? 3 : 2;
  // A rank's block is wider than the slack, so that a particle can only stray into a neighbour's.
  const RankGrid ranks(grid_, comm_->getSize(),
                       {dec.get<int>("Ranks X"), dec.get<int>("Ranks Y"), dec.get<int>("Ranks Z")},
                       migrationSlack_ + 1);
  dist_ = std::make_unique<GridDistribution>(grid_, comm_, reach + migrationSlack_, ranks);
  loadBalanceInterval_ = dec.get<int>("Load Balance Interval");
  loadBalanceThreshold_ = dec.get<double>("Load Balance Threshold");
  if (loadBalanceInterval_ < 0)
    throw DeckError("'Decomposition/Load Balance Interval' must be 0 (off) or positive, got " +
                    std::to_string(loadBalanceInterval_));
  if (!(loadBalanceThreshold_ >= 1.0))
    throw DeckError("'Decomposition/Load Balance Threshold' must be at least 1 (max / mean particles per rank), got " +
                    formatNumber(loadBalanceThreshold_));
}

void Simulation::checkGridNode(const std::string& where, double x, double y, double z) const {
  const double tolx = 1e-9 * grid_.hx, toly = 1e-9 * grid_.hy, tolz = 1e-9 * grid_.hz;
  const bool solid = grid_.dim == 3;
  if (!onGridLine(x, grid_.x0, grid_.hx) || !onGridLine(y, grid_.y0, grid_.hy) || x < grid_.x0 - tolx ||
      x > grid_.xMax() + tolx || y < grid_.y0 - toly || y > grid_.yMax() + toly ||
      (solid && (!onGridLine(z, grid_.z0, grid_.hz) || z < grid_.z0 - tolz || z > grid_.zMax() + tolz)))
    throw DeckError("'" + where + "/X', '" + where + "/Y'" + (solid ? ", '" + where + "/Z'" : std::string()) + " = (" +
                    formatNumber(x) + ", " + formatNumber(y) + (solid ? ", " + formatNumber(z) : std::string()) +
                    ") is not a grid node");
}

}  // namespace impm
