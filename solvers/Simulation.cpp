#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "core/InputDeck.hpp"
#include "core/output/VtkWriter.hpp"
#include "physics/InitialConditions.hpp"
#include "solvers/ExplicitStepper.hpp"
#include "solvers/ImplicitNewmark.hpp"

#ifndef IMPM_PLOT_SCRIPT
#define IMPM_PLOT_SCRIPT "apps/plot_history.py"
#endif

namespace impm {

using Teuchos::ParameterList;

namespace {

std::string fmt(double v) {
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}

double positive(const ParameterList& pl, const std::string& section, const std::string& key) {
  const double v = pl.get<double>(key);
  if (!(v > 0)) throw DeckError("'" + section + "/" + key + "' must be positive, got " + fmt(v));
  return v;
}
int positiveInt(const ParameterList& pl, const std::string& section, const std::string& key) {
  const int v = pl.get<int>(key);
  if (v <= 0) throw DeckError("'" + section + "/" + key + "' must be positive, got " + std::to_string(v));
  return v;
}

// True when x is on a grid line x0 + k h (to round-off).
bool onGridLine(double x, double x0, double h) {
  const double k = (x - x0) / h;
  return std::abs(k - std::round(k)) < 1e-6;
}

}  // namespace

Simulation::~Simulation() = default;

Simulation::Simulation(const ParameterList& deck, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                       const std::string& outputOverride)
    : deck_(deck), comm_(comm) {
  const ParameterList& problem = deck_.sublist("Problem");
  outputDir_ = outputOverride.empty() ? problem.get<std::string>("Output Directory") : outputOverride;
  if (outputDir_.empty()) throw DeckError("'Problem/Output Directory' must not be empty");

  // Grid.
  const ParameterList& g = deck_.sublist("Grid");
  grid_.x0 = g.get<double>("Origin X");
  grid_.y0 = g.get<double>("Origin Y");
  grid_.nx = positiveInt(g, "Grid", "Cells X");
  grid_.ny = positiveInt(g, "Grid", "Cells Y");
  grid_.hx = positive(g, "Grid", "Cell Size X");
  grid_.hy = positive(g, "Grid", "Cell Size Y");

  // Material.
  const ParameterList& m = deck_.sublist("Material");
  material_.E = positive(m, "Material", "Young Modulus");
  material_.density = positive(m, "Material", "Density");
  material_.nu = m.get<double>("Poisson Ratio");
  if (!(material_.nu > -1.0 && material_.nu < 0.5))
    throw DeckError("'Material/Poisson Ratio' must lie in (-1, 0.5), got " + fmt(material_.nu));
  material_.plane = m.get<std::string>("Plane Condition") == "Plane Stress" ? PlaneCondition::PlaneStress
                                                                              : PlaneCondition::PlaneStrain;
  body_.thickness = positive(m, "Material", "Thickness");

  // Body: inside the grid, edges on grid lines.
  const ParameterList& b = deck_.sublist("Body");
  body_.xMin = b.get<double>("X Min"); body_.xMax = b.get<double>("X Max");
  body_.yMin = b.get<double>("Y Min"); body_.yMax = b.get<double>("Y Max");
  body_.particlesPerCellX = positiveInt(b, "Body", "Particles Per Cell X");
  body_.particlesPerCellY = positiveInt(b, "Body", "Particles Per Cell Y");
  shape_ = deck_.sublist("Method").get<std::string>("Shape Function");
  if (shape_ == "FE Q4") body_.placement = Placement::GaussQ4;
  if (shape_ == "FE Q9") body_.placement = Placement::GaussQ9;
  if (!(body_.xMax > body_.xMin)) throw DeckError("'Body/X Max' must exceed 'Body/X Min'");
  if (!(body_.yMax > body_.yMin)) throw DeckError("'Body/Y Max' must exceed 'Body/Y Min'");
  const double tolx = 1e-9 * grid_.hx, toly = 1e-9 * grid_.hy;
  if (body_.xMin < grid_.x0 - tolx) throw DeckError("particles outside the grid: 'Body/X Min' = " + fmt(body_.xMin) + " is left of the grid origin " + fmt(grid_.x0));
  if (body_.xMax > grid_.xMax() + tolx) throw DeckError("particles outside the grid: 'Body/X Max' = " + fmt(body_.xMax) + " is beyond the grid's right edge " + fmt(grid_.xMax()));
  if (body_.yMin < grid_.y0 - toly) throw DeckError("particles outside the grid: 'Body/Y Min' = " + fmt(body_.yMin) + " is below the grid origin " + fmt(grid_.y0));
  if (body_.yMax > grid_.yMax() + toly) throw DeckError("particles outside the grid: 'Body/Y Max' = " + fmt(body_.yMax) + " is above the grid's top edge " + fmt(grid_.yMax()));
  for (auto [key, v, o, h] : {std::make_tuple("X Min", body_.xMin, grid_.x0, grid_.hx), std::make_tuple("X Max", body_.xMax, grid_.x0, grid_.hx),
                              std::make_tuple("Y Min", body_.yMin, grid_.y0, grid_.hy), std::make_tuple("Y Max", body_.yMax, grid_.y0, grid_.hy)})
    if (!onGridLine(v, o, h)) throw DeckError(std::string("'Body/") + key + "' = " + fmt(v) + " is not on a grid line");

  if (shape_ == "FE Q9") {  // elements of 2 x 2 cells, the body made of whole elements
    if (grid_.nx % 2 || grid_.ny % 2)
      throw DeckError("'Method/Shape Function' = FE Q9 needs even 'Grid/Cells X' and 'Grid/Cells Y' (an element is 2 x 2 cells), got " +
                      std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny));
    for (auto [key, v, o, h] : {std::make_tuple("X Min", body_.xMin, grid_.x0, grid_.hx), std::make_tuple("X Max", body_.xMax, grid_.x0, grid_.hx),
                                std::make_tuple("Y Min", body_.yMin, grid_.y0, grid_.hy), std::make_tuple("Y Max", body_.yMax, grid_.y0, grid_.hy)})
      if (std::lround((v - o) / h) % 2)
        throw DeckError(std::string("'Body/") + key + "' = " + fmt(v) + " is not on an element edge of FE Q9 (an even grid line)");
  }

