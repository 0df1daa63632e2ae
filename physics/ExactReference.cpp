#include "physics/ExactReference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "core/InputDeck.hpp"
#include "physics/BeamTheories.hpp"
#include "physics/ColumnExact.hpp"
#include "physics/ElasticaExact.hpp"
#include "physics/ExactSolutions.hpp"
#include "physics/LayeredBarExact.hpp"

namespace impm {

using Teuchos::ParameterList;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// The body an exact solution describes: Exact Solution/Body, or the first body; a Rectangle.
const BodySpec& exactBody(const ParameterList& e, const ExactContext& c) {
  const std::string name = e.get<std::string>("Body");
  const BodySpec* body = name.empty() ? &c.bodies.front() : nullptr;
  for (const auto& b : c.bodies)
    if (b.name == name) body = &b;
  if (!body) throw DeckError("'Exact Solution/Body' = '" + name + "' names no entry of Bodies");
  if (!body->rectangle)
    throw DeckError("'Exact Solution/Type' = " + e.get<std::string>("Type") +
                    " describes a rectangular body: 'Bodies/" + body->name + "' is not a Rectangle");
  return *body;
}

const LoadSpec& exactLoad(const ParameterList& e, const ExactContext& c) {
  const std::string loadName = e.get<std::string>("Load");
  for (const auto& s : c.loads)
    if (s.name == loadName) return s;
  throw DeckError("'Exact Solution/Load' = '" + loadName + "' names no entry of Loads");
}

double modulusFor(const ParameterList& e, const ExactContext& c, int material) {
  return e.get<std::string>("Modulus") == "Young Modulus" ? c.materials->parameters(material).E
                                                          : c.materials->barModulus(material);
}

class BarStep : public ExactReference {
 public:
  BarStep(const ParameterList& e, const ExactContext& c) {
    const BodySpec& b = exactBody(e, c);
    modulus_ = modulusFor(e, c, b.material);
    xMin_ = b.rect.xMin;
    series_ = e.get<std::string>("Form") == "Series";
    terms_ = e.get<int>("Series Terms");
    bar_ = BarStepExact{b.rect.length(), b.rect.height() * c.width(b.rect), modulus_, c.materials->density(b.material),
                        exactLoad(e, c).forceX};
  }
  std::string type() const override { return "Bar Step Load"; }
  double value(const std::string& q, double x0, double, double t) const override {
    const double x = x0 - xMin_;
    if (q == "Displacement X") return series_ ? bar_.displacementSeries(x, t, terms_) : bar_.displacementClosed(x, t);
    if (q == "Stress XX") return series_ ? bar_.stressSeries(x, t, terms_) : bar_.stressClosed(x, t);
    return kNaN;
  }

 private:
  BarStepExact bar_{};
  double xMin_ = 0;
  bool series_ = false;
  int terms_ = 2000;
};

class StandingWave : public ExactReference {
 public:
  StandingWave(const ParameterList& e, const ExactContext& c) {
    // The exact solution holds for this initial state, both ends fixed in x and no loads.
    if (c.initialCondition != "Standing Wave")
      throw DeckError(
          "'Exact Solution/Type' = Bar Standing Wave needs 'Initial Conditions/Type' = Standing Wave, got " +
          c.initialCondition);
    if (!c.loads.empty())
      throw DeckError(
          "'Exact Solution/Type' = Bar Standing Wave is free vibration: the deck must have no Loads (found '" +
          c.loads.front().name + "')");
    for (const std::string face : {"x-", "x+"}) {
      bool fixed = false;
      for (const auto& s : c.constraints) fixed = fixed || (s.where == "Face" && s.face == face && s.fixX);
      if (!fixed)
        throw DeckError("'Exact Solution/Type' = Bar Standing Wave needs a constraint fixing x on face " + face +
                        " of the body (Constraints: Where = Face, Face = " + face + ", Components = x or xy)");
    }
    const BodySpec& b = exactBody(e, c);
    modulus_ = modulusFor(e, c, b.material);
    xMin_ = b.rect.xMin;
    wave_ = BarStandingWaveExact{b.rect.length(), modulus_, c.materials->density(b.material), c.initialAmplitude,
                                 c.initialMode};
  }
  std::string type() const override { return "Bar Standing Wave"; }
  double value(const std::string& q, double x0, double, double t) const override {
    const double x = x0 - xMin_;
    if (q == "Displacement X") return wave_.displacement(x, t);
    if (q == "Velocity X") return wave_.velocity(x, t);
    if (q == "Stress XX") return wave_.stress(x, t);
    return kNaN;
  }
  void addSummary(ParameterList& s) const override { s.set("Exact Angular Frequency", wave_.omega()); }

