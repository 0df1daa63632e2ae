// Deck section Bodies: shapes filled with particles of one material each.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/Collective.hpp"
#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

#include <cmath>
#include <tuple>

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

const char* const build::kParticlePlacementDoc =
    "where the lattice fill puts the Particles Per Cell in a cell, per direction, all of equal volume (the cell's over "
    "the particles per cell; total mass rho x the body's volume). Uniform: the centres of n equal sub-cells (the "
    "midpoint rule: a rectangle's second moment of area through its depth H comes out low by the factor "
    "1 - (d/H)^2, d = the sub-cell size); Gauss: n/2 equal sub-cells, each holding the 2-point Gauss-Legendre pair "
    "(its centre +- half width / sqrt(3), equal weights), which integrates cubics exactly, so the second moment "
    "exactly; with 4 per cell the sub-cells are the half cells, on which quadratic B-splines are polynomials "
    "(the beam decks apps/beam_implicit_bspline_*). Gauss needs even Particles Per Cell; not for Particles File "
    "bodies or FE Q4 / FE Q9 (which place their own Gauss points)";

RCP<const ParameterList> build::bodiesTemplate() {
  auto pl = rcp(new ParameterList("Bodies"));
  choice(*pl, "Shape", "Rectangle", {"Rectangle", "Ellipse", "Polygon", "Particles File"},
         "Rectangle: X/Y Min/Max on grid lines; Ellipse: Center X/Y and Radius X/Y (a disk when equal; a ring "
         "with Inner Radius X/Y); "
         "Polygon: Vertices; Particles File: File. Lattice-filled shapes keep the sub-box centres inside the "
         "shape; Ellipse and Polygon particles share the shape's exact area as volume. In 3D (Grid/Dimension 3) "
         "a Rectangle is the box X/Y/Z Min/Max, and Particles File rows are x, y, z, volume; Ellipse and "
         "Polygon are 2D shapes");
  pl->set("Material", "", "name of the material (an entry of Materials)");
  number(*pl, "X Min", 0.0, "Rectangle: left edge (on a grid line)");
  number(*pl, "X Max", 1.0, "Rectangle: right edge (on a grid line)");
  number(*pl, "Y Min", 0.0, "Rectangle: bottom edge (on a grid line)");
  number(*pl, "Y Max", 1.0, "Rectangle: top edge (on a grid line)");
  number(*pl, "Z Min", 0.0, "Rectangle in 3D: back face (on a grid plane)");
  number(*pl, "Z Max", 1.0, "Rectangle in 3D: front face (on a grid plane)");
  number(*pl, "Center X", 0.5, "Ellipse: x of the centre");
  number(*pl, "Center Y", 0.5, "Ellipse: y of the centre");
  number(*pl, "Radius X", 0.25, "Ellipse: semi-axis along x");
  number(*pl, "Radius Y", 0.25, "Ellipse: semi-axis along y");
  number(*pl, "Inner Radius X", 0.0,
         "Ellipse: semi-axis along x of a centred hole (0: none; a ring with Inner Radius Y)");
  number(*pl, "Inner Radius Y", 0.0,
         "Ellipse: semi-axis along y of a centred hole (0: none; a ring with Inner Radius X)");
  pl->set("Vertices", "", "Polygon: 'x1, y1; x2, y2; x3, y3; ...' (either orientation, not self-crossing)");
  pl->set("File", "",
          "Particles File: CSV rows x, y, volume (m^3, i.e. area x Thickness); a relative path is "
          "relative to the working directory");
  pl->set("Particles Per Cell X", 2, "particles per cell in x (lattice fill)");
  pl->set("Particles Per Cell Y", 2, "particles per cell in y (lattice fill)");
  pl->set("Particles Per Cell Z", 2, "particles per cell in z (lattice fill, 3D)");
  choice(*pl, "Particle Placement", "Uniform", {"Uniform", "Gauss"}, kParticlePlacementDoc);
  number(*pl, "Velocity X", 0.0, "initial velocity, x (m/s)");
  number(*pl, "Velocity Y", 0.0, "initial velocity, y (m/s)");
  number(*pl, "Velocity Z", 0.0, "initial velocity, z (m/s; 3D)");
  number(*pl, "Angular Velocity", 0.0,
         "initial rigid rotation about z (rad/s, counter-clockwise seen from +z) about the Rotation Center: the "
         "particles start with Velocity + omega x (x - c); with 'Integrator/Explicit/Transfer' = APIC or TPIC their "
         "affine velocity starts at the rotation's (C r = omega x r). Not for Rigid bodies");
  number(*pl, "Angular Velocity X", 0.0, "3D: the initial angular velocity's x component (rad/s)");
  number(*pl, "Angular Velocity Y", 0.0, "3D: the initial angular velocity's y component (rad/s)");
  number(*pl, "Rotation Center X", 0.0, "the point c the initial rotation turns about, x");
  number(*pl, "Rotation Center Y", 0.0, "the same, y");
  number(*pl, "Rotation Center Z", 0.0, "the same, z (3D)");
  choice(*pl, "Initial Stress", "None", {"None", "Geostatic"},
         "None: the body starts stress-free. Geostatic: at rest under the deck's gravity (the Body Force loads' "
         "Acceleration Y < 0, nothing along x or z): sigma_yy = -rho g (Surface Y - y) from the overburden of its own "
         "material, sigma_xx = sigma_zz = K0 sigma_yy (plane stress: sigma_zz = 0); the elastoplastic models start "
         "with the elastic strain of that stress. Hold the body's sides (constraints or walls): the horizontal stress "
         "pushes on them. Not with Neo-Hookean (its stress is a function of F alone)");
  number(*pl, "K0", 0.0,
         "Initial Stress = Geostatic: the ratio of horizontal to vertical stress (> 0; elastic, "
         "laterally confined: nu / (1 - nu); normally consolidated soil: 1 - sin(phi))");
  number(*pl, "Surface Y", 0.0,
         "Initial Stress = Geostatic: the elevation of the free surface, at or above the body's "
         "highest particle (m)");
  pl->set("Rigid", false,
          "true: the body moves rigidly with Velocity X/Y/Z times its Time Function (a platen, an indenter, a wall at "
          "any angle) and meets the other bodies through 'Contact/Type' = Multi Field, as if infinitely heavy: they "
          "stop approaching it and slide on it by the pair's law. The force on it is its pairs' contact force in "
          "history.csv. Its material gives it mass only");
  timeFunctionKeys(*pl, "Constant", "Rigid bodies: the factor of Velocity X/Y/Z over time");
  const char* const normalDoc =
      "Rigid bodies with a plane contact surface (a wall, a platen): its outward normal, x component (any length; "
      "0, 0, 0: the contact normal comes from the bodies' volume gradients, which follow the staircase of "
      "particles on a surface across grid lines)";
  number(*pl, "Normal X", 0.0, normalDoc);
  number(*pl, "Normal Y", 0.0, "the same, y");
  number(*pl, "Normal Z", 0.0, "the same, z (3D)");
  return pl;
}