  // Integrator.
  const ParameterList& in = deck_.sublist("Integrator");
  dt_ = positive(in, "Integrator", "Time Step");
  steps_ = positiveInt(in, "Integrator", "Number of Steps");
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
    if (!(eopt.flip >= 0 && eopt.flip <= 1))
      throw DeckError("'Integrator/Explicit/FLIP Fraction' must lie in [0, 1], got " + fmt(eopt.flip));
    const double factor = positive(ex, "Integrator/Explicit", "Stability Factor");
    // Bilinear cells with lumped mass: omega_max = 2 c_p sqrt(1/hx^2 + 1/hy^2), so dt_crit =
    // 1 / (c_p sqrt(1/hx^2 + 1/hy^2)); h_min / c_p overestimates it (by 12% on the beam's 2:1
    // cells, where 0.9 h_min / c_p was measured to blow up).
    const double limit = factor / (material_.pWaveSpeed() * std::sqrt(1.0 / (grid_.hx * grid_.hx) + 1.0 / (grid_.hy * grid_.hy)));
    if (integratorType == "Explicit" && dt_ > limit)
      throw DeckError("'Integrator/Time Step' = " + fmt(dt_) + " exceeds the explicit stable limit " + fmt(limit) +
                      " (Stability Factor / (P-wave speed x sqrt(1/hx^2 + 1/hy^2)), P-wave speed " + fmt(material_.pWaveSpeed()) + " m/s)");
  }

  // Loads and constraints: names and positions checked against the grid.
  auto nodeOf = [&](const std::string& where, double x, double y) {
    if (!onGridLine(x, grid_.x0, grid_.hx) || !onGridLine(y, grid_.y0, grid_.hy) || x < grid_.x0 - tolx ||
        x > grid_.xMax() + tolx || y < grid_.y0 - toly || y > grid_.yMax() + toly)
      throw DeckError("'" + where + "/X', '" + where + "/Y' = (" + fmt(x) + ", " + fmt(y) + ") is not a grid node");
  };
  std::vector<ConstraintSpec> cspecs;
  const ParameterList& cl = deck_.sublist("Constraints");
  for (auto it = cl.begin(); it != cl.end(); ++it) {
    const ParameterList& c = cl.sublist(cl.name(it));
    ConstraintSpec s;
    s.name = cl.name(it);
    s.where = c.get<std::string>("Where");
    s.face = c.get<std::string>("Face");
    s.x = c.get<double>("X"); s.y = c.get<double>("Y");
    const std::string comp = c.get<std::string>("Components");
    s.fixX = comp.find('x') != std::string::npos;
    s.fixY = comp.find('y') != std::string::npos;
    if (s.where == "Node") nodeOf("Constraints/" + s.name, s.x, s.y);
    cspecs.push_back(s);
  }

  dist_ = std::make_unique<GridDistribution>(grid_, comm_);
  particles_ = createParticles(body_, material_, *dist_);
  constraints_ = NodalConstraints(cspecs, body_, *dist_);

  // Initial conditions, before the integrators (an implicit one computes a(0) from this state).
  const ParameterList& ic = deck_.sublist("Initial Conditions");
  const std::string icType = ic.get<std::string>("Type");
  const double icAmplitude = ic.get<double>("Amplitude");
  const int icMode = ic.get<int>("Mode");
  if (icType == "Standing Wave") {
    if (!(icAmplitude != 0.0 && std::isfinite(icAmplitude)))
      throw DeckError("'Initial Conditions/Amplitude' must be a non-zero velocity amplitude for Type = Standing Wave, got " +
                      fmt(icAmplitude));
    if (icMode < 1)
      throw DeckError("'Initial Conditions/Mode' must be at least 1 for Type = Standing Wave, got " + std::to_string(icMode));
    applyStandingWaveVelocity(particles_, body_.xMin, body_.length(), icAmplitude, icMode);
  }

  // Nearest particle to a point, over all ranks: (owner rank, local index, x0, y0).
  auto nearest = [&](double px, double py, int& owner, int& local, double& x0, double& y0) {
    auto xh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x0);
    double best = std::numeric_limits<double>::max();
    local = -1;
    for (int p = 0; p < particles_.count; ++p) {
      const double d = std::hypot(xh(p, 0) - px, xh(p, 1) - py);
      if (d < best - 1e-15 * (1 + d)) { best = d; local = p; }
    }
    double gbest = 0;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, best, Teuchos::outArg(gbest));
    const int candidate = (local >= 0 && best == gbest) ? comm_->getRank() : comm_->getSize();
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, candidate, Teuchos::outArg(owner));
    double pos[2] = {0, 0}, gpos[2];
    if (owner == comm_->getRank()) { pos[0] = xh(local, 0); pos[1] = xh(local, 1); } else { local = -1; }
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, 2, pos, gpos);
    x0 = gpos[0]; y0 = gpos[1];
  };

  std::vector<LoadSpec> lspecs;
  std::vector<int> loadParticle;
  const ParameterList& ll = deck_.sublist("Loads");
  for (auto it = ll.begin(); it != ll.end(); ++it) {
    const ParameterList& l = ll.sublist(ll.name(it));
    LoadSpec s;
    s.name = ll.name(it);
    s.type = l.get<std::string>("Type");
    s.face = l.get<std::string>("Face");
    s.x = l.get<double>("X"); s.y = l.get<double>("Y");
    s.forceX = l.get<double>("Force X"); s.forceY = l.get<double>("Force Y");
    const std::string tf = l.get<std::string>("Time Function");
    s.time.kind = tf == "Sine" ? TimeFunction::Kind::Sine : tf == "Constant" ? TimeFunction::Kind::Constant : TimeFunction::Kind::Step;
    s.time.omega = l.get<double>("Angular Frequency");
    s.time.startTime = l.get<double>("Start Time");
    if (s.time.kind == TimeFunction::Kind::Sine && !(s.time.omega > 0))
      throw DeckError("'Loads/" + s.name + "/Angular Frequency' must be positive for a Sine load");
    if (s.type == "Node Force") nodeOf("Loads/" + s.name, s.x, s.y);
    int owner = -1, local = -1;
    if (s.type == "Particle Force") {
      double x0, y0;
      nearest(s.x, s.y, owner, local, x0, y0);
    }
    loadParticle.push_back(local);
    lspecs.push_back(s);
  }
  loads_ = LoadSet(lspecs, body_, *dist_, loadParticle);

  const ParameterList& ml = deck_.sublist("Monitors");
  for (auto it = ml.begin(); it != ml.end(); ++it) {
    const ParameterList& mp = ml.sublist(ml.name(it));
    Monitor mon;
    mon.name = ml.name(it);
    mon.quantity = mp.get<std::string>("Quantity");
    nearest(mp.get<double>("X"), mp.get<double>("Y"), mon.owner, mon.localIndex, mon.x0, mon.y0);
    monitors_.push_back(mon);
  }

  // Exact solution, with the modulus it is asked to use.
  const ParameterList& e = deck_.sublist("Exact Solution");
  exactType_ = e.get<std::string>("Type");
  exactSeries_ = e.get<std::string>("Form") == "Series";
  exactTerms_ = positiveInt(e, "Exact Solution", "Series Terms");
  exactModulus_ = e.get<std::string>("Modulus") == "Young Modulus" ? material_.E : material_.barModulus();
  if (exactType_ == "Bar Standing Wave") {
    // The exact solution holds for this initial state, both ends fixed in x and no loads.
    if (icType != "Standing Wave")
      throw DeckError("'Exact Solution/Type' = Bar Standing Wave needs 'Initial Conditions/Type' = Standing Wave, got " + icType);
    if (!lspecs.empty())
      throw DeckError("'Exact Solution/Type' = Bar Standing Wave is free vibration: the deck must have no Loads (found '" +
                      lspecs.front().name + "')");
    for (const std::string face : {"x-", "x+"}) {
      bool fixed = false;
      for (const auto& c : cspecs) fixed = fixed || (c.where == "Face" && c.face == face && c.fixX);
      if (!fixed)
        throw DeckError("'Exact Solution/Type' = Bar Standing Wave needs a constraint fixing x on face " + face +
                        " of the body (Constraints: Where = Face, Face = " + face + ", Components = x or xy)");
    }
    wave_ = BarStandingWaveExact{body_.length(), exactModulus_, material_.density, icAmplitude, icMode};
  } else if (hasExact()) {
    const std::string loadName = e.get<std::string>("Load");
    const LoadSpec* load = nullptr;
    for (const auto& s : lspecs) if (s.name == loadName) load = &s;
    if (!load) throw DeckError("'Exact Solution/Load' = '" + loadName + "' names no entry of Loads");
    const double A = body_.height() * body_.thickness;
    if (exactType_ == "Bar Step Load") {
      bar_ = BarStepExact{body_.length(), A, exactModulus_, material_.density, load->forceX};
    } else {
      const double I = body_.thickness * std::pow(body_.height(), 3) / 12.0;
      beam_ = BeamHarmonicExact{body_.length(), load->x - body_.xMin, exactModulus_, I, material_.density * A,
                                load->forceY, load->time.omega};
      neutralAxisY_ = 0.5 * (body_.yMin + body_.yMax);
      timoshenko_ = e.get<std::string>("Beam Theory") == "Timoshenko";
      if (timoshenko_) {
        const double kappa = positive(e, "Exact Solution", "Shear Coefficient");
        const double G = material_.E / (2.0 * (1.0 + material_.nu));
        timo_ = TimoshenkoBeamHarmonic{body_.length(), load->x - body_.xMin, exactModulus_, G, kappa, A, I,
                                       material_.density, load->forceY, load->time.omega};
      }
      if (e.get<std::string>("Time Discretisation") == "Newmark") {
        // The whole history once per monitor (deflection only), indexed by step.
        const int terms = std::min(exactTerms_, 400);
        for (const auto& mon : monitors_) {
          const double x = mon.x0 - body_.xMin;
          newmarkHistory_.push_back(mon.quantity != "Displacement Y" ? std::vector<double>()
                                    : timoshenko_ ? timo_.deflectionHistoryNewmark(x, dt_, steps_, terms)
                                                  : deflectionHistoryNewmark(beam_, x, dt_, steps_, terms));
        }
      }
    }
  }

  const bool gimp = shape_ == "GIMP", fe = shape_ == "FE Q4" || shape_ == "FE Q9";
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
    iopt.consistentMass = im.get<std::string>("Mass Matrix") == "Consistent";
    iopt.seedGimpStiffness = im.get<std::string>("GIMP Stiffness") == "Integrated";
    iopt.fixedParticles = fe;
    if (iopt.preconditionerRefreshInterval < 1)
      throw DeckError("'Integrator/Implicit/Preconditioner Refresh Interval' must be at least 1");
    if (iopt.projectionIterations < 0)
      throw DeckError("'Integrator/Implicit/Consistent Projection Iterations' must not be negative");
    iopt.solverParams = Teuchos::rcp(new ParameterList(deck_.sublist("Implicit Solver")));
    try {
      if (gimp) integrator_ = std::make_unique<ImplicitNewmark<UniformGimp>>(particles_, *dist_, material_, constraints_, loads_, iopt);
      else if (shape_ == "FE Q9") integrator_ = std::make_unique<ImplicitNewmark<QuadraticLagrange>>(particles_, *dist_, material_, constraints_, loads_, iopt);
      else integrator_ = std::make_unique<ImplicitNewmark<LinearMpm>>(particles_, *dist_, material_, constraints_, loads_, iopt);
    } catch (const std::invalid_argument& e) {
      throw DeckError(e.what());
    }
  } else if (gimp) {
    integrator_ = std::make_unique<ExplicitStepper<UniformGimp>>(particles_, *dist_, material_, constraints_, loads_, eopt);
  } else {
    integrator_ = std::make_unique<ExplicitStepper<LinearMpm>>(particles_, *dist_, material_, constraints_, loads_, eopt);
  }
}

