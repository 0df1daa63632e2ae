#include "solvers/implicit/ImplicitStatistics.hpp"

#include <algorithm>
#include <iomanip>
#include <numeric>
#include <sstream>

namespace impm {

void ImplicitStatistics::recordStep(const NewtonResult& result, double secondsFinish) {
  secondsFinish_ += secondsFinish;
  newtonPerStep_.push_back(result.newtonIterations);
  if (result.newtonIterations > hardestStepIterations_) {
    hardestStepIterations_ = result.newtonIterations;
    hardestStepNorms_ = result.residualNorms;
  }
  krylovPerNewton_.insert(krylovPerNewton_.end(), result.krylovIterations.begin(), result.krylovIterations.end());
}

void ImplicitStatistics::addIterations(Teuchos::ParameterList& s) const {
  const auto& n = newtonPerStep_;
  const auto& k = krylovPerNewton_;
  s.set("Newton Iterations Mean", n.empty() ? 0.0 : std::accumulate(n.begin(), n.end(), 0.0) / n.size());
  s.set("Newton Iterations Max", n.empty() ? 0 : *std::max_element(n.begin(), n.end()));
  s.set("Krylov Iterations Per Newton Mean", k.empty() ? 0.0 : std::accumulate(k.begin(), k.end(), 0.0) / k.size());
  s.set("Krylov Iterations Per Newton Max", k.empty() ? 0 : *std::max_element(k.begin(), k.end()));
}

// ||R||_2 at each Newton iterate of the step that took the most iterations: the convergence rate
// (quadratic for Assembled Newton with the exact tangent; linear-ish for JFNK's inexact solves).
void ImplicitStatistics::addHardestStep(Teuchos::ParameterList& s) const {
  std::ostringstream norms;
  norms << std::setprecision(3);
  for (size_t k = 0; k < hardestStepNorms_.size(); ++k) norms << (k ? " " : "") << hardestStepNorms_[k];
  s.set("Residual Norms Of Hardest Step", norms.str());
}

void ImplicitStatistics::addCosts(Teuchos::ParameterList& s) const {
  s.set("Residual Evaluations", (int)residualEvaluations_);
  s.set("Seconds Step Set-Up", secondsSetUp_);
  s.set("Seconds Newton Solve", secondsSolve_);
  s.set("Seconds NOX Set-Up", secondsSolverSetUp_);
  s.set("Seconds Particle Update", secondsFinish_);
}

std::vector<double> ImplicitStatistics::scalars() const {
  return {double(hardestStepIterations_),
          double(residualEvaluations_),
          secondsSetUp_,
          secondsSolve_,
          secondsSolverSetUp_,
          secondsFinish_};
}

void ImplicitStatistics::restoreScalars(const std::vector<double>& s) {
  hardestStepIterations_ = int(s.at(0));
  residualEvaluations_ = long(s.at(1));
  secondsSetUp_ = s.at(2);
  secondsSolve_ = s.at(3);
  secondsSolverSetUp_ = s.at(4);
  secondsFinish_ = s.at(5);
}

void ImplicitStatistics::save(NamedArrays& state) const {
  state["implicit newton per step"].assign(newtonPerStep_.begin(), newtonPerStep_.end());
  state["implicit krylov per newton"].assign(krylovPerNewton_.begin(), krylovPerNewton_.end());
  state["implicit hardest step norms"] = hardestStepNorms_;
}

void ImplicitStatistics::restore(const NamedArrays& state) {
  const auto& newton = state.at("implicit newton per step");
  newtonPerStep_.assign(newton.begin(), newton.end());
  const auto& krylov = state.at("implicit krylov per newton");
  krylovPerNewton_.assign(krylov.begin(), krylov.end());
  hardestStepNorms_ = state.at("implicit hardest step norms");
}

}  // namespace impm
