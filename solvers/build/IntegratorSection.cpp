// Deck sections Integrator and Initial Conditions: the time step, the explicit or implicit
// integrator for the shape function, and the particles' initial state.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/Collective.hpp"
#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

#include <algorithm>
#include <cmath>

#include "physics/InitialConditions.hpp"
#include "solvers/ExplicitStepper.hpp"
#include "solvers/implicit/ImplicitNewmark.hpp"

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

void addIntegratorSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist("Integrator", false, "time integration");
  choice(p, "Type", "Explicit", {"Explicit", "Implicit"},
         "Explicit: USF/USL/MUSL; Implicit: Newmark average acceleration solved by Newton (see Implicit Solver)");
  number(p, "Time Step", 1.0e-8, "dt (s)");
  p.set("Number of Steps", 100, "number of time steps");
  ParameterList& e = p.sublist("Explicit", false, "explicit integrator options");
  choice(e, "Update Scheme", "USL", {"USF", "USL", "MUSL"}, "when the stress is updated");
  number(e, "FLIP Fraction", 1.0, "particle velocity update: 1 = FLIP, 0 = PIC, between = blend");
  choice(e, "Transfer", "FLIP/PIC", {"FLIP/PIC", "APIC", "TPIC", "XPIC"},
         "particle-grid transfer. FLIP/PIC: the FLIP Fraction blend; APIC (affine PIC, Jiang et al. 2015): each "
         "particle carries an affine velocity v_p + C_p (x - x_p) to the grid and takes back the PIC velocity and "
         "C_p = B_p D_p^-1, which conserves angular momentum; TPIC (Taylor PIC, Nakamura et al. 2023): the same "
         "with C_p = the grid velocity gradient at the particle. Both keep an affine velocity field exactly and "
         "damp far less than PIC. XPIC (Hammerquist & Nairn 2017): FLIP's update from an old velocity "
         "extrapolated on the grid to order XPIC Order, which removes FLIP's null-space noise (order 1 = PIC); one "
         "velocity field. Explicit integrator only, with FLIP Fraction 1 (not used) and Consistent Projection "
         "Iterations 0");
  e.set("XPIC Order", 5,
        "Transfer XPIC: the order m of XPIC(m), 1 to 40 (1 = PIC; each order above 1 costs one "
        "more pass over the particles)");
  number(e, "Mass Damping", 0.0,
         "mass-proportional damping c (1/s): each grid node's acceleration gets -c v_i (a force -c m_i v_i), for "
         "dynamic relaxation to a quasi-static state; a mode of angular frequency omega is critically damped at "
         "c = 2 omega, higher modes less (0: none, the scheme conserves energy)");
  e.set("Consistent Projection Iterations", 0,
        "Jacobi iterations towards the consistent-mass projection of particle momentum to grid velocity; "
        "0 = the classic lumped projection p/m, which smooths the velocity field by M_L^-1 M_C every step "
        "and about triples the lumped-mass wave dispersion; 1 removes that to O((kh)^4)");
  number(e, "Stability Factor", 1.0,
         "dt must not exceed this factor times 0.7 / (P-wave speed sqrt(1/hx^2 + 1/hy^2)): the critical step of "
         "lumped bilinear cells, times the smallest critical fraction measured over every transfer scheme "
         "(apps/stability_study.py) with a margin; above 1 a warning (the run may diverge)");
  ParameterList& im = p.sublist("Implicit", false, "implicit integrator options");
  im.set("Maximum Step Halvings", 4,
         "a step whose Newton iteration fails is retried with dt/2, dt/4, ... this many times");
  im.set("Consistent Projection Iterations", 0,
         "Jacobi iterations towards the consistent-mass projection of particle velocity and acceleration to "
         "the grid (0: lumped projection; see Integrator/Explicit); not used with Mass Matrix: Consistent, "
         "whose residual needs no projection");
  im.set("Preconditioner Refresh Interval", 1,
         "steps between numeric refactorisations of the Ifpack2 preconditioner (1: every step); its factors "
         "of a slightly older P remain a good preconditioner while the particles move little");
  im.set("Preconditioner Refresh GMRES Threshold", 0,
         "also rebuild the preconditioner at the step after one whose mean GMRES iterations per Newton "
         "iteration exceeded this (0: off)");
  im.set("Preconditioner At Every Newton Iteration", false,
         "Jacobian-Free with finite-strain materials: rebuild the preconditioner at every Newton iterate from the "
         "tangent at the trial state (material and geometric), instead of once per step");
  choice(im, "Mass Matrix", "Lumped", {"Lumped", "Consistent"},
         "Lumped: Guilkey & Weiss; Consistent: R uses M_C u and particles take their own Newmark update, "
         "which conserves the particles' energy (P then holds the consistent mass too, except with GIMP Stiffness = "
         "Integrated)");
  choice(im, "GIMP Stiffness", "Consistent", {"Integrated", "Consistent"},
         "GIMP's assembled stiffness (preconditioner, or Jacobian of Assembled Newton): Consistent = V_p B^T D B "
         "with the averaged gradients, the exact derivative of the GIMP internal force (Newton converges "
         "quadratically, GMRES in a few iterations); Integrated = the seed's D int_Omega_p B^T B, exact per "
         "particle-cell overlap but not the derivative of the GIMP force: once particles straddle cell lines "
         "GMRES stalls (about 200 iterations per Newton step on a padded cantilever, against a few with "
         "Consistent). Worth it "
         "only to reproduce the seed");
  choice(im, "Grid Acceleration", "Equilibrium", {"Equilibrium", "Projected"},
         "Lumped mass only. Equilibrium: each step starts from a_i = (F_ext + F_int)_i / m_i and the particles "
         "take the grid's velocity increment dt/2 (a_i + a_i,new); Projected: a_i projected from the "
         "particles' accelerations, v_p += dt/2 (a_p + a_p,new) (Guilkey & Weiss 2003), whose acceleration "
         "error grows at omega dt >> 1 (11 times the static stress after 40 large steps of a step load)");
  choice(im, "Transfer", "FLIP", {"FLIP", "APIC", "TPIC", "XPIC"},
         "particle velocity update. FLIP: by the grid's velocity increment (Equilibrium) or the particle's own "
         "Newmark rule (Projected); APIC, TPIC: the particles take the grid velocity at t + dt and its affine part "
         "C_p, and carry it to the grid; XPIC: FLIP's update from the XPIC(XPIC Order) velocity (see "
         "Integrator/Explicit/Transfer). APIC, TPIC and XPIC need the lumped mass, no projection correction and "
         "moving particles (not the FE reference)");
  im.set("XPIC Order", 5, "Transfer XPIC: the order m of XPIC(m), 1 to 40 (1 = PIC)");
  im.set("Adaptive Time Step", false,
         "sub-step each deck step adaptively on the Newton iteration count (after Uintah's ImpMPM): a sub-step "
         "that took more than 12 Newton iterations shrinks the next by 0.6, one that took fewer than 4 doubles it "
         "(never beyond the deck's Time Step), and a failed one is retried at half its size, down to Minimum Time "
         "Step. history.csv and the VTU files stay on the deck's steps");
  number(im, "Minimum Time Step", 0.0,
         "Adaptive Time Step: the smallest sub-step before the run stops (0: the deck's Time Step / 2^Maximum Step "
         "Halvings)");
  im.set("Consistent Initial Acceleration", true,
         "start from a(0) = M^-1 (F_ext(0) + F_int(0)) instead of zero particle accelerations");
  number(im, "Newmark Beta", 0.25,
         "beta of the Newmark scheme on the grid, u = dt v + dt^2 ((1/2 - beta) a + beta a_new); with gamma "
         "unconditionally stable when 2 beta >= gamma >= 1/2. 1/4 with gamma = 1/2: average acceleration, no "
         "numerical damping; gamma > 1/2 with beta = (gamma + 1/2)^2 / 4 damps the highest frequencies most "
         "(per step by |gamma - 3/2| / (gamma + 1/2) at omega dt -> infinity)");
  number(im, "Newmark Gamma", 0.5, "gamma of the Newmark scheme, v_new = v + dt ((1 - gamma) a + gamma a_new)");
}

void addInitialConditionsSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist("Initial Conditions", false, "initial particle state (default: at rest)");
  choice(p, "Type", "None", {"None", "Standing Wave", "Manufactured Solution"},
         "None: particles at rest; Standing Wave: zero displacement and v_x(X, 0) = Amplitude sin(Mode pi "
         "(X - X Min) / L), L = the body's length (one mode of a bar fixed at both ends); Manufactured Solution: "
         "zero displacement and the velocity of the deck's manufactured solution at t = 0 (Exact Solution/Type = "
         "Axis-Aligned Manufactured Solution)");
  number(p, "Amplitude", 0.0, "velocity amplitude V of the Standing Wave (m/s), non-zero");
  p.set("Mode", 1, "mode number n >= 1 of the Standing Wave (n half-waves along the body)");
}

void Simulation::readTime() {
  const ParameterList& in = deck_.sublist("Integrator");
  dt_ = positive(in, "Integrator", "Time Step");
  steps_ = positiveInt(in, "Integrator", "Number of Steps");
}

// Initial conditions, before the integrators (an implicit one computes a(0) from this state).
// The standing wave is one mode of the first body (or Exact Solution/Body).
void Simulation::applyInitialConditions() {
  const ParameterList& ic = deck_.sublist("Initial Conditions");
  const std::string icType = ic.get<std::string>("Type");
  if ((icType == "Manufactured Solution") != (manufactured_ != nullptr))
    throw DeckError(
        manufactured_ ? "'Initial Conditions/Type' must be Manufactured Solution with 'Exact Solution/Type' = "
                        "Axis-Aligned Manufactured Solution (the particles start on the solution), got " +
                            icType
                      : "'Initial Conditions/Type' = Manufactured Solution needs 'Exact Solution/Type' = Axis-Aligned "
                        "Manufactured Solution (the field it starts from)");
  if (manufactured_) applyManufacturedVelocity(particles_, *manufactured_);
  const double icAmplitude = ic.get<double>("Amplitude");
  const int icMode = ic.get<int>("Mode");
  if (icType == "Standing Wave") {
    if (!(icAmplitude != 0.0 && std::isfinite(icAmplitude)))
      throw DeckError(
          "'Initial Conditions/Amplitude' must be a non-zero velocity amplitude for Type = Standing Wave, got " +
          formatNumber(icAmplitude));
    if (icMode < 1)
      throw DeckError("'Initial Conditions/Mode' must be at least 1 for Type = Standing Wave, got " +
                      std::to_string(icMode));
    const BodySpec& b = bodyNamed("Exact Solution/Body", deck_.sublist("Exact Solution").get<std::string>("Body"));
    if (!b.rectangle)
      throw DeckError("'Initial Conditions/Type' = Standing Wave needs a Rectangle body: 'Bodies/" + b.name +
                      "' is not one");
    if (bodies_.size() > 1)
      throw DeckError("'Initial Conditions/Type' = Standing Wave is one mode of a single bar: the deck has " +
                      std::to_string(bodies_.size()) + " bodies");
    applyStandingWaveVelocity(particles_, b.rect.xMin, b.rect.length(), icAmplitude, icMode);
  }
}

