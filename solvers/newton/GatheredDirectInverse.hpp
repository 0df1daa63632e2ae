#pragma once

#include "solvers/newton/PreconditionerCache.hpp"

namespace impm {

// P^{-1} by sparse LU (Amesos2 KLU2) of P gathered onto rank 0: works around Amesos2 13.2, whose KLU2
// returns wrong solutions for a matrix distributed over several ranks (it is right on one rank, which
// is how it is used here: on a serial communicator). Every update refactors; apply() gathers the
// vectors to rank 0 and scatters the solution back. Meant for moderate sizes (a direct solve).
class GatheredDirectInverse : public PreconditionerCache {
 public:
  GatheredDirectInverse();
  ~GatheredDirectInverse() override;
  Teuchos::RCP<TpetraOperator> update(const Teuchos::RCP<const CrsMatrix>& P, long valuesVersion = -1) override;
  int initializations() const override { return factorizations_; }

 private:
  class Op;
  Teuchos::RCP<Op> op_;
  int factorizations_ = 0;
};

}  // namespace impm
