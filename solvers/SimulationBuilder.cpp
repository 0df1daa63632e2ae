// Simulation, part 1: from the validated deck to the objects of a run (grid, materials, bodies
// and particles, constraints, loads, monitors, exact solution, integrator). Every semantic check
// of the deck happens here, before anything is written: a DeckError names the key.
#include "solvers/Simulation.hpp"

#include "core/ShapeRegistry.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <tuple>
#include <type_traits>

#include "core/Collective.hpp"
#include "core/InputDeck.hpp"
#include "physics/InitialConditions.hpp"
#include "solvers/ExplicitStepper.hpp"
#include "physics/materials/MaterialRegistry.hpp"
#include "solvers/implicit/ImplicitNewmark.hpp"

namespace impm {

using Teuchos::ParameterList;

namespace {


double positive(const ParameterList& pl, const std::string& section, const std::string& key) {
  const double v = pl.get<double>(key);
  if (!(v > 0)) throw DeckError("'" + section + "/" + key + "' must be positive, got " + formatNumber(v));
  return v;
}
int positiveInt(const ParameterList& pl, const std::string& section, const std::string& key) {
  const int v = pl.get<int>(key);
  if (v <= 0) throw DeckError("'" + section + "/" + key + "' must be positive, got " + std::to_string(v));
  return v;
}

// The output directory can be created and written: it is a directory, or its nearest existing
// ancestor is one, in which a probe directory can be made (and is removed at once, so that a
// deck that fails later leaves nothing behind). A real probe, not access(): root passes
// access() on /proc and on read-only mounts. `key` names where the path came from.
void checkOutputDirectory(const std::string& dir, const std::string& key) {
  namespace fs = std::filesystem;
  const std::string what = key + " = '" + dir + "'";
  std::error_code ec;
  const fs::path target = fs::absolute(dir, ec).lexically_normal();
  if (ec) throw DeckError(what + ": " + ec.message());
  fs::path existing = target;
  fs::file_status status = fs::status(existing, ec);
  while (status.type() == fs::file_type::not_found && existing.has_relative_path()) {
    existing = existing.parent_path();
    status = fs::status(existing, ec);
  }
  if (!fs::is_directory(status)) {
    if (existing == target) throw DeckError(what + " exists and is not a directory");
    throw DeckError(what + " cannot be created: '" + existing.string() + "' is not a directory");
  }
  std::string probe = (existing / ".impm-write-test-XXXXXX").string();
  if (!mkdtemp(probe.data()))
    throw DeckError(what + (existing == target ? " is not writable" : " cannot be created") + ": no directory can be made in '" +
                    existing.string() + "' (" + std::strerror(errno) + ")");
  rmdir(probe.c_str());
}

// A grid of nx x ny cells and nodes per rank must fit impm's 32-bit local indices with two
// unknowns per node (Tpetra's LO is int).
constexpr long long kMaxGridNodes = std::numeric_limits<int>::max() / 2;

// Memory measured with /usr/bin/time (maximum resident set, OMP_NUM_THREADS=1, 2026-11): a
// rank's libraries and runtimes; per grid node, explicit (the Tpetra fields and maps) and
// implicit (plus matrix, preconditioner and Krylov space, for nodes the bodies cover); per
// particle, the views plus, on every rank, the fill of all bodies over the whole grid that
// numbers the particles independently of the decomposition.
constexpr double kBytesPerRank = 50e6;
constexpr double kBytesPerNodeExplicit = 320, kBytesPerNodeImplicitVoid = 450, kBytesPerNodeImplicitActive = 5000;
constexpr double kFillBytesPerParticlePerRank = 80;

// MemAvailable of /proc/meminfo in bytes (0 when unknown).
double availableMemoryBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kB = 0;
  std::string unit;
  while (meminfo >> key >> kB >> unit)
    if (key == "MemAvailable:") return kB * 1024.0;
  return 0.0;
}

// True when x is on a grid line x0 + k h (to round-off).
bool onGridLine(double x, double x0, double h) {
  const double k = (x - x0) / h;
  return std::abs(k - std::round(k)) < 1e-6;
}

}  // namespace

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

