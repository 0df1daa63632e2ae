#include "solvers/newton/GatheredDirectInverse.hpp"

#include <Amesos2.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultSerialComm.hpp>
#include <Tpetra_ComputeGatherMap.hpp>

#include <stdexcept>

#include "core/PhaseTimer.hpp"

namespace impm {

using Teuchos::RCP;
using Teuchos::rcp;

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
  RCP<const Map> map_, rowMap_;  // the unknowns' map and P's row map (kept to detect changes)
  RCP<const Map> rootMap_;       // all of map_'s indices on rank 0
  RCP<const Import> vecImport_, rowImport_;
  RCP<const Map> serialMap_;  // rank 0: 0..n-1 on a serial communicator
  RCP<CrsMatrix> serialP_;    // rank 0: P in rootMap_'s order
  RCP<Solver> solver_;        // rank 0: KLU2 on one process
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
    Kokkos::deep_copy(serialX.getLocalViewHost(Tpetra::Access::OverwriteAll),
                      rootX.getLocalViewHost(Tpetra::Access::ReadOnly));
    solver_->solve(Teuchos::ptrFromRef(serialY), Teuchos::ptrFromRef(static_cast<const MultiVector&>(serialX)));
    Kokkos::deep_copy(rootY.getLocalViewHost(Tpetra::Access::OverwriteAll),
                      serialY.getLocalViewHost(Tpetra::Access::ReadOnly));
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

}  // namespace impm