// A rank maps its particles onto its ghosted node columns; a particle that wandered beyond
// them (or off the grid) would be mapped to the wrong nodes. Particle migration between ranks
// is not implemented: stop with a clear message instead.
void Simulation::checkParticlesInReach(double t) const {
  const StructuredGrid g = grid_;
  const LocalNodeIndexer ix = dist_->ghostedIndexer();
  // Stencils reach one column beyond the particle's cell (GIMP: its domain's cells plus one).
  // At the grid's own edges stencils are clamped, so a body that fills the grid may stretch a
  // little past them (the seed's bar does); half a cell is allowed there.
  const double xLo = ix.colBegin > 0 ? g.nodeX(ix.colBegin) + g.hx : g.x0 - 0.5 * g.hx;
  const double xHi = ix.colEnd - 1 < g.nx ? g.nodeX(ix.colEnd - 1) - g.hx : g.xMax() + 0.5 * g.hx;
  const double yLo = g.y0 - 0.5 * g.hy, yHi = g.yMax() + 0.5 * g.hy;
  auto x = particles_.x; auto hs = particles_.halfSize;
  int outside = 0;
  Kokkos::parallel_reduce(
      "check_particles_in_reach", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count),
      KOKKOS_LAMBDA(int p, int& count) {
        if (!(x(p, 0) - hs(p, 0) >= xLo && x(p, 0) + hs(p, 0) <= xHi && x(p, 1) - hs(p, 1) >= yLo &&
              x(p, 1) + hs(p, 1) <= yHi))
          ++count;
      },
      outside);
  int total = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, outside, Teuchos::outArg(total));
  if (total > 0)
    throw std::runtime_error(std::to_string(total) + " particle(s) left the grid or the columns their MPI rank maps at t = " +
                             fmt(t) + " s (particle migration between ranks is not implemented: use a larger grid or fewer ranks)");
}