// Angular Velocity (about z; in 3D also X, Y) about Rotation Center X/Y/Z: the body's initial
// rigid rotation. A Rigid body's motion is its Velocity times its Time Function alone.
static void readRotation(const std::string& key, const ParameterList& b, int dim, BodySpec& body) {
  const char* const omegaKeys[3] = {"Angular Velocity X", "Angular Velocity Y", "Angular Velocity"};
  const char* const centerKeys[3] = {"Rotation Center X", "Rotation Center Y", "Rotation Center Z"};
  for (int d = 0; d < 3; ++d) {
    body.angularVelocity[d] = b.get<double>(omegaKeys[d]);
    body.rotationCenter[d] = b.get<double>(centerKeys[d]);
    if (!std::isfinite(body.angularVelocity[d]) || !std::isfinite(body.rotationCenter[d]))
      throw DeckError("'" + key + "/" + (std::isfinite(body.angularVelocity[d]) ? centerKeys[d] : omegaKeys[d]) +
                      "' must be finite");
  }
  for (int d = 0; d < 2 && dim == 2; ++d)
    if (body.angularVelocity[d] != 0.0)
      throw DeckError("'" + key + "/" + omegaKeys[d] + "' = " + formatNumber(body.angularVelocity[d]) +
                      " needs 'Grid/Dimension' = 3 (in 2D a body turns about z: 'Angular Velocity')");
  if (dim == 2 && body.rotationCenter[2] != 0.0)
    throw DeckError("'" + key + "/Rotation Center Z' = " + formatNumber(body.rotationCenter[2]) +
                    " needs 'Grid/Dimension' = 3");
  for (int d = 0; d < 3 && body.rigid; ++d)
    if (body.angularVelocity[d] != 0.0)
      throw DeckError("'" + key + "/" + omegaKeys[d] +
                      "' sets a deformable body's initial rotation; a Rigid body moves "
                      "with Velocity X/Y/Z times its Time Function only");
}