// Integrator/Explicit/Transfer. APIC, TPIC and XPIC replace the FLIP Fraction blend, carry no
// projection correction (it corrects v_p alone) and are wired into the explicit stepper only.
static void readTransfer(ExplicitOptions& eopt, const ParameterList& ex, bool explicitRun) {
  const std::string transfer = ex.get<std::string>("Transfer");
  eopt.transfer = transfer == "APIC"   ? ParticleTransfer::Apic
                  : transfer == "TPIC" ? ParticleTransfer::Tpic
                  : transfer == "XPIC" ? ParticleTransfer::Xpic
                                       : ParticleTransfer::FlipPic;
  eopt.xpicOrder = ex.get<int>("XPIC Order");
  if (eopt.transfer == ParticleTransfer::FlipPic) return;
  const std::string key = "'Integrator/Explicit/Transfer' = " + transfer;
  // NairnMPM's documentation finds XPIC(m) above about 40 unstable: the alternating binomial
  // series loses its digits.
  if (eopt.transfer == ParticleTransfer::Xpic && (eopt.xpicOrder < 1 || eopt.xpicOrder > 40))
    throw DeckError("'Integrator/Explicit/XPIC Order' must lie in [1, 40], got " + std::to_string(eopt.xpicOrder));
  if (!explicitRun)
    throw DeckError(key +
                    " is the explicit integrator's transfer: with 'Integrator/Type' = Implicit set "
                    "'Integrator/Implicit/Transfer' (FLIP, APIC or TPIC)");
  if (eopt.projectionIterations > 0)
    throw DeckError(key +
                    " needs 'Integrator/Explicit/Consistent Projection Iterations' = 0 (the projection correction " +
                    (eopt.transfer == ParticleTransfer::Xpic ? "and XPIC both filter v_p"
                                                             : "corrects v_p, not the affine velocity") +
                    "), got " + std::to_string(eopt.projectionIterations));
  if (eopt.flip != 1.0)
    throw DeckError(key +
                    " sets the particle velocity itself: leave 'Integrator/Explicit/FLIP Fraction' at 1 (it "
                    "blends FLIP and PIC with Transfer FLIP/PIC), got " +
                    formatNumber(eopt.flip));
}

