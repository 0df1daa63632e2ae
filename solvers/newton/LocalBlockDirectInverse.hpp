#pragma once

#include "solvers/newton/PreconditionerCache.hpp"

namespace impm {

// Block Jacobi with an exact solve of each block: on every rank, sparse LU (Amesos2 KLU2, on a
// serial communicator) of the rank's rows of P restricted to its own columns. What Ifpack2's
// AMESOS2 preconditioner computes across ranks, without its two faults in 13.2: KLU2 crashes on a
// rank with no rows (a rank whose cells hold no particle), and the wrapper's set-up is collective
// (Map::isSameAs), so that rank cannot simply be skipped. No communication at all.
class LocalBlockDirectInverse : public TpetraOperator {
 public:
  // Refactors the rank's block of P (a new symbolic factorisation when its pattern changed).
  void factor(const Teuchos::RCP<const CrsMatrix>& P);
  int symbolicFactorizations() const { return symbolic_; }

  Teuchos::RCP<const Map> getDomainMap() const override { return map_; }
  Teuchos::RCP<const Map> getRangeMap() const override { return map_; }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             Scalar alpha = Teuchos::ScalarTraits<Scalar>::one(),
             Scalar beta = Teuchos::ScalarTraits<Scalar>::zero()) const override;

 private:
  class Block;
  Teuchos::RCP<const Map> map_;
  Teuchos::RCP<Block> block_;  // null on a rank without rows
  int symbolic_ = 0;
};

}  // namespace impm
