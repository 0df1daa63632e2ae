// Simulation, part 2: the run loop (time steps, audits, particle migration and load balance; the
// outputs are its observers, solvers/run/RunObservers.hpp). Part 1 (SimulationBuilder.cpp) built the objects from the
// deck; part 3 (SimulationSummary.cpp) writes summary.yaml.
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

namespace {

// Where a rank's particles may be. A rank maps its particles onto its ghosted box of nodes; after
// migration every particle is within the migration slack of its rank's box, so this catches
// particles that left the grid (or a ghost band too narrow). Between ranks, stencils reach one
// cell beyond the particle domain's cells. At the grid's own edges a particle's centre must stay
// inside: an MPM point beyond the last node line loses the partition of unity (its weights no
// longer sum to 1), and a GIMP domain is clipped to the grid, which keeps at least half of it
// (ParticleStencil).
struct ParticleReach {
  double lo[3], hi[3];
  bool lowEdge[3], highEdge[3];
  int dim;
  ParticleReach(const StructuredGrid& g, const LocalNodeIndexer& ix) : lo{}, hi{}, lowEdge{}, highEdge{}, dim(g.dim) {
    for (int d = 0; d < dim; ++d) {
      lowEdge[d] = ix.lo[d] == 0;
      highEdge[d] = ix.end(d) - 1 >= g.cells(d);
      lo[d] = lowEdge[d] ? g.origin(d) : g.origin(d) + (ix.lo[d] + 1) * g.spacing(d);
      hi[d] = highEdge[d] ? g.origin(d) + g.cells(d) * g.spacing(d) : g.origin(d) + (ix.end(d) - 2) * g.spacing(d);
    }
  }
  template <class Vec>
  KOKKOS_INLINE_FUNCTION bool contains(const Vec& x, const Vec& hs, int p) const {
    bool inside = true;
    for (int d = 0; d < dim; ++d) {
      const double a = lowEdge[d] ? x(p, d) : x(p, d) - hs(p, d);
      const double b = highEdge[d] ? x(p, d) : x(p, d) + hs(p, d);
      inside = inside && a >= lo[d] && b <= hi[d];
    }
    return inside;
  }
};

// The after-step checks in one pass over the particles (they were two, 15-17% of an explicit
// run's time): the divergence measure (largest |stress| / c11, +inf for a non-finite or inverted
// particle) and the number of particles out of the rank's reach.
struct AuditParticles {
  using value_type = Simulation::ParticleAudit;
  ParticleSet::Vec x, halfSize, v;
  ParticleSet::Stress stress;
  ParticleSet::Scal volume;
  ParticleSet::Ids material;
  MaterialLaw law;
  ParticleReach reach;
  int dim, ns;
  bool fixedVolumes;

  KOKKOS_INLINE_FUNCTION void init(value_type& a) const { a = value_type{}; }
  KOKKOS_INLINE_FUNCTION void join(value_type& a, const value_type& b) const {
    a.divergence = b.divergence > a.divergence ? b.divergence : a.divergence;
    a.outOfReach += b.outOfReach;
  }
  KOKKOS_INLINE_FUNCTION void join(volatile value_type& a, const volatile value_type& b) const {
    a.divergence = b.divergence > a.divergence ? b.divergence : a.divergence;
    a.outOfReach += b.outOfReach;
  }
  KOKKOS_INLINE_FUNCTION void operator()(int p, value_type& a) const {
    // Non-finite values count as infinitely large. Small strain: |stress| / c11 is the size of
    // the strain. Finite strain: stresses of order c11 are legitimate, and the end of the run is
    // an inverted particle (det F <= 0), which also counts as infinite.
    double sum = 0.0, largest = 0.0;
    for (int d = 0; d < dim; ++d) sum += v(p, d);
    for (int i = 0; i < ns; ++i) {
      sum += stress(p, i);
      largest = std::fmax(largest, std::fabs(stress(p, i)));
    }
    const int m = material(p);
    const bool finiteStrain = law.finiteStrain(m);
    // NaN and Inf propagate into the sum; NaN fails every comparison, so test finiteness.
    const bool bad = !std::isfinite(sum) || (finiteStrain && !fixedVolumes && !(volume(p) > 0.0));
    const double measure = bad ? HUGE_VAL : finiteStrain ? 0.0 : largest / law.table(m, MaterialLaw::C11);
    a.divergence = measure > a.divergence ? measure : a.divergence;
    if (!reach.contains(x, halfSize, p)) ++a.outOfReach;
  }
};

}  // namespace

