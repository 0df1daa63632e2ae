#include "solvers/newton/MueLuPreconditioner.hpp"

#include <stdexcept>
#include <string>

#ifdef IMPM_HAVE_MUELU
// First: KokkosKernels 13.2's graph-colouring headers include each other in a circle, and MueLu's
// (non-ETI) aggregation headers reach them from the side that breaks it.
#include <KokkosGraph_Distance1Color.hpp>
#include <MueLu_CreateTpetraPreconditioner.hpp>
#include <MueLu_MasterList.hpp>
#include <MueLu_TpetraOperator.hpp>
#include <Teuchos_DefaultSerialComm.hpp>
#ifdef HAVE_MPI
#include <Teuchos_DefaultMpiComm.hpp>
#endif

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include "core/PhaseTimer.hpp"
#endif

namespace impm {

using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

Teuchos::ParameterList mueLuDefaults() {
  ParameterList d("MueLu");
  d.set("verbosity", "none");
  d.set("multigrid algorithm", "sa");
  d.set("problem: symmetric", true);
  d.set("aggregation: type", "uncoupled");
  // MueLu 13.2's Kokkos factories (aggregation, tentative prolongator) need twice the GMRES
  // iterations of the classic ones on the beam's P (26 against 13 per Newton on 160 x 16, V-cycle).
  d.set("use kokkos refactor", false);
  // A W-cycle with 3 symmetric Gauss-Seidel sweeps (Ifpack2 RELAXATION): 9 GMRES per Newton from
  // 80 x 8 to 320 x 32; a V-cycle needs 13, MueLu's default Chebyshev 27 (doc/performance.md,
  // "Preconditioners under refinement").
  d.set("cycle type", "W");
  d.set("smoother: type", "RELAXATION");
  ParameterList& smoother = d.sublist("smoother: params");
  smoother.set("relaxation: type", "Symmetric Gauss-Seidel");
  smoother.set("relaxation: sweeps", 3);
  d.set("coarse: type", "KLU2");
  d.set("coarse: max size", 500);
  return d;
}

#ifndef IMPM_HAVE_MUELU

bool mueLuAvailable() { return false; }

RCP<PreconditionerCache> makeMueLuPreconditioner(const ParameterList&) {
  throw std::invalid_argument(
      "invalid value 'MUELU' for 'Implicit Solver/Preconditioner': the Trilinos impm was built against has no "
      "MueLu (build one with cmake/setup-deps.sh, or enable MueLu and Xpetra in yours)");
}

#else

bool mueLuAvailable() { return true; }

namespace {

const std::string kWhere = "'Implicit Solver/MueLu";
using MueLuOperator = MueLu::TpetraOperator<Scalar, LO, GO, Node>;

// MueLu's and Teuchos' messages span lines (file, throw number, test, text): one line of the text.
std::string oneLine(const std::string& what) {
  std::istringstream in(what);
  std::string line, out;
  while (std::getline(in, line)) {
    const auto b = line.find_first_not_of(" \t");
    if (b == std::string::npos) continue;
    line = line.substr(b);
    if (line[0] == '/' || line.rfind("Throw number", 0) == 0 || line.rfind("Throw test that evaluated", 0) == 0)
      continue;
    out += (out.empty() ? "" : " ") + line;
  }
  if (out.size() > 400) out = out.substr(0, 400) + " ...";
  return out.empty() ? what : out;
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// Keys of one level of the list against MueLu's master list: unknown keys (with the nearest
// known one), sublists where values belong and the reverse; YAML integers become doubles where
// MueLu expects a double. Values themselves are left to MueLu.
void checkKeys(ParameterList& pl, const std::string& prefix, bool topLevel) {
  const ParameterList& master = *MueLu::MasterList::List();
  std::vector<std::string> toDouble;
  for (auto it = pl.begin(); it != pl.end(); ++it) {
    const std::string& key = pl.name(it);
    const std::string at = prefix + "/" + key + "'";
    if (topLevel && key.rfind("level ", 0) == 0 && pl.isSublist(key)) {
      checkKeys(pl.sublist(key), prefix + "/" + key, false);
      continue;
    }
    if (key == "number of equations" || key == "user data")
      throw std::invalid_argument(at +
                                  " is set by impm (the unknowns per grid node; their rigid-body modes and "
                                  "coordinates): remove it");
    const Teuchos::ParameterEntry* m = master.getEntryPtr(key);
    if (m == nullptr) {
      std::string best;
      size_t bestScore = 5;
      for (auto v = master.begin(); v != master.end(); ++v) {
        const size_t s = editDistance(key, master.name(v));
        if (s < bestScore) bestScore = s, best = master.name(v);
      }
      throw std::invalid_argument("unknown key " + at + " (MueLu has no such parameter" +
                                  (best.empty() ? std::string(")") : "; did you mean '" + best + "'?)"));
    }
    if (m->isList() != pl.entry(it).isList())
      throw std::invalid_argument(
          at + (m->isList() ? " must be a sublist, not a value" : " must be a value, not a sublist"));
    if (!m->isList() && m->isType<double>() && pl.entry(it).isType<int>()) toDouble.push_back(key);
  }
  for (const std::string& key : toDouble) pl.set(key, static_cast<double>(pl.get<int>(key)));
}

// MueLu's block size ("number of equations") needs every node to carry all its unknownsPerNode
// rows, in order, while impm leaves constrained components out of the unknowns (a roller keeps one
// of two). The padded system puts them back as decoupled rows (the diagonal only, which MueLu
// takes for Dirichlet rows). Its map is contiguous (0..N-1 over the ranks in order): MueLu hands
// the level-0 matrix to Amesos2 when it is small enough, and Amesos2 13.2 gave a wrong solve on the
// unknowns' gaps-and-all gids (measured: 49 GMRES per Newton on the 40 x 4 beam with a one-level
// "hierarchy", i.e. KLU2 alone, where AMESOS2 takes 1.4).
struct PaddedSystem {
  RCP<const Map> map;
  int upn = 1;
  std::vector<LO> position;      // padded local index of each local unknown
  std::vector<LO> firstUnknown;  // a local unknown of each padded node (for its coordinates)
  RCP<const Map> columns;        // P's column map, and the padded gid of each of its columns
  std::vector<GO> paddedColumn;

  PaddedSystem(const CrsMatrix& P, int unknownsPerNode) : upn(unknownsPerNode) {
    const Map& unknowns = *P.getDomainMap();
    const size_t n = unknowns.getNodeNumElements();
    position.resize(n);
    GO lastNode = -1;
    LO padded = 0;
    for (size_t k = 0; k < n; ++k) {
      const GO gid = unknowns.getGlobalElement((LO)k);
      const GO node = gid / upn;
      if (k == 0 || node != lastNode) {
        firstUnknown.push_back((LO)k);
        lastNode = node;
        padded += upn;
      }
      TEUCHOS_TEST_FOR_EXCEPTION(k > 0 && node == unknowns.getGlobalElement((LO)k - 1) / upn &&
                                     gid % upn <= unknowns.getGlobalElement((LO)k - 1) % upn,
                                 std::logic_error, "impm MueLu: a node's unknowns are not in component order");
      position[k] = padded - upn + (LO)(gid % upn);
    }
    const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
    map = rcp(new Map(invalid, (size_t)padded, 0, unknowns.getComm()));
    TEUCHOS_TEST_FOR_EXCEPTION(!P.getRowMap()->isSameAs(unknowns), std::logic_error,
                               "impm MueLu: P's row map is not its domain map");
    // The padded gid of every column of P: owned ones directly, the others through P's Import
    // (held in doubles, exact below 2^53).
    columns = P.getColMap();
    Vector own(P.getDomainMap());
    {
      auto o = own.getLocalViewHost(Tpetra::Access::OverwriteAll);
      for (size_t k = 0; k < n; ++k) o(k, 0) = (double)map->getGlobalElement(position[k]);
    }
    Vector col(columns);
    auto importer = P.getGraph()->getImporter();
    if (importer.is_null())
      Tpetra::deep_copy(col, own);
    else
      col.doImport(own, *importer, Tpetra::INSERT);
    auto c = col.getLocalViewHost(Tpetra::Access::ReadOnly);
    paddedColumn.resize(columns->getNodeNumElements());
    for (size_t k = 0; k < paddedColumn.size(); ++k) paddedColumn[k] = (GO)std::llround(c(k, 0));
  }

  // P on the padded map; the added rows carry the mean |diagonal| of the rank's rows of P.
  RCP<CrsMatrix> pad(const CrsMatrix& P) const {
    TEUCHOS_TEST_FOR_EXCEPTION(!P.getColMap()->isSameAs(*columns), std::logic_error,
                               "impm MueLu: P's columns changed without a new padded system");
    auto A = rcp(new CrsMatrix(map, P.getNodeMaxNumRowEntries()));
    const Map& unknowns = *P.getDomainMap();
    const Map& rows = *P.getRowMap();
    std::vector<GO> cols;
    std::vector<Scalar> vals;
    double diagSum = 0.0;
    for (LO i = 0; i < (LO)rows.getNodeNumElements(); ++i) {
      CrsMatrix::local_inds_host_view_type inds;
      CrsMatrix::values_host_view_type v;
      P.getLocalRowView(i, inds, v);
      const GO row = map->getGlobalElement(position[unknowns.getLocalElement(rows.getGlobalElement(i))]);
      cols.resize(inds.extent(0));
      vals.resize(inds.extent(0));
      for (size_t k = 0; k < inds.extent(0); ++k) {
        cols[k] = paddedColumn[inds(k)];
        vals[k] = v(k);
        if (cols[k] == row) diagSum += std::abs(vals[k]);
      }
      A->insertGlobalValues(row, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const Scalar>(vals));
    }
    const Scalar diag = rows.getNodeNumElements() ? diagSum / rows.getNodeNumElements() : 1.0;
    std::vector<char> present(map->getNodeNumElements(), 0);
    for (LO p : position) present[p] = 1;
    for (size_t a = 0; a < present.size(); ++a)
      if (!present[a]) {
        const GO g = map->getGlobalElement((LO)a);
        A->insertGlobalValues(g, Teuchos::ArrayView<const GO>(&g, 1), Teuchos::ArrayView<const Scalar>(&diag, 1));
      }
    A->fillComplete(map, map);
    return A;
  }

  // Node coordinates (one row per padded node) from the unknowns' coordinates.
  RCP<MultiVector> nodeCoordinates(const MultiVector& coords) const {
    const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
    auto nodeMap = rcp(new Map(invalid, firstUnknown.size(), 0, map->getComm()));
    auto out = rcp(new MultiVector(nodeMap, coords.getNumVectors()));
    auto c = coords.getLocalViewHost(Tpetra::Access::ReadOnly);
    auto o = out->getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t n = 0; n < firstUnknown.size(); ++n)
      for (size_t d = 0; d < coords.getNumVectors(); ++d) o(n, d) = c(firstUnknown[n], d);
    return out;
  }
};

// Rigid-body modes on the padded unknowns, about the mean of the node coordinates: translations,
// then rotations (2D: about z; 3D: about z, x, y).
RCP<MultiVector> rigidBodyModes(const MultiVector& nodeCoords, const RCP<const Map>& paddedMap, int dim) {
  const Map& padded = *paddedMap;
  std::vector<Scalar> mean(dim);
  nodeCoords.meanValue(Teuchos::ArrayView<Scalar>(mean));
  const int modes = dim == 2 ? 3 : 6;
  auto ns = rcp(new MultiVector(paddedMap, modes));
  auto c = nodeCoords.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto z = ns->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t k = 0; k < padded.getNodeNumElements(); ++k) {
    const size_t node = k / dim;  // the padded map lists whole nodes
    const int comp = (int)(k % dim);
    const double x = c(node, 0) - mean[0], y = c(node, 1) - mean[1], zc = dim == 3 ? c(node, 2) - mean[2] : 0.0;
    for (int m = 0; m < modes; ++m) z(k, m) = 0.0;
    z(k, comp) = 1.0;
    z(k, dim) = comp == 0 ? -y : comp == 1 ? x : 0.0;  // about z
    if (dim == 3) {
      z(k, 4) = comp == 1 ? -zc : comp == 2 ? y : 0.0;  // about x
      z(k, 5) = comp == 2 ? -x : comp == 0 ? zc : 0.0;  // about y
    }
  }
  return ns;
}

// The hierarchy on the padded system, applied to the unknowns: x is extended by zeros, and the
// padded rows of the result are dropped.
class PaddedOperator : public TpetraOperator {
 public:
  PaddedOperator(RCP<const Map> unknowns, std::shared_ptr<const PaddedSystem> padded, RCP<MueLuOperator> inner)
      : map_(std::move(unknowns)), padded_(std::move(padded)), inner_(std::move(inner)) {}
  RCP<const Map> getDomainMap() const override { return map_; }
  RCP<const Map> getRangeMap() const override { return map_; }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             Scalar alpha = Teuchos::ScalarTraits<Scalar>::one(),
             Scalar beta = Teuchos::ScalarTraits<Scalar>::zero()) const override {
    TEUCHOS_TEST_FOR_EXCEPTION(mode != Teuchos::NO_TRANS, std::logic_error, "impm MueLu: no transposed apply");
    const size_t nv = X.getNumVectors();
    const std::vector<LO>& pos = padded_->position;
    MultiVector Xp(padded_->map, nv), Yp(padded_->map, nv);  // zero-initialised
    {
      auto x = X.getLocalViewHost(Tpetra::Access::ReadOnly);
      auto xp = Xp.getLocalViewHost(Tpetra::Access::ReadWrite);
      for (size_t k = 0; k < pos.size(); ++k)
        for (size_t j = 0; j < nv; ++j) xp(pos[k], j) = x(k, j);
    }
    inner_->apply(Xp, Yp);
    auto yp = Yp.getLocalViewHost(Tpetra::Access::ReadOnly);
    if (beta == Teuchos::ScalarTraits<Scalar>::zero()) {
      auto y = Y.getLocalViewHost(Tpetra::Access::OverwriteAll);  // (beta = 0: Y may hold NaN)
      for (size_t k = 0; k < pos.size(); ++k)
        for (size_t j = 0; j < nv; ++j) y(k, j) = alpha * yp(pos[k], j);
    } else {
      auto y = Y.getLocalViewHost(Tpetra::Access::ReadWrite);
      for (size_t k = 0; k < pos.size(); ++k)
        for (size_t j = 0; j < nv; ++j) y(k, j) = alpha * yp(pos[k], j) + beta * y(k, j);
    }
  }
  MueLuOperator& inner() { return *inner_; }

