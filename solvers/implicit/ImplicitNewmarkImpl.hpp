// The definitions of ImplicitNewmark<Shape, Dim>, included by the translation units that
// instantiate it (ImplicitNewmark*.cpp, a few shapes each so that they compile in parallel).
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
    const size_t owned = dist.ownedNodeMap()->getNodeNumElements();
    contactVelocity_ = decltype(contactVelocity_)("contact_velocity", owned, fields_ * Dim);
    contactVelocityBefore_ = decltype(contactVelocity_)("contact_velocity_before", owned, fields_ * Dim);
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
  if (conditions_.hasWalls()) refuse("does not take Walls (a wall is a Rigid body in the explicit step)");
  if (conditions_.contact().hasRigid()) refuse("does not take Rigid bodies (they need the explicit integrator)");
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
    const ImplicitWallContact& walls = conditions_.implicitWalls();
    walls.template keepLoads<Exec>(s, SC::FextX);
    walls.template hold<Exec>(s, SC::Mass, SC::VelX, SC::AccX, SC::FreeX, cutoff, dt);
  }
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

// The contact force in the residual: a penalty on the contact law's correction of the trial state.
// At u, each field's end velocity v_new(u) (Newmark) goes through the contact law, which returns
// v* (approach removed, slip reduced by Coulomb friction, separating bodies unchanged); the force
//   F_c = alpha r m (v* - v_new) / c_v,   c_v = gamma / (beta dt) = d v_new / d u,
// acts on the field, with r = c1 + c_p^2 / h^2 (c_p the fastest pressure wave, h the smallest
// cell), a stiffness per unit mass of the node: its inertia c1 m and an estimate of its elastic
// stiffness. The same r at every node and the law's momentum balance make the forces of two bodies
// at a node equal and opposite; |F_t| <= mu |F_n| follows from the law's friction. As alpha grows
// the solution's end velocities tend to the law's (no approach); what remains is an approach of
// order 1 / alpha of the one the bodies would have without contact (the penalty's compliance).
// Each field's start acceleration comes from its own body's forces, without contact's: the end
// force carries the whole impulse. (Correcting the start accelerations by the law, as the explicit
// step corrects velocities, would make its friction act on the relative acceleration rather than
// on the slip: a block on an incline then slides 12% too far.) The residual kinks where bodies meet
// or start to slip; Newton needs a line search there (Backtrack, the default with contact).
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::addContactForces() {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  const NewmarkConstants k(opt_.newmark, dt_);
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
  auto vel = contactVelocity_;
  auto before = contactVelocityBefore_;
  const int fields = fields_, ss = stateStride_, ds = dispStride_, fs = forceStride_;
  Kokkos::parallel_for(
      "contact_trial_velocity", Kokkos::RangePolicy<Exec>(0, vel.extent(0)), KOKKOS_LAMBDA(int n) {
        for (int b = 0; b < fields; ++b)
          for (int c = 0; c < Dim; ++c) {
            const double v = s(n, b * ss + SC::VelX + c), a = s(n, b * ss + SC::AccX + c);
            const double vNew = v + k.velocityChange(a, k.newAcceleration(d(n, b * ds + DC::UX + c), v, a));
            vel(n, b * Dim + c) = vNew;
            before(n, b * Dim + c) = vNew;
          }
      });
  conditions_.contact().template exchange<Exec>(s, SC::Mass, geometryCol_, ss, vel, 0, -1, Dim, Dim, dt_, true,
                                                &contactPairForce_);
  double h = dist_.grid().spacing(0);
  for (int c = 1; c < Dim; ++c) h = std::min(h, dist_.grid().spacing(c));
  const double wave = mat_.maxPWaveSpeed();
  const double r = k.c1 + wave * wave / (h * h);
  const double coefficient = opt_.contactPenalty * r * opt_.newmark.beta * dt_ / opt_.newmark.gamma;
  Kokkos::parallel_for(
      "contact_penalty_force", Kokkos::RangePolicy<Exec>(0, vel.extent(0)), KOKKOS_LAMBDA(int n) {
        for (int b = 0; b < fields; ++b) {
          const double m = s(n, b * ss + SC::Mass);
          for (int c = 0; c < Dim; ++c)
            f(n, b * fs + FC::ForceX + c) += coefficient * m * (vel(n, b * Dim + c) - before(n, b * Dim + c));
        }
      });
  // The law's pair forces are sum m dv / dt, the penalty's coefficient dt times them. Reported is
  // the impulse the contact gives over the step per unit time, gamma F_c: the trapezoidal velocity
  // update takes gamma of the end force, and the start acceleration (from the fields' own forces)
  // none of the contact's (so that F_c is twice the force that holds a body at rest).
  for (double& value : contactPairForce_) value *= coefficient * dt_ * opt_.newmark.gamma;
}

