// One run of an input deck. SimulationBuilder.cpp builds the grid, materials, bodies and their
// particles, constraints, loads, monitors, the exact solution and the integrator from a validated
// deck, section by section (solvers/build/<Section>Section.cpp, each with its section's schema;
// every semantic check happens there, before anything is written); Simulation.cpp is the run loop
// (steps, audits, migration and load balance; the outputs are its observers,
// solvers/run/RunObservers.hpp); SimulationRestart.cpp writes checkpoints and continues from one
// (the format is solvers/Checkpoint.hpp's); SimulationSummary.cpp writes summary.yaml. Plots are
// the driver's (apps/).
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <array>
#include <map>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "physics/Body.hpp"
#include "physics/GridConditions.hpp"
#include "physics/ExactReference.hpp"
#include "physics/Materials.hpp"
#include "physics/Loads.hpp"
#include "solvers/History.hpp"
#include "solvers/Integrator.hpp"

namespace impm {

using Point = std::array<double, 3>;
struct ExplicitOptions;  // solvers/ExplicitStepper.hpp
struct ImplicitOptions;  // solvers/implicit/ImplicitNewmark.hpp
class HistoryOutput;     // solvers/run/RunObservers.hpp
class RunObservers;      // (x, y, z); z = 0 in 2D

// Particles out of the grid (or of their rank's nodes), or a CPDI domain beyond its stencil: the
// run stops (Simulation::run's failure contract). `advice` says what to change.
struct ParticlesOutOfReach : std::runtime_error {
  ParticlesOutOfReach(const std::string& what, std::string advice)
      : std::runtime_error(what), advice(std::move(advice)) {}
  std::string advice;
};

// What the run loop, its observers, the report and the summary take from the deck, read once by
// the builder (ProblemSection.cpp, IntegratorSection.cpp).
struct RunSettings {
  std::string problemName;    // Problem/Name
  std::string shapeFunction;  // Method/Shape Function
  int historyInterval = 1;    // Output/...
  int historyDigits = 10;
  int vtkInterval = 0;
  int checkpointInterval = 0;
  bool progress = true;
  double stabilityFactor = 1.0;  // Integrator/Explicit/Stability Factor (for the time-step advice)
  bool updateSchemeUsl = false;  // Integrator/Explicit/Update Scheme = USL (for the time-step advice)
};

class Simulation {
 public:
  // `deck` must have been through validateDeck(). Throws DeckError for bad values.
  Simulation(const Teuchos::ParameterList& deck, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
             const std::string& outputDirectoryOverride = "");
  ~Simulation();

  // The after-step checks' figures (auditParticles).
  struct ParticleAudit {
    double divergence = 0.0;
    int outOfReach = 0;
  };

  // Integrates the deck's number of steps and writes the outputs. `log` gets the progress
  // line and the error report (rank 0).
  RunResult run(std::ostream& log);
  // Continues from the checkpoint in `dir` (solvers/Checkpoint.hpp; SimulationRestart.cpp):
  // reads and checks it against this deck (CheckpointError, exit 2, before anything is
  // written) and takes its particles and the integrator's state; run() then starts at its step
  // and rewrites history.csv from its rows. Collective; call before run().
  void restartFrom(const std::string& dir);

  const ParticleSet& particles() const { return particles_; }
  // The time integrator, as the last step left it (tests evaluate an implicit step's residual and
  // matrix after a run).
  Integrator& integrator() { return *integrator_; }
  const GridDistribution& distribution() const { return *dist_; }
  const Materials& materials() const { return materials_; }
  const std::vector<BodySpec>& bodies() const { return bodies_; }
  const std::string& outputDirectory() const { return outputDir_; }
  bool hasExact() const { return exact_ != nullptr; }
  double exactModulus() const { return exact_ ? exact_->modulus() : 0.0; }

