// Monitors and the run's history: the monitored particle quantities (with their exact values)
// and, optionally, the energy and momentum sums, recorded every History Interval steps into
// history.csv (rank 0) and the RunResult; then the relative L2 errors and the energy and
// momentum drifts that summary.yaml reports.
#pragma once

#include <Teuchos_Comm.hpp>

#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/ParticleSet.hpp"
#include "physics/ExactReference.hpp"
#include "physics/GridConditions.hpp"
#include "physics/Materials.hpp"
#include "solvers/Integrator.hpp"

namespace impm {

// A particle quantity followed over the run: the particle nearest a point at t = 0, found by
// its global id.
struct Monitor {
  std::string name, quantity;
  long long particleId = -1;      // global id of the particle
  int owner = -1;                 // rank that holds the particle
  int localIndex = -1;            // its index on that rank
  double x0 = 0, y0 = 0, z0 = 0;  // its reference position (where the exact solution is evaluated)
};

struct RunResult {
  double wallSeconds = 0;
  long long particles = 0;
  int steps = 0;
  // The first step this run computed: 1, or k + 1 after a restart from a checkpoint at step k.
  int firstStep = 1;
  double particleStepsPerSecond = 0;
  // "completed", or why the run stopped early: "diverged", "newton failed", "left the grid".
  std::string status = "completed";
  // A run that stopped early (Simulation::run's failure contract): the step that failed, its
  // time and why, and the last good state: its step, time and VTU file (stem, in the output
  // directory). history.csv ends at the last good step's row.
  int failedStep = -1;
  double failedTime = 0;
  std::string failureReason;
  int lastGoodStep = -1;
  double lastGoodTime = 0;
  std::string lastGoodFile;
  // Particle migration between MPI ranks since this run (or restart) began, and the load
  // imbalance: the largest rank's particle count over the mean, at the end and at its worst.
  int migrations = 0, rebalances = 0;
  long long migratedParticles = 0;
  double loadImbalance = 1.0, loadImbalanceMax = 1.0;
  // The worst imbalance left right after a rebalance (0 before the first): what the balancer
  // achieves, as opposed to what migration between two checks brings back.
  double loadImbalanceAfterRebalanceMax = 0.0;
  // Peak resident memory of the process (getrusage), the largest rank's and the sum over ranks,
  // in bytes; set when the summary is written.
  double peakResidentBytesMax = 0, peakResidentBytesTotal = 0;
  std::map<std::string, double> relativeL2;  // monitor name -> relative L2 error over the history
  std::vector<double> time;                  // the recorded history
  std::map<std::string, std::vector<double>> computed, exact;
  // With Output/Energy And Momentum: per recorded time, and the drifts of summary.yaml.
  std::vector<double> kinetic, strain, momentumX, momentumY, momentumZ;
  // The grid conditions' reactions (the force each applies to the grid, per prescribed
  // component), per recorded time, by history.csv column (<condition>_reaction_<x|y|z>, in order).
  std::vector<std::string> reactionColumns;
  std::map<std::string, std::vector<double>> reactions;
  double energyRelativeDrift = 0, energyMaxRelativeDeviation = 0, momentumMaxRelativeChange = 0;
  // With an exact solution that knows the whole displacement field: per recorded time, the
  // volume-weighted RMS sqrt(sum V0 |u_p - u(X_p, t)|^2 / sum V0) and the largest particle error
  // over the field's body; then their values at the end and their peaks over the run.
  std::vector<double> fieldErrorRms, fieldErrorMax;
  double fieldErrorRmsEnd = 0, fieldErrorMaxEnd = 0, fieldErrorRmsPeak = 0, fieldErrorMaxPeak = 0;
  bool hasFieldError() const { return !fieldErrorRms.empty(); }
};

class History {
 public:
  // `exact` and `conditions` may be null. `firstTime` is a time at which the exact solution is
  // evaluated to find which monitors it has (NaN: none).
  History(std::vector<Monitor>& monitors, const ParticleSet& particles, const Materials& materials,
          const ExactReference* exact, bool energyAndMomentum, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
          double firstTime, const GridConditions* conditions = nullptr);

  // Rank 0 writes the header of `path`, values with `digits` significant digits; collective.
  void open(const std::string& path, int digits = 10);
  // One row at time t, into the file and into r. Collective.
  void record(double t, RunResult& r);
  void close();
  // Relative L2 errors and energy / momentum drifts of the recorded rows, into r.
  void finish(RunResult& r) const;
  // After particles migrate: each monitor's rank and local index from its global id.
  void locateMonitors();
  // Restart: the recorded rows of r (and the momentum scale) as named arrays for a checkpoint,
  // and back; replay() writes the restored rows into the file open() started, as record()
  // wrote them (so that a restarted run's history.csv is the uninterrupted run's).
  void saveState(const RunResult& r, NamedArrays& state) const;
  void restoreState(const NamedArrays& state, RunResult& r);
  void replay(const RunResult& r);

 private:
  double monitorValue(const Monitor& m) const;
  void writeRow(const RunResult& r, size_t row);  // rank 0
  // (RMS, max) of the particles' displacement error against the exact field at t. Collective.
  std::pair<double, double> displacementFieldError(double t) const;

  std::vector<Monitor>& monitors_;
  const ParticleSet& particles_;
  const Materials& materials_;
  const ExactReference* exact_;
  bool energy_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  std::vector<bool> withExact_;
  bool field_ = false;  // the exact solution knows the whole displacement field
  std::ofstream csv_;
  double momentumScale_ = 0;  // sum m |v| at the first row
  const GridConditions* conditions_ = nullptr;
  std::vector<std::string> reactionColumns_;
  std::vector<int> reactionIndex_;  // per column: condition x 3 + component in GridConditions::reactions
};

}  // namespace impm
