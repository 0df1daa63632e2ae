// Implicit MPM/GIMP after Guilkey & Weiss (2003), extended to GIMP (the seed, slides 2-6):
// Newmark average acceleration on the grid, solved for the grid displacement increment u of
// the step by a Newton iteration (NewtonSolver: NOX Jacobian-free Newton-Krylov, or Newton
// with the assembled stiffness).
//
//   R(u) = M (4/dt^2 u - 4/dt v - a) + F_int(u) - F_ext(t + dt) = 0   on the free dofs,
//
// where F_int(u) comes from the trial particle stresses sigma_p + D sym(grad u) through the
// same internal-force kernel the explicit stepper uses. Constrained components and nodes
// without mass are not unknowns (see ImplicitOptions::massTolerance).
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <memory>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleCellPairs.hpp"
#include "physics/GridConditions.hpp"
#include "physics/Materials.hpp"
#include "physics/Loads.hpp"
#include "solvers/Integrator.hpp"
#include "solvers/NewtonSolver.hpp"
#include "solvers/ProjectionCorrection.hpp"

namespace impm {

// The Newmark family on the grid:
//   u     = dt v + dt^2 ((1/2 - beta) a + beta a_new)   ->  a_new = c1 u - c2 v - c3 a
//   v_new = v + dt ((1 - gamma) a + gamma a_new)
// Average acceleration (beta = 1/4, gamma = 1/2, the default) conserves energy; gamma > 1/2 damps
// the highest frequencies (most with beta = (gamma + 1/2)^2 / 4).
struct NewmarkScheme {
  double beta = 0.25, gamma = 0.5;
  double c1(double dt) const { return 1.0 / (beta * (dt * dt)); }
  double c2(double dt) const { return 1.0 / (beta * dt); }
  double c3() const { return 0.5 / beta - 1.0; }
  bool averageAcceleration() const { return beta == 0.25 && gamma == 0.5; }
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
  int maxStepHalvings = 4;       // a step whose Newton iteration fails is retried with dt/2, dt/4, ...
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
  // Adaptive sub-steps within each deck step on the Newton iteration count (see step()); the
  // smallest sub-step allowed (0: dt / 2^maxStepHalvings).
  bool adaptiveTimeStep = false;
  double minimumTimeStep = 0.0;
  Teuchos::RCP<Teuchos::ParameterList> solverParams;  // the deck's "Implicit Solver" sublist
};

struct NewtonNotConverged : std::runtime_error {
  using std::runtime_error::runtime_error;
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
  Teuchos::RCP<const Map> unknownMap() const override { return unknownMap_; }
  void residual(const Vector& u, Vector& R) override;
  Teuchos::RCP<const CrsMatrix> jacobianMatrix(const Vector& u) override;
  long jacobianVersion() const override { return preconditionerVersion_; }
  Teuchos::RCP<const MultiVector> unknownCoordinates() const override;
  int unknownsPerNode() const override { return Dim; }
  double residualMagnitude(const Vector& u) override;

  // Statistics of the run so far.
  const std::vector<int>& newtonIterationsPerStep() const { return newtonPerStep_; }
  const std::vector<int>& krylovIterationsPerNewton() const { return krylovPerNewton_; }

 private:
  using Exec = ExecutionSpace;
  void setUpStep(double t, double dt);   // grid state at t, external force at t + dt, free dofs
  bool trySteps(double t, double dt, int depth);
  // One Newton solve of the step [t, t + dt]; false when Newton failed (nothing changed).
  bool solveStep(double t, double dt);
  void stepAdaptive(double t, double dt);
  void finishStep(const Vector& u);      // grid and particle update with the converged u
  void recordReactions(const Vector& u); // the grid conditions' reactions: the residual at their dofs
  void scatterUnknowns(const Vector& u); // u (free dofs) -> ghosted grid displacement
  void correctProjection();              // consistent-mass correction of v and a on the grid
  bool equilibriumAcceleration() const {
    return opt_.equilibriumAcceleration && !opt_.consistentMass && !opt_.fixedParticles;
  }