// ---- Residual and matrix ----------------------------------------------------------------------

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::scatterUnknowns(const Vector& u) {
  using DC = implicit::DisplacementColumns<Dim>;
  dispOwned_->putScalar(0.0);
  {
    auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto uv = u.getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto node = dofs_.node();
    auto comp = dofs_.component();
    auto field = dofs_.field();
    const int ds = dispStride_;
    Kokkos::parallel_for(
        "scatter_unknowns", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k) { d(node(k), field(k) * ds + DC::UX + comp(k)) = uv(k, 0); });
    // The prescribed dofs move by their increment (they are not unknowns; zero is already there).
    if (!conditions_.isZero(PrescribedField::Increment))
      conditions_.template write<Exec>(d, DC::UX, PrescribedField::Increment, ds);
  }
  dispGhosted_->doImport(*dispOwned_, *dist_.importer(), Tpetra::INSERT);
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::residual(const Vector& u, Vector& R) {
  using DC = implicit::DisplacementColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  PhaseTimer phase("residual");
  scatterUnknowns(u);
  forceGhosted_->putScalar(0.0);
  {
    auto f = forceGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    if (fbar_) {  // the cells' volume change first (core/kernels/FbarAveraging.hpp)
      gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX);
      fbar_->template accumulate<Exec>(ps_, 1.0);
      scatterTrialInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, mat_, d, DC::UX, f,
                                                  FC::ForceX, fbar_->correction(ps_));
    } else if (fields_ > 1) {
      const FieldColumns dispFields(ps_, conditions_.fieldOfBody(), dispStride_);
      const FieldColumns forceFields(ps_, conditions_.fieldOfBody(), forceStride_);
      scatterTrialInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, mat_, d, DC::UX, f,
                                                  FC::ForceX, NoStrainCorrection(), dispFields, forceFields);
    } else {
      scatterTrialInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, mat_, d, DC::UX, f,
                                                  FC::ForceX);
    }
    if (opt_.consistentMass)  // M_C u = sum_p m_p S_ip u_p with u_p = sum_j S_jp u_j
      particleToGridMassProduct<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX, f,
                                                  FC::MassProductX);
  }
  forceOwned_->putScalar(0.0);
  forceOwned_->doExport(*forceGhosted_, *dist_.importer(), Tpetra::ADD);
  if (fields_ > 1) addContactForces();
  const auto atNode = newmarkResidualAtNode<Dim>(stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 NewmarkConstants(opt_.newmark, dt_), opt_.consistentMass);
  auto uv = u.getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto r = R.getLocalViewDevice(Tpetra::Access::OverwriteAll);
  auto node = dofs_.node();
  auto comp = dofs_.component();
  auto field = dofs_.field();
  const int ss = stateStride_, fs = forceStride_;
  Kokkos::parallel_for(
      "implicit_residual", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
      KOKKOS_LAMBDA(int k) { r(k, 0) = atNode(node(k), comp(k), uv(k, 0), field(k) * ss, field(k) * fs); });
  if (!conditions_.empty()) {  // forceOwned_ now holds the forces at u (recordReactions reuses them)
    if (lastResidualPoint_.is_null() || lastResidualPoint_->getMap().get() != dofs_.map().get())
      lastResidualPoint_ = Teuchos::rcp(new Vector(dofs_.map(), false));
    Tpetra::deep_copy(*lastResidualPoint_, u);
  }
}

// The force that stops a held wall component over the step: -m v / dt - F_int - F_ext (the forces
// at the last residual's point).
template <class Shape, int Dim>
auto ImplicitNewmark<Shape, Dim>::heldWallReaction() const {
  using SC = implicit::StateColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const double dt = dt_;
  return KOKKOS_LAMBDA(int n, int d) {
    return -s(n, SC::Mass) * s(n, SC::VelX + d) / dt - f(n, FC::ForceX + d) - s(n, SC::FextX + d);
  };
}

