// The definitions of ImplicitNewmark<Shape, Dim>, included by the translation units that
// instantiate it (ImplicitNewmark*.cpp, a few shapes each so that they compile in parallel).
// This file holds its construction, the step's set-up and the step driver; the parts included at
// the end hold the residual and the matrix (NOX's model), the grid conditions' contributions, the
// end-of-step update and the checkpoint state.
#pragma once

#include "solvers/implicit/ImplicitNewmark.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include <chrono>
#include <cmath>
#include <sstream>

#include "core/PhaseTimer.hpp"
#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/InternalForce.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "core/kernels/Stiffness.hpp"
#include "solvers/implicit/ImplicitGridColumns.hpp"
#include "solvers/implicit/TrialInternalForce.hpp"

namespace impm {

namespace implicit {
std::string describeSolver(const Teuchos::ParameterList& p);  // ImplicitNewmark.cpp
// Nodes per direction of a stiffness block: cells (2), the seed's GIMP cells (2), Q9 elements (3),
// or the shape's stencil.
template <class Shape>
int stiffnessBlockNodes(bool seedGimpStiffness) {
  return seedGimpStiffness ? 2 : Shape::max_nodes_1d;
}
template <class Shape>
int stiffnessBlockStride() {
  return std::is_same<Shape, QuadraticLagrange>::value ? 2 : 1;
}
}  // namespace implicit

template <class Shape, int Dim>
ImplicitNewmark<Shape, Dim>::ImplicitNewmark(ParticleSet& particles, const GridDistribution& dist,
                                             const Materials& material, GridConditions& conditions,
                                             const LoadSet& loads, const ImplicitOptions& options)
    : ps_(particles),
      dist_(dist),
      mat_(material),
      conditions_(conditions),
      loads_(loads),
      opt_(options),
      projection_(dist),
      solver_(std::make_unique<NewtonSolver>(options.solverParams)),
      seedGimpStiffness_(std::is_same<Shape, UniformGimp>::value && options.seedGimpStiffness),
      assembler_(dist, implicit::stiffnessBlockNodes<Shape>(seedGimpStiffness_),
                 implicit::stiffnessBlockStride<Shape>(), options.stiffnessFill),
      refresh_(solver_->parameters().get<std::string>("Jacobian") == "Jacobian-Free",
               options.preconditionerRefreshInterval, options.preconditionerRefreshKrylov,
               options.preconditionerEveryNewton),
      control_(options.maxStepHalvings, options.adaptiveTimeStep, options.minimumTimeStep) {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  fields_ = conditions.fieldCount();
  if (fields_ > 1) {
    checkContactUsable();
    stateStride_ = SC::Count + 2 * Dim;
    geometryCol_ = SC::Count;
    dispStride_ = DC::Count;
    forceStride_ = FC::Count;
    dofs_.setFields(fields_, stateStride_, dist.grid().numNodes());
    assembler_.setFields(fields_, stateStride_);
  }
  const int stateColumns = fields_ > 1 ? fields_ * stateStride_ : SC::Count;
  stateOwned_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), stateColumns));
  stateGhosted_ = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), stateColumns));
  dispOwned_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), fields_ * DC::Count));
  dispGhosted_ = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), fields_ * DC::Count));
  forceOwned_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), fields_ * FC::Count));
  forceGhosted_ = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), fields_ * FC::Count));
  // (Linear MPM: every node a particle reaches is an unknown; see ImplicitOptions::massTolerance.)
  massCutoff_ =
      std::is_same<Shape, LinearMpm>::value ? 0.0 : opt_.massTolerance * heaviestParticleMass(ps_, *dist.comm());
  if (seedGimpStiffness_ && Dim == 3)
    throw std::invalid_argument(
        "'Integrator/Implicit/GIMP Stiffness' = Integrated (the seed's overlap integrals) is 2D only; use Consistent "
        "in 3D");
  if (opt_.fbar) {
    // (Tried: Newton on the assembled blocks at the barred state converges linearly at 0.35 per
    // iteration, and misses the tolerance within 20 iterations even in an elastic step.)
    if (!jacobianFree())
      throw std::invalid_argument(
          "'Method/Volumetric Locking' = F-bar needs 'Implicit Solver/Jacobian' = Jacobian-Free: "
          "the assembled Jacobian leaves out F-bar's coupling of the particles in a cell");
    fbar_ = std::make_unique<FbarAveraging<Dim>>(dist, mat_.count());
  }
  if (opt_.transfer != ParticleTransfer::FlipPic &&
      (opt_.fixedParticles || opt_.consistentMass || opt_.projectionIterations > 0))
    throw std::invalid_argument(
        "'Integrator/Implicit/Transfer' = APIC, TPIC or XPIC moves the particles with a "
        "lumped-mass grid: not with the FE reference, 'Mass Matrix' = Consistent or "
        "'Consistent Projection Iterations' > 0");
  if (carriesAffineVelocity(opt_.transfer)) {
    if (!ps_.hasAffine()) ps_.allocateAffine();
    endKinematics_ = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), KinColumns<Dim>::Count));
  }
  if (opt_.transfer == ParticleTransfer::Xpic)
    xpic_ = std::make_unique<XpicExtrapolation<Shape, Dim>>(dist, opt_.xpicOrder);
  if (opt_.fixedParticles) {
    gridKinematics_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), 2 * Dim));
    if (ps_.u.extent(0) != size_t(ps_.count)) ps_.u = ps_.newVector("u");
  }
}