const BodySpec& Simulation::bodyNamed(const std::string& key, const std::string& name) const {
  if (name.empty()) return bodies_.front();
  for (const auto& b : bodies_)
    if (b.name == name) return b;
  throw DeckError("'" + key + "' = '" + name + "' names no entry of Bodies");
}

void Simulation::buildBodies() {
  const ShapeInfo& shape = shapeInfo(shape_);
  const int fewest = shape.minimumCells;
  if (shape.minimumCells > 1 && !shape.quadraticElements &&
      (grid_.nx < fewest || grid_.ny < fewest || (grid_.dim == 3 && grid_.nz < fewest)))
    throw DeckError("'Method/Shape Function' = " + shape_ + " needs at least " + std::to_string(fewest) +
                    " cells per direction (a stencil spans " + std::to_string(shape.stencilNodes1d) + " nodes), got " +
                    std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny) +
                    (grid_.dim == 3 ? " x " + std::to_string(grid_.nz) : std::string()) + " cells");
  if (shape.quadraticElements && grid_.dim == 3 && grid_.nz % 2)
    throw DeckError("'Method/Shape Function' = FE Q9 (Hex27 in 3D) needs an even 'Grid/Cells Z', got " +
                    std::to_string(grid_.nz));
  if (shape.quadraticElements && (grid_.nx % 2 || grid_.ny % 2))
    throw DeckError(
        "'Method/Shape Function' = FE Q9 needs even 'Grid/Cells X' and 'Grid/Cells Y' (an element is 2 x 2 cells), "
        "got " +
        std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny));
  const ParameterList& bs = deck_.sublist("Bodies");
  if (bs.numParams() == 0) throw DeckError("'Bodies' is empty: add at least one body");
  for (auto it = bs.begin(); it != bs.end(); ++it) bodies_.push_back(readBody(bs.name(it), bs.sublist(bs.name(it))));
}

// Initial Stress = Geostatic: K0 and Surface Y, and a gravity along -y to take the overburden from.
void Simulation::readGeostaticStress(const std::string& key, const ParameterList& b, BodySpec& body) const {
  body.geostatic = b.get<std::string>("Initial Stress") == "Geostatic";
  body.k0 = b.get<double>("K0");
  body.surfaceY = b.get<double>("Surface Y");
  if (!body.geostatic) {
    for (const char* k : {"K0", "Surface Y"})
      if (b.get<double>(k) != 0.0)
        throw DeckError("'" + key + "/" + k + "' belongs to 'Initial Stress' = Geostatic; the body's is None");
    return;
  }
  if (!(body.k0 > 0))
    throw DeckError("'" + key + "/K0' must be positive for 'Initial Stress' = Geostatic, got " + formatNumber(body.k0));
  if (materials_.parameters(body.material).model == MaterialModel::NeoHookean)
    throw DeckError("'" + key +
                    "/Initial Stress' = Geostatic needs a material whose stress can start non-zero at F = I; "
                    "Neo-Hookean's is a function of F alone");
  geostaticGravity(key);  // refuses a deck without gravity along -y
}

// The gravity g > 0 along -y of the deck's Body Force loads (their Acceleration Y summed).
double Simulation::geostaticGravity(const std::string& key) const {
  const ParameterList& loads = deck_.sublist("Loads");
  double gy = 0;
  for (auto it = loads.begin(); it != loads.end(); ++it) {
    const ParameterList& l = loads.sublist(loads.name(it));
    if (l.get<std::string>("Type") != "Body Force") continue;
    if (l.get<double>("Acceleration X") != 0.0 || l.get<double>("Acceleration Z") != 0.0)
      throw DeckError("'" + key + "/Initial Stress' = Geostatic takes gravity along -y; 'Loads/" + loads.name(it) +
                      "' also accelerates along x or z");
    gy += l.get<double>("Acceleration Y");
  }
  if (!(gy < 0))
    throw DeckError("'" + key +
                    "/Initial Stress' = Geostatic needs gravity: a Body Force load with Acceleration Y < 0");
  return -gy;
}