Simulation::Simulation(const ParameterList& deck, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                       const std::string& outputOverride)
    : deck_(deck), comm_(comm) {
  const ParameterList& problem = deck_.sublist("Problem");
  outputDir_ = outputOverride.empty() ? problem.get<std::string>("Output Directory") : outputOverride;
  outputKey_ = outputOverride.empty() ? "'Problem/Output Directory'" : "--output";
  if (outputDir_.empty()) throw DeckError(outputKey_ + " must not be empty");
  // Before any work, on rank 0 (which creates it), the verdict shared by every rank.
  rethrowOnEveryRank(*comm_, comm_->getRank() == 0, [&] { checkOutputDirectory(outputDir_, outputKey_); });

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

  shape_ = deck_.sublist("Method").get<std::string>("Shape Function");
  const ShapeInfo& shape = shapeInfo(shape_);  // (the schema admits only the registry's names)
  if (shape.fixedParticles) placement_ = shape.quadraticElements ? Placement::GaussQ9 : Placement::GaussQ4;
  buildMaterialsAndBodies();

  const ParameterList& in = deck_.sublist("Integrator");
  dt_ = positive(in, "Integrator", "Time Step");
  steps_ = positiveInt(in, "Integrator", "Number of Steps");
  {
    // The output intervals: History Interval counts steps between rows (the last step is always
    // written), so it is at least 1; 0 has a meaning for VTK (first and last step only) and for
    // checkpoints (none); a negative value has none.
    const ParameterList& out = deck_.sublist("Output");
    const int historyInterval = out.get<int>("History Interval");
    if (historyInterval < 1)
      throw DeckError("'Output/History Interval' must be at least 1 (steps between rows of history.csv), got " +
                      std::to_string(historyInterval));
    const int digits = out.get<int>("History Digits");
    if (digits < 1 || digits > 17)
      throw DeckError("'Output/History Digits' must be from 1 to 17 (significant digits in history.csv), got " +
                      std::to_string(digits));
    if (out.get<int>("VTK Interval") < 0)
      throw DeckError("'Output/VTK Interval' must be 0 (first and last step only) or positive, got " +
                      std::to_string(out.get<int>("VTK Interval")));
    if (out.get<int>("Checkpoint Interval") < 0)
      throw DeckError("'Output/Checkpoint Interval' must be 0 (no checkpoints) or positive, got " +
                      std::to_string(out.get<int>("Checkpoint Interval")));
  }
  checkProblemSize(in.get<std::string>("Type") == "Implicit");

  std::vector<ConstraintSpec> cspecs = buildConstraints();
  // A CPDI domain's corners may lie in 3 cells per direction: its stencil reaches 2 cells beyond
  // the particle's own (Cpdi::max_nodes_1d), one cell more than the other shapes. The migration
  // slack widens the ghost band so that particles may stray that far before they migrate.
  const ParameterList& dec = deck_.sublist("Decomposition");
  migrationSlack_ = dec.get<int>("Migration Slack Cells");
  if (migrationSlack_ < 0)
    throw DeckError("'Decomposition/Migration Slack Cells' must be 0 or positive, got " + std::to_string(migrationSlack_));
  const int reach = shapeInfo(shape_).cornerDomains ? 3 : 2;
  // A rank's block is wider than the slack, so that a particle can only stray into a neighbour's.
  const RankGrid ranks(grid_, comm_->getSize(), {dec.get<int>("Ranks X"), dec.get<int>("Ranks Y"), dec.get<int>("Ranks Z")},
                       migrationSlack_ + 1);
  dist_ = std::make_unique<GridDistribution>(grid_, comm_, reach + migrationSlack_, ranks);
  loadBalanceInterval_ = dec.get<int>("Load Balance Interval");
  loadBalanceThreshold_ = dec.get<double>("Load Balance Threshold");
  if (loadBalanceInterval_ < 0)
    throw DeckError("'Decomposition/Load Balance Interval' must be 0 (off) or positive, got " + std::to_string(loadBalanceInterval_));
  if (!(loadBalanceThreshold_ >= 1.0))
    throw DeckError("'Decomposition/Load Balance Threshold' must be at least 1 (max / mean particles per rank), got " +
                    formatNumber(loadBalanceThreshold_));
  try {
    particles_ = createParticles(bodies_, materials_, *dist_, placement_, thickness_);
    materials_.initializeHistory(particles_);
  } catch (const std::invalid_argument& e) {
    throw DeckError(e.what());
  }
  checkConditionsReached(cspecs);
  constraints_ = GridConditions(cspecs, *dist_);
  constraintSpecs_ = cspecs;  // rebuilt for a new rank grid (load balance)

  // A manufactured solution (Exact Solution/Type) drives the initial state and a load: read it first.
  if (deck_.sublist("Exact Solution").get<std::string>("Type") == "Axis-Aligned Manufactured Solution") {
    ExactContext early;
    early.bodies = bodies_;
    early.materials = &materials_;
    early.dimension = grid_.dim;
    manufactured_ = std::make_unique<AxisAlignedManufactured>(axisAlignedManufactured(deck_.sublist("Exact Solution"), early));
  }

  // Initial conditions, before the integrators (an implicit one computes a(0) from this state).
  // The standing wave is one mode of the first body (or Exact Solution/Body).
  const ParameterList& ic = deck_.sublist("Initial Conditions");
  const std::string icType = ic.get<std::string>("Type");
  if ((icType == "Manufactured Solution") != (manufactured_ != nullptr))
    throw DeckError(manufactured_ ? "'Initial Conditions/Type' must be Manufactured Solution with 'Exact Solution/Type' = "
                                    "Axis-Aligned Manufactured Solution (the particles start on the solution), got " + icType
                                  : "'Initial Conditions/Type' = Manufactured Solution needs 'Exact Solution/Type' = Axis-Aligned "
                                    "Manufactured Solution (the field it starts from)");
  if (manufactured_) applyManufacturedVelocity(particles_, *manufactured_);
  const double icAmplitude = ic.get<double>("Amplitude");
  const int icMode = ic.get<int>("Mode");
  if (icType == "Standing Wave") {
    if (!(icAmplitude != 0.0 && std::isfinite(icAmplitude)))
      throw DeckError("'Initial Conditions/Amplitude' must be a non-zero velocity amplitude for Type = Standing Wave, got " +
                      formatNumber(icAmplitude));
    if (icMode < 1)
      throw DeckError("'Initial Conditions/Mode' must be at least 1 for Type = Standing Wave, got " + std::to_string(icMode));
    const BodySpec& b = bodyNamed("Exact Solution/Body", deck_.sublist("Exact Solution").get<std::string>("Body"));
    if (!b.rectangle) throw DeckError("'Initial Conditions/Type' = Standing Wave needs a Rectangle body: 'Bodies/" + b.name + "' is not one");
    if (bodies_.size() > 1)
      throw DeckError("'Initial Conditions/Type' = Standing Wave is one mode of a single bar: the deck has " +
                      std::to_string(bodies_.size()) + " bodies");
    applyStandingWaveVelocity(particles_, b.rect.xMin, b.rect.length(), icAmplitude, icMode);
  }

  std::vector<LoadSpec> lspecs = buildLoads();

  const ParameterList& ml = deck_.sublist("Monitors");
  for (auto it = ml.begin(); it != ml.end(); ++it) {
    const ParameterList& mp = ml.sublist(ml.name(it));
    Monitor mon;
    mon.name = ml.name(it);
    mon.quantity = mp.get<std::string>("Quantity");
    if (grid_.dim == 2 && (mon.quantity.back() == 'Z' && mon.quantity != "Stress ZZ"))
      throw DeckError("'Monitors/" + mon.name + "/Quantity' = " + mon.quantity + " needs 'Grid/Dimension' = 3");
    const Point at = pointOf(mp);
    nearestParticle(at, mon);
    checkNearParticle("'Monitors/" + mon.name + "' at", at, mon);
    monitors_.push_back(mon);
  }
  energyHistory_ = deck_.sublist("Output").get<bool>("Energy And Momentum");

  ExactContext context;
  context.bodies = bodies_;
  context.materials = &materials_;
  context.thickness = thickness_;
  context.dimension = grid_.dim;
  context.loads = lspecs;
  context.constraints = cspecs;
  context.initialCondition = icType;
  context.initialAmplitude = icAmplitude;
  context.initialMode = icMode;
  context.dt = dt_;
  context.steps = steps_;
  context.manufactured = manufactured_.get();
  exact_ = makeExactReference(deck_.sublist("Exact Solution"), context);

  buildIntegrator();
}

