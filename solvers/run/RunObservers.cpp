#include "solvers/run/RunObservers.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "core/Collective.hpp"

namespace impm {

// ---- history.csv ------------------------------------------------------------------------------

void HistoryOutput::begin(const RunPoint& first, RunResult& r) {
  lastRecordedStep_ = first.step;
  if (restarted_) {
    // The checkpoint's rows, as the interrupted run wrote them.
    history_.restoreState(restartState_, r);
    history_.locateMonitors();
    history_.replay(r);
  } else {
    history_.record(0.0, r);
  }
}

void HistoryOutput::afterStep(const RunPoint& done, RunResult& r) {
  if (done.step % interval_ != 0 && done.step != steps_) return;
  history_.record(done.t, r);
  lastRecordedStep_ = done.step;
}

void HistoryOutput::end(const RunPoint&, RunResult& r) {
  history_.close();
  history_.finish(r);
}

void HistoryOutput::fail(const RunFailure& failure, RunResult& r) {
  if (failure.stepNotTaken && lastRecordedStep_ < failure.failedStep - 1) {
    history_.record((failure.failedStep - 1) * dt_, r);
    lastRecordedStep_ = failure.failedStep - 1;
  }
  history_.close();
}

// ---- ParaView ---------------------------------------------------------------------------------

ParticleOutput::ParticleOutput(ParticleSet& particles, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                               const std::string& dir, bool restarted, int vtkInterval, int historyInterval, int steps,
                               double dt)
    : particles_(particles),
      comm_(comm),
      dir_(dir),
      restarted_(restarted),
      vtkInterval_(vtkInterval),
      historyInterval_(historyInterval),
      steps_(steps),
      dt_(dt),
      pvd_(dir + "/particles.pvd", comm->getSize()),
      keepGoodState_(!particles.fixedPositions()) {}

std::string ParticleOutput::write(const ParticleSet& ps, double t) {
  char stem[64];
  std::snprintf(stem, sizeof stem, "particles_%05d", count_++);
  // Each rank writes its piece, then rank 0 the index; a failure on any rank ends them all.
  const int rank = comm_->getRank();
  rethrowOnEveryRank(*comm_, true, [&] { writeParticlesVtu(dir_ + "/" + PvdIndex::pieceName(stem, rank), ps); });
  rethrowOnEveryRank(*comm_, rank == 0, [&] { pvd_.add(t, stem); });
  return std::string(stem);
}

// A restarted run: the checkpoint's VTU files that are in this output directory stay listed in
// particles.pvd, and the new ones continue their numbering.
void ParticleOutput::relistRestartedFiles(int firstStep) {
  namespace fs = std::filesystem;
  for (int m = 0; m <= firstStep; ++m) {
    if (m > 0 && (vtkInterval_ <= 0 || m % vtkInterval_ != 0 || m == steps_)) continue;
    char stem[64];
    std::snprintf(stem, sizeof stem, "particles_%05d", count_++);
    rethrowOnEveryRank(*comm_, comm_->getRank() == 0, [&] {
      bool present = true;
      for (int q = 0; q < comm_->getSize(); ++q)
        present = present && fs::exists(dir_ + "/" + PvdIndex::pieceName(stem, q));
      if (present) pvd_.add(m * dt_, stem);
    });
  }
}

void ParticleOutput::keepState(double t, int step) {
  if (!keepGoodState_) return;
  if ((int)everyParticle_.extent(0) != particles_.count) {
    everyParticle_ = ParticleSet::Ids("every_particle", particles_.count);
    auto all = everyParticle_;
    Kokkos::parallel_for(
        "iota", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count), KOKKOS_LAMBDA(int p) { all(p) = p; });
  }
  if ((int)goodState_.extent(0) != particles_.count || (int)goodState_.extent(1) != particles_.packedWidth())
    goodState_ = ParticleSet::Packed(Kokkos::view_alloc(Kokkos::WithoutInitializing, "good_state"), particles_.count,
                                     particles_.packedWidth());
  particles_.pack(everyParticle_, goodState_);
  Kokkos::fence();
  goodTime_ = t;
  goodStep_ = step;
}

std::string ParticleOutput::writeGoodState() {
  ParticleSet good;
  good.dim = particles_.dim;
  if (particles_.hasHistory()) {
    good.historyAllocated = true;
    good.history = ParticleSet::Hist("history", 0, ParticleSet::kHistoryCount);
  }
  if (particles_.hasAffine()) {  // the rows carry C_p (APIC, TPIC): read them as they were packed
    good.affineAllocated = true;
    good.affine = ParticleSet::Mat("affine", 0, good.dim, good.dim);
  }
  good.resize(0);
  good.unpackAppend(goodState_);
  Kokkos::fence();
  return write(good, goodTime_);
}

void ParticleOutput::begin(const RunPoint& first, RunResult&) {
  if (restarted_)
    relistRestartedFiles(first.step);
  else
    write(particles_, 0.0);
  keepState(first.t, first.step);
}

void ParticleOutput::afterStep(const RunPoint& done, RunResult&) {
  if (done.step % historyInterval_ == 0 || done.step == steps_) keepState(done.t, done.step);
  if (vtkInterval_ > 0 && done.step % vtkInterval_ == 0 && done.step != steps_) write(particles_, done.t);
}

void ParticleOutput::end(const RunPoint& last, RunResult&) { write(particles_, last.t); }

void ParticleOutput::fail(const RunFailure& failure, RunResult& r) {
  if (failure.stepNotTaken) {
    const double t = (failure.failedStep - 1) * dt_;
    r.lastGoodStep = failure.failedStep - 1;
    r.lastGoodTime = t;
    r.lastGoodFile = write(particles_, t);
  } else if (keepGoodState_) {
    r.lastGoodStep = goodStep_;
    r.lastGoodTime = goodTime_;
    r.lastGoodFile = writeGoodState();
  }
}

// ---- Progress ---------------------------------------------------------------------------------

void ProgressLine::begin(const RunPoint& first, RunResult&) {
  firstStep_ = first.step;
  tty_ = isatty(fileno(stderr));
  start_ = lastPrint_ = Clock::now();
}

void ProgressLine::afterStep(const RunPoint& done, RunResult&) {
  if (!enabled_) return;
  const auto now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double sinceLast = std::chrono::duration<double>(now - lastPrint_).count();
  if (elapsed <= 3.0 || sinceLast <= (tty_ ? 0.5 : 10.0)) return;
  const double eta = elapsed / (done.step - firstStep_) * (steps_ - done.step);
  std::fprintf(stderr, "%sstep %d/%d  t = %.4e s  %3.0f%%  elapsed %.1f s  ETA %.1f s%s", tty_ ? "\r" : "", done.step,
               steps_, done.t, 100.0 * done.step / steps_, elapsed, eta, tty_ ? "   " : "\n");
  lastPrint_ = now;
  printed_ = true;
}

void ProgressLine::end(const RunPoint&, RunResult&) {
  if (printed_ && tty_) std::fprintf(stderr, "\n");
}

// ---- summary.yaml -----------------------------------------------------------------------------

void SummaryOutput::write(RunResult& r) {
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  const double bytes = 1024.0 * double(usage.ru_maxrss);  // ru_maxrss is in KiB on Linux
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, bytes, Teuchos::outArg(r.peakResidentBytesMax));
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, bytes, Teuchos::outArg(r.peakResidentBytesTotal));
  rethrowOnEveryRank(*comm_, comm_->getRank() == 0, [&] { writer_(r); });
}

}  // namespace impm
