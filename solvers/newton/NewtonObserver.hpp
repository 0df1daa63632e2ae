// What NOX reports per Newton iteration that the solver statistics keep: the GMRES iterations of
// each Newton step (from NOX's solver statistics) and the residual norm ||R||_2 at the initial
// guess and after each Newton iteration (the convergence rate).
#pragma once

#include <NOX_Abstract_Group.H>
#include <NOX_Observer.hpp>
#include <NOX_Solver_Generic.H>
#include <NOX_SolverStats.hpp>

#include <vector>

namespace impm {

class NewtonObserver : public NOX::Observer {
 public:
  std::vector<int> iterations;
  std::vector<double> residualNorms;
  void runPreSolve(const NOX::Solver::Generic& solver) override {
    const NOX::Abstract::Group& g = solver.getSolutionGroup();
    if (g.isF()) residualNorms.push_back(g.getNormF());
  }
  void runPostIterate(const NOX::Solver::Generic& solver) override {
    // Also called after a converged initial guess or a failed direction, with no new linear solve.
    if (solver.getNumIterations() > static_cast<int>(iterations.size())) {
      iterations.push_back(solver.getSolverStatistics()->linearSolve.lastLinearSolve_NumIterations);
      const NOX::Abstract::Group& g = solver.getSolutionGroup();
      if (g.isF()) residualNorms.push_back(g.getNormF());
    }
  }
};

}  // namespace impm