 private:
  // The builder's phases, in the order the constructor runs them (solvers/build/<Section>Section.cpp).
  void readProblem(const std::string& outputOverride);
  void readGrid();
  void readMethod();
  void buildMaterials();
  void buildBodies();
  BodySpec readBody(const std::string& name, const Teuchos::ParameterList& entry);
  void readGeostaticStress(const std::string& key, const Teuchos::ParameterList& entry, BodySpec& body) const;
  double geostaticGravity(const std::string& key) const;
  void applyGeostaticStresses();
  void readRectangle(const std::string& key, const Teuchos::ParameterList& entry, BodySpec& body) const;
  void checkInsideGrid(const std::string& key, const BodySpec& body) const;
  void estimateBodySize(const BodySpec& body, size_t fileParticles);
  void readTime();
  void readOutputSettings();
  void distribute();
  void createParticlesAndConditions(const std::vector<ConstraintSpec>& cspecs);
  void readManufacturedSolution();
  void applyInitialConditions();
  void buildMonitors();
  void buildExactSolution(const std::vector<ConstraintSpec>& cspecs, const std::vector<LoadSpec>& lspecs);
  std::vector<ConstraintSpec> buildConstraints();
  std::vector<WallSpec> buildWalls() const;
  void checkParticlesBesideWalls(const std::vector<WallSpec>& walls) const;
  ContactSpec buildContact() const;  // ContactSection.cpp
  void checkContactUsable() const;
  void readRigidBodies(ContactSpec& spec) const;
  std::pair<int, int> contactPairBodies(const std::string& key, const std::string& value) const;
  TimeFunction timeFunctionOf(const Teuchos::ParameterList& list, const std::string& key) const;
  void readRigidMotion(const std::string& key, const Teuchos::ParameterList& b, BodySpec& body) const;
  void readMotion(const Teuchos::ParameterList& list, const std::string& key, ConstraintSpec& spec) const;
  void checkConditionOverlaps(const std::vector<ConstraintSpec>& specs) const;
  // A moving condition whose nodes no particle reaches moves nothing: refused (after the particles exist).
  void checkConditionsReached(const std::vector<ConstraintSpec>& specs) const;
  long long particlesReaching(const Point& lo, const Point& hi) const;
  std::vector<LoadSpec> buildLoads();
  void buildIntegrator();
  void makeIntegrator();
  ExplicitOptions readExplicitOptions(bool explicitRun);
  ImplicitOptions readImplicitOptions(bool fe) const;
  void noteLoadImbalance(RunResult& r) const;
  // Load balance: new cuts from the particle histograms; when they differ, adoptRankGrid. Returns
  // whether the cuts moved. Collective.
  bool rebalance();
  // Rebuilds everything that depends on the rank grid (maps, constraints, loads, integrator, whose
  // state is carried over; a Jacobian-free preconditioner is rebuilt), moving the particles to
  // their new ranks when `moveParticles`.
  void adoptRankGrid(const RankGrid& ranks, bool moveParticles);
  // The cuts in a checkpoint, and back (at the rank count that wrote them).
  void saveRankGrid(NamedArrays& state) const;
  void restoreRankGrid(const NamedArrays& state);
  // Over all ranks, in one pass over the particles: the largest |stress| / c11 of a particle (its
  // strain; +inf when a particle's velocity or stress is not finite, or it is inverted) and the
  // number of particles out of their rank's reach.
  ParticleAudit auditParticles() const;
  // Throws when particles left the grid or their rank's nodes (`total` over all ranks), and checks
  // CPDI domains.
  void reportParticlesOutOfReach(int total, double t) const;
  void checkParticlesInReach(double t) const;
  void checkCpdiDomainsInReach(double t) const;
  // Names the first particle (by global id) whose state is not finite or inverted, with its body.
  std::string describeBadParticle() const;
  // Above this the run has diverged: small-strain elasticity never reaches a strain of one.
  static constexpr double kDivergedStrain = 1.0;
  // What to change when the run diverged (the time step, with the explicit critical step).
  std::string timeStepAdvice() const;
  void writeSummary(const RunResult& r) const;
  void createOutputDirectory() const;
  void balanceLoad(History& history, RunResult& r);
  void redistribute(int step, const ParticleAudit& audit, History& history, RunResult& r);
  const HistoryOutput& addObservers(RunObservers& observers, History& history);
  std::string divergenceMessage(double divergence, int step, double t) const;
  void reportRun(const RunResult& r, std::ostream& log) const;
  // Output/Checkpoint Interval: the state after `step` (particles, integrator, history rows).
  void writeCheckpointAt(int step, const RunResult& r, const History& history) const;
  // The particle nearest a point at t = 0 over all ranks.
  void nearestParticle(const Point& point, Monitor& m) const;
  const BodySpec& bodyNamed(const std::string& key, const std::string& name) const;
  void checkGridNode(const std::string& where, double x, double y, double z) const;
  // X, Y (and Z in 3D) of a deck entry; "(x, y[, z])" for messages.
  Point pointOf(const Teuchos::ParameterList& list) const;
  std::string describePoint(const Point& p) const;
  // Deck errors found before anything is allocated or run: a grid or particle count beyond the
  // indices, or an estimated memory above the machine's (or Problem/Memory Limit GB).
  void checkProblemSize(bool implicit) const;
  // A Node Force on a grid node that no particle reaches at t = 0 (it would act on no mass).
  void checkNodeReached(const std::string& loadKey, const Point& point) const;
  // A point (Particle Force, monitor) farther than one cell diagonal from its nearest particle.
  void checkNearParticle(const std::string& what, const Point& point, const Monitor& nearest) const;