// Integrator/Explicit: the update scheme and its options, and the stable time step (checked for an
// explicit run; criticalStep_ is the explicit run's).
ExplicitOptions Simulation::readExplicitOptions(bool explicitRun) {
  const ParameterList& ex = deck_.sublist("Integrator").sublist("Explicit");
  const std::string integratorType = explicitRun ? "Explicit" : "Implicit";
  ExplicitOptions eopt;
  const std::string s = ex.get<std::string>("Update Scheme");
  eopt.scheme = s == "USF" ? ExplicitScheme::USF : s == "MUSL" ? ExplicitScheme::MUSL : ExplicitScheme::USL;
  settings_.updateSchemeUsl = eopt.scheme == ExplicitScheme::USL;
  eopt.flip = ex.get<double>("FLIP Fraction");
  eopt.fbar = fbar_;
  eopt.projectionIterations = ex.get<int>("Consistent Projection Iterations");
  if (eopt.projectionIterations < 0)
    throw DeckError("'Integrator/Explicit/Consistent Projection Iterations' must not be negative");
  eopt.massDamping = ex.get<double>("Mass Damping");
  if (!(eopt.massDamping >= 0) || !std::isfinite(eopt.massDamping))
    throw DeckError("'Integrator/Explicit/Mass Damping' must be finite and not negative, got " +
                    formatNumber(eopt.massDamping));
  if (!(eopt.flip >= 0 && eopt.flip <= 1))
    throw DeckError("'Integrator/Explicit/FLIP Fraction' must lie in [0, 1], got " + formatNumber(eopt.flip));
  readTransfer(eopt, ex, explicitRun);
  const double factor = positive(ex, "Integrator/Explicit", "Stability Factor");
  settings_.stabilityFactor = factor;
  // kTransferStabilityFraction x the critical step of lumped bilinear cells (ExplicitStepper.hpp);
  // c_p: the fastest material's. A factor above 1 leaves the measured stable range: allowed for
  // stability studies, with a warning, and the run's divergence guard stops a run that blows up.
  const double cp = materials_.maxPWaveSpeed();
  const double inverseSquares =
      1.0 / (grid_.hx * grid_.hx) + 1.0 / (grid_.hy * grid_.hy) + (grid_.dim == 3 ? 1.0 / (grid_.hz * grid_.hz) : 0.0);
  const double critical = kTransferStabilityFraction / (cp * std::sqrt(inverseSquares));
  const double limit = factor * critical;
  if (integratorType == "Explicit") criticalStep_ = critical;
  if (integratorType == "Explicit" && dt_ > limit)
    throw DeckError("'Integrator/Time Step' = " + formatNumber(dt_) + " exceeds the explicit stable limit " +
                    formatNumber(limit) + " (Stability Factor x " + formatNumber(kTransferStabilityFraction) +
                    (grid_.dim == 3 ? " / (P-wave speed x sqrt(1/hx^2 + 1/hy^2 + 1/hz^2)), P-wave speed "
                                    : " / (P-wave speed x sqrt(1/hx^2 + 1/hy^2)), P-wave speed ") +
                    formatNumber(cp) + " m/s)");
  if (integratorType == "Explicit" && factor > 1.0 && comm_->getRank() == 0)
    std::cerr << "impm: warning: 'Integrator/Explicit/Stability Factor' = " << formatNumber(factor)
              << " is above 1, beyond the measured stable limit of the particle transfers; the run may diverge\n";
  return eopt;
}

