// The interface the run loop drives: one time step from t to t + dt.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <map>
#include <string>
#include <vector>

namespace impm {

// State by name, for checkpoints (solvers/Checkpoint.hpp).
using NamedArrays = std::map<std::string, std::vector<double>>;

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual void step(double t, double dt) = 0;
  virtual std::string name() const = 0;
  // Solver statistics for summary.yaml.
  virtual void addStatistics(Teuchos::ParameterList& /*summary*/) const {}
  // What the integrator carries from one step to the next beyond the particles (and its
  // statistics), for a checkpoint; restoreState takes it back before the first step of a
  // restarted run. Arrays named "node ..." are per rank (see solvers/Checkpoint.hpp).
  virtual void saveState(NamedArrays& /*state*/) const {}
  virtual void restoreState(const NamedArrays& /*state*/) {}
};

}  // namespace impm