// Multi-field contact in the implicit step takes the lumped mass, moving particles, the FLIP/PIC
// transfer and the bodies' own fields: what it does not take is refused here.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::checkContactUsable() const {
  auto refuse = [](const std::string& what) {
    throw std::invalid_argument("'Contact/Type' = Multi Field with 'Integrator/Type' = Implicit: " + what);
  };
  if (opt_.consistentMass) refuse("needs 'Integrator/Implicit/Mass Matrix' = Lumped");
  if (opt_.fixedParticles) refuse("needs material points, not the FE reference");
  if (opt_.projectionIterations > 0) refuse("needs 'Integrator/Implicit/Consistent Projection Iterations' = 0");
  if (opt_.transfer != ParticleTransfer::FlipPic) refuse("needs 'Integrator/Implicit/Transfer' = FLIP/PIC");
  if (opt_.fbar) refuse("does not take 'Method/Volumetric Locking' = F-bar");
  if (!opt_.equilibriumAcceleration) refuse("needs 'Integrator/Implicit/Grid Acceleration' = Equilibrium");
}

template <class Shape, int Dim>
template <class F>
void ImplicitNewmark<Shape, Dim>::withFields(int stride, const F& f) const {
  if (fields_ > 1)
    f(FieldColumns(ps_, conditions_.fieldOfBody(), stride));
  else
    f(SingleField());
}

template <class Shape, int Dim>
ImplicitNewmark<Shape, Dim>::~ImplicitNewmark() = default;

template <class Shape, int Dim>
bool ImplicitNewmark<Shape, Dim>::jacobianFree() const {
  return solver_->parameters().get<std::string>("Jacobian") == "Jacobian-Free";
}

template <class Shape, int Dim>
std::string ImplicitNewmark<Shape, Dim>::name() const {
  const std::string method = opt_.fixedParticles ? (Dim == 3 ? (Shape::max_nodes_1d == 3 ? "FE Hex27" : "FE Hex8")
                                                             : (Shape::max_nodes_1d == 3 ? "FE Q9" : "FE Q4"))
                                                 : Shape::name;
  std::string scheme = "Newmark";
  if (!opt_.newmark.averageAcceleration()) {
    std::ostringstream os;
    os << "Newmark beta " << opt_.newmark.beta << " gamma " << opt_.newmark.gamma;
    scheme = os.str();
  }
  return std::string("implicit ") + method + " " + scheme + " (" + implicit::describeSolver(solver_->parameters()) +
         ")";
}

// ---- The step's set-up ------------------------------------------------------------------------

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::setUpStep(double t, double dt) {
  using SC = implicit::StateColumns<Dim>;
  PhaseTimer phase("implicit step set-up (p2g)");
  dt_ = dt;
  conditions_.setStep(t, dt);
  const StructuredGrid& g = dist_.grid();
  // Particles to grid at t: mass, momentum, m a; particle forces at t + dt.
  stateGhosted_->putScalar(0.0);
  {
    auto grid = stateGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    withFields(stateStride_, [&](const auto& columns) {
      particleToGridMassMomentum<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, grid, SC::Mass, SC::VelX, SC::AccX,
                                                   geometryCol_, columns, carriesAffineVelocity(opt_.transfer));
      loads_.template scatterParticleForces<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, grid, SC::FextX, t + dt,
                                                              columns);
    });
  }
  stateOwned_->putScalar(0.0);
  stateOwned_->doExport(*stateGhosted_, *dist_.importer(), Tpetra::ADD);

  // Consistent initial acceleration: a(0) = M^-1 (F_ext(0) + F_int(0)) (F_int as force on nodes).
  // With Grid Acceleration = Equilibrium the lumped grid takes a(t) that way at every step.
  const bool initialAcceleration = firstStep_ && opt_.consistentInitialAcceleration;
  const bool accelerationFromForces = initialAcceleration || equilibriumAcceleration();
  if (accelerationFromForces) forcesAtStart(t);
  firstStep_ = false;
  startKinematics(initialAcceleration);
  normalizeGridState(t, dt, accelerationFromForces);
  stateGhosted_->doImport(*stateOwned_, *dist_.importer(), Tpetra::INSERT);
  if (initialAcceleration && opt_.consistentMass) {
    // The particles start from the grid's consistent acceleration (their own Newmark update
    // needs a_p(0)).
    auto sgv = stateGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    interpolateToParticles<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, sgv, SC::AccX, ps_.a, 1.0, false);
  }
  PCurrent_ = false;
  if (dofs_.update(*stateOwned_, SC::FreeX)) assembler_.forgetMatrix();
}