// One entry of Bodies: its material, particles per cell, initial velocity, placement and shape.
BodySpec Simulation::readBody(const std::string& name, const ParameterList& b) {
  const std::string key = "Bodies/" + name;
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
    throw DeckError("'" + key + "/Shape' = " + shape +
                    " is a 2D shape; with 'Grid/Dimension' = 3 a body is a Rectangle (box) or a Particles File");
  if (grid_.dim == 2 && body.velocityZ != 0.0)
    throw DeckError("'" + key + "/Velocity Z' = " + formatNumber(body.velocityZ) + " needs 'Grid/Dimension' = 3");
  readRigidMotion(key, b, body);
  readRotation(key, b, grid_.dim, body);
  readGeostaticStress(key, b, body);
  if (b.get<std::string>("Particle Placement") == "Gauss") {
    // Gauss pairs in sub-cells: an even count per direction, and only where a lattice is filled.
    if (shape == "Particles File" || placement_ != Placement::Lattice)
      throw DeckError("'" + key + "/Particle Placement' = Gauss places a lattice fill's particles; " +
                      (shape == "Particles File"
                           ? std::string("a Particles File body takes its particles as given")
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
      readRectangle(key, b, body);
    } else if (shape == "Ellipse") {
      const double cx = b.get<double>("Center X"), cy = b.get<double>("Center Y");
      const double rx = positive(b, key, "Radius X"), ry = positive(b, key, "Radius Y");
      body.shape = makeEllipse(cx, cy, rx, ry, b.get<double>("Inner Radius X"), b.get<double>("Inner Radius Y"));
    } else if (shape == "Polygon") {
      const std::string vertices = b.get<std::string>("Vertices");
      try {
        body.shape = makePolygon(parsePolygonVertices(vertices));
      } catch (const std::invalid_argument& e) {
        throw DeckError("'" + key + "/Vertices': " + e.what());
      }
    } else {
      body.particlesFile = b.get<std::string>("File");
      if (body.particlesFile.empty())
        throw DeckError("'" + key + "/File' must name a particles file for Shape = Particles File");
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
  checkInsideGrid(key, body);
  estimateBodySize(body, fileParticles);
  return body;
}

// A Rigid body's motion: Velocity X/Y/Z times its Time Function (the particles start with its value at
// t = 0); a body that is not rigid keeps the default time function.
void Simulation::readRigidMotion(const std::string& key, const ParameterList& b, BodySpec& body) const {
  body.rigid = b.get<bool>("Rigid");
  body.motion = timeFunctionOf(b, key);
  const double normal[3] = {b.get<double>("Normal X"), b.get<double>("Normal Y"), b.get<double>("Normal Z")};
  const double length = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  if (length > 0.0 && !body.rigid)
    throw DeckError("'" + key + "/Normal X/Y/Z' give a rigid body's surface normal; set '" + key +
                    "/Rigid' = true or remove them");
  if (!std::isfinite(length)) throw DeckError("'" + key + "/Normal X/Y/Z' must be finite");
  if (grid_.dim == 2 && normal[2] != 0.0)
    throw DeckError("'" + key + "/Normal Z' = " + formatNumber(normal[2]) + " needs 'Grid/Dimension' = 3");
  for (int d = 0; d < 3 && length > 0.0; ++d) body.rigidNormal[d] = normal[d] / length;
  if (!body.rigid) {
    if (b.get<std::string>("Time Function") != "Constant")
      throw DeckError("'" + key + "/Time Function' = " + b.get<std::string>("Time Function") +
                      " scales a rigid body's velocity; set '" + key + "/Rigid' = true or remove it");
    return;
  }
  body.rigidVelocity = {body.velocityX, body.velocityY, body.velocityZ};
  const double start = body.motion(0.0);
  body.velocityX *= start;
  body.velocityY *= start;
  body.velocityZ *= start;
}

// A Rectangle body: X/Y(/Z) Min/Max ordered, inside the grid and on grid lines (FE Q9: element edges).
void Simulation::readRectangle(const std::string& key, const ParameterList& b, BodySpec& body) const {
  const double tolx = 1e-9 * grid_.hx, toly = 1e-9 * grid_.hy;
  RectangularBody& r = body.rect;
  r.xMin = b.get<double>("X Min");
  r.xMax = b.get<double>("X Max");
  r.yMin = b.get<double>("Y Min");
  r.yMax = b.get<double>("Y Max");
  if (!(r.xMax > r.xMin)) throw DeckError("'" + key + "/X Max' must exceed '" + key + "/X Min'");
  if (!(r.yMax > r.yMin)) throw DeckError("'" + key + "/Y Max' must exceed '" + key + "/Y Min'");
  if (r.xMin < grid_.x0 - tolx)
    throw DeckError("particles outside the grid: '" + key + "/X Min' = " + formatNumber(r.xMin) +
                    " is left of the grid origin " + formatNumber(grid_.x0));
  if (r.xMax > grid_.xMax() + tolx)
    throw DeckError("particles outside the grid: '" + key + "/X Max' = " + formatNumber(r.xMax) +
                    " is beyond the grid's right edge " + formatNumber(grid_.xMax()));
  if (r.yMin < grid_.y0 - toly)
    throw DeckError("particles outside the grid: '" + key + "/Y Min' = " + formatNumber(r.yMin) +
                    " is below the grid origin " + formatNumber(grid_.y0));
  if (r.yMax > grid_.yMax() + toly)
    throw DeckError("particles outside the grid: '" + key + "/Y Max' = " + formatNumber(r.yMax) +
                    " is above the grid's top edge " + formatNumber(grid_.yMax()));
  std::vector<std::tuple<const char*, double, double, double>> edges = {
      std::make_tuple("X Min", r.xMin, grid_.x0, grid_.hx), std::make_tuple("X Max", r.xMax, grid_.x0, grid_.hx),
      std::make_tuple("Y Min", r.yMin, grid_.y0, grid_.hy), std::make_tuple("Y Max", r.yMax, grid_.y0, grid_.hy)};
  if (grid_.dim == 3) {
    r.zMin = b.get<double>("Z Min");
    r.zMax = b.get<double>("Z Max");
    const double tolz = 1e-9 * grid_.hz;
    if (!(r.zMax > r.zMin)) throw DeckError("'" + key + "/Z Max' must exceed '" + key + "/Z Min'");
    if (r.zMin < grid_.z0 - tolz)
      throw DeckError("particles outside the grid: '" + key + "/Z Min' = " + formatNumber(r.zMin) +
                      " is behind the grid origin " + formatNumber(grid_.z0));
    if (r.zMax > grid_.zMax() + tolz)
      throw DeckError("particles outside the grid: '" + key + "/Z Max' = " + formatNumber(r.zMax) +
                      " is beyond the grid's front face " + formatNumber(grid_.zMax()));
    edges.push_back(std::make_tuple("Z Min", r.zMin, grid_.z0, grid_.hz));
    edges.push_back(std::make_tuple("Z Max", r.zMax, grid_.z0, grid_.hz));
  }
  for (auto [k, v, o, h] : edges) {
    if (!onGridLine(v, o, h))
      throw DeckError("'" + key + "/" + k + "' = " + formatNumber(v) + " is not on a grid line");
    // FE Q9: elements of 2 x 2 cells, the body made of whole elements.
    if (placement_ == Placement::GaussQ9 && std::lround((v - o) / h) % 2)
      throw DeckError("'" + key + "/" + k + "' = " + formatNumber(v) +
                      " is not on an element edge of FE Q9 (an even grid line)");
  }
  body.rectangle = true;
  body.shape = makeRectangle(r.xMin, r.xMax, r.yMin, r.yMax);
}

// A shape other than a grid-aligned rectangle stays inside the grid.
void Simulation::checkInsideGrid(const std::string& key, const BodySpec& body) const {
  const double tolx = 1e-9 * grid_.hx, toly = 1e-9 * grid_.hy;
  if (body.shape && !body.rectangle) {
    double xlo, xhi, ylo, yhi;
    body.shape->boundingBox(xlo, xhi, ylo, yhi);
    if (xlo < grid_.x0 - tolx || xhi > grid_.xMax() + tolx || ylo < grid_.y0 - toly || yhi > grid_.yMax() + toly)
      throw DeckError("particles outside the grid: '" + key + "' (" + body.shape->describe() +
                      ") extends beyond the grid [" + formatNumber(grid_.x0) + ", " + formatNumber(grid_.xMax()) +
                      "] x [" + formatNumber(grid_.y0) + ", " + formatNumber(grid_.yMax()) + "]");
  }
}

// For checkProblemSize: the body's particles (exact for lattice-filled rectangles and Gauss points,
// by area for other shapes) and the cells it covers.
void Simulation::estimateBodySize(const BodySpec& body, size_t fileParticles) {
  double cells = 0, particles = 0;
  if (!body.particlesFile.empty()) {
    particles = cells = (double)fileParticles;
  } else {
    cells = body.shape->area() / (grid_.hx * grid_.hy);
    double perCell = placement_ == Placement::GaussQ4 ? 4.0
                     : placement_ == Placement::GaussQ9
                         ? 9.0 / 4.0
                         : (double)body.rect.particlesPerCellX * body.rect.particlesPerCellY;
    if (grid_.dim == 3) {
      cells *= body.rect.depth() / grid_.hz;
      perCell *= placement_ == Placement::GaussQ4   ? 2.0
                 : placement_ == Placement::GaussQ9 ? 3.0 / 2.0
                                                    : body.rect.particlesPerCellZ;
    }
    particles = cells * perCell;
  }
  estimatedBodyCells_.push_back(cells);
  estimatedBodyParticles_.push_back(particles);
}

}  // namespace impm