 private:
  BarStandingWaveExact wave_{};
  double xMin_ = 0;
};

class SimplySupportedBeam : public ExactReference {
 public:
  SimplySupportedBeam(const ParameterList& e, const ExactContext& c) : dt_(c.dt), steps_(c.steps) {
    const BodySpec& b = exactBody(e, c);
    const RectangularBody& r = b.rect;
    const LoadSpec& load = exactLoad(e, c);
    const MaterialParameters& mat = c.materials->parameters(b.material);
    modulus_ = modulusFor(e, c, b.material);
    xMin_ = r.xMin;
    terms_ = std::min(e.get<int>("Series Terms"), 400);
    const double A = r.height() * c.width(r), I = c.width(r) * std::pow(r.height(), 3) / 12.0;
    beam_ = BeamHarmonicExact{r.length(), load.x - r.xMin, modulus_, I, mat.density * A, load.forceY, load.time.omega};
    neutralAxisY_ = 0.5 * (r.yMin + r.yMax);
    timoshenko_ = e.get<std::string>("Beam Theory") == "Timoshenko";
    if (timoshenko_) {
      const double kappa = e.get<double>("Shear Coefficient");
      if (!(kappa > 0))
        throw DeckError("'Exact Solution/Shear Coefficient' must be positive, got " + formatNumber(kappa));
      const double G = mat.E / (2.0 * (1.0 + mat.nu));
      timo_ = TimoshenkoBeamHarmonic{r.length(),  load.x - r.xMin, modulus_,       G, kappa, A, I,
                                     mat.density, load.forceY,     load.time.omega};
    }
    newmark_ = e.get<std::string>("Time Discretisation") == "Newmark";
  }
  std::string type() const override { return "Simply Supported Beam"; }
  double value(const std::string& q, double x0, double y0, double t) const override {
    const double x = x0 - xMin_;
    if (newmark_) {
      if (q != "Displacement Y") return kNaN;
      // The whole Newmark history once per position, indexed by step.
      auto it = newmarkHistory_.find(x);
      if (it == newmarkHistory_.end())
        it = newmarkHistory_
                 .emplace(x, timoshenko_ ? timo_.deflectionHistoryNewmark(x, dt_, steps_, terms_)
                                         : deflectionHistoryNewmark(beam_, x, dt_, steps_, terms_))
                 .first;
      const long k = std::lround(t / dt_);
      return k >= 0 && k < (long)it->second.size() ? it->second[k] : kNaN;
    }
    if (q == "Displacement Y") return timoshenko_ ? timo_.deflection(x, t, terms_) : beam_.deflection(x, t, terms_);
    if (q == "Stress XX" && !timoshenko_) return beam_.bendingStress(x, y0 - neutralAxisY_, t, terms_);
    return kNaN;
  }
  void addSummary(ParameterList& s) const override {
    s.set("Exact Beam Theory", timoshenko_ ? std::string("Timoshenko") : std::string("Euler-Bernoulli"));
    s.set("Exact Time Discretisation", newmark_ ? std::string("Newmark") : std::string("Exact"));
  }