const BodySpec& Simulation::bodyNamed(const std::string& key, const std::string& name) const {
  if (name.empty()) return bodies_.front();
  for (const auto& b : bodies_)
    if (b.name == name) return b;
  throw DeckError("'" + key + "' = '" + name + "' names no entry of Bodies");
}

void Simulation::buildMaterialsAndBodies() {
  const ParameterList& ms = deck_.sublist("Materials");
  std::vector<MaterialParameters> params;
  for (auto it = ms.begin(); it != ms.end(); ++it) {
    const std::string name = ms.name(it), key = "Materials/" + name;
    const MaterialParameters p = readMaterial(ms.sublist(name), key, [&](const MaterialModelInfo& model) {
      if (!model.finiteStrain) return;
      if (grid_.dim == 2 && deck_.sublist("Grid").get<std::string>("Plane Condition") == "Plane Stress")
        throw DeckError("'" + key + "/Model' = " + model.name + " is plane strain or 3D; 'Grid/Plane Condition' = Plane Stress "
                        "would need the out-of-plane stretch solved per particle (use Plane Strain or Grid/Dimension 3)");
      if (shapeInfo(shape_).fixedParticles)
        throw DeckError("'" + key + "/Model' = " + model.name + " needs moving particles; 'Method/Shape Function' = " + shape_ +
                        " is the small-strain finite-element reference (use MPM, GIMP or cpGIMP)");
    });
    params.push_back(p);
    materialNames_.push_back(name);
  }
  const PlaneCondition plane = grid_.dim == 3 ? PlaneCondition::Solid
                               : deck_.sublist("Grid").get<std::string>("Plane Condition") == "Plane Stress"
                                   ? PlaneCondition::PlaneStress
                                   : PlaneCondition::PlaneStrain;
  if (params.empty()) throw DeckError("'Materials' is empty: a deck with Bodies needs at least one material");
  materials_ = Materials(params, plane);

  const ShapeInfo& shape = shapeInfo(shape_);
  const int fewest = shape.minimumCells;
  if (shape.minimumCells > 1 && !shape.quadraticElements &&
      (grid_.nx < fewest || grid_.ny < fewest || (grid_.dim == 3 && grid_.nz < fewest)))
    throw DeckError("'Method/Shape Function' = " + shape_ + " needs at least " + std::to_string(fewest) +
                    " cells per direction (a stencil spans " + std::to_string(shape.stencilNodes1d) + " nodes), got " +
                    std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny) +
                    (grid_.dim == 3 ? " x " + std::to_string(grid_.nz) : std::string()) + " cells");
  if (shape.quadraticElements && grid_.dim == 3 && grid_.nz % 2)
    throw DeckError("'Method/Shape Function' = FE Q9 (Hex27 in 3D) needs an even 'Grid/Cells Z', got " + std::to_string(grid_.nz));
  if (shape.quadraticElements && (grid_.nx % 2 || grid_.ny % 2))
    throw DeckError("'Method/Shape Function' = FE Q9 needs even 'Grid/Cells X' and 'Grid/Cells Y' (an element is 2 x 2 cells), got " +
                    std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny));
  const ParameterList& bs = deck_.sublist("Bodies");
  if (bs.numParams() == 0) throw DeckError("'Bodies' is empty: add at least one body");
  const double tolx = 1e-9 * grid_.hx, toly = 1e-9 * grid_.hy;
  for (auto it = bs.begin(); it != bs.end(); ++it) {
    const std::string name = bs.name(it), key = "Bodies/" + name;
    const ParameterList& b = bs.sublist(name);
    BodySpec body;
    body.name = name;
    const std::string material = b.get<std::string>("Material");
    const auto found = std::find(materialNames_.begin(), materialNames_.end(), material);
    if (found == materialNames_.end()) {
      std::string known;
      for (const auto& n : materialNames_) known += (known.empty() ? "'" : ", '") + n + "'";
      throw DeckError("'" + key + "/Material' = '" + material + "' names no entry of Materials (known: " + known + ")");
    }
    body.material = (int)(found - materialNames_.begin());
    body.rect.particlesPerCellX = positiveInt(b, key, "Particles Per Cell X");
    body.rect.particlesPerCellY = positiveInt(b, key, "Particles Per Cell Y");
    if (grid_.dim == 3) body.rect.particlesPerCellZ = positiveInt(b, key, "Particles Per Cell Z");
    body.rect.thickness = thickness_;
    body.rect.placement = placement_;
    body.velocityX = b.get<double>("Velocity X");
    body.velocityY = b.get<double>("Velocity Y");
    body.velocityZ = b.get<double>("Velocity Z");
    const std::string shape = b.get<std::string>("Shape");
    if (grid_.dim == 3 && (shape == "Ellipse" || shape == "Polygon"))
      throw DeckError("'" + key + "/Shape' = " + shape + " is a 2D shape; with 'Grid/Dimension' = 3 a body is a Rectangle (box) or a Particles File");
    if (grid_.dim == 2 && body.velocityZ != 0.0)
      throw DeckError("'" + key + "/Velocity Z' = " + formatNumber(body.velocityZ) + " needs 'Grid/Dimension' = 3");
    if (b.get<std::string>("Particle Placement") == "Gauss") {
      // Gauss pairs in sub-cells: an even count per direction, and only where a lattice is filled.
      if (shape == "Particles File" || placement_ != Placement::Lattice)
        throw DeckError("'" + key + "/Particle Placement' = Gauss places a lattice fill's particles; " +
                        (shape == "Particles File" ? std::string("a Particles File body takes its particles as given")
                                                   : "'Method/Shape Function' = " + shape_ + " places its own Gauss points"));
      for (const char* axis : {"X", "Y", "Z"}) {
        if (axis[0] == 'Z' && grid_.dim == 2) continue;
        const int n = b.get<int>(std::string("Particles Per Cell ") + axis);
        if (n % 2)
          throw DeckError("'" + key + "/Particle Placement' = Gauss puts Gauss-Legendre pairs in sub-cells: '" + key +
                          "/Particles Per Cell " + axis + "' must be even, got " + std::to_string(n));
      }
      body.rect.latticePoints = LatticePoints::Gauss;
    }
    size_t fileParticles = 0;
    if (placement_ != Placement::Lattice && shape != "Rectangle")
      throw DeckError("'" + key + "/Shape' = " + shape + ": 'Method/Shape Function' = " + shape_ +
                      " places Gauss points in Rectangle bodies only");
    try {
      if (shape == "Rectangle") {
        RectangularBody& r = body.rect;
        r.xMin = b.get<double>("X Min"); r.xMax = b.get<double>("X Max");
        r.yMin = b.get<double>("Y Min"); r.yMax = b.get<double>("Y Max");
        if (!(r.xMax > r.xMin)) throw DeckError("'" + key + "/X Max' must exceed '" + key + "/X Min'");
        if (!(r.yMax > r.yMin)) throw DeckError("'" + key + "/Y Max' must exceed '" + key + "/Y Min'");
        if (r.xMin < grid_.x0 - tolx) throw DeckError("particles outside the grid: '" + key + "/X Min' = " + formatNumber(r.xMin) + " is left of the grid origin " + formatNumber(grid_.x0));
        if (r.xMax > grid_.xMax() + tolx) throw DeckError("particles outside the grid: '" + key + "/X Max' = " + formatNumber(r.xMax) + " is beyond the grid's right edge " + formatNumber(grid_.xMax()));
        if (r.yMin < grid_.y0 - toly) throw DeckError("particles outside the grid: '" + key + "/Y Min' = " + formatNumber(r.yMin) + " is below the grid origin " + formatNumber(grid_.y0));
        if (r.yMax > grid_.yMax() + toly) throw DeckError("particles outside the grid: '" + key + "/Y Max' = " + formatNumber(r.yMax) + " is above the grid's top edge " + formatNumber(grid_.yMax()));
        std::vector<std::tuple<const char*, double, double, double>> edges = {
            std::make_tuple("X Min", r.xMin, grid_.x0, grid_.hx), std::make_tuple("X Max", r.xMax, grid_.x0, grid_.hx),
            std::make_tuple("Y Min", r.yMin, grid_.y0, grid_.hy), std::make_tuple("Y Max", r.yMax, grid_.y0, grid_.hy)};
        if (grid_.dim == 3) {
          r.zMin = b.get<double>("Z Min"); r.zMax = b.get<double>("Z Max");
          const double tolz = 1e-9 * grid_.hz;
          if (!(r.zMax > r.zMin)) throw DeckError("'" + key + "/Z Max' must exceed '" + key + "/Z Min'");
          if (r.zMin < grid_.z0 - tolz) throw DeckError("particles outside the grid: '" + key + "/Z Min' = " + formatNumber(r.zMin) + " is behind the grid origin " + formatNumber(grid_.z0));
          if (r.zMax > grid_.zMax() + tolz) throw DeckError("particles outside the grid: '" + key + "/Z Max' = " + formatNumber(r.zMax) + " is beyond the grid's front face " + formatNumber(grid_.zMax()));
          edges.push_back(std::make_tuple("Z Min", r.zMin, grid_.z0, grid_.hz));
          edges.push_back(std::make_tuple("Z Max", r.zMax, grid_.z0, grid_.hz));
        }
        for (auto [k, v, o, h] : edges) {
          if (!onGridLine(v, o, h)) throw DeckError("'" + key + "/" + k + "' = " + formatNumber(v) + " is not on a grid line");
          // FE Q9: elements of 2 x 2 cells, the body made of whole elements.
          if (placement_ == Placement::GaussQ9 && std::lround((v - o) / h) % 2)
            throw DeckError("'" + key + "/" + k + "' = " + formatNumber(v) + " is not on an element edge of FE Q9 (an even grid line)");
        }
        body.rectangle = true;
        body.shape = makeRectangle(r.xMin, r.xMax, r.yMin, r.yMax);
      } else if (shape == "Ellipse") {
        const double cx = b.get<double>("Center X"), cy = b.get<double>("Center Y");
        const double rx = positive(b, key, "Radius X"), ry = positive(b, key, "Radius Y");
        body.shape = makeEllipse(cx, cy, rx, ry);
      } else if (shape == "Polygon") {
        const std::string vertices = b.get<std::string>("Vertices");
        try {
          body.shape = makePolygon(parsePolygonVertices(vertices));
        } catch (const std::invalid_argument& e) {
          throw DeckError("'" + key + "/Vertices': " + e.what());
        }
      } else {
        body.particlesFile = b.get<std::string>("File");
        if (body.particlesFile.empty()) throw DeckError("'" + key + "/File' must name a particles file for Shape = Particles File");
        try {
          // Checked here, before anything runs.
          fileParticles = readParticlesFile(body.particlesFile, grid_.dim, thickness_).size();
        } catch (const std::exception& e) {
          throw DeckError("'" + key + "/File': " + e.what());
        }
      }
    } catch (const std::invalid_argument& e) {
      throw DeckError("'" + key + "': " + e.what());
    }
    if (body.shape && !body.rectangle) {
      double xlo, xhi, ylo, yhi;
      body.shape->boundingBox(xlo, xhi, ylo, yhi);
      if (xlo < grid_.x0 - tolx || xhi > grid_.xMax() + tolx || ylo < grid_.y0 - toly || yhi > grid_.yMax() + toly)
        throw DeckError("particles outside the grid: '" + key + "' (" + body.shape->describe() + ") extends beyond the grid [" +
                        formatNumber(grid_.x0) + ", " + formatNumber(grid_.xMax()) + "] x [" + formatNumber(grid_.y0) + ", " + formatNumber(grid_.yMax()) + "]");
    }
    // For checkProblemSize: particles (exact for lattice-filled rectangles and Gauss points,
    // by area for other shapes) and the cells the body covers.
    double cells = 0, particles = 0;
    if (!body.particlesFile.empty()) {
      particles = cells = (double)fileParticles;
    } else {
      cells = body.shape->area() / (grid_.hx * grid_.hy);
      double perCell = placement_ == Placement::GaussQ4   ? 4.0
                       : placement_ == Placement::GaussQ9 ? 9.0 / 4.0
                                                          : (double)body.rect.particlesPerCellX * body.rect.particlesPerCellY;
      if (grid_.dim == 3) {
        cells *= body.rect.depth() / grid_.hz;
        perCell *= placement_ == Placement::GaussQ4 ? 2.0 : placement_ == Placement::GaussQ9 ? 3.0 / 2.0 : body.rect.particlesPerCellZ;
      }
      particles = cells * perCell;
    }
    estimatedBodyCells_.push_back(cells);
    estimatedBodyParticles_.push_back(particles);
    bodies_.push_back(body);
  }
}