double Simulation::monitorValue(const Monitor& mon) const {
  if (mon.owner != comm_->getRank()) return 0.0;
  const int p = mon.localIndex;
  auto read = [](const auto& view, int i, int c) {
    double v;
    Kokkos::deep_copy(v, Kokkos::subview(view, i, c));
    return v;
  };
  const std::string& q = mon.quantity;
  const bool fixed = particles_.fixedPositions();
  if (q == "Displacement X") return fixed ? read(particles_.u, p, 0) : read(particles_.x, p, 0) - mon.x0;
  if (q == "Displacement Y") return fixed ? read(particles_.u, p, 1) : read(particles_.x, p, 1) - mon.y0;
  if (q == "Velocity X") return read(particles_.v, p, 0);
  if (q == "Velocity Y") return read(particles_.v, p, 1);
  if (q == "Stress XX") return read(particles_.stress, p, 0);
  if (q == "Stress YY") return read(particles_.stress, p, 1);
  return read(particles_.stress, p, 2);
}

double Simulation::exactValue(const Monitor& mon, double t) const {
  const std::string& q = mon.quantity;
  const double NaN = std::numeric_limits<double>::quiet_NaN();
  if (exactType_ == "Bar Step Load") {
    const double x = mon.x0 - body_.xMin;
    if (q == "Displacement X") return exactSeries_ ? bar_.displacementSeries(x, t, exactTerms_) : bar_.displacementClosed(x, t);
    if (q == "Stress XX") return exactSeries_ ? bar_.stressSeries(x, t, exactTerms_) : bar_.stressClosed(x, t);
  } else if (exactType_ == "Bar Standing Wave") {
    const double x = mon.x0 - body_.xMin;
    if (q == "Displacement X") return wave_.displacement(x, t);
    if (q == "Velocity X") return wave_.velocity(x, t);
    if (q == "Stress XX") return wave_.stress(x, t);
  } else if (exactType_ == "Simply Supported Beam") {
    const double x = mon.x0 - body_.xMin;
    const int terms = std::min(exactTerms_, 400);
    if (!newmarkHistory_.empty()) {
      const auto& h = newmarkHistory_[&mon - monitors_.data()];
      const long k = std::lround(t / dt_);
      return k >= 0 && k < (long)h.size() ? h[k] : NaN;
    }
    if (q == "Displacement Y") return timoshenko_ ? timo_.deflection(x, t, terms) : beam_.deflection(x, t, terms);
    if (q == "Stress XX" && !timoshenko_) return beam_.bendingStress(x, mon.y0 - neutralAxisY_, t, terms);
  }
  return NaN;
}