 private:
  BeamHarmonicExact beam_{};
  TimoshenkoBeamHarmonic timo_{};
  bool timoshenko_ = false, newmark_ = false;
  double xMin_ = 0, neutralAxisY_ = 0, dt_ = 0;
  int steps_ = 0, terms_ = 400;
  mutable std::map<double, std::vector<double>> newmarkHistory_;
};

// All Rectangle bodies side by side along x (sorted by X Min), fixed at the left end, the step
// load at the right end. Exact Solution/Body is not used: the rod is every body.
class LayeredBar : public ExactReference {
 public:
  LayeredBar(const ParameterList& e, const ExactContext& c) {
    std::vector<const BodySpec*> bodies;
    for (const auto& b : c.bodies) {
      if (!b.rectangle)
        throw DeckError("'Exact Solution/Type' = Layered Bar Step Load needs Rectangle bodies: 'Bodies/" + b.name +
                        "' is not one");
      bodies.push_back(&b);
    }
    std::sort(bodies.begin(), bodies.end(), [](auto a, auto b) { return a->rect.xMin < b->rect.xMin; });
    const double x0 = bodies.front()->rect.xMin;
    const double height = bodies.front()->rect.height();
    std::vector<LayeredBarExact::Segment> segments;
    for (size_t k = 0; k < bodies.size(); ++k) {
      const RectangularBody& r = bodies[k]->rect;
      const double tol = 1e-9 * (bodies.back()->rect.xMax - x0);
      if (k > 0 && std::abs(r.xMin - bodies[k - 1]->rect.xMax) > tol)
        throw DeckError(
            "'Exact Solution/Type' = Layered Bar Step Load needs the bodies to touch end to end along x: 'Bodies/" +
            bodies[k]->name + "' starts at X Min = " + formatNumber(r.xMin) + ", 'Bodies/" + bodies[k - 1]->name +
            "' ends at X Max = " + formatNumber(bodies[k - 1]->rect.xMax));
      if (std::abs(r.height() - height) > 1e-9 * height)
        throw DeckError("'Exact Solution/Type' = Layered Bar Step Load needs bodies of one height: 'Bodies/" +
                        bodies[k]->name + "' differs");
      segments.push_back(
          {r.xMin - x0, r.xMax - x0, modulusFor(e, c, bodies[k]->material), c.materials->density(bodies[k]->material)});
    }
    // The modulus reported is the first segment's; each segment uses its own.
    modulus_ = segments.front().E;
    xMin_ = x0;
    const LoadSpec& load = exactLoad(e, c);
    const RectangularBody& last = bodies.back()->rect;
    if (load.type != "Face Traction" || load.face != "x+" || load.body.xMax != last.xMax)
      throw DeckError("'Exact Solution/Load' = '" + load.name +
                      "': Layered Bar Step Load needs a Face Traction on face x+ of "
                      "the rightmost body ('Bodies/" +
                      bodies.back()->name + "')");
    try {
      bar_ = std::make_unique<LayeredBarExact>(segments, height * c.width(last), load.forceX, c.dt * c.steps * 1.0001);
    } catch (const std::exception& ex) {
      throw DeckError(std::string("'Exact Solution/Type' = Layered Bar Step Load: ") + ex.what());
    }
  }
  std::string type() const override { return "Layered Bar Step Load"; }
  double value(const std::string& q, double x0, double, double t) const override {
    const double x = x0 - xMin_;
    if (q == "Displacement X") return bar_->displacement(x, t);
    if (q == "Velocity X") return bar_->velocity(x, t);
    if (q == "Stress XX") return bar_->stress(x, t);
    return kNaN;
  }