// Integrator/Implicit/Transfer: APIC, TPIC and XPIC move the particles with the lumped-mass grid's
// velocity; the FE reference's Gauss points do not move, the consistent mass and the projection
// correction act on v_p alone.
static void readImplicitTransfer(ImplicitOptions& iopt, const ParameterList& im) {
  const std::string transfer = im.get<std::string>("Transfer");
  iopt.transfer = transfer == "APIC"   ? ParticleTransfer::Apic
                  : transfer == "TPIC" ? ParticleTransfer::Tpic
                  : transfer == "XPIC" ? ParticleTransfer::Xpic
                                       : ParticleTransfer::FlipPic;
  iopt.xpicOrder = im.get<int>("XPIC Order");
  if (iopt.transfer == ParticleTransfer::FlipPic) return;
  const std::string key = "'Integrator/Implicit/Transfer' = " + transfer;
  if (iopt.transfer == ParticleTransfer::Xpic && (iopt.xpicOrder < 1 || iopt.xpicOrder > 40))
    throw DeckError("'Integrator/Implicit/XPIC Order' must lie in [1, 40], got " + std::to_string(iopt.xpicOrder));
  if (iopt.fixedParticles)
    throw DeckError(key +
                    " moves the particles: the FE reference ('Method/Shape Function' = FE ...) keeps its Gauss "
                    "points in place; use Transfer FLIP");
  if (iopt.consistentMass) throw DeckError(key + " needs 'Integrator/Implicit/Mass Matrix' = Lumped");
  if (iopt.projectionIterations > 0)
    throw DeckError(key +
                    " needs 'Integrator/Implicit/Consistent Projection Iterations' = 0 (the projection "
                    "correction acts on v_p alone), got " +
                    std::to_string(iopt.projectionIterations));
}

// Integrator/Implicit: the Newmark scheme, the step control and the preconditioner refresh.
ImplicitOptions Simulation::readImplicitOptions(bool fe) const {
  const ParameterList& im = deck_.sublist("Integrator").sublist("Implicit");
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
  iopt.fbar = fbar_;
  iopt.contactPenalty = deck_.sublist("Contact").get<double>("Implicit Penalty");
  for (const BodySpec& body : bodies_)  // a rigid body's material gives it mass only
    if (!body.rigid) iopt.contactWaveSpeed = std::max(iopt.contactWaveSpeed, materials_.pWaveSpeed(body.material));
  readImplicitTransfer(iopt, im);
  iopt.newmark.beta = im.get<double>("Newmark Beta");
  iopt.newmark.gamma = im.get<double>("Newmark Gamma");
  if (!(iopt.newmark.gamma >= 0.5 && 2 * iopt.newmark.beta >= iopt.newmark.gamma && iopt.newmark.beta <= 1.0))
    throw DeckError("'Integrator/Implicit/Newmark Beta' = " + formatNumber(iopt.newmark.beta) +
                    " and 'Newmark Gamma' = " + formatNumber(iopt.newmark.gamma) +
                    ": the implicit integrator needs an unconditionally stable Newmark scheme, 2 beta >= gamma >= 1/2 "
                    "(and beta <= 1)");
  iopt.adaptiveTimeStep = im.get<bool>("Adaptive Time Step");
  iopt.minimumTimeStep = im.get<double>("Minimum Time Step");
  if (!(iopt.minimumTimeStep >= 0))
    throw DeckError("'Integrator/Implicit/Minimum Time Step' must not be negative, got " +
                    formatNumber(iopt.minimumTimeStep));
  if (iopt.minimumTimeStep > dt_)
    throw DeckError("'Integrator/Implicit/Minimum Time Step' = " + formatNumber(iopt.minimumTimeStep) +
                    " s exceeds 'Integrator/Time Step' = " + formatNumber(dt_) + " s");
  if (iopt.preconditionerRefreshInterval < 1)
    throw DeckError("'Integrator/Implicit/Preconditioner Refresh Interval' must be at least 1");
  if (iopt.projectionIterations < 0)
    throw DeckError("'Integrator/Implicit/Consistent Projection Iterations' must not be negative");
  iopt.solverParams = Teuchos::rcp(new ParameterList(deck_.sublist("Implicit Solver")));
  // Contact's penalty kinks the residual where bodies meet or start to slip: a line search unless
  // the deck chose otherwise.
  ParameterList& solver = *iopt.solverParams;
  if (deck_.sublist("Contact").get<std::string>("Type") == "Multi Field" &&
      (!solver.isParameter("Line Search") || solver.getEntry("Line Search").isDefault()))
    solver.set("Line Search", "Backtrack");
  return iopt;
}

