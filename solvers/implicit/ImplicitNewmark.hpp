// Implicit MPM/GIMP after Guilkey & Weiss (2003), extended to GIMP (the seed, slides 2-6): the
// step driver. Newmark on the grid (solvers/implicit/NewmarkScheme.hpp), solved for the grid displacement increment u
// of the step by a Newton iteration (NewtonSolver: NOX Jacobian-free Newton-Krylov, or Newton with the assembled
// stiffness).
//
//   R(u) = M (4/dt^2 u - 4/dt v - a) + F_int(u) - F_ext(t + dt) = 0   on the free dofs,
//
// where F_int(u) comes from the trial particle stresses sigma_p + D sym(grad u) through the
// same internal-force kernel the explicit stepper uses. Prescribed components and nodes
// without mass are not unknowns (see ImplicitOptions::massTolerance). One step:
//   setUpStep     particles to grid, the grid state at t, prescribed motion, free dofs (FreeDofMap)
//   Newton        residual(u) and jacobianMatrix(u) (StiffnessAssembler, PreconditionerRefresh)
//   finishStep    reactions, grid acceleration and velocity increment, stress, particle update
// with StepControl halving or sub-stepping a step whose Newton iteration fails.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <memory>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleCellPairs.hpp"
#include "core/kernels/AffineTransfer.hpp"
#include "core/kernels/FbarAveraging.hpp"
#include "physics/GridConditions.hpp"
#include "physics/Materials.hpp"
#include "physics/Loads.hpp"
#include "solvers/Integrator.hpp"
#include "solvers/newton/NewtonSolver.hpp"
#include "solvers/ProjectionCorrection.hpp"
#include "solvers/XpicExtrapolation.hpp"
#include "solvers/implicit/FreeDofMap.hpp"
#include "solvers/implicit/ImplicitStatistics.hpp"
#include "solvers/implicit/NewmarkScheme.hpp"
#include "solvers/implicit/PreconditionerRefresh.hpp"
#include "solvers/implicit/StepControl.hpp"
#include "solvers/implicit/StiffnessAssembler.hpp"

