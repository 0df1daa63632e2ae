#include "solvers/ImplicitModelEvaluator.hpp"

#include <Amesos2.hpp>
#include <Ifpack2_Factory.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultSerialComm.hpp>
#include <Tpetra_ComputeGatherMap.hpp>
#include <Thyra_DefaultPreconditioner.hpp>
#include <Thyra_TpetraLinearOp.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>

#include "core/PhaseTimer.hpp"

#include <stdexcept>

namespace impm {

using Teuchos::RCP;
using Teuchos::rcp;
using TOE = Thyra::TpetraOperatorVectorExtraction<Scalar, LO, GO, Node>;
using ThyraTpetraOp = Thyra::TpetraLinearOp<Scalar, LO, GO, Node>;

// ---------------------------------------------------------------------------------------------
// IfpackPreconditionerCache

IfpackPreconditionerCache::IfpackPreconditionerCache(const std::string& type,
                                                     const Teuchos::ParameterList& params)
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
    throw std::invalid_argument("invalid value '" + type_ + "' for 'Implicit Solver/Preconditioner' (Ifpack2: " +
                                e.what() + ")");
  }
  if (prec.is_null())
    throw std::invalid_argument("invalid value '" + type_ + "' for 'Implicit Solver/Preconditioner'");
  // Some Ifpack2 preconditioners (Relaxation) validate and fill in the list they are given: hand
  // them a copy so the deck's list stays as written.
  Teuchos::ParameterList copy(params_);
  // Ifpack2's Amesos2 wrapper throws unless its options come in a sublist called "Amesos2": an
  // empty one means KLU2 with its defaults.
  if (type == "AMESOS2" && !copy.isSublist("Amesos2")) copy.sublist("Amesos2");
  if (type == "SCHWARZ" && !avoidAmesosOnEmptyBlock(copy, P->getNodeNumRows() == 0) &&
      copy.isType<std::string>("subdomain solver name") && copy.get<std::string>("subdomain solver name") == "AMESOS2" &&
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

// ---------------------------------------------------------------------------------------------
// LocalBlockDirectInverse

class LocalBlockDirectInverse::Block {
 public:
  using Solver = Amesos2::Solver<CrsMatrix, MultiVector>;
  RCP<const Map> serialMap;
  RCP<CrsMatrix> A;              // the rank's block, on a serial communicator
  std::vector<size_t> rowStart;  // its pattern, to tell whether a symbolic factorisation stands
  std::vector<LO> cols;
  RCP<Solver> solver;
};

void LocalBlockDirectInverse::factor(const RCP<const CrsMatrix>& P) {
  map_ = P->getRangeMap();
  const RCP<const Map> rowMap = P->getRowMap(), colMap = P->getColMap();
  const size_t n = rowMap->getNodeNumElements();
  if (n == 0) {
    block_ = Teuchos::null;
    return;
  }
  // The block: rows of this rank, columns that are rows of this rank, in local numbering.
  std::vector<size_t> rowStart(1, 0);
  std::vector<LO> cols;
  std::vector<Scalar> vals;
  for (LO i = 0; i < static_cast<LO>(n); ++i) {
    CrsMatrix::local_inds_host_view_type inds;
    CrsMatrix::values_host_view_type v;
    P->getLocalRowView(i, inds, v);
    for (size_t k = 0; k < inds.extent(0); ++k) {
      const LO local = rowMap->getLocalElement(colMap->getGlobalElement(inds(k)));
      if (local == Teuchos::OrdinalTraits<LO>::invalid()) continue;
      cols.push_back(local);
      vals.push_back(v(k));
    }
    rowStart.push_back(cols.size());
  }
  const bool samePattern = !block_.is_null() && block_->rowStart == rowStart && block_->cols == cols;
  if (!samePattern) {
    block_ = rcp(new Block());
    RCP<const Teuchos::Comm<int>> self = rcp(new Teuchos::SerialComm<int>());
    block_->serialMap = rcp(new Map(n, 0, self));
    size_t widest = 1;
    for (size_t i = 0; i < n; ++i) widest = std::max(widest, rowStart[i + 1] - rowStart[i]);
    block_->A = rcp(new CrsMatrix(block_->serialMap, widest));
    for (size_t i = 0; i < n; ++i) {
      std::vector<GO> g(cols.begin() + rowStart[i], cols.begin() + rowStart[i + 1]);
      block_->A->insertGlobalValues(GO(i), Teuchos::ArrayView<const GO>(g),
                                    Teuchos::ArrayView<const Scalar>(vals.data() + rowStart[i], rowStart[i + 1] - rowStart[i]));
    }
    block_->A->fillComplete();
    block_->rowStart = std::move(rowStart);
    block_->cols = std::move(cols);
    block_->solver = Amesos2::create<CrsMatrix, MultiVector>("klu2", block_->A);
    block_->solver->symbolicFactorization();
    ++symbolic_;
  } else {
    // Same pattern: new values only (by global column: the serial matrix's ids are the block's).
    block_->A->resumeFill();
    for (size_t i = 0; i < n; ++i) {
      const size_t a = block_->rowStart[i], b = block_->rowStart[i + 1];
      std::vector<GO> g(block_->cols.begin() + a, block_->cols.begin() + b);
      block_->A->replaceGlobalValues(GO(i), Teuchos::ArrayView<const GO>(g),
                                     Teuchos::ArrayView<const Scalar>(vals.data() + a, b - a));
    }
    block_->A->fillComplete();
  }
  block_->solver->numericFactorization();
}

void LocalBlockDirectInverse::apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode, Scalar alpha,
                                    Scalar beta) const {
  TEUCHOS_TEST_FOR_EXCEPTION(mode != Teuchos::NO_TRANS, std::logic_error,
                             "impm::LocalBlockDirectInverse: only the non-transposed inverse is available");
  if (block_.is_null()) {  // no rows here
    Y.scale(beta);
    return;
  }
  const size_t nv = X.getNumVectors();
  MultiVector serialX(block_->serialMap, nv), serialY(block_->serialMap, nv);
  Kokkos::deep_copy(serialX.getLocalViewHost(Tpetra::Access::OverwriteAll), X.getLocalViewHost(Tpetra::Access::ReadOnly));
  block_->solver->solve(Teuchos::ptrFromRef(serialY), Teuchos::ptrFromRef(static_cast<const MultiVector&>(serialX)));
  auto y = Y.getLocalViewHost(Tpetra::Access::ReadWrite);
  auto s = serialY.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (size_t i = 0; i < y.extent(0); ++i)
    for (size_t j = 0; j < nv; ++j) y(i, j) = beta == 0.0 ? alpha * s(i, j) : alpha * s(i, j) + beta * y(i, j);
}