// The reaction of each grid condition: the residual of the converged step at its dofs, the
// force the condition applies so that its nodes move as prescribed. The forces at u are those of
// the last residual when it was evaluated at u (NOX's convergence check normally is), else one
// more residual evaluation provides them.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::recordReactions(const Vector& u) {
  using DC = implicit::DisplacementColumns<Dim>;
  if (conditions_.empty()) return;
  int sameHere = 0;
  if (!lastResidualPoint_.is_null() && lastResidualPoint_->getMap().get() == u.getMap().get()) {
    auto a = lastResidualPoint_->getLocalViewHost(Tpetra::Access::ReadOnly);
    auto b = u.getLocalViewHost(Tpetra::Access::ReadOnly);
    sameHere = 1;
    for (size_t k = 0; k < a.extent(0) && sameHere; ++k) sameHere = a(k, 0) == b(k, 0);
  }
  int same = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MIN, sameHere, Teuchos::outArg(same));
  if (!same) {
    Vector R(dofs_.map(), false);
    residual(u, R);
  }
  const auto atNode = newmarkResidualAtNode<Dim>(stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 NewmarkConstants(opt_.newmark, dt_), opt_.consistentMass);
  auto disp = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  if (fields_ > 1) {  // summed over the fields
    const int fields = fields_, ss = stateStride_, ds = dispStride_, fs = forceStride_;
    conditions_.template recordReaction<Exec>(KOKKOS_LAMBDA(int n, int d) {
      double sum = 0.0;
      for (int b = 0; b < fields; ++b) sum += atNode(n, d, disp(n, b * ds + DC::UX + d), b * ss, b * fs);
      return sum;
    });
    conditions_.recordContactForces(contactPairForce_);
  } else {
    conditions_.template recordReaction<Exec>(
        KOKKOS_LAMBDA(int n, int d) { return atNode(n, d, disp(n, DC::UX + d)); });
  }
  if (conditions_.hasWalls()) conditions_.template recordImplicitWallReactions<Exec>(heldWallReaction());
}

// Implicit walls: after a converged solve, the components to release or hold (collective); when
// any changed, the free dofs follow and the step is to be solved again.
template <class Shape, int Dim>
bool ImplicitNewmark<Shape, Dim>::reviseWallContacts(const Vector& u) {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  Vector R(dofs_.map(), false);
  residual(u, R);  // the forces at u, and u in the grid displacement
  const double tolerance = 1e-9 * dist_.grid().spacing(0);
  const ImplicitWallContact& walls = conditions_.implicitWalls();
  int local = 0;
  {
    const auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    const auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    const NewmarkConstants k(opt_.newmark, dt_);
    const auto endVelocity = KOKKOS_LAMBDA(int n, int c) {
      const double v = s(n, SC::VelX + c), a = s(n, SC::AccX + c);
      return v + k.velocityChange(a, k.newAcceleration(d(n, DC::UX + c), v, a));
    };
    local = walls.template revise<Exec>(d, DC::UX, s, SC::Mass, heldWallReaction(), endVelocity, k.dt, tolerance);
  }
  int changes = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_SUM, local, Teuchos::outArg(changes));
  if (changes == 0) return false;
  {
    auto st = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    walls.template loadFriction<Exec>(st, SC::FextX);
    walls.template hold<Exec>(st, SC::Mass, SC::VelX, SC::AccX, SC::FreeX, massCutoff_, dt_);
  }
  stateGhosted_->doImport(*stateOwned_, *dist_.importer(), Tpetra::INSERT);
  PCurrent_ = false;
  if (dofs_.update(*stateOwned_, SC::FreeX)) assembler_.forgetMatrix();
  return true;
}

