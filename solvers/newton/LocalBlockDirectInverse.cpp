#include "solvers/newton/LocalBlockDirectInverse.hpp"

#include <Amesos2.hpp>
#include <Teuchos_DefaultSerialComm.hpp>

#include <stdexcept>

#include "core/PhaseTimer.hpp"

namespace impm {

using Teuchos::RCP;
using Teuchos::rcp;

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
      block_->A->insertGlobalValues(
          GO(i), Teuchos::ArrayView<const GO>(g),
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
  Kokkos::deep_copy(serialX.getLocalViewHost(Tpetra::Access::OverwriteAll),
                    X.getLocalViewHost(Tpetra::Access::ReadOnly));
  block_->solver->solve(Teuchos::ptrFromRef(serialY), Teuchos::ptrFromRef(static_cast<const MultiVector&>(serialX)));
  auto y = Y.getLocalViewHost(Tpetra::Access::ReadWrite);
  auto s = serialY.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (size_t i = 0; i < y.extent(0); ++i)
    for (size_t j = 0; j < nv; ++j) y(i, j) = beta == 0.0 ? alpha * s(i, j) : alpha * s(i, j) + beta * y(i, j);
}

}  // namespace impm