 private:
  std::unique_ptr<LayeredBarExact> bar_;
  double xMin_ = 0;
};

// The column compacting under its own weight, quasi-static: the load factor of the body force
// at time t gives the equilibrium state (physics/ColumnExact.hpp).
class SelfWeightColumn : public ExactReference {
 public:
  SelfWeightColumn(const ParameterList& e, const ExactContext& c) {
    const BodySpec& b = exactBody(e, c);
    const LoadSpec& load = exactLoad(e, c);
    if (load.type != "Body Force" || !(load.accelerationY < 0) || load.accelerationX != 0 || load.accelerationZ != 0)
      throw DeckError(
          "'Exact Solution/Type' = Column Under Self-Weight needs 'Exact Solution/Load' to name a Body Force "
          "with Acceleration Y < 0 only (gravity); '" +
          load.name + "' is not");
    if (c.dimension != 2 || c.materials->plane() != PlaneCondition::PlaneStrain)
      throw DeckError(
          "'Exact Solution/Type' = Column Under Self-Weight is the 2D plane-strain column (Grid/Plane Condition = "
          "Plane Strain)");
    const MaterialParameters& m = c.materials->parameters(b.material);
    if (m.model == MaterialModel::DruckerPrager || m.model == MaterialModel::MohrCoulomb)
      throw DeckError(
          "'Exact Solution/Type' = Column Under Self-Weight has closed forms for the Linear Elastic, "
          "Neo-Hookean and J2 Plasticity models; the body's material is " +
          Materials::modelName(m.model));
    column_.height = b.rect.height();
    column_.density = m.density;
    column_.gravity = -load.accelerationY;
    column_.lambda = m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu));
    column_.mu = m.E / (2 * (1 + m.nu));
    column_.law = m.model == MaterialModel::NeoHookean     ? SelfWeightColumnExact::Law::NeoHookean
                  : m.model == MaterialModel::J2Plasticity ? SelfWeightColumnExact::Law::J2
                                                           : SelfWeightColumnExact::Law::Linear;
    column_.yieldStress = m.yieldStress;
    column_.hardening = m.hardening;
    modulus_ = column_.lambda + 2 * column_.mu;  // the constrained modulus M of the laterally confined column
    yMin_ = b.rect.yMin;
    time_ = load.time;
    fieldBody_ = (int)(&b - c.bodies.data());
  }
  std::string type() const override { return "Column Under Self-Weight"; }
  double value(const std::string& q, double, double y0, double t) const override {
    const double Y = y0 - yMin_, f = time_(t);
    if (q == "Displacement Y") return column_.displacementY(Y, f);
    if (q == "Stress YY") return column_.stressYY(Y, f);
    if (q == "Stress XX") return column_.stressXX(Y, f);
    return kNaN;
  }
  bool displacementAt(const double* X, double t, int dim, double* u) const override {
    for (int d = 0; d < dim; ++d) u[d] = 0.0;  // laterally confined: the column only settles
    u[1] = column_.displacementY(X[1] - yMin_, time_(t));
    return true;
  }
  const SelfWeightColumnExact& column() const { return column_; }

 private:
  SelfWeightColumnExact column_{};
  double yMin_ = 0;
  TimeFunction time_{};
};

// Wallstedt & Guilkey's axis-aligned manufactured solution (physics/ManufacturedSolution.hpp):
// every monitor quantity and the whole displacement field of its body.
class AxisAlignedManufacturedReference : public ExactReference {
 public:
  AxisAlignedManufacturedReference(const ParameterList& e, const ExactContext& c)
      : field_(axisAlignedManufactured(e, c)) {
    const BodySpec& b = exactBody(e, c);
    fieldBody_ = (int)(&b - c.bodies.data());
    modulus_ = c.materials->parameters(b.material).E;  // the time scale omega = pi sqrt(E / rho0) / L
  }
  std::string type() const override { return "Axis-Aligned Manufactured Solution"; }
  double value(const std::string& q, double x0, double y0, double t) const override {
    const double X[3] = {x0, y0, 0.0};
    return valueAt(q, X, t);
  }
  double valueAt(const std::string& q, const double* X, double t) const override {
    for (int d = 0; d < field_.dim; ++d) {
      const std::string axis(1, char('X' + d));
      if (q == "Displacement " + axis) return field_.displacement(X, t, d);
      if (q == "Velocity " + axis) return field_.velocity(X, t, d);
    }
    if (q == "Stress XX") return field_.stress(X, t, 0);
    if (q == "Stress YY") return field_.stress(X, t, 1);
    if (q == "Stress ZZ") return field_.stress(X, t, 2);
    if (q == "Stress XY" || q == "Stress YZ" || q == "Stress XZ") return 0.0;
    return kNaN;
  }
  bool displacementAt(const double* X, double t, int dim, double* u) const override {
    for (int d = 0; d < dim; ++d) u[d] = field_.displacement(X, t, d);
    return true;
  }
  void addSummary(ParameterList& s) const override {
    ParameterList& m = s.sublist("Manufactured Solution");
    m.set("Amplitude", field_.amplitude);
    m.set("Side", field_.length);
    m.set("Angular Frequency", field_.omega);
    m.set("Largest Stretch Change", 2 * AxisAlignedManufactured::kPi * field_.amplitude / field_.length);
  }

