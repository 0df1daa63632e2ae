// Simulation, part 2: the run loop (time steps, particle migration and load balance; the outputs
// are its observers, solvers/run/RunObservers.hpp; the after-step checks are SimulationAudit.cpp).
// Part 1 (SimulationBuilder.cpp) built the objects from the deck; part 3 (SimulationSummary.cpp)
// writes summary.yaml.
#include "solvers/Simulation.hpp"
#include "core/ShapeRegistry.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>

#include "core/Collective.hpp"
#include "core/CpdiDomainCheck.hpp"
#include "core/InputDeck.hpp"
#include "core/ParticleMigration.hpp"
#include "core/output/VtkWriter.hpp"
#include "solvers/History.hpp"
#include "solvers/implicit/ImplicitNewmark.hpp"
#include "solvers/run/RunObservers.hpp"

namespace impm {

using Teuchos::ParameterList;

Simulation::~Simulation() = default;

// The largest rank's particle count over the mean (particles move between ranks by migration only).
void Simulation::noteLoadImbalance(RunResult& r) const {
  const long long local = particles_.count;
  long long largest = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, local, Teuchos::outArg(largest));
  const double mean = double(r.particles) / comm_->getSize();
  r.loadImbalance = mean > 0 ? largest / mean : 1.0;
  r.loadImbalanceMax = std::max(r.loadImbalanceMax, r.loadImbalance);
}

// The run: outputs opened, the initial load balance, then per step
//   integrator step -> audit (diverged?) -> migration and load balance -> reach check -> observers
// (history rows, VTU, checkpoints, progress; solvers/run/RunObservers.hpp), and the report.
RunResult Simulation::run(std::ostream& log) {
  const int firstStep = restartStep_;
  createOutputDirectory();
  RunResult r;
  const long long localCount = particles_.count;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, localCount, Teuchos::outArg(r.particles));
  r.steps = steps_;
  r.firstStep = firstStep + 1;
  noteLoadImbalance(r);

  History history(monitors_, particles_, materials_, exact_.get(), energyHistory_, comm_, dt_, &constraints_);
  rethrowOnEveryRank(*comm_, true, [&] { history.open(outputDir_ + "/history.csv", settings_.historyDigits); });
  RunObservers observers;
  const HistoryOutput& historyOutput = addObservers(observers, history);

  // Load balance (Decomposition/Load Balance Interval): at the start and every interval steps.
  if (!restarted_) balanceLoad(history, r);

  observers.begin({firstStep, firstStep * dt_}, r);
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  // Every run that stops early ends alike (the failure contract, RunObservers.hpp); then one
  // message (exit 1). Collective: every rank reaches it together (the failures are decided on
  // reduced values).
  auto failRun = [&](int failedStep, const std::string& status, const std::string& reason, const std::string& advice,
                     bool stepNotTaken) -> std::runtime_error {
    r.status = status;
    r.failedStep = failedStep;
    r.failedTime = failedStep * dt_;
    r.failureReason = reason;
    r.steps = failedStep - 1;
    r.wallSeconds = std::chrono::duration<double>(clock::now() - start).count();
    observers.fail({failedStep, stepNotTaken}, r);
    std::string where =
        "; history.csv (to step " + std::to_string(historyOutput.lastRecordedStep()) + ") and summary.yaml";
    if (r.lastGoodStep >= 0)
      where += ", and the last good state (step " + std::to_string(r.lastGoodStep) +
               ", t = " + formatNumber(r.lastGoodTime) + " s) as " + r.lastGoodFile + "_r*.vtu,";
    return std::runtime_error(reason + (advice.empty() ? std::string() : "; " + advice) + where + " are in " +
                              outputDir_);
  };

  for (int n = firstStep; n < steps_; ++n) {
    try {
      integrator_->step(n * dt_, dt_);
    } catch (const NewtonNotConverged& e) {
      throw failRun(n + 1, "newton failed", e.what(), "", true);
    }
    const double tNew = (n + 1) * dt_;
    // Before migration and the reach check: a diverging run throws particles off the grid, and
    // that message would hide the cause. One reduction per step: an unstable explicit step
    // grows ~300x per step, leaving the grid within a few steps.
    const ParticleAudit audit = auditParticles();
    if (audit.divergence > kDivergedStrain)  // the last good state is the last history row's
      throw failRun(n + 1, "diverged", divergenceMessage(audit.divergence, n + 1, tNew), timeStepAdvice(), false);
    try {
      redistribute(n + 1, audit, history, r);
    } catch (const ParticlesOutOfReach& e) {
      throw failRun(n + 1, "left the grid", e.what(), e.advice, false);
    }
    observers.afterStep({n + 1, tNew}, r);
  }
  r.wallSeconds = std::chrono::duration<double>(clock::now() - start).count();
  r.particleStepsPerSecond = r.wallSeconds > 0 ? double(r.particles) * (steps_ - firstStep) / r.wallSeconds : 0.0;
  observers.end({steps_, steps_ * dt_}, r);
  if (comm_->getRank() == 0) reportRun(r, log);
  return r;
}