// ---------------------------------------------------------------------------------------------
// GatheredDirectInverse

class GatheredDirectInverse::Op : public TpetraOperator {
 public:
  void factor(const RCP<const CrsMatrix>& P);

  RCP<const Map> getDomainMap() const override { return map_; }
  RCP<const Map> getRangeMap() const override { return map_; }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             Scalar alpha = Teuchos::ScalarTraits<Scalar>::one(),
             Scalar beta = Teuchos::ScalarTraits<Scalar>::zero()) const override;

 private:
  using Solver = Amesos2::Solver<CrsMatrix, MultiVector>;
  RCP<const Map> map_, rowMap_;     // the unknowns' map and P's row map (kept to detect changes)
  RCP<const Map> rootMap_;          // all of map_'s indices on rank 0
  RCP<const Import> vecImport_, rowImport_;
  RCP<const Map> serialMap_;        // rank 0: 0..n-1 on a serial communicator
  RCP<CrsMatrix> serialP_;          // rank 0: P in rootMap_'s order
  RCP<Solver> solver_;              // rank 0: KLU2 on one process
};

void GatheredDirectInverse::Op::factor(const RCP<const CrsMatrix>& P) {
  if (map_.get() != P->getRangeMap().get()) {
    map_ = P->getRangeMap();
    rootMap_ = Tpetra::Details::computeGatherMap(map_, Teuchos::null);
    vecImport_ = rcp(new Import(map_, rootMap_));
    rowImport_ = Teuchos::null;
  }
  if (rowImport_.is_null() || rowMap_.get() != P->getRowMap().get()) {
    rowMap_ = P->getRowMap();
    rowImport_ = rcp(new Import(rowMap_, rootMap_));
  }
  // Collective: P's rows onto rank 0.
  RCP<CrsMatrix> rootP = Tpetra::importAndFillCompleteCrsMatrix<CrsMatrix>(P, *rowImport_, rootMap_, rootMap_);

  // Rank 0: copy into a matrix on a serial communicator and factor it there. Failures are broadcast so
  // that no rank is left waiting in a collective call.
  const RCP<const Teuchos::Comm<int>> comm = map_->getComm();
  int ok = 1;
  std::string error;
  if (comm->getRank() == 0) {
    try {
      const size_t n = rootMap_->getNodeNumElements();
      RCP<const Teuchos::Comm<int>> self = rcp(new Teuchos::SerialComm<int>());
      if (serialMap_.is_null() || serialMap_->getGlobalNumElements() != n) serialMap_ = rcp(new Map(n, 0, self));
      serialP_ = rcp(new CrsMatrix(serialMap_, rootP->getNodeMaxNumRowEntries()));
      const RCP<const Map> colMap = rootP->getColMap();
      std::vector<GO> cols;
      std::vector<Scalar> vals;
      for (LO i = 0; i < static_cast<LO>(n); ++i) {
        CrsMatrix::local_inds_host_view_type inds;
        CrsMatrix::values_host_view_type v;
        rootP->getLocalRowView(i, inds, v);
        cols.resize(inds.extent(0));
        vals.resize(inds.extent(0));
        for (size_t k = 0; k < inds.extent(0); ++k) {
          cols[k] = rootMap_->getLocalElement(colMap->getGlobalElement(inds(k)));
          vals[k] = v(k);
        }
        serialP_->insertGlobalValues(GO(i), Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const Scalar>(vals));
      }
      serialP_->fillComplete();
      solver_ = Amesos2::create<CrsMatrix, MultiVector>("klu2", serialP_);
      solver_->symbolicFactorization().numericFactorization();
    } catch (const std::exception& e) {
      ok = 0;
      error = e.what();
    }
  }
  Teuchos::broadcast(*comm, 0, &ok);
  TEUCHOS_TEST_FOR_EXCEPTION(!ok, std::runtime_error,
                             "impm::NewtonSolver: direct factorisation of the assembled matrix failed"
                                 << (error.empty() ? std::string() : ": " + error));
}