void Simulation::checkProblemSize(bool implicit) const {
  const bool solid = grid_.dim == 3;
  const std::string cells = std::string(solid ? "'Grid/Cells X' x 'Grid/Cells Y' x 'Grid/Cells Z' = " : "'Grid/Cells X' x 'Grid/Cells Y' = ") +
                            std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny) +
                            (solid ? " x " + std::to_string(grid_.nz) : std::string());
  const double nodes = (grid_.nx + 1.0) * (grid_.ny + 1.0) * (solid ? grid_.nz + 1.0 : 1.0);
  if (nodes * grid_.dim / 2 > kMaxGridNodes)
    throw DeckError(cells + " makes " + formatNumber(nodes) + " grid nodes, more than impm's 32-bit local indices hold with " +
                    std::to_string(grid_.dim) + " unknowns per node");
  double particles = 0, coveredCells = 0;
  size_t largest = 0;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    particles += estimatedBodyParticles_[b];
    coveredCells += estimatedBodyCells_[b];
    if (estimatedBodyParticles_[b] > estimatedBodyParticles_[largest]) largest = b;
  }
  // The keys that set the largest body's particle count.
  const BodySpec& big = bodies_[largest];
  const std::string key = "'Bodies/" + big.name;
  const std::string source =
      !big.particlesFile.empty() ? key + "/File'"
      : placement_ != Placement::Lattice
          ? key + "' (the Gauss points of 'Method/Shape Function' = " + shape_ + ")"
          : key + "/Particles Per Cell X' x 'Particles Per Cell Y' = " + std::to_string(big.rect.particlesPerCellX) + " x " +
                std::to_string(big.rect.particlesPerCellY);
  if (particles > std::numeric_limits<int>::max())
    throw DeckError("the bodies make an estimated " + formatNumber(particles) + " particles (" + source + "), more than the " +
                    std::to_string(std::numeric_limits<int>::max()) + " that a particle index holds");

  const double limitGB = deck_.sublist("Problem").get<double>("Memory Limit GB");
  if (!(limitGB >= 0)) throw DeckError("'Problem/Memory Limit GB' must not be negative, got " + formatNumber(limitGB));
  const int ranks = comm_->getSize();
  // The implicit figures were measured in 2D; in 3D a node's matrix row couples dim / 2 times
  // more components with (reach)^3 / (reach)^2 more nodes (reach 3 cells for MPM and FE Q4, 5
  // for GIMP, cpGIMP, quadratic B-splines and FE Q9, 7 for cubic B-splines and CPDI), and each particle's
  // dense stiffness block holds (dim x nodes)^2 values (24^2 for MPM, 81^2 for GIMP, quadratic B-splines
  // and Hex27, 192^2 for cubic B-splines and CPDI, 4 nodes per direction; the 2D constants include their blocks).
  const double blockNodes = shapeInfo(shape_).stencilNodes1d, reach = 2.0 * blockNodes - 1.0;
  const double activeScale = solid ? 1.5 * 1.5 * reach : 1.0;
  const double blockBytesPerParticle = implicit && solid ? 8.0 * std::pow(grid_.dim * std::pow(blockNodes, grid_.dim), 2) : 0.0;
  const double gridBytes =
      implicit ? nodes * kBytesPerNodeImplicitVoid +
                     std::min(nodes, 2 * coveredCells) * kBytesPerNodeImplicitActive * activeScale
               : nodes * kBytesPerNodeExplicit;
  const double particleBytes =
      particles * (ParticleSet::bytesPerParticle(grid_.dim) + blockBytesPerParticle + kFillBytesPerParticlePerRank * ranks);
  const double needed = ranks * kBytesPerRank + gridBytes + particleBytes;
  auto gigabytes = [](double bytes) { return formatNumber(std::max(0.01, std::round(bytes / 1e7) / 100)) + " GB"; };
  // The machine's memory is read on rank 0 only: every rank takes its verdict.
  rethrowOnEveryRank(*comm_, comm_->getRank() == 0, [&] {
    const double limit = limitGB > 0 ? limitGB * 1e9 : availableMemoryBytes();
    if (limit > 0 && needed > limit)
      throw DeckError("the run needs an estimated " + gigabytes(needed) + " (grid " + gigabytes(gridBytes) + ": " + cells +
                      "; particles " + gigabytes(particleBytes) + ": " + formatNumber(particles) + " particles, the most from " + source +
                      "), more than " +
                      (limitGB > 0 ? "'Problem/Memory Limit GB' = " + formatNumber(limitGB)
                                   : "the " + gigabytes(limit) + " available (MemAvailable; 'Problem/Memory Limit GB' sets a limit)"));
  });
}

