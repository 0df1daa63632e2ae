// A reusable Newton solver for one implicit (Newmark) time step: NOX on Thyra over Tpetra.
//
// The implicit integrator supplies R(u) and an assembled matrix P ~ dR/du through ResidualModel;
// NewtonSolver::solve() drives R(u) = 0 with either
//   - Jacobian-free Newton-Krylov (default): J v ~ (R(u + d v) - R(u)) / d inside Belos GMRES,
//     right-preconditioned by an Ifpack2 preconditioner built from P, or
//   - assembled Newton: the Jacobian is P itself, solved by Amesos2 (KLU2) or by
//     Ifpack2-preconditioned Belos GMRES to a tight tolerance.
// Convergence: (displacement norm AND energy norm) OR absolute residual norm OR the residual within
// a few hundred times its own round-off (ResidualMagnitudeTest), at most "Maximum Newton
// Iterations" (see validParameters() for every key).
//
// Every call here is collective: call the constructor and solve() on all ranks of the map's
// communicator. The unknown map may change from one solve() to the next.
//
// Persistence: the model evaluator, the NOX group (with its Jacobian-free operator and linear solver
// object), the status tests and the NOX solver are built at the first solve() and kept while later
// calls pass the same ResidualModel object with the same unknown map (the same Map object, or one
// with the same global indices on every rank); such a call only resets them to the new initial guess,
// so that nothing computed for the previous residual function (F, P, the preconditioner's values,
// the Newton direction) is reused, only structure. Another model or another map rebuilds them.
#pragma once

#include "core/Types.hpp"
#include "solvers/newton/NewtonParameters.hpp"
#include "solvers/newton/ResidualModel.hpp"

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include <memory>
#include <string>
#include <vector>

namespace Thyra {
template <class Scalar>
class LinearOpWithSolveFactoryBase;
}

namespace impm {

struct NewtonResult {
  bool converged = false;
  int newtonIterations = 0;
  // Per Newton iteration: GMRES iterations, 0 for a direct solve (1 for the direct solve on more than
  // one rank, done as one GMRES iteration preconditioned by the exact inverse).
  std::vector<int> krylovIterations;
  // ||R||_2 at the initial guess and after each Newton iteration.
  std::vector<double> residualNorms;
  // Final values of the three criteria: ||R(u)||_2 (absolute, unscaled), ||du_k|| / ||u_k|| and
  // |du_k . R_k| / |du_0 . R_0| (both -1 when no Newton step was taken).
  double finalResidualNorm = 0, displacementNorm = 0, energyNorm = 0;
  // ||R|| / S at the end (ResidualModel::residualMagnitude; -1 when not evaluated).
  double residualMagnitudeRatio = -1;
  std::string reason;  // why it stopped, human readable
  // Cost accounting (same on every rank).
  int residualEvaluations = 0;            // calls of ResidualModel::residual (J-free products included)
  int jacobianEvaluations = 0;            // calls of ResidualModel::jacobianMatrix
  int preconditionerInitializations = 0;  // Ifpack2 initialize() calls (symbolic setup)
  // Building (or, when reused, resetting) the model evaluator, NOX group, status tests and solver;
  // excludes the residual at the initial guess and the one reduction that decides on reuse (on several
  // ranks it absorbs the wait for the slowest one).
  double setupSeconds = 0;
  double solveSeconds = 0;  // wall time of the whole solve() call
  // True when this call reused the NOX set-up of the previous call (same model, same unknown map);
  // false when it was built afresh.
  bool reusedSetUp = false;
};

class PreconditionerCache;  // solvers/newton/PreconditionerCache.hpp

class NewtonSolver {
 public:
  // `params` is the deck's "Implicit Solver" sublist: validated here with defaults filled in
  // (top-level keys only; the pass-through sublists are copied, never modified). Null means all
  // defaults. Throws std::invalid_argument naming 'Implicit Solver/<key>' on any bad entry.
  explicit NewtonSolver(const Teuchos::RCP<Teuchos::ParameterList>& params);
  ~NewtonSolver();
  NewtonSolver(const NewtonSolver&) = delete;
  NewtonSolver& operator=(const NewtonSolver&) = delete;

  static Teuchos::RCP<const Teuchos::ParameterList> validParameters() { return newtonValidParameters(); }

  // Solves R(u) = 0 starting from u (in: initial guess, out: solution). u must be on
  // model.unknownMap(). Collective. u holds the last iterate even when not converged.
  NewtonResult solve(ResidualModel& model, Vector& u);

  // The validated "Implicit Solver" list (defaults filled in).
  const Teuchos::ParameterList& parameters() const { return *params_; }

  // How many times solve() has built the NOX set-up (model evaluator, group, status tests, solver).
  int setUpBuilds() const { return setUpBuilds_; }

 private:
  Teuchos::RCP<Teuchos::ParameterList> params_;
  NewtonSettings settings_;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> lowsFactory_;
  Teuchos::RCP<PreconditionerCache> prec_;  // Ifpack2 or MueLu; null for "None" / direct solves
  // Assembled + Amesos2 on more than one rank: Amesos2 13.2's KLU2 gives wrong solutions once the
  // matrix is distributed (its gathered-matrix path), so P is gathered to rank 0 and factored there by
  // KLU2 on a serial communicator; that exact inverse preconditions a Belos fixed point iteration
  // (the direct solve and at most two refinement steps; not GMRES: see NewtonSolver.cpp).
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> gatheredLowsFactory_;
  Teuchos::RCP<PreconditionerCache> gatheredDirect_;

  // What solve() keeps between calls (solvers/newton/NewtonSolver.cpp); null before the first call and after
  // a call that threw.
  struct NoxSetUp;
  std::unique_ptr<NoxSetUp> nox_;
  int setUpBuilds_ = 0;

  // Whether nox_ was built for this model and map (collective: one reduction over the map's
  // communicator, so that every rank takes the same branch).
  bool canReuse(const ResidualModel& model, const Map& map, bool gathered) const;
  // The model evaluator and NOX group for this model and map (a new set-up), or the kept ones
  // reset to the initial guess u.
  void buildSetUp(ResidualModel& model, const Teuchos::RCP<const Map>& map, const Vector& u, bool gathered,
                  const Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& lows,
                  const Teuchos::RCP<PreconditionerCache>& prec);
  void resetSetUp(const Vector& u);
  // Status tests: finite residual, then (NormF OR (displacement AND energy) OR magnitude), then
  // MaxIters; and the NOX solver over them.
  void buildStatusTestsAndSolver(ResidualModel& model);
  // Why NOX stopped, in words (NewtonResult::reason).
  std::string describeOutcome(const NewtonResult& result, int status) const;
};

}  // namespace impm
