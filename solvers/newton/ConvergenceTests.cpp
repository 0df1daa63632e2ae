#include "solvers/newton/ConvergenceTests.hpp"

#include <NOX_Abstract_Group.H>
#include <NOX_Solver_Generic.H>
#include <NOX_Solver_LineSearchBased.H>
#include <NOX_Thyra_Vector.H>
#include <NOX_Utils.H>
#include <Thyra_TpetraThyraWrappers.hpp>

#include <cmath>
#include <limits>
#include <ostream>

namespace impm {

namespace {

// update = the Newton direction of iteration k, (x_k - x_{k-1}) / lambda_k with lambda_k the step
// the line search took (1 for Full Step): a damped step must not pass for a converged one. False
// when there is no previous iterate yet.
bool computeUpdate(const NOX::Solver::Generic& solver, Teuchos::RCP<NOX::Abstract::Vector>& update) {
  if (solver.getNumIterations() < 1) return false;
  const NOX::Abstract::Vector& x = solver.getSolutionGroup().getX();
  const NOX::Abstract::Vector& xOld = solver.getPreviousSolutionGroup().getX();
  if (update.is_null() || update->length() != x.length()) update = x.clone(NOX::ShapeCopy);
  update->update(1.0, x, -1.0, xOld, 0.0);
  const auto* lineSearch = dynamic_cast<const NOX::Solver::LineSearchBased*>(&solver);
  const double step = lineSearch != nullptr ? lineSearch->getStepSize() : 1.0;
  if (step > 0.0 && step != 1.0) update->scale(1.0 / step);
  return true;
}

void indentBy(std::ostream& os, int indent) {
  for (int j = 0; j < indent; ++j) os << ' ';
}

}  // namespace

// ---------------------------------------------------------------------------------------------
DisplacementNormTest::DisplacementNormTest(double tolerance) : tolerance_(tolerance) {}

NOX::StatusTest::StatusType DisplacementNormTest::checkStatus(const NOX::Solver::Generic& solver,
                                                              NOX::StatusTest::CheckType checkType) {
  // Norms are cheap next to a residual evaluation, so evaluate even for CheckType None (keeps the
  // reported values current); the status then says Unevaluated as NOX asks.
  if (!computeUpdate(solver, update_)) {
    ratio_ = updateNorm_ = solutionNorm_ = -1;
    status_ = checkType == NOX::StatusTest::None ? NOX::StatusTest::Unevaluated : NOX::StatusTest::Unconverged;
    return status_;
  }
  updateNorm_ = update_->norm(NOX::Abstract::Vector::TwoNorm);
  solutionNorm_ = solver.getSolutionGroup().getX().norm(NOX::Abstract::Vector::TwoNorm);
  if (solutionNorm_ > 0)
    ratio_ = updateNorm_ / solutionNorm_;
  else
    ratio_ = updateNorm_ > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  if (checkType == NOX::StatusTest::None)
    status_ = NOX::StatusTest::Unevaluated;
  else
    status_ = (updateNorm_ <= tolerance_ * solutionNorm_) ? NOX::StatusTest::Converged : NOX::StatusTest::Unconverged;
  return status_;
}

std::ostream& DisplacementNormTest::print(std::ostream& stream, int indent) const {
  indentBy(stream, indent);
  stream << status_ << "Displacement Norm ||du||/||u|| = " << NOX::Utils::sciformat(ratio_, 3)
         << " <= " << NOX::Utils::sciformat(tolerance_, 3) << "\n";
  return stream;
}

// ---------------------------------------------------------------------------------------------
EnergyNormTest::EnergyNormTest(double tolerance) : tolerance_(tolerance) {}

NOX::StatusTest::StatusType EnergyNormTest::checkStatus(const NOX::Solver::Generic& solver,
                                                        NOX::StatusTest::CheckType checkType) {
  const int k = solver.getNumIterations();
  if (k == 0) reference_ = -1;  // a new solve (or a reset solver)
  const NOX::Abstract::Group& previous = solver.getPreviousSolutionGroup();
  if (!computeUpdate(solver, update_) || !previous.isF()) {
    ratio_ = energy_ = -1;
    status_ = checkType == NOX::StatusTest::None ? NOX::StatusTest::Unevaluated : NOX::StatusTest::Unconverged;
    return status_;
  }
  energy_ = std::fabs(update_->innerProduct(previous.getF()));
  // The reference is the first update's energy; if the first check was skipped, the earliest seen.
  if (k == 1 || reference_ < 0) reference_ = energy_;
  if (reference_ > 0)
    ratio_ = energy_ / reference_;
  else
    ratio_ = energy_ > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  if (checkType == NOX::StatusTest::None)
    status_ = NOX::StatusTest::Unevaluated;
  else
    status_ = (energy_ <= tolerance_ * reference_) ? NOX::StatusTest::Converged : NOX::StatusTest::Unconverged;
  return status_;
}

std::ostream& EnergyNormTest::print(std::ostream& stream, int indent) const {
  indentBy(stream, indent);
  stream << status_ << "Energy Norm |du.R|/|du0.R0| = " << NOX::Utils::sciformat(ratio_, 3)
         << " <= " << NOX::Utils::sciformat(tolerance_, 3) << "\n";
  return stream;
}

// ---------------------------------------------------------------------------------------------
ResidualMagnitudeTest::ResidualMagnitudeTest(ResidualModel& model, double tolerance)
    : model_(model), tolerance_(tolerance) {}

NOX::StatusTest::StatusType ResidualMagnitudeTest::checkStatus(const NOX::Solver::Generic& solver,
                                                               NOX::StatusTest::CheckType checkType) {
  const NOX::Abstract::Group& group = solver.getSolutionGroup();
  if (checkType == NOX::StatusTest::None || !group.isF()) {
    status_ = checkType == NOX::StatusTest::None ? NOX::StatusTest::Unevaluated : NOX::StatusTest::Unconverged;
    return status_;
  }
  const auto& x = dynamic_cast<const NOX::Thyra::Vector&>(group.getX());
  const auto u =
      Thyra::TpetraOperatorVectorExtraction<Scalar, LO, GO, Node>::getConstTpetraVector(x.getThyraRCPVector());
  magnitude_ = model_.residualMagnitude(*u);
  const double normF = group.getNormF();
  ratio_ = magnitude_ > 0 ? normF / magnitude_ : (magnitude_ == 0 && normF == 0 ? 0.0 : -1.0);
  // Stalled: the last Newton iteration did not halve ||R|| (or R vanished).
  const NOX::Abstract::Group& previous = solver.getPreviousSolutionGroup();
  const bool stalled =
      normF == 0.0 || (solver.getNumIterations() >= 1 && previous.isF() && normF >= kStagnation * previous.getNormF());
  status_ = (magnitude_ >= 0 && normF <= tolerance_ * magnitude_ && stalled) ? NOX::StatusTest::Converged
                                                                             : NOX::StatusTest::Unconverged;
  return status_;
}

std::ostream& ResidualMagnitudeTest::print(std::ostream& stream, int indent) const {
  indentBy(stream, indent);
  stream << status_ << "Residual Magnitude ||R||/S = " << NOX::Utils::sciformat(ratio_, 3)
         << " <= " << NOX::Utils::sciformat(tolerance_, 3) << "\n";
  return stream;
}

}  // namespace impm