void Simulation::checkNodeReached(const std::string& key, const Point& point) const {
  Point node = {0, 0, 0};
  for (int d = 0; d < grid_.dim; ++d)
    node[d] = grid_.origin(d) + grid_.spacing(d) * std::lround((point[d] - grid_.origin(d)) / grid_.spacing(d));
  if (particlesReaching(node, node) == 0)
    throw DeckError("'" + key + "/Type' = Node Force at " + describePoint(point) +
                    ": no particle reaches this grid node at t = 0, so the force would act on no mass; put it on a node of a "
                    "body, or use a Particle Force");
}

void Simulation::checkConditionsReached(const std::vector<ConstraintSpec>& specs) const {
  for (const ConstraintSpec& s : specs) {
    if (s.motion == ConstraintSpec::Motion::Fixed) continue;
    const std::vector<NodeIndex> nodes = constraintNodes(s, grid_);
    // (Face and box node sets are boxes of nodes: a particle reaching their bounding box reaches one of them.)
    Point lo = {1e300, 1e300, 1e300}, hi = {-1e300, -1e300, -1e300};
    for (const auto& ijk : nodes)
      for (int d = 0; d < grid_.dim; ++d) {
        const double x = grid_.origin(d) + grid_.spacing(d) * ijk[d];
        lo[d] = std::min(lo[d], x);
        hi[d] = std::max(hi[d], x);
      }
    if (particlesReaching(lo, hi) == 0)
      throw DeckError("'Constraints/" + s.name + "/Motion' = " +
                      (s.motion == ConstraintSpec::Motion::Velocity ? "Velocity" : "Displacement") +
                      ": no particle reaches its grid nodes at t = 0, so it would move nothing; put it where a body is");
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

std::string Simulation::describePoint(const Point& p) const {
  return "(" + formatNumber(p[0]) + ", " + formatNumber(p[1]) + (grid_.dim == 3 ? ", " + formatNumber(p[2]) : std::string()) + ")";
}

void Simulation::checkNearParticle(const std::string& what, const Point& p, const Monitor& nearest) const {
  const double dz = grid_.dim == 3 ? nearest.z0 - p[2] : 0.0, hz = grid_.dim == 3 ? grid_.hz : 0.0;
  const double distance = std::sqrt(std::pow(nearest.x0 - p[0], 2) + std::pow(nearest.y0 - p[1], 2) + dz * dz);
  const double cell = std::sqrt(grid_.hx * grid_.hx + grid_.hy * grid_.hy + hz * hz);
  if (distance > cell)
    throw DeckError(what + " " + describePoint(p) + ": the nearest particle, at " +
                    describePoint({nearest.x0, nearest.y0, nearest.z0}) + ", is " + formatNumber(distance) +
                    " m away, farther than one cell diagonal (" + formatNumber(cell) + " m): no body there");
}

Point Simulation::pointOf(const ParameterList& list) const {
  return {list.get<double>("X"), list.get<double>("Y"), grid_.dim == 3 ? list.get<double>("Z") : 0.0};
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
    s.x = node[0]; s.y = node[1]; s.z = node[2];
    s.xMin = c.get<double>("X Min"); s.xMax = c.get<double>("X Max");
    s.yMin = c.get<double>("Y Min"); s.yMax = c.get<double>("Y Max");
    if (grid_.dim == 3) { s.zMin = c.get<double>("Z Min"); s.zMax = c.get<double>("Z Max"); }
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
      if (!b.rectangle) throw DeckError("'" + key + "': Where = Face needs a Rectangle body; 'Bodies/" + b.name + "' is not one");
      s.body = b.rect;
    }
    if (s.where == "Box") {
      if (!(s.xMax >= s.xMin && s.yMax >= s.yMin && s.zMax >= s.zMin))
        throw DeckError("'" + key + "': the box needs X Max >= X Min, Y Max >= Y Min (and Z Max >= Z Min)");
      if (boxNodes(grid_, s.xMin, s.xMax, s.yMin, s.yMax, s.zMin, s.zMax).empty())
        throw DeckError("'" + key + "': the box [" + formatNumber(s.xMin) + ", " + formatNumber(s.xMax) + "] x [" + formatNumber(s.yMin) + ", " +
                        formatNumber(s.yMax) + "] holds no grid node");
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
    s.x = point[0]; s.y = point[1]; s.z = point[2];
    s.forceX = l.get<double>("Force X"); s.forceY = l.get<double>("Force Y"); s.forceZ = l.get<double>("Force Z");
    s.accelerationX = l.get<double>("Acceleration X"); s.accelerationY = l.get<double>("Acceleration Y");
    s.accelerationZ = l.get<double>("Acceleration Z");
    if (grid_.dim == 2 && (s.forceZ != 0.0 || s.accelerationZ != 0.0))
      throw DeckError("'" + key + "/" + (s.forceZ != 0.0 ? "Force Z" : "Acceleration Z") + "' is not zero: z components need 'Grid/Dimension' = 3");
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
      if (!b.rectangle) throw DeckError("'" + key + "': a Face Traction needs a Rectangle body; 'Bodies/" + b.name + "' is not one");
      s.body = b.rect;
    }
    if (s.type == "Body Force" && !bodyName.empty())
      s.bodyIndex = (int)(&bodyNamed(key + "/Body", bodyName) - bodies_.data());
    if (s.type == "Manufactured Body Force") {
      if (!manufactured_)
        throw DeckError("'" + key + "/Type' = Manufactured Body Force needs 'Exact Solution/Type' = Axis-Aligned Manufactured "
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
  if (manufactured_ && std::none_of(specs.begin(), specs.end(), [](const LoadSpec& s) { return s.type == "Manufactured Body Force"; }))
    throw DeckError("'Exact Solution/Type' = Axis-Aligned Manufactured Solution needs a load of 'Type' = Manufactured Body "
                    "Force in Loads (without it the field is not a solution)");
  loadSpecs_ = specs;  // rebuilt for a new rank grid (load balance)
  loadParticleIds_ = loadParticle;
  loads_ = LoadSet(specs, *dist_, loadParticle, (int)bodies_.size(), shapeInfo(shape_).quadraticElements);
  loads_.locateParticles(particles_);
  return specs;
}

void Simulation::buildIntegrator() {
  const ParameterList& in = deck_.sublist("Integrator");
  const std::string integratorType = in.get<std::string>("Type");
  const ParameterList& ex = in.sublist("Explicit");
  ExplicitOptions eopt;
  {
    const std::string s = ex.get<std::string>("Update Scheme");
    eopt.scheme = s == "USF" ? ExplicitScheme::USF : s == "MUSL" ? ExplicitScheme::MUSL : ExplicitScheme::USL;
    eopt.flip = ex.get<double>("FLIP Fraction");
    eopt.projectionIterations = ex.get<int>("Consistent Projection Iterations");
    if (eopt.projectionIterations < 0)
      throw DeckError("'Integrator/Explicit/Consistent Projection Iterations' must not be negative");
    eopt.massDamping = ex.get<double>("Mass Damping");
    if (!(eopt.massDamping >= 0) || !std::isfinite(eopt.massDamping))
      throw DeckError("'Integrator/Explicit/Mass Damping' must be finite and not negative, got " +
                      formatNumber(eopt.massDamping));
    if (!(eopt.flip >= 0 && eopt.flip <= 1))
      throw DeckError("'Integrator/Explicit/FLIP Fraction' must lie in [0, 1], got " + formatNumber(eopt.flip));
    const double factor = positive(ex, "Integrator/Explicit", "Stability Factor");
    // kTransferStabilityFraction x the critical step of lumped bilinear cells (ExplicitStepper.hpp);
    // c_p: the fastest material's. A factor above 1 leaves the measured stable range: allowed for
    // stability studies, with a warning, and the run's divergence guard stops a run that blows up.
    const double cp = materials_.maxPWaveSpeed();
    const double inverseSquares = 1.0 / (grid_.hx * grid_.hx) + 1.0 / (grid_.hy * grid_.hy) +
                                  (grid_.dim == 3 ? 1.0 / (grid_.hz * grid_.hz) : 0.0);
    const double critical = kTransferStabilityFraction / (cp * std::sqrt(inverseSquares));
    const double limit = factor * critical;
    if (integratorType == "Explicit") criticalStep_ = critical;
    if (integratorType == "Explicit" && dt_ > limit)
      throw DeckError("'Integrator/Time Step' = " + formatNumber(dt_) + " exceeds the explicit stable limit " + formatNumber(limit) +
                      " (Stability Factor x " + formatNumber(kTransferStabilityFraction) +
                      (grid_.dim == 3 ? " / (P-wave speed x sqrt(1/hx^2 + 1/hy^2 + 1/hz^2)), P-wave speed "
                                      : " / (P-wave speed x sqrt(1/hx^2 + 1/hy^2)), P-wave speed ") +
                      formatNumber(cp) + " m/s)");
    if (integratorType == "Explicit" && factor > 1.0 && comm_->getRank() == 0)
      std::cerr << "impm: warning: 'Integrator/Explicit/Stability Factor' = " << formatNumber(factor)
                << " is above 1, beyond the measured stable limit of the particle transfers; the run may diverge\n";
  }

  const bool fe = shapeInfo(shape_).fixedParticles;
  if (fe && integratorType != "Implicit")
    throw DeckError("'Method/Shape Function' = " + shape_ + " runs with 'Integrator/Type' = Implicit only, got " + integratorType);
  // Solver options are checked whatever the integrator, so that a bad one never waits for a
  // later implicit run to be found.
  if (integratorType != "Implicit") {
    try {
      NewtonSolver check(Teuchos::rcp(new ParameterList(deck_.sublist("Implicit Solver"))));
    } catch (const std::invalid_argument& e) {
      throw DeckError(e.what());
    }
  }
  if (integratorType == "Implicit") {
    const ParameterList& im = in.sublist("Implicit");
    ImplicitOptions iopt;
    iopt.maxStepHalvings = im.get<int>("Maximum Step Halvings");
    if (iopt.maxStepHalvings < 0) throw DeckError("'Integrator/Implicit/Maximum Step Halvings' must not be negative");
    iopt.consistentInitialAcceleration = im.get<bool>("Consistent Initial Acceleration");
    iopt.projectionIterations = im.get<int>("Consistent Projection Iterations");
    iopt.preconditionerRefreshInterval = im.get<int>("Preconditioner Refresh Interval");
    iopt.preconditionerRefreshKrylov = im.get<int>("Preconditioner Refresh GMRES Threshold");
    iopt.preconditionerEveryNewton = im.get<bool>("Preconditioner At Every Newton Iteration");
    if (iopt.preconditionerRefreshKrylov < 0)
      throw DeckError("'Integrator/Implicit/Preconditioner Refresh GMRES Threshold' must not be negative (0: off), got " +
                      std::to_string(iopt.preconditionerRefreshKrylov));
    iopt.consistentMass = im.get<std::string>("Mass Matrix") == "Consistent";
    iopt.seedGimpStiffness = im.get<std::string>("GIMP Stiffness") == "Integrated";
    iopt.equilibriumAcceleration = im.get<std::string>("Grid Acceleration") == "Equilibrium";
    iopt.fixedParticles = fe;
    iopt.newmark.beta = im.get<double>("Newmark Beta");
    iopt.newmark.gamma = im.get<double>("Newmark Gamma");
    if (!(iopt.newmark.gamma >= 0.5 && 2 * iopt.newmark.beta >= iopt.newmark.gamma && iopt.newmark.beta <= 1.0))
      throw DeckError("'Integrator/Implicit/Newmark Beta' = " + formatNumber(iopt.newmark.beta) + " and 'Newmark Gamma' = " +
                      formatNumber(iopt.newmark.gamma) +
                      ": the implicit integrator needs an unconditionally stable Newmark scheme, 2 beta >= gamma >= 1/2 "
                      "(and beta <= 1)");
    iopt.adaptiveTimeStep = im.get<bool>("Adaptive Time Step");
    iopt.minimumTimeStep = im.get<double>("Minimum Time Step");
    if (!(iopt.minimumTimeStep >= 0))
      throw DeckError("'Integrator/Implicit/Minimum Time Step' must not be negative, got " + formatNumber(iopt.minimumTimeStep));
    if (iopt.minimumTimeStep > dt_)
      throw DeckError("'Integrator/Implicit/Minimum Time Step' = " + formatNumber(iopt.minimumTimeStep) +
                      " s exceeds 'Integrator/Time Step' = " + formatNumber(dt_) + " s");
    if (iopt.preconditionerRefreshInterval < 1)
      throw DeckError("'Integrator/Implicit/Preconditioner Refresh Interval' must be at least 1");
    if (iopt.projectionIterations < 0)
      throw DeckError("'Integrator/Implicit/Consistent Projection Iterations' must not be negative");
    iopt.solverParams = Teuchos::rcp(new ParameterList(deck_.sublist("Implicit Solver")));
    // The shape's type from the registry (core/ShapeRegistry.hpp), then the dimension.
    auto implicitOf = [&](auto dimension) -> std::unique_ptr<Integrator> {
      constexpr int Dim = decltype(dimension)::value;
      return visitShape(shape_, [&](auto shape, const ShapeInfo&) -> std::unique_ptr<Integrator> {
        using Shape = typename decltype(shape)::type;
        return std::make_unique<ImplicitNewmark<Shape, Dim>>(particles_, *dist_, materials_, constraints_, loads_, iopt);
      });
    };
    try {
      integrator_ = grid_.dim == 3 ? implicitOf(std::integral_constant<int, 3>{}) : implicitOf(std::integral_constant<int, 2>{});
    } catch (const std::invalid_argument& e) {
      throw DeckError(e.what());
    }
  } else {
    auto explicitOf = [&](auto dimension) -> std::unique_ptr<Integrator> {
      constexpr int Dim = decltype(dimension)::value;
      return visitShape(shape_, [&](auto shape, const ShapeInfo&) -> std::unique_ptr<Integrator> {
        using Shape = typename decltype(shape)::type;
        if constexpr (std::is_same_v<Shape, QuadraticLagrange>) {
          return nullptr;  // (FE Q9 is implicit only: refused above)
        } else {
          return std::make_unique<ExplicitStepper<Shape, Dim>>(particles_, *dist_, materials_, constraints_, loads_, eopt);
        }
      });
    };
    integrator_ = grid_.dim == 3 ? explicitOf(std::integral_constant<int, 3>{}) : explicitOf(std::integral_constant<int, 2>{});
  }
}

void Simulation::nearestParticle(const Point& point, Monitor& m) const {
  auto xh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x0);
  auto idh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.id);
  const int dim = particles_.dim;
  double best = std::numeric_limits<double>::max();
  int local = -1;
  for (int p = 0; p < particles_.count; ++p) {
    double d2 = 0;
    for (int d = 0; d < dim; ++d) d2 += (xh(p, d) - point[d]) * (xh(p, d) - point[d]);
    const double dist = std::sqrt(d2);
    if (dist < best - 1e-15 * (1 + dist)) { best = dist; local = p; }
  }
  double gbest = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, best, Teuchos::outArg(gbest));
  const int candidate = (local >= 0 && best == gbest) ? comm_->getRank() : comm_->getSize();
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, candidate, Teuchos::outArg(m.owner));
  double pos[4] = {0, 0, 0, 0}, gpos[4];
  if (m.owner == comm_->getRank()) {
    for (int d = 0; d < dim; ++d) pos[d] = xh(local, d);
    pos[3] = (double)idh(local);
  } else {
    local = -1;
  }
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, 4, pos, gpos);
  m.localIndex = local;
  m.x0 = gpos[0]; m.y0 = gpos[1]; m.z0 = gpos[2];
  m.particleId = std::llround(gpos[3]);
}

}  // namespace impm
