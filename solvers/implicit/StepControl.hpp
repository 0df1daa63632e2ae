// How one deck step of an implicit run is taken: as one Newton solve of dt, or on failure as
// 2^k sub-steps (k <= maxStepHalvings); or, with adaptive sub-steps, as sub-steps sized by the
// Newton iteration count of the last one (Uintah ImpMPM's policy). Throws NewtonNotConverged.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace impm {

struct NewtonNotConverged : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class StepControl {
 public:
  // One Newton solve of [t, t + dt]: converged (the state advanced) or not (nothing changed).
  struct Outcome {
    bool converged = false;
    int newtonIterations = 0;
    std::string reason;  // why Newton stopped, when it failed
  };
  using Solve = std::function<Outcome(double t, double dt)>;

  StepControl(int maxStepHalvings, bool adaptive, double minimumTimeStep)
      : maxStepHalvings_(maxStepHalvings), adaptive_(adaptive), minimumTimeStep_(minimumTimeStep) {}

  void step(double t, double dt, const Solve& solve);

  // "Step Halvings" and, when adaptive, the "Adaptive Time Step" sublist of the solver summary.
  void addHalvings(Teuchos::ParameterList& solver) const { solver.set("Step Halvings", halvings_); }
  void addAdaptive(Teuchos::ParameterList& solver) const;

  // Checkpoint: the carried sub-step, the halvings and the sub-step statistics.
  double carriedSubStep() const { return subStep_; }
  int halvings() const { return halvings_; }
  std::vector<double> subStepStatistics() const {
    return {smallestSubStep_, largestSubStep_, double(subSteps_), double(rejectedSubSteps_)};
  }
  void restore(double carriedSubStep, double halvings, const std::vector<double>& subStepStatistics);

 private:
  bool halving(double t, double dt, int depth, const Solve& solve);
  void adaptive(double t, double dt, const Solve& solve);

  int maxStepHalvings_;
  bool adaptive_;
  double minimumTimeStep_;
  std::string lastFailure_;
  int halvings_ = 0;
  // Adaptive: the sub-step carried from step to step (0: not started), and the counts.
  double subStep_ = 0.0, smallestSubStep_ = 0.0, largestSubStep_ = 0.0;
  long long subSteps_ = 0, rejectedSubSteps_ = 0;
};

}  // namespace impm
