// The interface the run loop drives: one time step from t to t + dt.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <string>

namespace impm {

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual void step(double t, double dt) = 0;
  virtual std::string name() const = 0;
  // Solver statistics for summary.yaml.
  virtual void addStatistics(Teuchos::ParameterList& /*summary*/) const {}
};

}  // namespace impm
