// The interface of the preconditioners the Newton solver builds from the assembled matrix P
// (Ifpack2, MueLu, the direct inverses), and the Tpetra operator types they share.
#pragma once

#include <Ifpack2_Preconditioner.hpp>
#include <Teuchos_ParameterList.hpp>

#include "solvers/newton/ResidualModel.hpp"

namespace impm {

using RowMatrix = Tpetra::RowMatrix<Scalar, LO, GO, Node>;
using TpetraOperator = Tpetra::Operator<Scalar, LO, GO, Node>;
using Ifpack2Preconditioner = Ifpack2::Preconditioner<Scalar, LO, GO, Node>;

// For an Ifpack2 SCHWARZ list (the Ifpack2 preconditioner's, or MueLu's "coarse: params") on a
// rank that owns no rows: an AMESOS2 subdomain solve becomes RILUK. KLU2 throws on an empty block,
// on that rank alone, and the other ranks would wait for it in a collective for ever; the subdomain
// solve is local and, on an empty block, the same nothing whatever the solver. Returns whether it
// changed the list.
bool avoidAmesosOnEmptyBlock(Teuchos::ParameterList& schwarz, bool rankIsEmpty);

// An approximate (or exact) inverse of P, kept up to date with the matrix it is handed. Collective.
class PreconditionerCache {
 public:
  virtual ~PreconditionerCache() = default;
  // Brings the operator up to date with P (fill complete, maps equal to the unknown map).
  // `valuesVersion` (from ResidualModel::jacobianVersion) lets an up-to-date operator skip its
  // numeric set-up when P is the same object with the same values; -1 means "unknown".
  virtual Teuchos::RCP<TpetraOperator> update(const Teuchos::RCP<const CrsMatrix>& P, long valuesVersion = -1) = 0;
  // Symbolic setups (Ifpack2 initialize(), symbolic factorisation) so far.
  virtual int initializations() const = 0;
  // The unknowns' node coordinates (ResidualModel::unknownCoordinates, may be null), handed over
  // before each update() for preconditioners that use geometry (MueLu's rigid-body modes).
  virtual void setUnknownGeometry(const Teuchos::RCP<const MultiVector>& /*coordinates*/, int /*unknownsPerNode*/) {}
};

}  // namespace impm