namespace impm {

// Rigid bodies (physics/MultiFieldContact.hpp): a rigid body's field is no unknown of the step. At
// each node where it has mass it starts at V(t) with the acceleration A = (V(t + dt) - V(t)) / dt
// and moves by dt (V(t) + V(t + dt)) / 2, whose Newmark update (any beta and gamma) is a_new = A
// and the end velocity V(t + dt): its particles, taking the grid's increments, move rigidly. The
// other bodies meet it through the contact penalty, where the law takes it as infinitely heavy.
struct RigidFieldMotion {
  Kokkos::View<const double**, Kokkos::LayoutRight, DeviceType> motion;  // per field: V(t), V(t + dt)
  double dt;
  KOKKOS_INLINE_FUNCTION double start(int f, int c) const { return motion(f, c); }
  KOKKOS_INLINE_FUNCTION double change(int f, int c) const { return motion(f, 3 + c) - motion(f, c); }
  KOKKOS_INLINE_FUNCTION double acceleration(int f, int c) const { return change(f, c) / dt; }
  KOKKOS_INLINE_FUNCTION double increment(int f, int c) const { return 0.5 * dt * (motion(f, c) + motion(f, 3 + c)); }
};

struct ImplicitOptions {
  NewmarkScheme newmark;
  // Nodes lighter than this fraction of the heaviest particle are void (not unknowns), so that the
  // matrix has no near-zero rows: with smooth weights (GIMP, cpGIMP, CPDI, B-splines) a node reached
  // with a tiny weight also has a tiny gradient and stiffness. Linear MPM ignores it (every node a
  // particle reaches is an unknown): its gradient is a full 1/h at any weight, so a particle within
  // round-off of a grid line reaches the node across it with a weight of 1e-16, and holding that
  // node at u = 0 strains the particle by u / h (a falling body, test_newmark); its row is then
  // carried by the stiffness.
  double massTolerance = 1e-12;
  int maxStepHalvings = 4;                    // a step whose Newton iteration fails is retried with dt/2, dt/4, ...
  bool consistentInitialAcceleration = true;  // a(0) = M^-1 (F_ext(0) - F_int(0)) instead of zero
  // Jacobi iterations towards the consistent-mass projection of particle velocity and
  // acceleration to the grid (0: lumped p / m). See ExplicitStepper.
  int projectionIterations = 0;
  // Steps between numeric refactorisations of the preconditioner (its factors of an older P
  // stay a good preconditioner while particles move little); 1 = every step.
  int preconditionerRefreshInterval = 1;
  // Also rebuild it at the step after one whose mean GMRES iterations per Newton exceeded this
  // (0: off); or at every Newton iterate from the trial-state tangent (finite strain).
  int preconditionerRefreshKrylov = 0;
  bool preconditionerEveryNewton = false;
  // Consistent mass: R uses M_C u = S^T M_p S u (one particle round trip per residual) and the
  // particles take the Newmark update themselves (a_p,new = 4/dt^2 u_p - 4/dt v_p - a_p), so
  // that particle kinetic plus strain energy is what the trapezoidal rule conserves. P holds
  // the consistent mass too (except with the seed's GIMP stiffness, whose cell blocks cannot:
  // lumped there). Default: lumped (Guilkey & Weiss).
  bool consistentMass = false;
  // GIMP's preconditioner / assembled Jacobian: the seed's stiffness integrated over particle
  // domains (true), or V_p B^T D B with the averaged gradients, the exact derivative of the
  // GIMP internal force (false).
  bool seedGimpStiffness = false;
  // Lumped mass, moving particles: the grid acceleration at the start of a step from the forces,
  // a_i = (F_ext + F_int)_i / m_i, and the particles' velocity from the grid's trapezoidal
  // increment dt/2 (a_i + a_i,new) (true, "Equilibrium"); or a_i projected from the particles'
  // accelerations and v_p += dt/2 (a_p + a_p,new) (false, "Projected": Guilkey & Weiss 2003).
  // The projected acceleration is not the one the forces give, and the trapezoidal rule keeps
  // such an error alive: at omega dt >> 1 it grows each step (stress 11 times the static value
  // after 40 steps of a step-loaded block; test_patch).
  bool equilibriumAcceleration = true;
  // Finite-element reference mode: the particles are Gauss points and do not move; the grid
  // carries the velocity and acceleration from step to step (no projection from particles).
  bool fixedParticles = false;
  // F-bar volumetric-locking control (core/kernels/FbarAveraging.hpp): in the residual and the
  // particle update. Jacobian-free Newton only: the residual's directional derivative then
  // carries F-bar's coupling of a cell's particles, which the assembled blocks leave out (the
  // preconditioner is built from them all the same).
  bool fbar = false;
  // FlipPic: the particle's own Newmark update of v_p (or the grid's increment, Equilibrium);
  // Apic, Tpic: v_p and C_p from the grid's end-of-step velocity (core/kernels/AffineTransfer.hpp),
  // with the lumped mass and moving particles only.
  // Xpic: the FLIP update from the XPIC(xpicOrder) velocity (solvers/XpicExtrapolation.hpp).
  ParticleTransfer transfer = ParticleTransfer::FlipPic;
  int xpicOrder = 5;
  // Adaptive sub-steps within each deck step on the Newton iteration count (see step()); the
  // smallest sub-step allowed (0: dt / 2^maxStepHalvings).
  bool adaptiveTimeStep = false;
  double minimumTimeStep = 0.0;
  // How the assembled P's values are summed (StiffnessAssembler.hpp; the same bits either way).
  StiffnessFill stiffnessFill = StiffnessFill::Auto;
  // Multi-field contact (physics/MultiFieldContact.hpp): the penalty factor alpha of the contact
  // force in the residual (see ImplicitNewmark::addContactForces).
  double contactPenalty = 30.0;
  // The P-wave speed in the penalty's stiffness: the fastest of the deformable bodies' materials
  // (a rigid body's material gives it mass only); 0: the fastest material of the table.
  double contactWaveSpeed = 0.0;
  Teuchos::RCP<Teuchos::ParameterList> solverParams;  // the deck's "Implicit Solver" sublist
};

template <class Shape, int Dim = 2>
class ImplicitNewmark : public Integrator, public ResidualModel {
 public:
  ImplicitNewmark(ParticleSet& particles, const GridDistribution& dist, const Materials& material,
                  GridConditions& conditions, const LoadSet& loads, const ImplicitOptions& options);
  ~ImplicitNewmark() override;