 private:
  RCP<const Map> map_;
  std::shared_ptr<const PaddedSystem> padded_;
  RCP<MueLuOperator> inner_;
};

class MueLuPreconditionerCache : public PreconditionerCache {
 public:
  explicit MueLuPreconditionerCache(const ParameterList& deck) : params_(deck) {
    checkKeys(params_, kWhere, true);
    // impm's defaults where the deck is silent; the smoother's type and its parameters go together.
    const ParameterList defaults = mueLuDefaults();
    const bool ownSmoother = params_.isParameter("smoother: type") || params_.isSublist("smoother: params");
    ownCoarse_ = params_.isParameter("coarse: type") || params_.isSublist("coarse: params");
    for (auto it = defaults.begin(); it != defaults.end(); ++it) {
      const std::string& key = defaults.name(it);
      if (ownSmoother && (key == "smoother: type" || key == "smoother: params")) continue;
      if (!params_.isParameter(key)) params_.setEntry(key, defaults.entry(it));
    }
    probe();
  }

  void setUnknownGeometry(const RCP<const MultiVector>& coordinates, int unknownsPerNode) override {
    coords_ = coordinates;
    upn_ = unknownsPerNode;
  }

  // Same policy as IfpackPreconditionerCache: a new hierarchy for a new matrix object or graph (or
  // new unknowns' geometry); the same matrix with new values re-runs the set-up on the kept
  // hierarchy (MueLu's "reuse: type" decides what it keeps); same values: nothing to do.
  RCP<TpetraOperator> update(const RCP<const CrsMatrix>& P, long valuesVersion) override {
    PhaseTimer phase("preconditioner set-up");
    const bool sameStructure =
        op_ != nullptr && P.get() == matrix_.get() && P->isStaticGraph() && coords_.get() == coordsOfOp_.get();
    if (sameStructure && valuesVersion >= 0 && valuesVersion == valuesVersion_) return op_->op;
    try {
      if (!sameStructure) {
        op_ = build(P, coarseForRanks(P->getComm()->getSize(), P->getNodeNumRows() == 0), coords_, upn_);
        matrix_ = P;
        coordsOfOp_ = coords_;
        ++initializations_;
      } else {
        MueLu::ReuseTpetraPreconditioner(op_->padded->pad(*P), op_->op->inner());
      }
    } catch (const std::exception& e) {
      op_ = nullptr;
      throw std::runtime_error("impm::NewtonSolver: MueLu set-up failed: " + oneLine(e.what()));
    }
    valuesVersion_ = valuesVersion;
    return op_->op;
  }
  int initializations() const override { return initializations_; }

