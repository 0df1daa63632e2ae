// NOX status tests for the implicit MPM Newton iteration (Guilkey & Weiss 2003 style criteria).
//
// With x_k the k-th Newton iterate (x_0 the initial guess) and du_k = x_k - x_{k-1} the update of
// Newton iteration k (k >= 1):
//   DisplacementNormTest: converged when ||du_k||_2 <= tol * ||x_k||_2.
//   EnergyNormTest:       converged when |du_k . R(x_{k-1})| <= tol * |du_1 . R(x_0)|, i.e. the
//                         work of the residual that produced the update, relative to the first one.
// Both read x_k from NOX's solution group and x_{k-1}, R(x_{k-1}) from its previous solution group,
// so they work with any NOX::Abstract::Group. Both are Unconverged before the first Newton step.
// All vector operations are collective: checkStatus must run on all ranks (NOX does so).
#pragma once

#include <NOX_StatusTest_Generic.H>
#include <NOX_Abstract_Vector.H>

#include <Teuchos_RCP.hpp>

#include <iosfwd>

namespace impm {

class DisplacementNormTest : public NOX::StatusTest::Generic {
 public:
  explicit DisplacementNormTest(double tolerance);

  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic& solver,
                                          NOX::StatusTest::CheckType checkType) override;
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  std::ostream& print(std::ostream& stream, int indent = 0) const override;

  double tolerance() const { return tolerance_; }
  // ||du_k|| / ||x_k|| at the last check (0 when both vanish, -1 before the first Newton step).
  double ratio() const { return ratio_; }
  double updateNorm() const { return updateNorm_; }
  double solutionNorm() const { return solutionNorm_; }

 private:
  double tolerance_;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
  double ratio_ = -1, updateNorm_ = -1, solutionNorm_ = -1;
  Teuchos::RCP<NOX::Abstract::Vector> update_;
};

class EnergyNormTest : public NOX::StatusTest::Generic {
 public:
  explicit EnergyNormTest(double tolerance);

  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic& solver,
                                          NOX::StatusTest::CheckType checkType) override;
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  std::ostream& print(std::ostream& stream, int indent = 0) const override;

  double tolerance() const { return tolerance_; }
  // |du_k . R_{k-1}| / |du_1 . R_0| at the last check (-1 before the first Newton step).
  double ratio() const { return ratio_; }
  double energy() const { return energy_; }
  double referenceEnergy() const { return reference_; }

 private:
  double tolerance_;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
  double ratio_ = -1, energy_ = -1, reference_ = -1;
  Teuchos::RCP<NOX::Abstract::Vector> update_;
};

}  // namespace impm
