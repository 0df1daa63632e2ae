// Deck sections Monitors and Exact Solution: the particle quantities history.csv follows and the
// exact solution they are compared with.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/Collective.hpp"
#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

#include <cmath>

#include "physics/InitialConditions.hpp"

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

RCP<const ParameterList> build::monitorsTemplate() {
  auto pl = rcp(new ParameterList("Monitors"));
  choice(*pl, "Quantity", "Displacement X",
         {"Displacement X", "Displacement Y", "Displacement Z", "Velocity X", "Velocity Y", "Velocity Z", "Stress XX",
          "Stress YY", "Stress XY", "Stress ZZ", "Stress YZ", "Stress XZ"},
         "particle quantity recorded in history.csv (Z and the YZ, XZ stresses in 3D; Stress ZZ in 2D is the "
         "out-of-plane stress, zero in plane stress)");
  number(*pl, "X", 0.0, "the particle nearest (X, Y[, Z]) at t = 0 is monitored");
  number(*pl, "Y", 0.0, "the particle nearest (X, Y[, Z]) at t = 0 is monitored");
  number(*pl, "Z", 0.0, "the particle nearest (X, Y, Z) at t = 0 is monitored (3D)");
  return pl;
}

void addExactSolutionSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist("Exact Solution", false, "exact solution for the monitors, if any");
  choice(p, "Type", "None",
         {"None", "Bar Step Load", "Simply Supported Beam", "Bar Standing Wave", "Layered Bar Step Load",
          "Column Under Self-Weight", "Axis-Aligned Manufactured Solution", "Cantilever End Load"},
         "Bar Step Load: 1D rod fixed at X Min under the step load named by Load at X Max; "
         "Layered Bar Step Load: the same rod made of all the Rectangle bodies side by side along x, each of its "
         "own material, the load at the right end of the last: the wave fronts traced through every interface "
         "(transmitted 2 Z_b/(Z_a + Z_b), reflected (Z_b - Z_a)/(Z_a + Z_b)); displacement, velocity and stress XX; "
         "Simply Supported Beam: Euler-Bernoulli beam under the harmonic point load named by Load; "
         "Bar Standing Wave: 1D rod fixed in x at both ends (Constraints on faces x- and x+), no loads, "
         "started by Initial Conditions/Type = Standing Wave: u = (V/omega) sin(n pi X/L) sin(omega t), "
         "omega = c n pi / L (displacement, velocity and stress XX); "
         "Column Under Self-Weight: a plane-strain column on a fixed base with rollers on both sides under the "
         "Body Force named by Load (Acceleration Y < 0), quasi-static at the load's current factor: "
         "sigma_yy = -f rho0 g (l0 - Y) exactly, and the stretch and displacement of the linear or neo-Hookean "
         "law (physics/ColumnExact.hpp; displacement Y, stress YY and XX; modulus: the constrained lambda + 2 mu); "
         "Axis-Aligned Manufactured Solution: Wallstedt & Guilkey's (2008) field u_d = A sin(2 pi (X_d - o_d) / L) "
         "sin(omega t), omega = pi sqrt(E / rho0) / L, on a square (cube) neo-Hookean Body of side L with rollers "
         "on every face, driven by a Load of Type = Manufactured Body Force and started by Initial Conditions/Type "
         "= Manufactured Solution (physics/ManufacturedSolution.hpp); every displacement, velocity and stress, "
         "and the whole displacement field (summary.yaml: Displacement Field Error); "
         "Cantilever End Load: the elastica of the body clamped at X Min (a Face x- constraint, xy) under the "
         "dead end load that is the sum of the deck's loads (Particle Forces along y at X Max, one time function), "
         "quasi-static at k f(t), k = P L^2 / (Modulus I) (physics/ElasticaExact.hpp; displacement X and Y, the "
         "cross-section rotating rigidly with the centreline)");
  choice(p, "Modulus", "Plane Condition", {"Plane Condition", "Young Modulus"},
         "modulus of the exact solution: Plane Condition = E in plane stress, E/(1-nu^2) in plane strain");
  p.set("Load", "", "name of the load (in Loads) that the exact solution is driven by (not used by Bar Standing Wave)");
  p.set("Body", "", "the body the exact solution describes (empty: the first body; a Rectangle)");
  number(p, "Amplitude", 0.0, "Axis-Aligned Manufactured Solution: displacement amplitude A (m), 0 < A < L / (4 pi)");
  choice(p, "Form", "Closed", {"Closed", "Series"}, "bar: d'Alembert closed form or Fourier series");
  p.set("Series Terms", 2000, "terms of the series");
  choice(p, "Beam Theory", "Euler-Bernoulli", {"Euler-Bernoulli", "Timoshenko"},
         "beam: Euler-Bernoulli (the benchmark's formula), or Timoshenko (shear deformation and rotary "
         "inertia; deflection only, no stress)");
  number(p, "Shear Coefficient", 5.0 / 6.0, "Timoshenko shear coefficient kappa (5/6 for a rectangle)");
  choice(p, "Time Discretisation", "Exact", {"Exact", "Newmark"},
         "beam: Exact in time, or each mode advanced by the Newmark average-acceleration recurrence at the "
         "run's time step (what an exact-in-space Newmark integration gives: isolates the spatial error)");
}

// A manufactured solution (Exact Solution/Type) drives the initial state and a load: read first.
void Simulation::readManufacturedSolution() {
  if (deck_.sublist("Exact Solution").get<std::string>("Type") == "Axis-Aligned Manufactured Solution") {
    ExactContext early;
    early.bodies = bodies_;
    early.materials = &materials_;
    early.dimension = grid_.dim;
    manufactured_ =
        std::make_unique<AxisAlignedManufactured>(axisAlignedManufactured(deck_.sublist("Exact Solution"), early));
  }
}

void Simulation::buildMonitors() {
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
}

void Simulation::buildExactSolution(const std::vector<ConstraintSpec>& cspecs, const std::vector<LoadSpec>& lspecs) {
  ExactContext context;
  context.bodies = bodies_;
  context.materials = &materials_;
  context.thickness = thickness_;
  context.dimension = grid_.dim;
  context.loads = lspecs;
  context.constraints = cspecs;
  const ParameterList& ic = deck_.sublist("Initial Conditions");
  context.initialCondition = ic.get<std::string>("Type");
  context.initialAmplitude = ic.get<double>("Amplitude");
  context.initialMode = ic.get<int>("Mode");
  context.dt = dt_;
  context.steps = steps_;
  context.manufactured = manufactured_.get();
  exact_ = makeExactReference(deck_.sublist("Exact Solution"), context);
}

std::string Simulation::describePoint(const Point& p) const {
  return "(" + formatNumber(p[0]) + ", " + formatNumber(p[1]) +
         (grid_.dim == 3 ? ", " + formatNumber(p[2]) : std::string()) + ")";
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
    if (dist < best - 1e-15 * (1 + dist)) {
      best = dist;
      local = p;
    }
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
  m.x0 = gpos[0];
  m.y0 = gpos[1];
  m.z0 = gpos[2];
  m.particleId = std::llround(gpos[3]);
}

}  // namespace impm