RunResult Simulation::run(std::ostream& log) {
  namespace fs = std::filesystem;
  const int rank = comm_->getRank();
  const ParameterList& out = deck_.sublist("Output");
  const int historyInterval = std::max(1, out.get<int>("History Interval"));
  const int vtkInterval = out.get<int>("VTK Interval");
  const bool progress = out.get<bool>("Progress");

  if (rank == 0) fs::create_directories(outputDir_);
  comm_->barrier();

  RunResult r;
  const long long localCount = particles_.count;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, localCount, Teuchos::outArg(r.particles));
  r.steps = steps_;

  std::vector<bool> withExact;
  for (const auto& mon : monitors_) withExact.push_back(hasExact() && !std::isnan(exactValue(mon, dt_)));

  std::ofstream csv;
  if (rank == 0) {
    csv.open(outputDir_ + "/history.csv");
    csv << "time";
    for (size_t k = 0; k < monitors_.size(); ++k) {
      csv << ',' << monitors_[k].name;
      if (withExact[k]) csv << ',' << monitors_[k].name << "_exact";
    }
    csv << '\n' << std::setprecision(10);
  }
  auto record = [&](double t) {
    std::vector<double> local(monitors_.size()), global(monitors_.size());
    for (size_t k = 0; k < monitors_.size(); ++k) local[k] = monitorValue(monitors_[k]);
    if (!monitors_.empty())
      Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, (int)local.size(), local.data(), global.data());
    r.time.push_back(t);
    if (rank == 0) csv << t;
    for (size_t k = 0; k < monitors_.size(); ++k) {
      r.computed[monitors_[k].name].push_back(global[k]);
      if (rank == 0) csv << ',' << global[k];
      if (withExact[k]) {
        const double ex = exactValue(monitors_[k], t);
        r.exact[monitors_[k].name].push_back(ex);
        if (rank == 0) csv << ',' << ex;
      }
    }
    if (rank == 0) csv << '\n';
  };

  PvdIndex pvd(outputDir_ + "/particles.pvd", comm_->getSize());
  int vtkCount = 0;
  auto writeVtk = [&](double t) {
    char stem[64];
    std::snprintf(stem, sizeof stem, "particles_%05d", vtkCount++);
    writeParticlesVtu(outputDir_ + "/" + PvdIndex::pieceName(stem, rank), particles_);
    comm_->barrier();
    if (rank == 0) pvd.add(t, stem);
  };

  record(0.0);
  writeVtk(0.0);
  const bool tty = isatty(fileno(stderr));
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  auto lastPrint = start;
  bool printedProgress = false;
  for (int n = 0; n < steps_; ++n) {
    const double t = n * dt_;
    try {
      integrator_->step(t, dt_);
    } catch (const NewtonNotConverged& e) {
      // Keep what was computed: the history so far, the last converged particles and a summary.
      if (rank == 0) csv.close();
      writeVtk(t);
      r.wallSeconds = std::chrono::duration<double>(clock::now() - start).count();
      r.steps = n;
      r.status = std::string("stopped: ") + e.what();
      if (rank == 0) writeSummary(r);
      throw std::runtime_error(std::string(e.what()) + "; the last converged state (t = " + fmt(t) +
                               " s) is in " + outputDir_);
    }
    const double tNew = (n + 1) * dt_;
    checkParticlesInReach(tNew);
    if ((n + 1) % historyInterval == 0 || n + 1 == steps_) record(tNew);
    if (vtkInterval > 0 && (n + 1) % vtkInterval == 0 && n + 1 != steps_) writeVtk(tNew);
    if (progress && rank == 0) {
      const auto now = clock::now();
      const double elapsed = std::chrono::duration<double>(now - start).count();
      const double sinceLast = std::chrono::duration<double>(now - lastPrint).count();
      if (elapsed > 3.0 && sinceLast > (tty ? 0.5 : 10.0)) {
        const double eta = elapsed / (n + 1) * (steps_ - n - 1);
        std::fprintf(stderr, "%sstep %d/%d  t = %.4e s  %3.0f%%  elapsed %.1f s  ETA %.1f s%s", tty ? "\r" : "", n + 1,
                     steps_, tNew, 100.0 * (n + 1) / steps_, elapsed, eta, tty ? "   " : "\n");
        lastPrint = now;
        printedProgress = true;
      }
    }
  }
  if (printedProgress && tty && rank == 0) std::fprintf(stderr, "\n");
  r.wallSeconds = std::chrono::duration<double>(clock::now() - start).count();
  r.particleStepsPerSecond = r.wallSeconds > 0 ? double(r.particles) * steps_ / r.wallSeconds : 0.0;
  writeVtk(steps_ * dt_);
  if (rank == 0) csv.close();

  for (size_t k = 0; k < monitors_.size(); ++k) {
    if (!withExact[k]) continue;
    const auto& c = r.computed[monitors_[k].name];
    const auto& e = r.exact[monitors_[k].name];
    double num = 0, den = 0;
    for (size_t i = 0; i < c.size(); ++i) { num += (c[i] - e[i]) * (c[i] - e[i]); den += e[i] * e[i]; }
    r.relativeL2[monitors_[k].name] = den > 0 ? std::sqrt(num / den) : std::sqrt(num);
  }
  if (rank == 0) {
    writeSummary(r);
    log << deck_.sublist("Problem").get<std::string>("Name") << ": " << integrator_->name() << ", "
        << material_.planeName() << ", " << r.particles << " particles, " << steps_ << " steps in " << std::setprecision(3)
        << r.wallSeconds << " s (" << r.particleStepsPerSecond / 1e6 << " M particle-steps/s)\n";
    for (const auto& [name, err] : r.relativeL2)
      log << "  relative L2 error of " << name << " against the exact solution (modulus " << std::setprecision(4)
          << exactModulus_ << " Pa): " << std::setprecision(3) << 100 * err << " %\n";
    if (out.get<bool>("Plot") && hasExact()) {
      const char* env = std::getenv("IMPM_PLOT_SCRIPT");
      const std::string script = env ? env : IMPM_PLOT_SCRIPT;
      const std::string title = deck_.sublist("Problem").get<std::string>("Name");
      const std::string cmd = "/usr/bin/python3 '" + script + "' '" + outputDir_ + "' --title '" + title + "'";
      if (std::system(cmd.c_str()) != 0) log << "  warning: the plot could not be written (" << cmd << ")\n";
      else log << "  plot: " << outputDir_ << "/plot.png\n";
    }
  }
  return r;
}

