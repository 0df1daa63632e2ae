#include "solvers/newton/IfpackPreconditioner.hpp"

#include <Ifpack2_Factory.hpp>
#include <Teuchos_DefaultSerialComm.hpp>

#include <stdexcept>

#include "core/PhaseTimer.hpp"

namespace impm {

using Teuchos::RCP;
using Teuchos::rcp;

IfpackPreconditionerCache::IfpackPreconditionerCache(const std::string& type, const Teuchos::ParameterList& params)
    : type_(type), params_(params) {
  // Check the type and the parameters now, on a 1x1 matrix over a serial communicator (so this
  // is not collective), rather than at the first time step.
  RCP<const Teuchos::Comm<int>> self = rcp(new Teuchos::SerialComm<int>());
  auto map = rcp(new Map(1, 0, self));
  auto A = rcp(new CrsMatrix(map, 1));
  const GO row = 0;
  const Scalar one = 1.0;
  A->insertGlobalValues(row, Teuchos::ArrayView<const GO>(&row, 1), Teuchos::ArrayView<const Scalar>(&one, 1));
  A->fillComplete();
  create(A);
}

bool avoidAmesosOnEmptyBlock(Teuchos::ParameterList& schwarz, bool rankIsEmpty) {
  if (!rankIsEmpty || !schwarz.isType<std::string>("subdomain solver name") ||
      schwarz.get<std::string>("subdomain solver name") != "AMESOS2")
    return false;
  schwarz.set("subdomain solver name", "RILUK");
  schwarz.remove("subdomain solver parameters", false);
  return true;
}

RCP<Ifpack2Preconditioner> IfpackPreconditionerCache::create(const RCP<const CrsMatrix>& P) const {
  const std::string& type = type_;
  RCP<Ifpack2Preconditioner> prec;
  try {
    prec = Ifpack2::Factory::create<RowMatrix>(type, RCP<const RowMatrix>(P));
  } catch (const std::exception& e) {
    throw std::invalid_argument("invalid value '" + type_ +
                                "' for 'Implicit Solver/Preconditioner' (Ifpack2: " + e.what() + ")");
  }
  if (prec.is_null()) throw std::invalid_argument("invalid value '" + type_ + "' for 'Implicit Solver/Preconditioner'");
  // Some Ifpack2 preconditioners (Relaxation) validate and fill in the list they are given: hand
  // them a copy so the deck's list stays as written.
  Teuchos::ParameterList copy(params_);
  // Ifpack2's Amesos2 wrapper throws unless its options come in a sublist called "Amesos2": an
  // empty one means KLU2 with its defaults.
  if (type == "AMESOS2" && !copy.isSublist("Amesos2")) copy.sublist("Amesos2");
  if (type == "SCHWARZ" && !avoidAmesosOnEmptyBlock(copy, P->getNodeNumRows() == 0) &&
      copy.isType<std::string>("subdomain solver name") &&
      copy.get<std::string>("subdomain solver name") == "AMESOS2" &&
      !copy.sublist("subdomain solver parameters").isSublist("Amesos2"))
    copy.sublist("subdomain solver parameters").sublist("Amesos2");
  try {
    prec->setParameters(copy);
  } catch (const std::exception& e) {
    throw std::invalid_argument("'Implicit Solver/Ifpack2' rejected by Ifpack2 " + type_ + ": " + e.what());
  }
  return prec;
}

RCP<TpetraOperator> IfpackPreconditionerCache::update(const RCP<const CrsMatrix>& P, long valuesVersion) {
  PhaseTimer phase("preconditioner set-up");
  if (type_ == "AMESOS2" && P->getComm()->getSize() > 1) {
    if (blockDirect_.is_null()) blockDirect_ = rcp(new LocalBlockDirectInverse());
    const bool current = P.get() == matrix_.get() && valuesVersion >= 0 && valuesVersion == valuesVersion_;
    if (!current) {
      blockDirect_->factor(P);
      ++computations_;
      initializations_ = blockDirect_->symbolicFactorizations();
    }
    matrix_ = P;
    valuesVersion_ = valuesVersion;
    return blockDirect_;
  }
  // Same object with a static (const) graph: only the values can have changed, so the symbolic
  // setup stands. Anything else may have a new structure: start from a fresh preconditioner.
  const bool sameStructure = !prec_.is_null() && P.get() == matrix_.get() && P->isStaticGraph();
  // Ifpack2 13.2's Amesos2 wrapper (alone, or as Schwarz's subdomain solve) copies the rank's
  // block of P in initialize() whenever that block is not P itself (several ranks), and compute()
  // refactors the copy: without a new initialize() it would keep the first step's values.
  const bool copiesInInitialize = type_ == "SCHWARZ" || (type_ == "AMESOS2" && P->getComm()->getSize() > 1);
  if (sameStructure && copiesInInitialize && !(valuesVersion >= 0 && valuesVersion == valuesVersion_)) {
    prec_->initialize();
    ++initializations_;
  }
  if (!sameStructure) {
    prec_ = create(P);
    matrix_ = P;
    prec_->initialize();
    ++initializations_;
  } else if (valuesVersion >= 0 && valuesVersion == valuesVersion_) {
    return prec_;  // same matrix, same values: the factors stand
  }
  prec_->compute();
  ++computations_;
  valuesVersion_ = valuesVersion;
  return prec_;
}

}  // namespace impm