// || |P| |u| + |m (c2 v + c3 a)| + |F_ext| ||_2 over the free dofs (ResidualModel::residualMagnitude):
// with the step's assembled P when there is one (the stiffness carries the large terms of a stiff
// body's internal force), else with its lumped-mass part c1 m alone.
template <class Shape, int Dim>
double ImplicitNewmark<Shape, Dim>::residualMagnitude(const Vector& u) {
  using SC = implicit::StateColumns<Dim>;
  const auto map = dofs_.map();
  Vector absU(map, false), sum(map, false);
  absU.abs(u);
  const auto P = assembler_.matrix();
  const bool withP = !P.is_null() && P->getRowMap().get() == map.get();
  if (withP) {
    // Every assembly bumps the Jacobian version (a new P object too): |P| is taken once per P.
    if (absP_.is_null() || absPVersion_ != refresh_.jacobianVersion()) {
      absP_ = Teuchos::rcp(new CrsMatrix(*P, Teuchos::Copy));
      auto values = absP_->getLocalMatrixDevice().values;
      Kokkos::parallel_for(
          "abs_P", Kokkos::RangePolicy<Exec>(0, values.extent(0)),
          KOKKOS_LAMBDA(int k) { values(k) = std::fabs(values(k)); });
      absPVersion_ = refresh_.jacobianVersion();
    }
    absP_->apply(absU, sum);
  } else {
    sum.putScalar(0.0);
  }
  {
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto au = absU.getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto out = sum.getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto node = dofs_.node();
    auto comp = dofs_.component();
    auto field = dofs_.field();
    const int ss = stateStride_;
    const NewmarkConstants k(opt_.newmark, dt_);
    const double c1 = k.c1, c2 = k.c2, c3 = k.c3;
    Kokkos::parallel_for(
        "residual_magnitude", Kokkos::RangePolicy<Exec>(0, node.extent(0)), KOKKOS_LAMBDA(int i) {
          const int n = node(i), d = comp(i), o = field(i) * ss;
          const double m = s(n, o + SC::Mass);
          const double start = std::fabs(m * (c2 * s(n, o + SC::VelX + d) + c3 * s(n, o + SC::AccX + d))) +
                               std::fabs(s(n, o + SC::FextX + d));
          out(i, 0) = (withP ? out(i, 0) : m * c1 * au(i, 0)) + start;
        });
  }
  return sum.norm2();
}

// The stiffness kernels' blocks: the seed's overlap-integrated GIMP stiffness (cells, 2D), or one
// stencil block per particle (with the consistent mass c1 M_C in it when the residual has it).
template <class Shape, int Dim>
BlockMatrices ImplicitNewmark<Shape, Dim>::stiffnessBlocks(bool trialTangent) const {
  const StructuredGrid& g = dist_.grid();
  // With several fields, each block belongs to its particle's body's field.
  const auto withFieldOf = [&](BlockMatrices blocks, Kokkos::View<const int*, DeviceType> particle) {
    if (fields_ == 1) return blocks;
    blocks.field = Kokkos::View<int*, DeviceType>("block_field", blocks.count);
    auto out = blocks.field;
    auto body = ps_.body;
    auto fieldOf = conditions_.fieldOfBody();
    const bool perParticle = particle.extent(0) == 0;
    Kokkos::parallel_for(
        "stiffness_block_field", Kokkos::RangePolicy<Exec>(0, blocks.count),
        KOKKOS_LAMBDA(int k) { out(k) = fieldOf(body(perParticle ? k : particle(k))); });
    return blocks;
  };
  if constexpr (Dim == 2) {
    if (seedGimpStiffness_) {
      const ParticleCellPairs pairs = buildParticleCellPairs<Exec>(g, ps_, false);
      return withFieldOf(overlapStiffness<Exec>(g, pairs, ps_, mat_.law()), pairs.particle);
    }
  }
  const double massFactor = opt_.consistentMass ? opt_.newmark.c1(dt_) : 0.0;
  return withFieldOf(stencilStiffness<Exec, Shape, Dim>(g, ps_, mat_.law(), massFactor, trialTangent),
                     Kokkos::View<const int*, DeviceType>());
}

// P = c1 M + K over the free dofs (K over particle-cell pairs, exact over overlaps for GIMP).
// Small strain: P does not depend on u and is assembled at most once per step; the trial tangent
// (finite strain, see PreconditionerRefresh) at every Newton iterate. The consistent mass goes
// into the stencil blocks, so that P is the Jacobian of the consistent-mass residual; the seed's
// GIMP blocks (cells) cannot hold a GIMP stencil's mass coupling, so P keeps the lumped mass there.
template <class Shape, int Dim>
Teuchos::RCP<const CrsMatrix> ImplicitNewmark<Shape, Dim>::jacobianMatrix(const Vector& u) {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  PhaseTimer phase("stiffness assembly");
  const bool trialTangent = refresh_.trialTangent(mat_.anyFiniteStrain() && !seedGimpStiffness_);
  if (PCurrent_ && !trialTangent) return assembler_.matrix();
  if (!restoredP_.empty()) {
    assembler_.restore(restoredP_, dofs_);
    restoredP_.clear();
  }
  if (trialTangent) {
    // grad u of the trial displacement at each particle, for the stiffness kernel.
    scatterUnknowns(u);
    auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX);
    if (fbar_) {  // the preconditioner's tangent at the barred state (without F-bar's cell coupling)
      fbar_->template accumulate<Exec>(ps_, 1.0);
      fbar_->template correctGradients<Exec>(ps_);
    }
  }
  if (refresh_.keep(!assembler_.matrix().is_null(), trialTangent)) {
    PCurrent_ = true;
    return assembler_.matrix();
  }
  const bool graphChanged = assembler_.updatePattern(*stateGhosted_, SC::FreeX, dofs_);
  const bool consistentMassInP = opt_.consistentMass && !seedGimpStiffness_;
  assembler_.fill(stiffnessBlocks(trialTangent), dofs_, consistentMassInP ? nullptr : stateOwned_.get(), SC::Mass,
                  opt_.newmark.c1(dt_));
  refresh_.assembled(graphChanged);
  PCurrent_ = true;
  return assembler_.matrix();
}