// The run's outputs, in the order they act: history rows, ParaView files (and the last good
// state), checkpoints, the progress line, the summary. Returns the history's, whose last row the
// failure message names.
const HistoryOutput& Simulation::addObservers(RunObservers& observers, History& history) {
  const int historyInterval = settings_.historyInterval;  // >= 1, checked by the builder
  auto& historyOutput =
      observers.add(std::make_unique<HistoryOutput>(history, restarted_, restartState_, historyInterval, steps_, dt_));
  observers.add(std::make_unique<ParticleOutput>(particles_, comm_, outputDir_, restarted_, settings_.vtkInterval,
                                                 historyInterval, steps_, dt_));
  observers.add(std::make_unique<CheckpointOutput>(
      settings_.checkpointInterval,
      [this, &history](int step, const RunResult& result) { writeCheckpointAt(step, result, history); }));
  observers.add(std::make_unique<ProgressLine>(settings_.progress && comm_->getRank() == 0, steps_));
  observers.add(std::make_unique<SummaryOutput>(comm_, [this](const RunResult& result) { writeSummary(result); }));
  return historyOutput;
}

// When the imbalance exceeds the threshold (and balancing is on): new cuts between the ranks.
// Monitors follow their particles by global id.
void Simulation::balanceLoad(History& history, RunResult& r) {
  if (loadBalanceInterval_ <= 0 || comm_->getSize() == 1 || r.loadImbalance <= loadBalanceThreshold_) return;
  if (!rebalance()) return;
  ++r.rebalances;
  history.locateMonitors();
  noteLoadImbalance(r);
  r.loadImbalanceAfterRebalanceMax = std::max(r.loadImbalanceAfterRebalanceMax, r.loadImbalance);
}

// After step `step`: particles migrate to their ranks (lazily, Migration Slack Cells), the load is
// balanced every Load Balance Interval steps, and every particle must still be within its rank's
// reach (throws ParticlesOutOfReach). The audit's reach count holds unless particles changed ranks.
void Simulation::redistribute(int step, const ParticleAudit& audit, History& history, RunResult& r) {
  bool particlesMoved = false;
  if (const long long moved = migrateParticles(particles_, *dist_, migrationSlack_); moved > 0) {
    particlesMoved = true;
    // Local indices changed: find the monitored and loaded particles by global id.
    loads_.locateParticles(particles_);
    history.locateMonitors();
    ++r.migrations;
    r.migratedParticles += moved;
    noteLoadImbalance(r);
  }
  if (loadBalanceInterval_ > 0 && step % loadBalanceInterval_ == 0) {
    const int before = r.rebalances;
    balanceLoad(history, r);
    particlesMoved = particlesMoved || r.rebalances != before;
  }
  if (particlesMoved)
    checkParticlesInReach(step * dt_);
  else
    reportParticlesOutOfReach(audit.outOfReach, step * dt_);
}

// Rank 0 creates the directory (checked when the deck was read); a failure ends every rank.
void Simulation::createOutputDirectory() const {
  rethrowOnEveryRank(*comm_, comm_->getRank() == 0, [&] {
    std::error_code ec;
    std::filesystem::create_directories(outputDir_, ec);
    if (ec) throw DeckError(outputKey_ + " = '" + outputDir_ + "' cannot be created: " + ec.message());
  });
}

// The closing lines: the run, its errors against the exact solution, the energy drift.
void Simulation::reportRun(const RunResult& r, std::ostream& log) const {
  log << settings_.problemName << ": " << integrator_->name() << ", " << materials_.planeName() << ", " << r.particles
      << " particles, " << steps_ << " steps in " << std::setprecision(3) << r.wallSeconds << " s ("
      << r.particleStepsPerSecond / 1e6 << " M particle-steps/s)\n";
  for (const auto& [name, err] : r.relativeL2)
    log << "  relative L2 error of " << name << " against the exact solution (modulus " << std::setprecision(4)
        << exactModulus() << " Pa): " << std::setprecision(3) << 100 * err << " %\n";
  if (r.hasFieldError())
    log << "  displacement field error against the exact solution: RMS " << std::setprecision(3) << r.fieldErrorRmsEnd
        << " m, max " << r.fieldErrorMaxEnd << " m at the end (peaks over the run " << r.fieldErrorRmsPeak << ", "
        << r.fieldErrorMaxPeak << " m)\n";
  if (energyHistory_)
    log << "  total energy drift " << std::setprecision(3) << r.energyRelativeDrift << " (max deviation "
        << r.energyMaxRelativeDeviation << "), momentum max relative change " << r.momentumMaxRelativeChange << "\n";
}

}  // namespace impm