 private:
  AxisAlignedManufactured field_;
};

// The cantilever under a dead end load, quasi-static: the elastica (physics/ElasticaExact.hpp) at
// the load parameter k f(t), f the named load's time function. The beam is the body, clamped at
// its X Min, centreline at mid-height; the end load is the sum of the deck's loads, all Particle
// Forces along y near X Max sharing one time function (the end section's load may be split over
// particles placed symmetrically about the centreline). A particle at distance eta from the
// centreline moves with the plane cross-section (Euler-Bernoulli kinematics).
class CantileverEndLoad : public ExactReference {
 public:
  CantileverEndLoad(const ParameterList& e, const ExactContext& c) {
    const BodySpec& b = exactBody(e, c);
    const LoadSpec& named = exactLoad(e, c);
    const RectangularBody& r = b.rect;
    if (c.dimension != 2)
      throw DeckError("'Exact Solution/Type' = Cantilever End Load is the 2D beam (Grid/Dimension = 2)");
    double force = 0;
    for (const auto& s : c.loads) {
      if (s.type != "Particle Force" || s.forceX != 0 || s.forceY == 0 || std::abs(s.x - r.xMax) > 0.05 * r.length() ||
          s.time.kind != named.time.kind || s.time.rampTime != named.time.rampTime ||
          s.time.startTime != named.time.startTime)
        throw DeckError(
            "'Exact Solution/Type' = Cantilever End Load needs every load to be a Particle Force with Force Y "
            "only, at the free end (X near the body's X Max = " +
            formatNumber(r.xMax) + ") and with the time function of '" + named.name + "': 'Loads/" + s.name +
            "' is not");
      force += s.forceY;
    }
    bool clamped = false;
    for (const auto& s : c.constraints)
      clamped = clamped || (s.where == "Face" && s.face == "x-" && s.fixX && s.fixY && s.body.xMin == r.xMin);
    if (!clamped)
      throw DeckError(
          "'Exact Solution/Type' = Cantilever End Load needs the beam clamped at X Min: a constraint with "
          "Where = Face, Face = x-, Components = xy on 'Bodies/" +
          b.name + "'");
    modulus_ = modulusFor(e, c, b.material);
    const double I = c.width(r) * std::pow(r.height(), 3) / 12.0;
    length_ = r.length();
    xMin_ = r.xMin;
    yCentre_ = 0.5 * (r.yMin + r.yMax);
    down_ = force < 0 ? 1.0 : -1.0;
    k_ = std::abs(force) * length_ * length_ / (modulus_ * I);
    time_ = named.time;
  }
  std::string type() const override { return "Cantilever End Load"; }
  double value(const std::string& q, double x0, double y0, double t) const override {
    if (q != "Displacement X" && q != "Displacement Y") return kNaN;
    const double s = std::clamp((x0 - xMin_) / length_, 0.0, 1.0), eta = y0 - yCentre_;
    const CantileverElastica::Point p = CantileverElastica(k_ * time_(t)).at(s);
    if (q == "Displacement X") return -p.u * length_ + down_ * eta * std::sin(p.theta);
    return -down_ * p.w * length_ + eta * (std::cos(p.theta) - 1.0);
  }
  void addSummary(ParameterList& s) const override {
    const CantileverElastica::Point tip = CantileverElastica(k_).tip();
    s.set("Exact Load Parameter", k_);
    s.set("Exact Tip Displacement X", -tip.u * length_);
    s.set("Exact Tip Displacement Y", -down_ * tip.w * length_);
  }