// ---- The end of the step ----------------------------------------------------------------------

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::finishStep(const Vector& u) {
  PhaseTimer phase("g2p and stress update");
  recordReactions(u);
  scatterUnknowns(u);
  gridUpdate();
  dispGhosted_->doImport(*dispOwned_, *dist_.importer(), Tpetra::INSERT);
  updateParticles();
}

// Grid acceleration at t + dt and the velocity increment on the free dofs (zero elsewhere, the
// prescribed motion at the conditions' dofs); the FE reference keeps the grid's own v and a.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::gridUpdate() {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  const NewmarkConstants k(opt_.newmark, dt_);
  const double dt = k.dt, gamma = k.gamma;
  {
    auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    const int fields = fields_, ss = stateStride_, ds = dispStride_;
    Kokkos::parallel_for(
        "implicit_grid_acceleration", Kokkos::RangePolicy<Exec>(0, d.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int b = 0; b < fields; ++b) {
            const int o = b * ss, q = b * ds;
            for (int c = 0; c < Dim; ++c) {
              const bool free = s(n, o + SC::FreeX + c) > 0.5;
              const double a = s(n, o + SC::AccX + c);
              const double aNew = free ? k.newAcceleration(d(n, q + DC::UX + c), s(n, o + SC::VelX + c), a) : 0.0;
              d(n, q + DC::AnewX + c) = aNew;
              d(n, q + DC::DvX + c) = free ? k.velocityChange(a, aNew) : 0.0;
            }
          }
        });
    conditions_.template write<Exec>(d, DC::AnewX, PrescribedField::Acceleration, ds);
    conditions_.template write<Exec>(d, DC::DvX, PrescribedField::VelocityChange, ds);
    if (conditions_.hasWalls()) {
      conditions_.implicitWalls().template stop<Exec>(d, DC::AnewX, DC::DvX, s, SC::VelX, dt);
      conditions_.template rubImplicitWalls<Exec>(d, DC::AnewX, DC::DvX, s, SC::Mass, SC::VelX, heldWallReaction(), dt,
                                                  gamma);
    }
  }
  if (!opt_.fixedParticles) return;
  auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto kin = gridKinematics_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
  Kokkos::parallel_for(
      "grid_newmark_update", Kokkos::RangePolicy<Exec>(0, d.extent(0)), KOKKOS_LAMBDA(int n) {
        for (int c = 0; c < Dim; ++c) {
          const double aNew = d(n, DC::AnewX + c);
          kin(n, c) = s(n, SC::FreeX + c) > 0.5
                          ? s(n, SC::VelX + c) + dt * ((1 - gamma) * s(n, SC::AccX + c) + gamma * aNew)
                          : 0.0;
          kin(n, Dim + c) = aNew;
        }
      });
  conditions_.template write<Exec>(kin, 0, PrescribedField::EndVelocity);
  conditions_.template write<Exec>(kin, Dim, PrescribedField::Acceleration);
}