void GatheredDirectInverse::Op::apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode, Scalar alpha,
                                      Scalar beta) const {
  TEUCHOS_TEST_FOR_EXCEPTION(mode != Teuchos::NO_TRANS, std::logic_error,
                             "impm::GatheredDirectInverse: only the non-transposed inverse is available");
  const size_t nv = X.getNumVectors();
  MultiVector rootX(rootMap_, nv), rootY(rootMap_, nv);
  rootX.doImport(X, *vecImport_, Tpetra::INSERT);
  if (!solver_.is_null() && map_->getComm()->getRank() == 0) {
    MultiVector serialX(serialMap_, nv), serialY(serialMap_, nv);
    Kokkos::deep_copy(serialX.getLocalViewHost(Tpetra::Access::OverwriteAll), rootX.getLocalViewHost(Tpetra::Access::ReadOnly));
    solver_->solve(Teuchos::ptrFromRef(serialY), Teuchos::ptrFromRef(static_cast<const MultiVector&>(serialX)));
    Kokkos::deep_copy(rootY.getLocalViewHost(Tpetra::Access::OverwriteAll), serialY.getLocalViewHost(Tpetra::Access::ReadOnly));
  }
  if (beta == Teuchos::ScalarTraits<Scalar>::zero()) {
    Y.doExport(rootY, *vecImport_, Tpetra::REPLACE);
    if (alpha != Teuchos::ScalarTraits<Scalar>::one()) Y.scale(alpha);
  } else {
    MultiVector Z(map_, nv);
    Z.doExport(rootY, *vecImport_, Tpetra::REPLACE);
    Y.update(alpha, Z, beta);
  }
}

GatheredDirectInverse::GatheredDirectInverse() = default;
GatheredDirectInverse::~GatheredDirectInverse() = default;

RCP<TpetraOperator> GatheredDirectInverse::update(const RCP<const CrsMatrix>& P, long /*valuesVersion*/) {
  if (op_.is_null()) op_ = rcp(new Op());
  op_->factor(P);
  ++factorizations_;
  return op_;
}

// ---------------------------------------------------------------------------------------------
// ImplicitModelEvaluator

ImplicitModelEvaluator::ImplicitModelEvaluator(
    ResidualModel& model, const RCP<const Map>& map,
    const RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& W_factory, bool supportsWop,
    const RCP<PreconditionerCache>& prec)
    : model_(&model),
      map_(map),
      space_(Thyra::createVectorSpace<Scalar, LO, GO, Node>(map)),
      W_factory_(W_factory),
      supportsWop_(supportsWop),
      prec_(prec) {}

void ImplicitModelEvaluator::beginSolve() {
  P_ = Teuchos::null;  // xOfP_ and diff_ stay allocated; they are only read while P_ is set
  residualEvaluations_ = 0;
  jacobianEvaluations_ = 0;
}

Thyra::ModelEvaluatorBase::InArgs<double> ImplicitModelEvaluator::createInArgs() const {
  Thyra::ModelEvaluatorBase::InArgsSetup<double> inArgs;
  inArgs.setModelEvalDescription(this->description());
  inArgs.setSupports(Thyra::ModelEvaluatorBase::IN_ARG_x);
  return std::move(inArgs);
}