 private:
  double k_ = 0, length_ = 1, xMin_ = 0, yCentre_ = 0, down_ = 1;
  TimeFunction time_{};
};

}  // namespace

std::unique_ptr<ExactReference> makeExactReference(const ParameterList& e, const ExactContext& c) {
  const std::string type = e.get<std::string>("Type");
  if (e.get<int>("Series Terms") <= 0)
    throw DeckError("'Exact Solution/Series Terms' must be positive, got " +
                    std::to_string(e.get<int>("Series Terms")));
  if (type == "Bar Step Load") return std::make_unique<BarStep>(e, c);
  if (type == "Bar Standing Wave") return std::make_unique<StandingWave>(e, c);
  if (type == "Simply Supported Beam") return std::make_unique<SimplySupportedBeam>(e, c);
  if (type == "Layered Bar Step Load") return std::make_unique<LayeredBar>(e, c);
  if (type == "Column Under Self-Weight") return std::make_unique<SelfWeightColumn>(e, c);
  if (type == "Axis-Aligned Manufactured Solution") return std::make_unique<AxisAlignedManufacturedReference>(e, c);
  if (type == "Cantilever End Load") return std::make_unique<CantileverEndLoad>(e, c);
  return nullptr;
}

AxisAlignedManufactured axisAlignedManufactured(const ParameterList& e, const ExactContext& c) {
  const BodySpec& b = exactBody(e, c);
  const std::string what = "'Exact Solution/Type' = Axis-Aligned Manufactured Solution";
  if (c.bodies.size() != 1)
    throw DeckError(what + " describes a single body; the deck has " + std::to_string(c.bodies.size()));
  const MaterialParameters& m = c.materials->parameters(b.material);
  if (m.model != MaterialModel::NeoHookean)
    throw DeckError(what + " is a neo-Hookean field: 'Bodies/" + b.name +
                    "' must be made of a material with Model = Neo-Hookean");
  AxisAlignedManufactured f;
  f.dim = c.dimension;
  f.length = b.rect.length();
  for (int d = 0; d < f.dim; ++d) {
    const double side = b.rect.hi(d) - b.rect.lo(d);
    if (std::abs(side - f.length) > 1e-12 * f.length)
      throw DeckError(what + " needs a square (3D: cube) body: 'Bodies/" + b.name + "' is " + formatNumber(f.length) +
                      " long in x and " + formatNumber(side) + " in " + std::string(1, char('x' + d)));
    f.origin[d] = b.rect.lo(d);
  }
  f.amplitude = e.get<double>("Amplitude");
  const double largestStrain = 2 * AxisAlignedManufactured::kPi * std::abs(f.amplitude) / f.length;
  if (!(f.amplitude > 0) || !(largestStrain < 0.5))
    throw DeckError("'Exact Solution/Amplitude' must be positive and below L / (4 pi) = " +
                    formatNumber(f.length / (4 * AxisAlignedManufactured::kPi)) +
                    " (stretches of 1 +/- 2 pi A / L within 50%), got " + formatNumber(f.amplitude));
  f.mu = m.E / (2 * (1 + m.nu));
  f.lambda = m.E * m.nu / ((1 + m.nu) * (1 - 2 * m.nu));
  f.density = m.density;
  f.omega = AxisAlignedManufactured::kPi * std::sqrt(m.E / m.density) / f.length;
  return f;
}

}  // namespace impm