// F_int + F_ext at t on the owned nodes (force column), for a(t) = M^-1 (F_ext + F_int).
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::forcesAtStart(double t) {
  using FC = implicit::ForceColumns<Dim>;
  const StructuredGrid& g = dist_.grid();
  forceGhosted_->putScalar(0.0);
  {
    auto f = forceGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    withFields(forceStride_, [&](const auto& columns) {
      accumulateInternalForce<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, ps_.stress, f, FC::ForceX, columns);
      loads_.template scatterParticleForces<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, f, FC::ForceX, t,
                                                              columns);
    });
  }
  forceOwned_->putScalar(0.0);
  forceOwned_->doExport(*forceGhosted_, *dist_.importer(), Tpetra::ADD);
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
  loads_.template applyNodal<Exec>(f, FC::ForceX, t);
}

// Fixed particles (FE reference), lumped mass: the grid keeps its own v and a from the last
// step (a projection from the Gauss points would smooth them by M_L^-1 M_C). With the
// consistent mass the projection M_C v = sum_p m_p S_ip v_p is already exact. Moving particles
// with the lumped mass: the projection correction (when asked for).
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::startKinematics(bool initialAcceleration) {
  using SC = implicit::StateColumns<Dim>;
  const bool gridCarriesState = opt_.fixedParticles && !opt_.consistentMass && !initialAcceleration;
  if (gridCarriesState) {
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto k = gridKinematics_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    Kokkos::parallel_for(
        "grid_state_from_last_step", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
          const double m = s(n, SC::Mass);
          for (int d = 0; d < Dim; ++d) {
            s(n, SC::VelX + d) = m * k(n, d);
            s(n, SC::AccX + d) = m * k(n, Dim + d);
          }
        });
  } else if (!initialAcceleration && !opt_.consistentMass) {
    // (The consistent-mass residual works on the particle momentum sums themselves: it needs
    // no projection correction, and with one the particles were seen to leave the grid.)
    correctProjection();
  }
}

// v = p / m and a = (m a) / m or F / m on nodes with mass (zero elsewhere), F_ext at t + dt, the
// free flags; then the grid conditions: their dofs start the step with the prescribed motion and
// are not unknowns.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::normalizeGridState(double t, double dt, bool accelerationFromForces) {
  using SC = implicit::StateColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
  loads_.template applyNodal<Exec>(s, SC::FextX, t + dt);
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const double cutoff = massCutoff_;
  const int fields = fields_, ss = stateStride_, fs = forceStride_;
  Kokkos::parallel_for(
      "implicit_grid_state", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
        for (int b = 0; b < fields; ++b) {
          const int o = b * ss, q = b * fs;
          const double m = s(n, o + SC::Mass);
          const bool massive = m > cutoff;
          for (int d = 0; d < Dim; ++d) {
            s(n, o + SC::VelX + d) = massive ? s(n, o + SC::VelX + d) / m : 0.0;
            s(n, o + SC::AccX + d) =
                massive ? (accelerationFromForces ? f(n, q + FC::ForceX + d) / m : s(n, o + SC::AccX + d) / m) : 0.0;
            s(n, o + SC::FreeX + d) = massive ? 1.0 : 0.0;
          }
        }
      });
  conditions_.template write<Exec>(s, SC::VelX, PrescribedField::StartVelocity, ss);
  conditions_.template write<Exec>(s, SC::AccX, PrescribedField::StartAcceleration, ss);
  conditions_.template write<Exec>(s, SC::FreeX, PrescribedField::Zero, ss);
  if (conditions_.hasWalls()) {
    conditions_.implicitWalls().template hold<Exec>(s, SC::Mass, SC::VelX, SC::AccX, SC::FreeX, cutoff, dt, ss);
  }
  forEachRigidDof(
      s, KOKKOS_LAMBDA(int n, int f, int c, const RigidFieldMotion& rigid) {
        s(n, f * ss + SC::VelX + c) = rigid.start(f, c);
        s(n, f * ss + SC::AccX + c) = rigid.acceleration(f, c);
        s(n, f * ss + SC::FreeX + c) = 0.0;
      });
}