  ParticleSet& ps_;
  const GridDistribution& dist_;
  Materials mat_;
  GridConditions& conditions_;
  const LoadSet& loads_;
  ImplicitOptions opt_;
  ProjectionCorrection<Shape, Dim> projection_;
  std::unique_ptr<NewtonSolver> solver_;
  double dt_ = 0, massCutoff_ = 0;
  bool firstStep_ = true;

  // Owned and ghosted node multivectors: grid state (mass, v, a, F_ext), displacement, force.
  Teuchos::RCP<MultiVector> stateOwned_, stateGhosted_, dispOwned_, dispGhosted_, forceOwned_, forceGhosted_;
  // Free dofs of this step: owned local node and component, and the unknown map.
  Kokkos::View<int*, DeviceType> freeNode_, freeComp_;
  Teuchos::RCP<const Map> unknownMap_;
  std::vector<GO> freeGids_;
  Teuchos::RCP<Vector> lastResidualPoint_;  // the u of the last residual (its forces are in forceOwned_)
  mutable Teuchos::RCP<MultiVector> unknownCoords_;  // built on first request for unknownMap_

  // The assembled matrix of the current step; its graph (and the overlap matrix and Export
  // it is summed through) is reused while the pattern of particle-cell pairs and free dofs
  // stays the same, so that only values are refilled and Ifpack2 keeps its symbolic set-up.
  Teuchos::RCP<CrsMatrix> P_, overlapP_;
  Teuchos::RCP<const Export> pExporter_;
  std::vector<GO> patternKey_;
  bool PCurrent_ = false;
  long jacobianVersion_ = 0;       // bumped at every (re)assembly
  long preconditionerVersion_ = 0; // bumped when the preconditioner must be refactored
  int stepsSinceAssembly_ = 0;
  bool refreshRequested_ = false;
  // Offsets into overlapP_'s local values: per ghost-region block and local dof pair (r, c), and
  // per owned free dof for the mass diagonal.
  std::vector<size_t> blockOffsets_, diagOffsets_;
  // |P| (P's values in absolute value) for residualMagnitude, and the P version it was taken of.
  Teuchos::RCP<CrsMatrix> absP_;
  long absPVersion_ = -1;
  // Blocks of the assembled stiffness: nodes per direction and spacing of their first nodes
  // (cells: 2 and 1; Q9 elements: 3 and 2; GIMP and quadratic B-spline stencils: 3 and 1; cubic B-splines: 4 and 1).
  int blockNodes_ = 2, blockStride_ = 1;
  bool seedGimpStiffness_ = false;  // the seed's overlap-integrated K (GIMP only)
  Teuchos::RCP<MultiVector> gridKinematics_;  // fixed particles: grid v, a at the end of the last step

  // Restart: the checkpoint's P (per row: gid, entry count, then column gid and value pairs),
  // taken as P_ at the first jacobianMatrix() when its rows are this step's free dofs.
  std::vector<double> restoredP_;
  void takeRestoredP();

  std::vector<int> newtonPerStep_, krylovPerNewton_;
  int halvings_ = 0;
  std::string lastFailure_;  // the reason of the last Newton solve that failed (for the message)
  int hardestStepIterations_ = -1;
  std::vector<double> hardestStepNorms_;
  // Adaptive time step: the sub-step carried from step to step (0: not started), the counts.
  double subStep_ = 0.0, smallestSubStep_ = 0.0, largestSubStep_ = 0.0;
  long long subSteps_ = 0, rejectedSubSteps_ = 0;
  long residualEvaluations_ = 0;
  double secondsSetUp_ = 0, secondsSolve_ = 0, secondsSolverSetUp_ = 0, secondsFinish_ = 0;
};

}  // namespace impm