  // One step of dt, as one Newmark step or, if Newton fails, as 2^k substeps (k <= maxStepHalvings).
  // Throws NewtonNotConverged, leaving the particles at their last converged state.
  void step(double t, double dt) override;
  std::string name() const override;
  void addStatistics(Teuchos::ParameterList& summary) const override;
  // The first-step flag, the adaptive sub-step, the preconditioner refresh counters, the FE
  // reference's grid kinematics and the statistics (solvers/Checkpoint.hpp); and, at the same
  // rank count, the assembled P a Jacobian-free run keeps between refreshes (its preconditioner
  // is rebuilt from the same values). At another rank count P is assembled afresh.
  void saveState(NamedArrays& state) const override;
  void restoreState(const NamedArrays& state) override;

  // The set-up step() does before solving (grid state at t, loads at t + dt, free dofs); public
  // so that tests can evaluate the residual and the matrix of one step.
  void prepareStep(double t, double dt) { setUpStep(t, dt); }

  // ResidualModel (for the current step's set-up).
  Teuchos::RCP<const Map> unknownMap() const override { return dofs_.map(); }
  void residual(const Vector& u, Vector& R) override;
  Teuchos::RCP<const CrsMatrix> jacobianMatrix(const Vector& u) override;
  long jacobianVersion() const override { return refresh_.preconditionerVersion(); }
  Teuchos::RCP<const MultiVector> unknownCoordinates() const override { return dofs_.coordinates(dist_.grid()); }
  int unknownsPerNode() const override { return Dim; }
  double residualMagnitude(const Vector& u) override;

  // Statistics of the run so far.
  const std::vector<int>& newtonIterationsPerStep() const { return statistics_.newtonIterationsPerStep(); }
  const std::vector<int>& krylovIterationsPerNewton() const { return statistics_.krylovIterationsPerNewton(); }

 private:
  using Exec = ExecutionSpace;
  // The step's set-up: particles to grid at t (mass, momentum, m a; F_ext at t + dt), the grid's
  // v and a at t, the prescribed motion and the free dofs.
  void setUpStep(double t, double dt);
  void forcesAtStart(double t);                    // F_int + F_ext at t, for the acceleration from forces
  void startKinematics(bool initialAcceleration);  // v, a at t from the momentum sums or the grid
  void normalizeGridState(double t, double dt, bool accelerationFromForces);
  StepControl::Outcome solveStep(double t, double dt);  // one Newton solve of [t, t + dt]
  void finishStep(const Vector& u);                     // grid and particle update with the converged u
  bool reviseWallContacts(const Vector& u);             // walls: release / hold components; true if any changed
  bool reviseContactStates(const Vector& u);            // contact: the active set anew; true if any changed
  void saveContactStates(NamedArrays& state) const;     // checkpoint: the contact active set, by node id
  void restoreContactStates(const NamedArrays& state);
  void saveWallStates(NamedArrays& state) const;  // checkpoint: the walls' active set, by node id and wall
  void restoreWallStates(const NamedArrays& state);
  // With contact, solves of one step before the last active set stands.
  static constexpr int kMaxContactSolves = 8;
  auto heldWallReaction() const;
  void gridUpdate();       // a_new and the velocity increment on the grid
  void updateParticles();  // stress, then x, v, a of the particles
  template <ParticleTransfer Transfer>
  void updateAffineParticles();           // APIC, TPIC: x, v, C_p, a from the grid at t + dt
  void recordReactions(const Vector& u);  // the grid conditions' reactions: the residual at their dofs
  void scatterUnknowns(const Vector& u);  // u (free dofs) -> ghosted grid displacement
  void correctProjection();               // consistent-mass correction of v and a on the grid
  // Multi-field contact: what the implicit step does not take refused; the penalty contact force
  // at the trial displacement in the residual.
  void checkContactUsable() const;
  void addContactForces();
  double contactPenaltyCoefficient() const;
  typename StiffnessAssembler<Dim>::NodeCouplings contactStiffness(const Vector& u, bool scattered);
  // Rigid bodies: body(n, f, c, motion) at each owned node n where rigid field f has mass, per
  // component c; `mass` the owned grid state (RigidFieldMotion).
  template <class StateView, class Body>
  void forEachRigidDof(const StateView& mass, const Body& body) const;
  auto trialEndVelocity() const;  // field b's trial end velocity at owned node n, component c
  // Runs f(columns) with each particle's field in grid views whose fields are `stride` columns
  // apart: SingleField with one field (the kernels' columns stay compile-time constants), or
  // FieldColumns.
  template <class F>
  void withFields(int stride, const F& f) const;
  bool equilibriumAcceleration() const {
    return opt_.equilibriumAcceleration && !opt_.consistentMass && !opt_.fixedParticles;
  }
  bool jacobianFree() const;
  BlockMatrices stiffnessBlocks(bool trialTangent) const;