void Simulation::writeSummary(const RunResult& r) const {
  ParameterList s("summary");
  s.set("Problem", deck_.sublist("Problem").get<std::string>("Name"));
  s.set("Method", deck_.sublist("Method").get<std::string>("Shape Function"));
  s.set("Integrator", integrator_->name());
  s.set("Plane Condition", material_.planeName());
  s.set("Particles", (int)r.particles);
  s.set("Steps", r.steps);
  s.set("Time Step", dt_);
  s.set("End Time", dt_ * r.steps);
  s.set("MPI Ranks", comm_->getSize());
  s.set("Threads", (int)ExecutionSpace::concurrency());
  s.set("Execution Space", std::string(ExecutionSpace::name()));
  s.set("Wall Time", r.wallSeconds);
  s.set("Particle Steps Per Second", r.particleStepsPerSecond);
  s.set("Status", r.status);
  s.set("Exact Solution", exactType_);
  if (hasExact()) {
    s.set("Exact Modulus", exactModulus_);
    if (exactType_ == "Simply Supported Beam") {
      s.set("Exact Beam Theory", timoshenko_ ? std::string("Timoshenko") : std::string("Euler-Bernoulli"));
      s.set("Exact Time Discretisation", newmarkHistory_.empty() ? std::string("Exact") : std::string("Newmark"));
    }
    if (exactType_ == "Bar Standing Wave") s.set("Exact Angular Frequency", wave_.omega());
    ParameterList& err = s.sublist("Relative L2 Error");
    for (const auto& [name, e] : r.relativeL2) err.set(name, e);
  }
  // Where each monitor sits (its particle's reference position), so that studies can evaluate
  // other reference solutions at the same point.
  ParameterList& mons = s.sublist("Monitors");
  for (const auto& m : monitors_) {
    ParameterList& e = mons.sublist(m.name);
    e.set("Quantity", m.quantity);
    e.set("X", m.x0);
    e.set("Y", m.y0);
  }
  integrator_->addStatistics(s);
  const std::string path = outputDir_ + "/summary.yaml";
  Teuchos::writeParameterListToYamlFile(s, path + ".tmp");
  std::filesystem::rename(path + ".tmp", path);
}

}  // namespace impm