 private:
  struct Built {
    std::shared_ptr<const PaddedSystem> padded;
    RCP<PaddedOperator> op;
  };

  // The list for a run on `ranks` ranks. Amesos2 13.2's KLU2 solves wrongly on a matrix spread
  // over several ranks (a tridiagonal system on 2 ranks: relative error 7.9, with this Trilinos
  // and with the one built without MueLu), so MueLu's default coarse solve cannot be used there.
  // impm's default becomes an additive Schwarz whose overlap (8) takes in most of the small coarse
  // matrix, with ILU(10) of each rank's overlapped block: as good as its exact LU on the beam (the
  // same GMRES counts), and, unlike Ifpack2's AMESOS2, it survives a rank without rows (KLU2's
  // numeric factorisation fails there: a cantilever split in y over 2 ranks).
  //
  // A deck's own SCHWARZ coarse solve with an AMESOS2 subdomain solve goes through
  // avoidAmesosOnEmptyBlock: a rank that owns no rows of P gets no coarse rows either from MueLu's
  // uncoupled aggregation, and KLU2 would throw there.
  ParameterList coarseForRanks(int ranks, bool rankIsEmpty) const {
    if (ranks == 1) return params_;
    const std::string type = params_.get<std::string>("coarse: type");
    if (type == "SCHWARZ" && rankIsEmpty && params_.isSublist("coarse: params")) {
      ParameterList list(params_);
      avoidAmesosOnEmptyBlock(list.sublist("coarse: params"), true);
      return list;
    }
    const bool direct = type == "KLU2" || type == "KLU" || type == "Klu" || type == "Klu2";
    if (!direct) return params_;
    if (ownCoarse_)
      throw std::invalid_argument(
          kWhere + "/coarse: type' = " + type +
          ": Amesos2 13.2 solves wrongly on more than one MPI rank; leave 'coarse: type' "
          "unset (impm then uses SCHWARZ with ILU(10) of each rank's block) or name an Ifpack2 type");
    ParameterList list(params_);
    list.set("coarse: type", "SCHWARZ");
    ParameterList& coarse = list.sublist("coarse: params");
    coarse.set("schwarz: overlap level", 8);
    coarse.set("subdomain solver name", "RILUK");
    coarse.sublist("subdomain solver parameters").set("fact: iluk level-of-fill", 10);
    return list;
  }

