// What the run loop tells its outputs, and the outputs themselves. The loop (Simulation::run)
// takes the steps, audits them and redistributes the particles; after each completed step every
// observer in turn does its part: history rows, ParaView files, checkpoints, the progress line,
// and at the end (or when the run stops early) the summary.
//
// A run that stops early ends alike whatever the cause (Simulation::run's failure contract):
// history.csv up to the last good step's row, the last good particles as VTU, summary.yaml with
// the Status and the Failure. Each observer's fail() writes its part; they are called in order
// (history, particles, ..., summary) so that the summary sees what the others wrote.
#pragma once

#include <Teuchos_Comm.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/ParticleSet.hpp"
#include "core/output/VtkWriter.hpp"
#include "solvers/History.hpp"

namespace impm {

// Where the loop is: the step just completed (or, at begin(), the first step's index) and its time.
struct RunPoint {
  int step = 0;
  double t = 0.0;
};

// A run stopping early at `failedStep`. When `stepNotTaken` the failed step left the particles at
// the state before it (Newton failed), which is then the last good state; otherwise (a diverged
// state, particles out of the grid) the state kept at the last history row is.
struct RunFailure {
  int failedStep = 0;
  bool stepNotTaken = false;
};

class RunObserver {
 public:
  virtual ~RunObserver() = default;
  virtual void begin(const RunPoint& /*first*/, RunResult& /*r*/) {}
  virtual void afterStep(const RunPoint& /*done*/, RunResult& /*r*/) {}
  virtual void end(const RunPoint& /*last*/, RunResult& /*r*/) {}
  virtual void fail(const RunFailure& /*failure*/, RunResult& /*r*/) {}
};

// The observers of one run, called in order.
class RunObservers {
 public:
  template <class T>
  T& add(std::unique_ptr<T> observer) {
    T& ref = *observer;
    list_.push_back(std::move(observer));
    return ref;
  }
  void begin(const RunPoint& p, RunResult& r) {
    for (auto& o : list_) o->begin(p, r);
  }
  void afterStep(const RunPoint& p, RunResult& r) {
    for (auto& o : list_) o->afterStep(p, r);
  }
  void end(const RunPoint& p, RunResult& r) {
    for (auto& o : list_) o->end(p, r);
  }
  void fail(const RunFailure& f, RunResult& r) {
    for (auto& o : list_) o->fail(f, r);
  }

 private:
  std::vector<std::unique_ptr<RunObserver>> list_;
};

// history.csv: a row at the start (or the checkpoint's rows, replayed), every `interval` steps and
// at the last step; at the end the errors and drifts of RunResult.
class HistoryOutput : public RunObserver {
 public:
  HistoryOutput(History& history, bool restarted, const NamedArrays& restartState, int interval, int steps, double dt)
      : history_(history),
        restarted_(restarted),
        restartState_(restartState),
        interval_(interval),
        steps_(steps),
        dt_(dt) {}
  void begin(const RunPoint& first, RunResult& r) override;
  void afterStep(const RunPoint& done, RunResult& r) override;
  void end(const RunPoint& last, RunResult& r) override;
  void fail(const RunFailure& failure, RunResult& r) override;
  int lastRecordedStep() const { return lastRecordedStep_; }

 private:
  History& history_;
  bool restarted_;
  const NamedArrays& restartState_;
  int interval_, steps_;
  double dt_;
  int lastRecordedStep_ = 0;  // the step of history.csv's last row
};

// particles.pvd and its VTU files: at the start, every `interval` steps (0: none) and at the end.
// It also keeps the state at each history row (packed as for migration, every history interval
// rather than every step, so that the explicit hot loop stays as it is): when a later step
// diverges, that is written as the last good state. The FE reference's fixed Gauss points, which
// neither move nor invert, are not kept.
class ParticleOutput : public RunObserver {
 public:
  ParticleOutput(ParticleSet& particles, const Teuchos::RCP<const Teuchos::Comm<int>>& comm, const std::string& dir,
                 bool restarted, int vtkInterval, int historyInterval, int steps, double dt);
  void begin(const RunPoint& first, RunResult& r) override;
  void afterStep(const RunPoint& done, RunResult& r) override;
  void end(const RunPoint& last, RunResult& r) override;
  void fail(const RunFailure& failure, RunResult& r) override;

 private:
  std::string write(const ParticleSet& ps, double t);  // one VTU per rank and the index; collective
  void relistRestartedFiles(int firstStep);
  void keepState(double t, int step);
  std::string writeGoodState();

  ParticleSet& particles_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  std::string dir_;
  bool restarted_;
  int vtkInterval_, historyInterval_, steps_;
  double dt_;
  PvdIndex pvd_;
  int count_ = 0;
  bool keepGoodState_;
  ParticleSet::Packed goodState_;
  ParticleSet::Ids everyParticle_;
  double goodTime_ = 0;
  int goodStep_ = 0;
};

// Checkpoints every `interval` steps (0: none), through the simulation's writer.
class CheckpointOutput : public RunObserver {
 public:
  using Writer = std::function<void(int step, const RunResult& r)>;
  CheckpointOutput(int interval, Writer writer) : interval_(interval), writer_(std::move(writer)) {}
  void afterStep(const RunPoint& done, RunResult& r) override {
    if (interval_ > 0 && done.step % interval_ == 0) writer_(done.step, r);
  }

 private:
  int interval_;
  Writer writer_;
};

// The progress line on rank 0 (stderr): after 3 s, every 0.5 s on a terminal (one line, rewritten)
// or every 10 s otherwise.
class ProgressLine : public RunObserver {
 public:
  ProgressLine(bool enabled, int steps) : enabled_(enabled), steps_(steps) {}
  void begin(const RunPoint& first, RunResult& r) override;
  void afterStep(const RunPoint& done, RunResult& r) override;
  void end(const RunPoint& last, RunResult& r) override;

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  int steps_, firstStep_ = 0;
  bool tty_ = false, printed_ = false;
  Clock::time_point start_, lastPrint_;
};

// summary.yaml at the end or on failure, with the peak resident memory of the ranks.
class SummaryOutput : public RunObserver {
 public:
  using Writer = std::function<void(const RunResult& r)>;
  SummaryOutput(const Teuchos::RCP<const Teuchos::Comm<int>>& comm, Writer writer)
      : comm_(comm), writer_(std::move(writer)) {}
  void end(const RunPoint&, RunResult& r) override { write(r); }
  void fail(const RunFailure&, RunResult& r) override { write(r); }

 private:
  void write(RunResult& r);  // collective
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  Writer writer_;
};

}  // namespace impm
