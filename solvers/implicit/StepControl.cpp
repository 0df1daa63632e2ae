#include "solvers/implicit/StepControl.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace impm {

void StepControl::step(double t, double dt, const Solve& solve) {
  if (adaptive_) {
    adaptive(t, dt, solve);
    return;
  }
  if (!halving(t, dt, 0, solve)) {
    std::ostringstream msg;
    msg << "Newton did not converge in the step from t = " << t << " s (dt = " << dt << " s), even with dt halved "
        << maxStepHalvings_ << " times; the last attempt " << lastFailure_;
    throw NewtonNotConverged(msg.str());
  }
}

bool StepControl::halving(double t, double dt, int depth, const Solve& solve) {
  const Outcome outcome = solve(t, dt);
  if (outcome.converged) return true;
  lastFailure_ = outcome.reason;
  if (depth >= maxStepHalvings_) return false;
  ++halvings_;
  return halving(t, 0.5 * dt, depth + 1, solve) && halving(t + 0.5 * dt, 0.5 * dt, depth + 1, solve);
}

// Uintah ImpMPM's policy on the Newton count n of the last sub-step: n > 12 -> h *= 0.6,
// n < 4 -> h *= 2 (at most the deck's dt), failure -> h /= 2 and retry. (Uintah also restarts a
// step above 25 iterations; here NOX's own iteration limit fails it.) The sub-steps end exactly
// on the deck's step, so that the outputs keep their times.
void StepControl::adaptive(double t, double dt, const Solve& solve) {
  const double hMin = minimumTimeStep_ > 0 ? minimumTimeStep_ : dt / std::pow(2.0, maxStepHalvings_);
  if (subStep_ <= 0) subStep_ = dt;
  const double tEnd = t + dt;
  double tc = t;
  while (tc < tEnd - 1e-12 * dt) {
    const double h = std::min(subStep_, tEnd - tc);
    const Outcome outcome = solve(tc, h);
    if (!outcome.converged) {
      lastFailure_ = outcome.reason;
      ++rejectedSubSteps_;
      ++halvings_;
      if (0.5 * h < hMin * (1 - 1e-12)) {
        std::ostringstream msg;
        msg << "Newton did not converge in the sub-step from t = " << tc << " s (dt = " << h
            << " s), and half of it is below the smallest sub-step " << hMin
            << " s ('Integrator/Implicit/Minimum Time Step' or Time Step / 2^Maximum Step Halvings); the last attempt "
            << lastFailure_;
        throw NewtonNotConverged(msg.str());
      }
      subStep_ = 0.5 * h;
      continue;
    }
    ++subSteps_;
    smallestSubStep_ = smallestSubStep_ > 0 ? std::min(smallestSubStep_, h) : h;
    largestSubStep_ = std::max(largestSubStep_, h);
    tc += h;
    const int n = outcome.newtonIterations;
    // (A sub-step cut short by the end of the deck step does not shrink the carried size.)
    if (n > 12)
      subStep_ = 0.6 * h;
    else if (n < 4)
      subStep_ = std::min(2.0 * std::max(h, subStep_), dt);
  }
}

void StepControl::addAdaptive(Teuchos::ParameterList& solver) const {
  if (!adaptive_) return;
  Teuchos::ParameterList& a = solver.sublist("Adaptive Time Step");
  a.set("Sub-Steps", (int)subSteps_);
  a.set("Rejected Sub-Steps", (int)rejectedSubSteps_);
  a.set("Smallest Sub-Step", smallestSubStep_);
  a.set("Largest Sub-Step", largestSubStep_);
}

void StepControl::restore(double carriedSubStep, double halvings, const std::vector<double>& s) {
  subStep_ = carriedSubStep;
  halvings_ = int(halvings);
  smallestSubStep_ = s.at(0);
  largestSubStep_ = s.at(1);
  subSteps_ = (long long)s.at(2);
  rejectedSubSteps_ = (long long)s.at(3);
}

}  // namespace impm
