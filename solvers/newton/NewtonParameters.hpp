// The deck's "Implicit Solver" list: its schema (every key with its default and documentation),
// the check of each key with one message naming 'Implicit Solver/<key>', and the settings the
// Newton solver derives from it: the tolerances, and the matrix-free operator, Stratimikos and NOX
// lists (impm's derived settings are defaults there; the deck's keys win).
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <string>

namespace impm {

struct NewtonSettings {
  enum class JacobianMode { JacobianFree, Assembled };
  enum class AssembledSolver { Amesos2, Belos };

  JacobianMode jacobian = JacobianMode::JacobianFree;
  AssembledSolver assembledSolver = AssembledSolver::Amesos2;
  std::string preconditioner;
  double displacementTol = 0, energyTol = 0, residualTol = 0, magnitudeTol = 0, linearTol = 0;
  int maxNewton = 0, maxKrylov = 0;
  Teuchos::RCP<Teuchos::ParameterList> jacobianFreeOperator;  // NOX::Thyra::MatrixFreeJacobianOperator
  Teuchos::RCP<Teuchos::ParameterList> stratimikos;           // the linear solver
  Teuchos::RCP<Teuchos::ParameterList> nox;                   // NOX (without the observer)

  bool jacobianFree() const { return jacobian == JacobianMode::JacobianFree; }
  // Assembled Newton solved by sparse LU.
  bool direct() const { return jacobian == JacobianMode::Assembled && assembledSolver == AssembledSolver::Amesos2; }
  // An Ifpack2 or MueLu preconditioner: Jacobian-free, or assembled with GMRES.
  bool usesPreconditioner() const {
    return preconditioner != "None" && (jacobianFree() || assembledSolver == AssembledSolver::Belos);
  }

  // Validates `pl` in place (defaults filled in; the pass-through sublists are copied, never
  // modified) and derives the settings. Throws std::invalid_argument naming the key.
  static NewtonSettings fromList(Teuchos::ParameterList& pl);
};

// The schema of the "Implicit Solver" list.
Teuchos::RCP<const Teuchos::ParameterList> newtonValidParameters();

// "'Implicit Solver/<key>'", for messages.
std::string implicitSolverKey(const std::string& key);
// A value in 3-digit scientific notation, for messages.
std::string scientific(double v);

}  // namespace impm