Simulation::ParticleAudit Simulation::auditParticles() const {
  const AuditParticles audit{particles_.x,
                             particles_.halfSize,
                             particles_.v,
                             particles_.stress,
                             particles_.volume,
                             particles_.material,
                             materials_.law(),
                             ParticleReach(grid_, dist_->ghostedIndexer()),
                             particles_.dim,
                             particles_.stressCount(),
                             particles_.fixedPositions()};
  ParticleAudit local;
  Kokkos::parallel_reduce("particle_audit", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count), audit, local);
  ParticleAudit global;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, local.divergence, Teuchos::outArg(global.divergence));
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, local.outOfReach, Teuchos::outArg(global.outOfReach));
  return global;
}

void Simulation::checkParticlesInReach(double t) const { reportParticlesOutOfReach(auditParticles().outOfReach, t); }

void Simulation::reportParticlesOutOfReach(int total, double t) const {
  if (total > 0)
    throw ParticlesOutOfReach(
        std::to_string(total) +
            " particle(s) left the grid or the nodes their MPI rank maps at t = " + formatNumber(t) + " s",
        "use a larger grid");
  if (shapeInfo(shape_).cornerDomains) checkCpdiDomainsInReach(t);
}

// CPDI domains: at most 4 nodes per direction (CpdiStencil.hpp), inside the rank's node columns.
void Simulation::checkCpdiDomainsInReach(double t) const {
  const CpdiDomainReport r = grid_.dim == 3
                                 ? checkCpdiDomains<ExecutionSpace, 3>(grid_, dist_->ghostedIndexer(), particles_)
                                 : checkCpdiDomains<ExecutionSpace, 2>(grid_, dist_->ghostedIndexer(), particles_);
  int local[2] = {r.tooLarge, r.outOfReach}, total[2] = {0, 0};
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, 2, local, total);
  if (total[0] + total[1] == 0) return;
  const long long mine = r.firstId >= 0 ? r.firstId : std::numeric_limits<long long>::max();
  long long first = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, mine, Teuchos::outArg(first));
  throw ParticlesOutOfReach(
      "at t = " + formatNumber(t) + " s the CPDI domain of particle " + std::to_string(first) + " (global id) " +
          (total[0] > 0
               ? "spans more than 3 cells in a direction (its corners x_p +- F l0 e_i need more than 4 nodes; " +
                     std::to_string(total[0]) + " particle(s))"
               : "reaches beyond the node columns its MPI rank maps (" + std::to_string(total[1]) + " particle(s))"),
      total[0] > 0 ? "use more particles per cell or a coarser grid" : "use fewer MPI ranks");
}

std::string Simulation::describeBadParticle() const {
  // The lowest global id among the particles with a non-finite state or det F <= 0, over all
  // ranks; then its owner describes it.
  auto v = particles_.v;
  auto stress = particles_.stress;
  auto V = particles_.volume;
  auto id = particles_.id;
  const int dim = particles_.dim, ns = particles_.stressCount();
  const bool fixedVolumes = particles_.fixedPositions();
  long long localFirst = std::numeric_limits<long long>::max();
  Kokkos::parallel_reduce(
      "find_bad_particle", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count),
      KOKKOS_LAMBDA(int p, long long& first) {
        double sum = 0.0;
        for (int d = 0; d < dim; ++d) sum += v(p, d);
        for (int i = 0; i < ns; ++i) sum += stress(p, i);
        const bool bad = !std::isfinite(sum) || (!fixedVolumes && !(V(p) > 0.0));
        if (bad && id(p) < first) first = id(p);
      },
      Kokkos::Min<long long>(localFirst));
  long long first = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, localFirst, Teuchos::outArg(first));
  std::string here;
  if (first == localFirst && first != std::numeric_limits<long long>::max()) {
    auto hid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.id);
    auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
    auto hx0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x0);
    auto hV = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.volume);
    auto hV0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.volume0);
    auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.body);
    for (int p = 0; p < particles_.count; ++p) {
      if (hid(p) != first) continue;
      std::ostringstream os;
      auto point = [&](const auto& view) {
        std::string s = "(";
        for (int d = 0; d < dim; ++d) s += (d ? ", " : "") + formatNumber(view(p, d));
        return s + ")";
      };
      os << "particle " << first << " of body '" << bodies_[hb(p)].name << "' (reference position " << point(hx0)
         << ", now at " << point(hx) << ")";
      if (!fixedVolumes && !(hV(p) > 0.0))
        os << " is inverted: det F = " << formatNumber(hV(p) / hV0(p));
      else
        os << " has a velocity or stress that is not finite";
      here = os.str();
    }
  }
  // The owner's description to every rank (rank of the owner is the one with a non-empty string).
  int length = (int)here.size(), longest = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, length, Teuchos::outArg(longest));
  std::vector<int> mine(longest + 1, 0), all(longest + 1, 0);
  std::copy(here.begin(), here.end(), mine.begin());
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, longest + 1, mine.data(), all.data());
  return std::string(all.begin(), std::find(all.begin(), all.end(), 0));
}