  // The validated deck: the builder's phases read it; a checkpoint stores it and a restart checks
  // against it (SimulationRestart.cpp). The run loop, observers and summary read settings_.
  Teuchos::ParameterList deck_;
  RunSettings settings_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  std::string outputDir_;
  std::string outputKey_;  // where outputDir_ comes from, for messages
  StructuredGrid grid_;
  double thickness_ = 1;
  Materials materials_;
  std::vector<std::string> materialNames_;
  std::vector<BodySpec> bodies_;
  std::vector<double> estimatedBodyParticles_, estimatedBodyCells_;  // per body, for checkProblemSize
  std::string shape_;                                                // Method/Shape Function
  bool fbar_ = false;                                                // Method/Volumetric Locking = F-bar
  Placement placement_ = Placement::Lattice;
  std::unique_ptr<GridDistribution> dist_;
  int migrationSlack_ = 0;  // Decomposition/Migration Slack Cells
  int loadBalanceInterval_ = 0;
  double loadBalanceThreshold_ = 1.1;
  std::vector<ConstraintSpec> constraintSpecs_;
  std::vector<WallSpec> wallSpecs_;
  ContactSpec contactSpec_;
  std::vector<LoadSpec> loadSpecs_;
  std::vector<long long> loadParticleIds_;
  ParticleSet particles_;
  GridConditions constraints_;
  LoadSet loads_;
  std::vector<Monitor> monitors_;
  std::unique_ptr<Integrator> integrator_;
  std::shared_ptr<const ExplicitOptions> explicitOptions_;  // read once from the deck
  std::shared_ptr<const ImplicitOptions> implicitOptions_;  // null for an explicit run
  std::unique_ptr<ExactReference> exact_;
  std::unique_ptr<AxisAlignedManufactured> manufactured_;  // Exact Solution/Type = Axis-Aligned Manufactured Solution
  double dt_ = 0;
  double criticalStep_ =
      0;  // explicit: 0.7 / (c_p sqrt(1/hx^2 + 1/hy^2 [+ 1/hz^2])) (Stability Factor 1); 0 for implicit runs
  int steps_ = 0;
  bool energyHistory_ = false;
  // Restart (restartFrom): the step run() starts at and the checkpoint's history rows.
  int restartStep_ = 0;
  bool restarted_ = false;
  NamedArrays restartState_;
};

}  // namespace impm