// Stress from the converged displacement (weights at x_p(t)), then the particle update: x += u
// (the FE reference's Gauss points keep their place and their displacement apart), v by the grid's
// own increment (Equilibrium, FLIP) or the particle's trapezoidal rule, a = a_new.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::updateParticles() {
  using DC = implicit::DisplacementColumns<Dim>;
  auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  withFields(dispStride_, [&](const auto& columns) {
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX, columns);
  });
  const DomainConvection domain = ConvectsDomain<Shape>::value ? DomainConvection(dist_.grid()) : DomainConvection();
  if (fbar_) {
    fbar_->template accumulate<Exec>(ps_, 1.0);
    updateStress<Exec, Dim>(ps_, mat_.law(), 1.0, true, domain, fbar_->correction(ps_));
  } else {
    updateStress<Exec, Dim>(ps_, mat_.law(), 1.0, /*updateVolume=*/!opt_.fixedParticles, domain);
  }
  if (opt_.transfer == ParticleTransfer::Apic) return updateAffineParticles<ParticleTransfer::Apic>();
  if (opt_.transfer == ParticleTransfer::Tpic) return updateAffineParticles<ParticleTransfer::Tpic>();
  // XPIC: v_p <- sum S v* from the step's start velocity; the update below adds the increment.
  if (xpic_)
    xpic_->replaceParticleVelocity(*stateOwned_, implicit::StateColumns<Dim>::Mass, implicit::StateColumns<Dim>::VelX,
                                   ps_, conditions_, massCutoff_, true);
  const StructuredGrid g = dist_.grid();
  const LocalNodeIndexer ix = dist_.ghostedIndexer();
  auto x = ps_.x;
  auto hs = ps_.halfSize;
  auto v = ps_.v;
  auto a = ps_.a;
  auto up = ps_.u;
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps_);
  const NewmarkConstants k(opt_.newmark, dt_);
  const double c1 = k.c1, c2 = k.c2, c3 = k.c3, dt = k.dt, gamma = k.gamma;
  const bool consistent = opt_.consistentMass, fixed = opt_.fixedParticles;
  const bool gridIncrement = equilibriumAcceleration();
  withFields(dispStride_, [&](const auto& fields) {
    Kokkos::parallel_for(
        "implicit_g2p", Kokkos::RangePolicy<Exec>(0, ps_.count), KOKKOS_LAMBDA(int p) {
          const ParticleStencil<Shape, Dim> stn(g, x, hs, deformation, p);
          double u[Dim] = {}, an[Dim] = {}, dv[Dim] = {};
          const int o = fields.offset(p);
          stn.forEachNode(ix, [&](int n, double w, const double*) {
            for (int c = 0; c < Dim; ++c) {
              u[c] += w * d(n, o + DC::UX + c);
              an[c] += w * d(n, o + DC::AnewX + c);
              dv[c] += w * d(n, o + DC::DvX + c);
            }
          });
          for (int c = 0; c < Dim; ++c) {
            if (consistent) an[c] = c1 * u[c] - c2 * v(p, c) - c3 * a(p, c);  // the particle's own Newmark update
            if (fixed)
              up(p, c) += u[c];
            else
              x(p, c) += u[c];
            if (gridIncrement)
              v(p, c) += dv[c];
            else
              v(p, c) += dt * ((1 - gamma) * a(p, c) + gamma * an[c]);
            a(p, c) = an[c];
          }
        });
  });
}

// APIC and TPIC: the grid velocity at t + dt, v_i + dv_i, and a_new on every ghosted node; then
// x_p += sum S u_i, v_p = sum S v_i(t + dt), C_p from the same field, a_p = sum S a_new (weights
// at x_p(t)). The particles' own Newmark update is not used: their velocity is the grid's.
template <class Shape, int Dim>
template <ParticleTransfer Transfer>
void ImplicitNewmark<Shape, Dim>::updateAffineParticles() {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  using K = KinColumns<Dim>;
  auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  {
    auto s = stateGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto kin = endKinematics_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
    Kokkos::parallel_for(
        "implicit_end_kinematics", Kokkos::RangePolicy<Exec>(0, kin.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int c = 0; c < Dim; ++c) {
            kin(n, K::VelX + c) = s(n, SC::VelX + c) + d(n, DC::DvX + c);
            kin(n, K::AccX + c) = d(n, DC::AnewX + c);
          }
        });
  }
  auto kin = endKinematics_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const StructuredGrid g = dist_.grid();
  const LocalNodeIndexer ix = dist_.ghostedIndexer();
  const FixedParticleViews<Dim> pv(ps_);
  auto x = pv.x;
  auto v = pv.v;
  auto a = pv.a;
  auto affine = pv.affine;
  gatherFromGrid<Exec, Shape, Dim>(
      "implicit_g2p_affine", g, ps_, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st) {
        double xp[Dim], vi[Dim] = {}, ai[Dim] = {}, grad[Dim][Dim] = {}, C[Dim][Dim], u[Dim] = {};
        for (int c = 0; c < Dim; ++c) xp[c] = x(p, c);
        gatherAffineKinematics<Transfer>(st, g, ix, kin, 0, xp, vi, ai, grad, C);
        st.forEachNode(ix, [&](int n, double w, const double*) {
          for (int c = 0; c < Dim; ++c) u[c] += w * d(n, DC::UX + c);
        });
        for (int c = 0; c < Dim; ++c) {
          x(p, c) += u[c];
          v(p, c) = vi[c];
          a(p, c) = ai[c];
          for (int j = 0; j < Dim; ++j) affine(p, c, j) = C[c][j];
        }
      });
}