std::string Simulation::timeStepAdvice() const {
  const std::string step = "'Integrator/Time Step' = " + formatNumber(dt_) + " s";
  if (criticalStep_ <= 0) return "reduce " + step;
  if (dt_ > criticalStep_)
    return "reduce " + step + ": it is " + formatNumber(dt_ / criticalStep_) + " times the stable step " +
           formatNumber(criticalStep_) +
           " s of these cells and particles, allowed by 'Integrator/Explicit/Stability Factor' = " +
           formatNumber(deck_.sublist("Integrator").sublist("Explicit").get<double>("Stability Factor")) +
           " (keep it at most 1)";
  std::string advice =
      "reduce " + step + " (the stable step of these cells and particles is " + formatNumber(criticalStep_) + " s)";
  // Within the stable step, linear MPM with USL still inverts a particle that crosses alone into
  // a cell (its far nodes' tiny mass takes a huge velocity; doc/method.md, "Cell crossing: MPM against GIMP"): a
  // smaller step only makes that rarer.
  if (shape_ == "MPM" && deck_.sublist("Integrator").sublist("Explicit").get<std::string>("Update Scheme") == "USL")
    advice +=
        ", or, if a particle crossed a cell line alone (impact, a moving free surface), use 'Method/Shape Function' = "
        "GIMP (or cpGIMP, CPDI, a B-spline) or 'Integrator/Explicit/Update Scheme' = MUSL: linear MPM with USL "
        "can invert such a particle at any time step";
  return advice;
}

// The run: outputs opened, the initial load balance, then per step
//   integrator step -> audit (diverged?) -> migration and load balance -> reach check -> observers
// (history rows, VTU, checkpoints, progress; solvers/run/RunObservers.hpp), and the report.
RunResult Simulation::run(std::ostream& log) {
  const ParameterList& out = deck_.sublist("Output");
  const int firstStep = restartStep_;
  createOutputDirectory();
  RunResult r;
  const long long localCount = particles_.count;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, localCount, Teuchos::outArg(r.particles));
  r.steps = steps_;
  r.firstStep = firstStep + 1;
  noteLoadImbalance(r);

  History history(monitors_, particles_, materials_, exact_.get(), energyHistory_, comm_, dt_, &constraints_);
  rethrowOnEveryRank(*comm_, true, [&] { history.open(outputDir_ + "/history.csv", out.get<int>("History Digits")); });
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
  const ParameterList& out = deck_.sublist("Output");
  const int historyInterval = out.get<int>("History Interval");  // >= 1, checked by the builder
  auto& historyOutput =
      observers.add(std::make_unique<HistoryOutput>(history, restarted_, restartState_, historyInterval, steps_, dt_));
  observers.add(std::make_unique<ParticleOutput>(particles_, comm_, outputDir_, restarted_,
                                                 out.get<int>("VTK Interval"), historyInterval, steps_, dt_));
  observers.add(std::make_unique<CheckpointOutput>(
      out.get<int>("Checkpoint Interval"),
      [this, &history](int step, const RunResult& result) { writeCheckpointAt(step, result, history); }));
  observers.add(std::make_unique<ProgressLine>(out.get<bool>("Progress") && comm_->getRank() == 0, steps_));
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

// Why the state of `step` is bad: a non-finite or inverted particle (named), or a strain of order one.
std::string Simulation::divergenceMessage(double divergence, int step, double t) const {
  std::string why;
  if (std::isinf(divergence)) {
    const std::string which = describeBadParticle();
    why = which.empty() ? std::string("a particle velocity or stress is not finite") : which;
  } else {
    why = "a particle stress is " + formatNumber(divergence) +
          " times its material's P-wave modulus (a strain of order one)";
  }
  return "the run diverged at step " + std::to_string(step) + " (t = " + formatNumber(t) + " s): " + why;
}

// The closing lines: the run, its errors against the exact solution, the energy drift.
void Simulation::reportRun(const RunResult& r, std::ostream& log) const {
  log << deck_.sublist("Problem").get<std::string>("Name") << ": " << integrator_->name() << ", "
      << materials_.planeName() << ", " << r.particles << " particles, " << steps_ << " steps in "
      << std::setprecision(3) << r.wallSeconds << " s (" << r.particleStepsPerSecond / 1e6 << " M particle-steps/s)\n";
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