// The lumped projection v_i = sum m_p S_ip v_p / m_i smooths the grid state every step (by
// M_L^-1 M_C), so that the grid does not carry on exactly from the Newmark update of the last
// step. Jacobi iterations towards the consistent projection remove that to O((kh)^4).
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::correctProjection() {
  using SC = implicit::StateColumns<Dim>;
  if (opt_.projectionIterations <= 0) return;
  projection_.apply(*stateOwned_, SC::Mass, SC::VelX, ps_, ps_.v, conditions_, PrescribedField::StartVelocity,
                    massCutoff_, opt_.projectionIterations);
  projection_.apply(*stateOwned_, SC::Mass, SC::AccX, ps_, ps_.a, conditions_, PrescribedField::StartAcceleration,
                    massCutoff_, opt_.projectionIterations);
}

// ---- Driving the step -------------------------------------------------------------------------

template <class Shape, int Dim>
StepControl::Outcome ImplicitNewmark<Shape, Dim>::solveStep(double t, double dt) {
  using clock = std::chrono::steady_clock;
  auto t0 = clock::now();
  if (conditions_.hasWalls()) conditions_.implicitWalls().beginStep();  // (and keeps the set for a retry)
  if (fields_ > 1) conditions_.keepImplicitContactStates(dist_.ownedNodeMap()->getNodeNumElements());
  setUpStep(t, dt);
  // With walls, the solve is repeated until the held wall components settle (at most
  // ImplicitWallContact::maxSolves() solves; the last one stands); with contact, until its active
  // set settles (at most kMaxContactSolves).
  Teuchos::RCP<Vector> u;
  NewtonResult result;
  auto t2 = t0;
  for (int solve = 1;; ++solve) {
    u = Teuchos::rcp(new Vector(dofs_.map(), true));
    const auto t1 = clock::now();
    result = [&] {
      PhaseTimer phase("Newton solve (NOX)");
      return solver_->solve(*this, *u);
    }();
    t2 = clock::now();
    statistics_.recordAttempt(result, std::chrono::duration<double>(t1 - t0).count(),
                              std::chrono::duration<double>(t2 - t1).count());
    if (!result.converged) {
      if (fields_ > 1) conditions_.restoreImplicitContactStates();
      if (conditions_.hasWalls()) conditions_.implicitWalls().restore();
      return {false, result.newtonIterations, result.reason};
    }
    t0 = clock::now();
    const bool contactChanged = fields_ > 1 && solve < kMaxContactSolves && reviseContactStates(*u);
    const bool wallsChanged =
        conditions_.hasWalls() && solve < ImplicitWallContact::maxSolves() && reviseWallContacts(*u);
    if (!contactChanged && !wallsChanged) break;
    contactResolves_ += contactChanged;
    wallResolves_ += wallsChanged;
  }
  finishStep(*u);
  statistics_.recordStep(result, std::chrono::duration<double>(clock::now() - t2).count());
  refresh_.noteKrylovIterations(result.krylovIterations);
  return {true, result.newtonIterations, ""};
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::step(double t, double dt) {
  control_.step(t, dt, [this](double ts, double h) { return solveStep(ts, h); });
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::addStatistics(Teuchos::ParameterList& summary) const {
  Teuchos::ParameterList& s = summary.sublist("Solver");
  statistics_.addIterations(s);
  control_.addHalvings(s);
  s.set("Stiffness Assemblies", (int)refresh_.jacobianVersion());
  statistics_.addHardestStep(s);
  control_.addAdaptive(s);
  statistics_.addCosts(s);
  if (fields_ > 1) s.set("Contact Re-solves", int(contactResolves_));
  if (conditions_.hasWalls()) s.set("Wall Re-solves", int(wallResolves_));
  s.set("Configuration", implicit::describeSolver(solver_->parameters()));
}

}  // namespace impm

#include "solvers/implicit/ImplicitNewmarkCheckpoint.hpp"
#include "solvers/implicit/ImplicitNewmarkConditions.hpp"
#include "solvers/implicit/ImplicitNewmarkResidual.hpp"
#include "solvers/implicit/ImplicitNewmarkUpdate.hpp"
