#include "solvers/MueLuPreconditioner.hpp"

#include <stdexcept>
#include <string>

#ifdef IMPM_HAVE_MUELU
#include <MueLu_CreateTpetraPreconditioner.hpp>
#include <MueLu_MasterList.hpp>
#include <MueLu_TpetraOperator.hpp>
#include <Teuchos_DefaultSerialComm.hpp>

#include <algorithm>
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
  // Symmetric Gauss-Seidel (Ifpack2 RELAXATION): fewer GMRES iterations on the beam's P than
  // MueLu's default Chebyshev (see README, "Preconditioners under refinement").
  d.set("smoother: type", "RELAXATION");
  ParameterList& smoother = d.sublist("smoother: params");
  smoother.set("relaxation: type", "Symmetric Gauss-Seidel");
  smoother.set("relaxation: sweeps", 2);
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
      throw std::invalid_argument(at + " is set by impm (the unknowns per grid node; their rigid-body modes and "
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
      throw std::invalid_argument(at + (m->isList() ? " must be a sublist, not a value" : " must be a value, not a sublist"));
    if (!m->isList() && m->isType<double>() && pl.entry(it).isType<int>()) toDouble.push_back(key);
  }
  for (const std::string& key : toDouble) pl.set(key, static_cast<double>(pl.get<int>(key)));
}

// Per node (in the order of the unknowns): gid / unknownsPerNode and the node's coordinates.
RCP<MultiVector> nodeCoordinates(const MultiVector& coords, int upn) {
  const Map& map = *coords.getMap();
  auto c = coords.getLocalViewHost(Tpetra::Access::ReadOnly);
  std::vector<GO> nodes;
  std::vector<size_t> first;
  for (size_t k = 0; k < map.getNodeNumElements(); ++k) {
    const GO node = map.getGlobalElement((LO)k) / upn;
    if (nodes.empty() || nodes.back() != node) {
      nodes.push_back(node);
      first.push_back(k);
    }
  }
  const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
  auto nodeMap = rcp(new Map(invalid, Teuchos::ArrayView<const GO>(nodes), 0, map.getComm()));
  auto out = rcp(new MultiVector(nodeMap, coords.getNumVectors()));
  auto o = out->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t n = 0; n < nodes.size(); ++n)
    for (size_t d = 0; d < coords.getNumVectors(); ++d) o(n, d) = c(first[n], d);
  return out;
}

// Rigid-body modes on the unknowns (gid = upn node + component), about the mean of the
// coordinates: translations, then rotations (2D: about z; 3D: about z, x, y).
RCP<MultiVector> rigidBodyModes(const MultiVector& coords, int dim) {
  std::vector<Scalar> mean(dim);
  coords.meanValue(Teuchos::ArrayView<Scalar>(mean));
  const int modes = dim == 2 ? 3 : 6;
  auto ns = rcp(new MultiVector(coords.getMap(), modes));
  auto c = coords.getLocalViewHost(Tpetra::Access::ReadOnly);
  auto z = ns->getLocalViewHost(Tpetra::Access::OverwriteAll);
  const Map& map = *coords.getMap();
  for (size_t k = 0; k < map.getNodeNumElements(); ++k) {
    const int comp = (int)(map.getGlobalElement((LO)k) % dim);
    const double x = c(k, 0) - mean[0], y = c(k, 1) - mean[1], zc = dim == 3 ? c(k, 2) - mean[2] : 0.0;
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

class MueLuPreconditionerCache : public PreconditionerCache {
 public:
  explicit MueLuPreconditionerCache(const ParameterList& deck) : params_(deck) {
    checkKeys(params_, kWhere, true);
    // impm's defaults where the deck is silent; the smoother's type and its parameters go together.
    const ParameterList defaults = mueLuDefaults();
    const bool ownSmoother = params_.isParameter("smoother: type") || params_.isSublist("smoother: params");
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
        !op_.is_null() && P.get() == matrix_.get() && P->isStaticGraph() && coords_.get() == coordsOfOp_.get();
    if (sameStructure && valuesVersion >= 0 && valuesVersion == valuesVersion_) return op_;
    try {
      if (!sameStructure) {
        op_ = build(P, params_, coords_, upn_);
        matrix_ = P;
        coordsOfOp_ = coords_;
        ++initializations_;
      } else {
        MueLu::ReuseTpetraPreconditioner(Teuchos::rcp_const_cast<CrsMatrix>(P), *op_);
      }
    } catch (const std::exception& e) {
      op_ = Teuchos::null;
      throw std::runtime_error("impm::NewtonSolver: MueLu set-up failed: " + oneLine(e.what()));
    }
    valuesVersion_ = valuesVersion;
    return op_;
  }
  int initializations() const override { return initializations_; }

 private:
  static RCP<MueLuOperator> build(const RCP<const CrsMatrix>& P, const ParameterList& params,
                                  const RCP<const MultiVector>& coords, int upn) {
    ParameterList list(params);
    list.set("number of equations", upn);
    if (!coords.is_null() && (upn == 2 || upn == 3) && (int)coords->getNumVectors() == upn) {
      ParameterList& user = list.sublist("user data");
      user.set<RCP<MultiVector>>("Nullspace", rigidBodyModes(*coords, upn));
      user.set<RCP<MultiVector>>("Coordinates", nodeCoordinates(*coords, upn));
    }
    RCP<TpetraOperator> A = Teuchos::rcp_const_cast<CrsMatrix>(P);
    return MueLu::CreateTpetraPreconditioner<Scalar, LO, GO, Node>(A, list);
  }

  // A hierarchy of at least two levels on a small 2D-elasticity-like matrix (a chain of 40 nodes,
  // 2 unknowns each) over a serial communicator, and one application: MueLu and Ifpack2 check the
  // values of the list here rather than at the first time step.
  void probe() const {
    RCP<const Teuchos::Comm<int>> self = rcp(new Teuchos::SerialComm<int>());
    const int nodes = 40, upn = 2, n = nodes * upn;
    auto map = rcp(new Map(n, 0, self));
    auto A = rcp(new CrsMatrix(map, 3));
    for (GO r = 0; r < n; ++r) {
      std::vector<GO> cols{r};
      std::vector<Scalar> vals{2.1};
      if (r - upn >= 0) cols.push_back(r - upn), vals.push_back(-1.0);
      if (r + upn < n) cols.push_back(r + upn), vals.push_back(-1.0);
      A->insertGlobalValues(r, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const Scalar>(vals));
    }
    A->fillComplete();
    auto coords = rcp(new MultiVector(map, upn));
    {
      auto c = coords->getLocalViewHost(Tpetra::Access::OverwriteAll);
      for (int r = 0; r < n; ++r) c(r, 0) = r / upn, c(r, 1) = 0.1 * (r / upn % 3);
    }
    ParameterList list(params_);
    list.set("coarse: max size", 10);
    try {
      RCP<MueLuOperator> op = build(A, list, coords, upn);
      Vector x(map), y(map);
      x.putScalar(1.0);
      op->apply(x, y);
    } catch (const std::exception& e) {
      throw std::invalid_argument(kWhere + "' rejected by MueLu: " + oneLine(e.what()));
    }
  }

  ParameterList params_;
  RCP<const MultiVector> coords_, coordsOfOp_;
  int upn_ = 1;
  RCP<MueLuOperator> op_;
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
