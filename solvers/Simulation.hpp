// One run of an input deck: builds the grid, particles, material, constraints, loads,
// monitors, exact solution and integrator from a validated deck (every semantic check
// happens here, before anything is written), then integrates and writes the outputs.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "physics/Body.hpp"
#include "physics/Constraints.hpp"
#include "physics/BeamTheories.hpp"
#include "physics/ExactSolutions.hpp"
#include "physics/LinearElastic.hpp"
#include "physics/Loads.hpp"
#include "solvers/Integrator.hpp"

namespace impm {

struct Monitor {
  std::string name, quantity;
  int owner = -1;          // rank that holds the particle
  int localIndex = -1;     // particle index on that rank
  double x0 = 0, y0 = 0;   // its reference position (where the exact solution is evaluated)
};

struct RunResult {
  double wallSeconds = 0;
  long long particles = 0;
  int steps = 0;
  double particleStepsPerSecond = 0;
  std::string status = "completed";
  std::map<std::string, double> relativeL2;  // monitor name -> relative L2 error over the history
  std::vector<double> time;                  // the recorded history
  std::map<std::string, std::vector<double>> computed, exact;
};

class Simulation {
 public:
  // `deck` must have been through validateDeck(). Throws DeckError for bad values.
  Simulation(const Teuchos::ParameterList& deck, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
             const std::string& outputDirectoryOverride = "");
  ~Simulation();

  // Integrates the deck's number of steps and writes the outputs. `log` gets the progress
  // line and the error report (rank 0).
  RunResult run(std::ostream& log);

  const ParticleSet& particles() const { return particles_; }
  const GridDistribution& distribution() const { return *dist_; }
  const LinearElastic& material() const { return material_; }
  const std::string& outputDirectory() const { return outputDir_; }
  double exactModulus() const { return exactModulus_; }

 private:
  bool hasExact() const { return exactType_ != "None"; }
  double monitorValue(const Monitor& m) const;
  void checkParticlesInReach(double t) const;
  double exactValue(const Monitor& m, double t) const;
  void writeSummary(const RunResult& r) const;

  Teuchos::ParameterList deck_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  std::string outputDir_;
  StructuredGrid grid_;
  LinearElastic material_;
  RectangularBody body_;
  std::string shape_;  // Method/Shape Function
  std::unique_ptr<GridDistribution> dist_;
  ParticleSet particles_;
  NodalConstraints constraints_;
  LoadSet loads_;
  std::vector<Monitor> monitors_;
  std::unique_ptr<Integrator> integrator_;
  double dt_ = 0;
  int steps_ = 0;
  std::string exactType_ = "None";
  double exactModulus_ = 0;
  BarStepExact bar_{};
  BarStandingWaveExact wave_{};
  BeamHarmonicExact beam_{};
  bool timoshenko_ = false;
  TimoshenkoBeamHarmonic timo_{};
  std::vector<std::vector<double>> newmarkHistory_;  // per monitor, per step (Time Discretisation: Newmark)
  bool exactSeries_ = false;
  int exactTerms_ = 2000;
  double neutralAxisY_ = 0;
};

}  // namespace impm