  // MueLu on P padded to whole nodes, with "number of equations" = unknowns per node, and the
  // rigid-body modes and node coordinates when the model gives its geometry.
  static std::shared_ptr<Built> build(const RCP<const CrsMatrix>& P, const ParameterList& params,
                                      const RCP<const MultiVector>& coords, int upn) {
    // The unknowns' order is the domain map's (the vectors'); P's row map may list them otherwise.
    auto padded = std::make_shared<const PaddedSystem>(*P, upn);
    ParameterList list(params);
    list.set("number of equations", upn);
    if (!coords.is_null() && (upn == 2 || upn == 3) && (int)coords->getNumVectors() == upn) {
      RCP<MultiVector> nodeCoords = padded->nodeCoordinates(*coords);
      ParameterList& user = list.sublist("user data");
      user.set<RCP<MultiVector> >("Nullspace", rigidBodyModes(*nodeCoords, padded->map, upn));
      user.set<RCP<MultiVector> >("Coordinates", nodeCoords);
    }
    RCP<CrsMatrix> A = padded->pad(*P);
    RCP<MueLuOperator> mueLu = MueLu::CreateTpetraPreconditioner<Scalar, LO, GO, Node>(A, list);
    auto b = std::make_shared<Built>();
    b->padded = padded;
    b->op = rcp(new PaddedOperator(P->getDomainMap(), padded, mueLu));
    return b;
  }