// The integrator for the shape function (its type from the registry, core/ShapeRegistry.hpp) and
// the dimension. Solver options are checked whatever the integrator, so that a bad one never
// waits for a later implicit run to be found.
void Simulation::buildIntegrator() {
  const std::string integratorType = deck_.sublist("Integrator").get<std::string>("Type");
  const ExplicitOptions eopt = readExplicitOptions(integratorType == "Explicit");
  const bool fe = shapeInfo(shape_).fixedParticles;
  if (fe && integratorType != "Implicit")
    throw DeckError("'Method/Shape Function' = " + shape_ + " runs with 'Integrator/Type' = Implicit only, got " +
                    integratorType);
  if (integratorType != "Implicit") {
    try {
      NewtonSolver check(Teuchos::rcp(new ParameterList(deck_.sublist("Implicit Solver"))));
    } catch (const std::invalid_argument& e) {
      throw DeckError(e.what());
    }
  }
  explicitOptions_ = std::make_shared<const ExplicitOptions>(eopt);
  if (integratorType == "Implicit") implicitOptions_ = std::make_shared<const ImplicitOptions>(readImplicitOptions(fe));
  const bool affine = integratorType == "Explicit" ? carriesAffineVelocity(eopt.transfer)
                                                   : carriesAffineVelocity(implicitOptions_->transfer);
  if (affine) {
    // Before a restart reads the checkpoint: its rows carry C_p.
    particles_.allocateAffine();
    setRotationAffineVelocity(particles_, bodies_);
  }
  makeIntegrator();
}

// The integrator from the options read once (buildIntegrator), on the current distribution: also
// after a load balance, which replaces the maps, conditions and loads it refers to.
void Simulation::makeIntegrator() {
  if (implicitOptions_) {
    ImplicitOptions iopt = *implicitOptions_;
    // The solver validates its list in place: each integrator gets its own copy of the deck's.
    iopt.solverParams = Teuchos::rcp(new ParameterList(*implicitOptions_->solverParams));
    // The shape's type from the registry (core/ShapeRegistry.hpp), then the dimension.
    auto implicitOf = [&](auto dimension) -> std::unique_ptr<Integrator> {
      constexpr int Dim = decltype(dimension)::value;
      return visitShape(shape_, [&](auto shape, const ShapeInfo&) -> std::unique_ptr<Integrator> {
        using Shape = typename decltype(shape)::type;
        return std::make_unique<ImplicitNewmark<Shape, Dim>>(particles_, *dist_, materials_, constraints_, loads_,
                                                             iopt);
      });
    };
    try {
      integrator_ =
          grid_.dim == 3 ? implicitOf(std::integral_constant<int, 3>{}) : implicitOf(std::integral_constant<int, 2>{});
    } catch (const std::invalid_argument& e) {
      throw DeckError(e.what());
    }
  } else {
    const ExplicitOptions& eopt = *explicitOptions_;
    auto explicitOf = [&](auto dimension) -> std::unique_ptr<Integrator> {
      constexpr int Dim = decltype(dimension)::value;
      return visitShape(shape_, [&](auto shape, const ShapeInfo&) -> std::unique_ptr<Integrator> {
        using Shape = typename decltype(shape)::type;
        if constexpr (std::is_same_v<Shape, QuadraticLagrange>) {
          return nullptr;  // (FE Q9 is implicit only: refused above)
        } else {
          return std::make_unique<ExplicitStepper<Shape, Dim>>(particles_, *dist_, materials_, constraints_, loads_,
                                                               eopt);
        }
      });
    };
    try {  // the stepper's refusals name the deck key they concern: bad input, exit 2
      integrator_ =
          grid_.dim == 3 ? explicitOf(std::integral_constant<int, 3>{}) : explicitOf(std::integral_constant<int, 2>{});
    } catch (const std::invalid_argument& e) {
      throw DeckError(e.what());
    }
  }
}

}  // namespace impm
