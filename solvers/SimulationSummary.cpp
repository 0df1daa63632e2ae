// Simulation, part 3: summary.yaml (the keys are listed in doc/user-guide.md, "Outputs").
#include "solvers/Simulation.hpp"

#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include <filesystem>

#include "core/PhaseTimer.hpp"

namespace impm {

using Teuchos::ParameterList;

namespace {

void addFailure(ParameterList& s, const RunResult& r) {
  if (r.failedStep >= 0) {
    ParameterList& d = s.sublist("Failure");
    d.set("Step", r.failedStep);
    d.set("Time", r.failedTime);
    d.set("Reason", r.failureReason);
    d.set("Last Good Step", r.lastGoodStep);
    d.set("Last Good Time", r.lastGoodTime);
    d.set("Last Good State",
          r.lastGoodFile.empty() ? std::string("none") : r.lastGoodFile + "_r*.vtu (in particles.pvd)");
  }
}

// The force each grid condition applied to the grid at the last recorded step, and its largest
// magnitude over the run (per prescribed component).
void addReactions(ParameterList& s, const RunResult& r) {
  if (!r.reactionColumns.empty() && !r.time.empty()) {
    ParameterList& reactions = s.sublist("Reactions");
    for (const std::string& column : r.reactionColumns) {
      const std::vector<double>& values = r.reactions.at(column);
      ParameterList& c = reactions.sublist(column);
      c.set("Final", values.back());
      double peak = 0;
      for (double v : values) peak = std::abs(v) > std::abs(peak) ? v : peak;
      c.set("Peak", peak);
    }
  }
}

void addEnergyAndMomentum(ParameterList& s, const RunResult& r, int dim) {
  if (!r.time.empty()) {
    ParameterList& e = s.sublist("Energy");
    e.set("Initial Total", r.kinetic.front() + r.strain.front());
    e.set("Final Total", r.kinetic.back() + r.strain.back());
    e.set("Total Relative Drift", r.energyRelativeDrift);
    e.set("Max Relative Deviation", r.energyMaxRelativeDeviation);
    ParameterList& m = s.sublist("Momentum");
    m.set("Initial X", r.momentumX.front());
    m.set("Initial Y", r.momentumY.front());
    m.set("Final X", r.momentumX.back());
    m.set("Final Y", r.momentumY.back());
    if (dim == 3) {
      m.set("Initial Z", r.momentumZ.front());
      m.set("Final Z", r.momentumZ.back());
    }
    m.set("Max Relative Change", r.momentumMaxRelativeChange);
  }
}

// Where each monitor sits (its particle's reference position), so that studies can evaluate
// other reference solutions at the same point.
void addMonitors(ParameterList& s, const std::vector<Monitor>& monitors, int dim) {
  ParameterList& mons = s.sublist("Monitors");
  for (const auto& m : monitors) {
    ParameterList& e = mons.sublist(m.name);
    e.set("Quantity", m.quantity);
    e.set("Particle Id", (long long)m.particleId);
    e.set("X", m.x0);
    e.set("Y", m.y0);
    if (dim == 3) e.set("Z", m.z0);
  }
}

}  // namespace

void Simulation::writeSummary(const RunResult& r) const {
  ParameterList s("summary");
  s.set("Problem", settings_.problemName);
  s.set("Method", settings_.shapeFunction);
  s.set("Integrator", integrator_->name());
  s.set("Plane Condition", materials_.planeName());
  s.set("Bodies", (int)bodies_.size());
  s.set("Materials", materials_.count());
  s.set("Particles", (int)r.particles);
  s.set("Steps", r.steps);
  s.set("First Step", r.firstStep);  // 1, or the checkpoint's step + 1 after a restart
  s.set("Time Step", dt_);
  s.set("End Time", dt_ * r.steps);
  s.set("MPI Ranks", comm_->getSize());
  {
    const RankGrid& ranks = dist_->rankGrid();
    ParameterList& d = s.sublist("Decomposition");
    std::string shape = std::to_string(ranks.dims(0)) + " x " + std::to_string(ranks.dims(1));
    if (grid_.dim == 3) shape += " x " + std::to_string(ranks.dims(2));
    d.set("Rank Grid", shape);
    d.set("Migration Slack Cells", migrationSlack_);
    d.set("Migrations", r.migrations);
    d.set("Migrated Particles", (long long)r.migratedParticles);
    d.set("Load Balance Interval", loadBalanceInterval_);
    d.set("Rebalances", r.rebalances);
    d.set("Load Imbalance", r.loadImbalance);
    d.set("Load Imbalance Max", r.loadImbalanceMax);
    if (r.rebalances > 0) d.set("Load Imbalance After Rebalance Max", r.loadImbalanceAfterRebalanceMax);
  }
  s.set("Threads", (int)ExecutionSpace::concurrency());
  s.set("Execution Space", std::string(ExecutionSpace::name()));
  s.set("Wall Time", r.wallSeconds);
  s.set("Particle Steps Per Second", r.particleStepsPerSecond);
  s.set("Peak Resident Bytes Per Rank Max", r.peakResidentBytesMax);
  s.set("Peak Resident Bytes Total", r.peakResidentBytesTotal);
  s.set("Status", r.status);
  addFailure(s, r);
  s.set("Exact Solution", exact_ ? exact_->type() : std::string("None"));
  if (exact_) {
    s.set("Exact Modulus", exact_->modulus());
    exact_->addSummary(s);
    ParameterList& err = s.sublist("Relative L2 Error");
    for (const auto& [name, e] : r.relativeL2) err.set(name, e);
    if (r.hasFieldError()) {
      ParameterList& f = s.sublist("Displacement Field Error");
      f.set("RMS At End", r.fieldErrorRmsEnd);
      f.set("Max At End", r.fieldErrorMaxEnd);
      f.set("Peak RMS", r.fieldErrorRmsPeak);
      f.set("Peak Max", r.fieldErrorMaxPeak);
    }
  }
  addReactions(s, r);
  if (energyHistory_) addEnergyAndMomentum(s, r, grid_.dim);
  addMonitors(s, monitors_, grid_.dim);
  integrator_->addStatistics(s);
  if (PhaseTimer::enabled()) {
    // Rank 0's totals in seconds (impm --timers prints min/mean/max over ranks).
    ParameterList& timers = s.sublist("Timers");
    for (const auto& [name, timer] : PhaseTimer::timers()) timers.set(name, timer->totalElapsedTime());
  }
  const std::string path = outputDir_ + "/summary.yaml";
  Teuchos::writeParameterListToYamlFile(s, path + ".tmp");
  std::filesystem::rename(path + ".tmp", path);
}

}  // namespace impm
