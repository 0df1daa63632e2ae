#pragma once

#include <string>

#include "solvers/newton/LocalBlockDirectInverse.hpp"
#include "solvers/newton/PreconditionerCache.hpp"

namespace impm {

// An Ifpack2 preconditioner of a given type: initialize() (symbolic) when P is a new object or its
// graph may have changed, compute() (numeric) on every update. AMESOS2 on several ranks is a
// LocalBlockDirectInverse (the same block-Jacobi LU).
class IfpackPreconditionerCache : public PreconditionerCache {
 public:
  // Throws std::invalid_argument naming 'Implicit Solver/Preconditioner' or 'Implicit Solver/Ifpack2'
  // when Ifpack2 does not know `type` or rejects `params` (checked on a 1x1 matrix, not collective).
  IfpackPreconditionerCache(const std::string& type, const Teuchos::ParameterList& params);

  Teuchos::RCP<TpetraOperator> update(const Teuchos::RCP<const CrsMatrix>& P, long valuesVersion = -1) override;
  int initializations() const override { return initializations_; }

  const std::string& type() const { return type_; }
  int computations() const { return computations_; }

 private:
  Teuchos::RCP<Ifpack2Preconditioner> create(const Teuchos::RCP<const CrsMatrix>& P) const;

  std::string type_;
  Teuchos::ParameterList params_;
  Teuchos::RCP<Ifpack2Preconditioner> prec_;
  Teuchos::RCP<LocalBlockDirectInverse> blockDirect_;
  Teuchos::RCP<const CrsMatrix> matrix_;  // held so its address cannot be reused by a new matrix
  int initializations_ = 0, computations_ = 0;
  long valuesVersion_ = -1;
};

}  // namespace impm