  // A hierarchy of at least two levels on a small 2D-elasticity-like matrix (a chain of 40 nodes,
  // 2 unknowns each, the first node's second one constrained away) over a one-process communicator, and
  // one application: MueLu and Ifpack2 check the values of the list here rather than at the first
  // time step.
  void probe() const {
#ifdef HAVE_MPI
    // (MueLu 13.2's Hierarchy::describe casts the communicator to Teuchos::MpiComm when built with MPI.)
    RCP<const Teuchos::Comm<int> > self = rcp(new Teuchos::MpiComm<int>(MPI_COMM_SELF));
#else
    RCP<const Teuchos::Comm<int> > self = rcp(new Teuchos::SerialComm<int>());
#endif
    const int nodes = 40, upn = 2, n = nodes * upn;
    std::vector<GO> gids;
    for (GO r = 0; r < n; ++r)
      if (r != 1) gids.push_back(r);
    auto map = rcp(
        new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), Teuchos::ArrayView<const GO>(gids), 0, self));
    auto A = rcp(new CrsMatrix(map, 3));
    for (GO r : gids) {
      std::vector<GO> cols{r};
      std::vector<Scalar> vals{2.1};
      if (r - upn >= 0 && r - upn != 1) cols.push_back(r - upn), vals.push_back(-1.0);
      if (r + upn < n) cols.push_back(r + upn), vals.push_back(-1.0);
      A->insertGlobalValues(r, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const Scalar>(vals));
    }
    A->fillComplete();
    auto coords = rcp(new MultiVector(map, upn));
    {
      auto c = coords->getLocalViewHost(Tpetra::Access::OverwriteAll);
      for (size_t k = 0; k < gids.size(); ++k) c(k, 0) = gids[k] / upn, c(k, 1) = 0.1 * (gids[k] / upn % 3);
    }
    ParameterList list(params_);
    list.set("coarse: max size", 10);
    try {
      std::shared_ptr<Built> b = build(A, list, coords, upn);
      Vector x(map), y(map);
      x.putScalar(1.0);
      b->op->apply(x, y);
    } catch (const std::exception& e) {
      throw std::invalid_argument(kWhere + "' rejected by MueLu: " + oneLine(e.what()));
    }
  }

  ParameterList params_;
  RCP<const MultiVector> coords_, coordsOfOp_;
  int upn_ = 1;
  bool ownCoarse_ = false;  // the deck chose the coarse solver
  std::shared_ptr<Built> op_;
  RCP<const CrsMatrix> matrix_;  // held so its address cannot be reused by a new matrix
  int initializations_ = 0;
  long valuesVersion_ = -1;
};

}  // namespace

RCP<PreconditionerCache> makeMueLuPreconditioner(const ParameterList& params) {
  return rcp(new MueLuPreconditionerCache(params));
}

#endif

}  // namespace impm