Thyra::ModelEvaluatorBase::OutArgs<double> ImplicitModelEvaluator::createOutArgsImpl() const {
  Thyra::ModelEvaluatorBase::OutArgsSetup<double> outArgs;
  outArgs.setModelEvalDescription(this->description());
  outArgs.setSupports(Thyra::ModelEvaluatorBase::OUT_ARG_f);
  if (supportsWop_) outArgs.setSupports(Thyra::ModelEvaluatorBase::OUT_ARG_W_op);
  if (!prec_.is_null()) outArgs.setSupports(Thyra::ModelEvaluatorBase::OUT_ARG_W_prec);
  return std::move(outArgs);
}

RCP<Thyra::LinearOpBase<double>> ImplicitModelEvaluator::create_W_op() const {
  TEUCHOS_TEST_FOR_EXCEPTION(!supportsWop_, std::logic_error,
                             "impm::ImplicitModelEvaluator: W_op requested but not supported");
  return rcp(new ThyraTpetraOp());
}

RCP<Thyra::PreconditionerBase<double>> ImplicitModelEvaluator::create_W_prec() const {
  if (prec_.is_null()) return Teuchos::null;
  return rcp(new Thyra::DefaultPreconditioner<double>());
}

RCP<const CrsMatrix> ImplicitModelEvaluator::matrixAt(const Vector& x) const {
  if (!P_.is_null()) {
    diff_->update(1.0, x, -1.0, *xOfP_, 0.0);
    if (diff_->normInf() == 0.0) return P_;
  }
  RCP<const CrsMatrix> P = model_->jacobianMatrix(x);
  ++jacobianEvaluations_;
  TEUCHOS_TEST_FOR_EXCEPTION(P.is_null() || !P->isFillComplete(), std::runtime_error,
                             "impm::NewtonSolver: ResidualModel::jacobianMatrix returned a null or "
                             "not fill-complete matrix");
  if (P.get() != P_.get()) {
    // Collective (Map::isSameAs); cheap when the maps are the model's own map objects.
    TEUCHOS_TEST_FOR_EXCEPTION(!P->getRangeMap()->isSameAs(*map_) || !P->getDomainMap()->isSameAs(*map_),
                               std::runtime_error,
                               "impm::NewtonSolver: the matrix from ResidualModel::jacobianMatrix must have "
                               "range and domain maps equal to ResidualModel::unknownMap()");
  }
  if (xOfP_.is_null()) {
    xOfP_ = rcp(new Vector(map_));
    diff_ = rcp(new Vector(map_));
  }
  Tpetra::deep_copy(*xOfP_, x);
  P_ = P;
  return P_;
}

void ImplicitModelEvaluator::evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& inArgs,
                                           const Thyra::ModelEvaluatorBase::OutArgs<double>& outArgs) const {
  TEUCHOS_TEST_FOR_EXCEPTION(inArgs.get_x().is_null(), std::logic_error,
                             "impm::ImplicitModelEvaluator: evalModel without x");
  const RCP<const Vector> x = TOE::getConstTpetraVector(inArgs.get_x());

  const RCP<Thyra::VectorBase<double>> f_out = outArgs.get_f();
  if (!f_out.is_null()) {
    const RCP<Vector> f = TOE::getTpetraVector(f_out);
    model_->residual(*x, *f);
    ++residualEvaluations_;
  }

  if (supportsWop_) {
    const RCP<Thyra::LinearOpBase<double>> W_out = outArgs.get_W_op();
    if (!W_out.is_null()) {
      // Re-point NOX's W_op at the current P: Amesos2 sees a new matrix object (full factorisation)
      // or the same one with new values (numeric refactorisation).
      auto W = Teuchos::rcp_dynamic_cast<ThyraTpetraOp>(W_out, true);
      W->constInitialize(space_, space_, matrixAt(*x));
    }
  }

  if (!prec_.is_null()) {
    const RCP<Thyra::PreconditionerBase<double>> W_prec_out = outArgs.get_W_prec();
    if (!W_prec_out.is_null()) {
      const RCP<const CrsMatrix> P = matrixAt(*x);
      prec_->setUnknownGeometry(model_->unknownCoordinates(), model_->unknownsPerNode());
      RCP<TpetraOperator> M = prec_->update(P, model_->jacobianVersion());
      auto prec = Teuchos::rcp_dynamic_cast<Thyra::DefaultPreconditioner<double>>(W_prec_out, true);
      const RCP<Thyra::LinearOpBase<double>> op = Thyra::tpetraLinearOp<Scalar, LO, GO, Node>(space_, space_, M);
      prec->initializeRight(op);  // (a typed RCP would be ambiguous between the const and non-const overloads)
    }
  }
}

}  // namespace impm