  ParticleSet& ps_;
  const GridDistribution& dist_;
  Materials mat_;
  GridConditions& conditions_;
  const LoadSet& loads_;
  ImplicitOptions opt_;
  ProjectionCorrection<Shape, Dim> projection_;
  std::unique_ptr<FbarAveraging<Dim>> fbar_;
  std::unique_ptr<XpicExtrapolation<Shape, Dim>> xpic_;
  std::unique_ptr<NewtonSolver> solver_;
  double dt_ = 0, massCutoff_ = 0;
  bool firstStep_ = true;
  bool seedGimpStiffness_ = false;  // the seed's overlap-integrated K (GIMP, 2D): cell blocks

  // Velocity fields: one, or one per body with multi-field contact. Field f's columns sit f times
  // the stride after field 0's: in the grid state (with the contact geometry, volume gradient and
  // mass-weighted position, at geometryCol_), the displacement and the force multivectors.
  int fields_ = 1;
  int stateStride_ = 0, dispStride_ = 0, forceStride_ = 0, geometryCol_ = -1;
  // Owned and ghosted node multivectors (solvers/implicit/ImplicitGridColumns.hpp): grid state
  // (mass, v, a, F_ext, free flags), displacement, force.
  Teuchos::RCP<MultiVector> stateOwned_, stateGhosted_, dispOwned_, dispGhosted_, forceOwned_, forceGhosted_;
  FreeDofMap<Dim> dofs_;
  Teuchos::RCP<Vector> lastResidualPoint_;  // the u of the last residual (its forces are in forceOwned_)

  // The assembled matrix: valid for this step's set-up (PCurrent_), assembled when the refresh
  // policy says so.
  StiffnessAssembler<Dim> assembler_;
  PreconditionerRefresh refresh_;
  bool PCurrent_ = false;
  // |P| (P's values in absolute value) for residualMagnitude, and the P version it was taken of.
  Teuchos::RCP<CrsMatrix> absP_;
  long absPVersion_ = -1;
  std::vector<double> restoredP_;             // a checkpoint's P, taken at the first jacobianMatrix()
  Teuchos::RCP<MultiVector> gridKinematics_;  // fixed particles: grid v, a at the end of the last step
  Teuchos::RCP<MultiVector> endKinematics_;   // APIC, TPIC: ghosted grid v, a at t + dt (KinColumns)

  StepControl control_;
  ImplicitStatistics statistics_;
  // The solves repeated for a changed active set: contact, walls (a solve both changed counts in both).
  long contactResolves_ = 0, wallResolves_ = 0;
};

}  // namespace impm
