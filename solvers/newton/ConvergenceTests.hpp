// NOX status tests for the implicit MPM Newton iteration (Guilkey & Weiss 2003 style criteria).
//
// With x_k the k-th Newton iterate (x_0 the initial guess) and du_k = (x_k - x_{k-1}) / lambda_k the
// Newton direction of iteration k (k >= 1; lambda_k the line search's step, 1 for a full step):
//   DisplacementNormTest: converged when ||du_k||_2 <= tol * ||x_k||_2.
//   EnergyNormTest:       converged when |du_k . R(x_{k-1})| <= tol * |du_1 . R(x_0)|, i.e. the
//                         work of the residual that produced the update, relative to the first one.
//   ResidualMagnitudeTest: converged when ||R(x_k)||_2 <= tol * S(x_k) AND the iteration has
//                         stalled, ||R(x_k)|| >= ||R(x_{k-1})|| / 2 (k >= 1). S is the size of the
//                         terms R is summed from (ResidualModel::residualMagnitude): R's round-off
//                         is bounded by about eps S, and a Newton (or Jacobian-free, whose
//                         difference quotients add their own noise) iteration stalls at that floor;
//                         a stiff body's translation makes S, and so the floor, large. Both
//                         conditions: small against the problem's own scale, and no longer falling.
// The first two read x_k from NOX's solution group and x_{k-1}, R(x_{k-1}) from its previous solution group,
// so they work with any NOX::Abstract::Group. Both are Unconverged before the first Newton step.
// All vector operations are collective: checkStatus must run on all ranks (NOX does so).
#pragma once

#include <NOX_StatusTest_Generic.H>
#include <NOX_Abstract_Vector.H>

#include <Teuchos_RCP.hpp>

#include "solvers/newton/ResidualModel.hpp"

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

// Needs the solver's groups to be NOX::Thyra groups over Tpetra vectors (NewtonSolver's).
class ResidualMagnitudeTest : public NOX::StatusTest::Generic {
 public:
  ResidualMagnitudeTest(ResidualModel& model, double tolerance);

  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic& solver,
                                          NOX::StatusTest::CheckType checkType) override;
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  std::ostream& print(std::ostream& stream, int indent = 0) const override;

  double tolerance() const { return tolerance_; }
  // ||R|| / S at the last check (-1 when S is unknown).
  double ratio() const { return ratio_; }
  double magnitude() const { return magnitude_; }

 private:
  ResidualModel& model_;
  double tolerance_;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
  double ratio_ = -1, magnitude_ = -1;
  static constexpr double kStagnation = 0.5;
};

}  // namespace impm