// ---- Driving the step -------------------------------------------------------------------------

template <class Shape, int Dim>
StepControl::Outcome ImplicitNewmark<Shape, Dim>::solveStep(double t, double dt) {
  using clock = std::chrono::steady_clock;
  auto t0 = clock::now();
  if (conditions_.hasWalls()) conditions_.implicitWalls().beginStep();
  setUpStep(t, dt);
  // With walls, the solve is repeated until the held wall components settle (at most
  // ImplicitWallContact::maxSolves() solves; the last one stands).
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
    if (!result.converged) return {false, result.newtonIterations, result.reason};
    t0 = clock::now();
    if (!conditions_.hasWalls() || solve >= ImplicitWallContact::maxSolves() || !reviseWallContacts(*u)) break;
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
  s.set("Configuration", implicit::describeSolver(solver_->parameters()));
}

// ---- Checkpoint -------------------------------------------------------------------------------

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::saveState(NamedArrays& state) const {
  std::vector<double> scalars = {double(firstStep_), control_.carriedSubStep(), double(control_.halvings())};
  for (const auto& part : {refresh_.state(), statistics_.scalars(), control_.subStepStatistics()})
    scalars.insert(scalars.end(), part.begin(), part.end());
  state["implicit scalars"] = scalars;
  statistics_.save(state);
  // A Jacobian-free run reuses P (and its preconditioner) for later steps: kept, per rank.
  state["implicit ranks"] = {double(dist_.comm()->getSize())};
  if (jacobianFree() && !assembler_.matrix().is_null()) assembler_.save(state["node implicit P"]);
  if (opt_.fixedParticles) {
    // The grid's own v and a (owned nodes) with their global ids: per rank.
    auto k = gridKinematics_->getLocalViewHost(Tpetra::Access::ReadOnly);
    const auto map = dist_.ownedNodeMap();
    auto& gids = state["node implicit grid kinematics gids"];
    auto& values = state["node implicit grid kinematics"];
    for (size_t n = 0; n < k.extent(0); ++n) {
      gids.push_back(double(map->getGlobalElement((LO)n)));
      for (int c = 0; c < 2 * Dim; ++c) values.push_back(k(n, c));
    }
  }
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::restoreState(const NamedArrays& state) {
  const std::vector<double>& s = state.at("implicit scalars");
  if (s.size() != 17)
    throw std::runtime_error("checkpoint: 'implicit scalars' has " + std::to_string(s.size()) + " entries, not 17");
  firstStep_ = s[0] != 0;
  refresh_.restore(s[3], s[4], s[5], s[6]);
  statistics_.restoreScalars(std::vector<double>(s.begin() + 7, s.begin() + 13));
  control_.restore(s[1], s[2], std::vector<double>(s.begin() + 13, s.end()));
  statistics_.restore(state);
  const auto ranks = state.find("implicit ranks"), P = state.find("node implicit P");
  if (ranks != state.end() && P != state.end() && int(ranks->second.at(0)) == dist_.comm()->getSize())
    restoredP_ = P->second;
  if (opt_.fixedParticles) {
    const auto& gids = state.at("node implicit grid kinematics gids");
    const auto& values = state.at("node implicit grid kinematics");
    auto k = gridKinematics_->getLocalViewHost(Tpetra::Access::OverwriteAll);
    const auto map = dist_.ownedNodeMap();
    for (size_t i = 0; i < gids.size(); ++i) {
      const LO n = map->getLocalElement((GO)gids[i]);
      if (n == Teuchos::OrdinalTraits<LO>::invalid()) continue;
      for (int c = 0; c < 2 * Dim; ++c) k(n, c) = values[i * 2 * Dim + c];
    }
  }
}

}  // namespace impm
