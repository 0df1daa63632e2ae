// The implicit run's solver statistics for summary.yaml: Newton iterations per step, GMRES
// iterations per Newton iteration, the residual history of the hardest step, the residual
// evaluations and where the time went.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <vector>

#include "solvers/Integrator.hpp"
#include "solvers/newton/NewtonSolver.hpp"

namespace impm {

class ImplicitStatistics {
 public:
  // Every Newton solve, converged or not: its cost.
  void recordAttempt(const NewtonResult& result, double secondsSetUp, double secondsSolve) {
    secondsSetUp_ += secondsSetUp;
    secondsSolve_ += secondsSolve;
    secondsSolverSetUp_ += result.setupSeconds;
    residualEvaluations_ += result.residualEvaluations;
  }
  // A converged step: its iterations.
  void recordStep(const NewtonResult& result, double secondsFinish);

  const std::vector<int>& newtonIterationsPerStep() const { return newtonPerStep_; }
  const std::vector<int>& krylovIterationsPerNewton() const { return krylovPerNewton_; }

  // The "Solver" entries, in the summary's order: iterations, then (after the caller's halvings and
  // assemblies) the hardest step, then the costs.
  void addIterations(Teuchos::ParameterList& solver) const;
  void addHardestStep(Teuchos::ParameterList& solver) const;
  void addCosts(Teuchos::ParameterList& solver) const;

  // Checkpoint: the scalars (hardest step iterations, residual evaluations, four timers) and the
  // three series under "implicit ..." names.
  std::vector<double> scalars() const;
  void restoreScalars(const std::vector<double>& s);
  void save(NamedArrays& state) const;
  void restore(const NamedArrays& state);

 private:
  std::vector<int> newtonPerStep_, krylovPerNewton_;
  int hardestStepIterations_ = -1;
  std::vector<double> hardestStepNorms_;
  long residualEvaluations_ = 0;
  double secondsSetUp_ = 0, secondsSolve_ = 0, secondsSolverSetUp_ = 0, secondsFinish_ = 0;
};

}  // namespace impm
