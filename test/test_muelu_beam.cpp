// Preconditioner: MUELU (smoothed-aggregation AMG, solvers/newton/MueLuPreconditioner.cpp). On the seed
// beam (apps/beam_implicit_mpm_plane_strain.yaml: implicit MPM, Jacobian-free Newton-Krylov,
// linear tolerance 1e-8) at 80 x 8 and 160 x 16 cells (hierarchies of 2 and 3 levels): at most 10
// GMRES iterations per Newton iteration on average, and the mid-span deflection of the direct
// solve (AMESOS2) to the Newton tolerance. The one-level hierarchy is the exact inverse through
// impm's padding, on one rank and two. And the deck checks of the 'Implicit Solver/MueLu' list.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include <Tpetra_CrsMatrix.hpp>

#include "RunHistory.hpp"
#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/newton/IfpackPreconditioner.hpp"
#include "solvers/newton/ImplicitModelEvaluator.hpp"
#include "solvers/newton/MueLuPreconditioner.hpp"
#include "solvers/newton/NewtonSolver.hpp"
#include "solvers/Simulation.hpp"

namespace {

using Teuchos::ParameterList;

struct BeamRun {
  double newtonPerStep = 0, gmresPerNewton = 0, w = 0, wMax = 0;
};

// The beam deck on nx x nx/10 cells (4 x 4 particles per cell), `steps` steps of dt = 1e-3.
BeamRun runBeam(int nx, const std::string& preconditioner, int steps, Teuchos::FancyOStream& out) {
  auto deck = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/beam_implicit_mpm_plane_strain.yaml");
  impm::validateDeck(*deck);
  const int ny = nx / 10;
  deck->sublist("Grid")
      .set("Cells X", nx)
      .set("Cells Y", ny)
      .set("Cell Size X", 10.0 / nx)
      .set("Cell Size Y", 0.5 / ny);
  deck->sublist("Integrator").set("Number of Steps", steps);
  ParameterList& solver = deck->sublist("Implicit Solver");
  solver.set("Preconditioner", preconditioner);
  solver.remove("Ifpack2");  // the deck's ILU level of fill
  deck->sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
  const std::string dir = "test_output/muelu_beam_" + preconditioner + "_" + std::to_string(nx);
  impm::Simulation sim(*deck, Tpetra::getDefaultComm(), dir);
  const impm::RunResult r = impm_test::runToCompletion(sim, "beam");
  const auto hist = impm_test::readHistory(dir + "/history.csv");
  const auto& w = hist.at("w_mid");
  BeamRun b{impm_test::summaryValue(dir, "Newton Iterations Mean"),
            impm_test::summaryValue(dir, "Krylov Iterations Per Newton Mean"), w.back(), 0.0};
  for (double v : w) b.wMax = std::max(b.wMax, std::abs(v));
  out << std::setprecision(8) << preconditioner << ", " << nx << " x " << ny << " cells: " << b.newtonPerStep
      << " Newton per step, " << b.gmresPerNewton << " GMRES per Newton, w(L/2) = " << b.w << "\n";
  return b;
}

TEUCHOS_UNIT_TEST(MueLuBeam, FewKrylovIterationsAndTheDirectSolution) {
  if (!impm::mueLuAvailable()) {
    out << "this Trilinos has no MueLu: MUELU must be refused\n";
    auto pl = Teuchos::rcp(new ParameterList("Implicit Solver"));
    pl->set("Preconditioner", "MUELU");
    TEST_THROW(impm::NewtonSolver s(pl), std::invalid_argument);
    return;
  }
  for (int nx : {80, 160}) {
    const BeamRun amg = runBeam(nx, "MUELU", 10, out);
    const BeamRun direct = runBeam(nx, "AMESOS2", 10, out);
    TEST_COMPARE(amg.gmresPerNewton, <=, 10.0);
    TEST_COMPARE(amg.newtonPerStep, <=, direct.newtonPerStep + 0.5);
    // The deck's Newton tolerance: a second Newton step changes w(L/2) by ~2.5e-8 of its amplitude.
    TEST_COMPARE(std::abs(amg.w - direct.w), <=, 1e-7 * direct.wMax);
  }
}

// A small SPD, diagonally dominant 2-component operator on the 4-neighbour graph of 12 x 6 nodes,
// with impm's unknown numbering (gid = 2 node + component) and constrained components left out
// (gaps): node 0 entirely, the last node's second component. Rank r owns the nodes of its share
// `shares[r]` (fractions of the node count, in rank order); a share of 0 leaves a rank without rows.
struct SmallSystem {
  Teuchos::RCP<impm::CrsMatrix> P;
  Teuchos::RCP<impm::MultiVector> coords;
};

SmallSystem smallSystem(const std::vector<double>& shares) {
  using impm::GO;
  auto comm = Tpetra::getDefaultComm();
  const int nx = 12, ny = 6, upn = 2, rank = comm->getRank();
  auto constrained = [&](GO node, int c) { return node == 0 || (node == nx * ny - 1 && c == 1); };
  double before = 0.0;
  for (int r = 0; r < rank; ++r) before += shares[r];
  const GO first = std::llround(before * nx * ny), last = std::llround((before + shares[rank]) * nx * ny);
  std::vector<GO> gids;  // whole nodes only
  for (GO node = first; node < last; ++node)
    for (int c = 0; c < upn; ++c)
      if (!constrained(node, c)) gids.push_back(upn * node + c);
  auto map = Teuchos::rcp(new impm::Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                        Teuchos::ArrayView<const GO>(gids), 0, comm));
  // An SPD, diagonally dominant 2-component operator on the 4-neighbour node graph.
  auto P = Teuchos::rcp(new impm::CrsMatrix(map, 16));
  auto coords = Teuchos::rcp(new impm::MultiVector(map, 2));
  {
    auto x = coords->getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t k = 0; k < gids.size(); ++k) {
      const GO node = gids[k] / upn;
      const int c = (int)(gids[k] % upn), i = (int)(node % nx), j = (int)(node / nx);
      x(k, 0) = i, x(k, 1) = j;
      std::vector<GO> cols{gids[k]};
      std::vector<double> vals{4.5};
      const int di[] = {1, -1, 0, 0}, dj[] = {0, 0, 1, -1};
      for (int n = 0; n < 4; ++n) {
        const int a = i + di[n], b = j + dj[n];
        if (a < 0 || a >= nx || b < 0 || b >= ny) continue;
        const GO other = (GO)b * nx + a;
        for (int cc = 0; cc < upn; ++cc)
          if (!constrained(other, cc)) cols.push_back(upn * other + cc), vals.push_back(cc == c ? -1.0 : 0.1);
      }
      P->insertGlobalValues(gids[k], Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(vals));
    }
  }
  P->fillComplete();
  return {P, coords};
}

// |M^-1 P x - x| / |x| for a random x, M being the preconditioner `cache` builds for `system`.
double inverseError(const SmallSystem& system, impm::PreconditionerCache& cache) {
  cache.setUnknownGeometry(system.coords, 2);
  auto M = cache.update(system.P, -1);
  impm::Vector x(system.P->getDomainMap()), Px(system.P->getDomainMap()), y(system.P->getDomainMap());
  x.randomize();
  system.P->apply(x, Px);
  M->apply(Px, y);
  y.update(-1.0, x, 1.0);
  return y.norm2() / x.norm2();
}

// The same for the MUELU preconditioner of `list`.
double inverseError(const SmallSystem& system, const ParameterList& list) {
  auto cache = impm::makeMueLuPreconditioner(list);
  return inverseError(system, *cache);
}

// A one-level "hierarchy" (the matrix below `coarse: max size`) is MueLu's coarse solve alone. On
// one rank that is KLU2; on two, a SCHWARZ coarse solve whose overlap (8) takes in this whole
// graph with KLU2 on each rank's (whole) block. Either way the preconditioner must be the exact
// inverse of P, through impm's padding of constrained components. The padding once sent MueLu the
// gapped gids, and Amesos2 13.2 solved wrongly on them (49 GMRES per Newton on the 40 x 4 beam);
// Amesos2's KLU2 on a matrix over two ranks is wrong too.
TEUCHOS_UNIT_TEST(MueLuBeam, OneLevelIsTheExactInverseThroughThePadding) {
  if (!impm::mueLuAvailable()) return;
  const int ranks = Tpetra::getDefaultComm()->getSize();
  const SmallSystem system = smallSystem(std::vector<double>(ranks, 1.0 / ranks));
  ParameterList list;
  list.set("coarse: max size", 100000);  // one level: the coarse solve on the whole padded P
  if (ranks > 1) {
    list.set("coarse: type", "SCHWARZ");
    list.sublist("coarse: params").set("schwarz: overlap level", 8).set("subdomain solver name", "AMESOS2");
  }
  const double error = inverseError(system, list);
  out << "|M^-1 P x - x| / |x| = " << error << " on " << ranks << " rank(s)\n";
  TEST_COMPARE(error, <, 1e-10);
  const auto& P = system.P;
  const auto& coords = system.coords;
  const int upn = 2;

  // A deck that asks for KLU2 itself is told why not, on more than one rank.
  if (ranks > 1) {
    ParameterList klu;
    klu.set("coarse: max size", 100000).set("coarse: type", "KLU2");
    auto refused = impm::makeMueLuPreconditioner(klu);  // (the deck-time check is one-process: fine)
    refused->setUnknownGeometry(coords, upn);
    std::string message;
    try {
      refused->update(P);
    } catch (const std::exception& e) {
      message = e.what();
    }
    out << message << "\n";
    TEST_ASSERT(message.find("'Implicit Solver/MueLu/coarse: type' = KLU2") != std::string::npos);
  }
}

// impm's own coarse solve on several ranks (SCHWARZ, ILU(10) of each rank's overlapped block) on
// the same one-level system: equal shares, and a rank without rows (Ifpack2's AMESOS2 fails there).
// ILU(10) of the whole 142-row block drops some fill (measured: 3e-5 and 1e-5); a preconditioner
// that close to P^-1 costs GMRES an iteration or two, while a wrong padding or a lost rank gives
// O(1) (0.55 when KLU2 ran over two ranks).
TEUCHOS_UNIT_TEST(MueLuBeam, DefaultCoarseSolveOnSeveralRanksAlsoWithAnEmptyRank) {
  if (!impm::mueLuAvailable()) return;
  const int ranks = Tpetra::getDefaultComm()->getSize();
  if (ranks == 1) {
    out << "one rank: the coarse solve is KLU2 (OneLevelIsTheExactInverseThroughThePadding)\n";
    return;
  }
  ParameterList list;
  list.set("coarse: max size", 100000);
  std::vector<double> equal(ranks, 1.0 / ranks), lastEmpty(ranks, 1.0 / (ranks - 1));
  lastEmpty.back() = 0.0;
  for (const auto& shares : {equal, lastEmpty}) {
    double error = -1.0;
    TEST_NOTHROW(error = inverseError(smallSystem(shares), list));
    out << "|M^-1 P x - x| / |x| = " << error << (shares.back() == 0.0 ? " (last rank without rows)\n" : "\n");
    TEST_COMPARE(error, >=, 0.0);
    TEST_COMPARE(error, <, 1e-3);
  }
}

// A deck's own AMESOS2 subdomain solve (SCHWARZ, as Ifpack2 preconditioner or as MueLu's coarse
// solve) on a rank without rows: KLU2 throws there, on that rank alone, and the other ranks would
// wait for it in a collective for ever (a hang, not an error). That rank takes RILUK, a local solve
// on an empty block. With an overlap (8) that takes in the whole graph, each rank's LU is of the
// whole P: the preconditioner must be P's exact inverse, empty rank or not.
TEUCHOS_UNIT_TEST(MueLuBeam, AmesosSubdomainSolvesSurviveARankWithoutRows) {
  const int ranks = Tpetra::getDefaultComm()->getSize();
  if (ranks == 1) {
    out << "one rank: no rank can be empty\n";
    return;
  }
  std::vector<double> equal(ranks, 1.0 / ranks), lastEmpty(ranks, 1.0 / (ranks - 1));
  lastEmpty.back() = 0.0;
  for (const auto& shares : {equal, lastEmpty}) {
    const SmallSystem system = smallSystem(shares);
    const char* which = shares.back() == 0.0 ? " (last rank without rows)" : "";
    ParameterList schwarz;
    schwarz.set("schwarz: overlap level", 8).set("subdomain solver name", "AMESOS2");
    impm::IfpackPreconditionerCache ifpack("SCHWARZ", schwarz);
    double error = -1.0;
    TEST_NOTHROW(error = inverseError(system, ifpack));
    out << "Ifpack2 SCHWARZ/AMESOS2: |M^-1 P x - x| / |x| = " << error << which << "\n";
    TEST_COMPARE(error, >=, 0.0);
    TEST_COMPARE(error, <, 1e-10);
    if (!impm::mueLuAvailable()) continue;
    ParameterList list;
    list.set("coarse: max size", 100000).set("coarse: type", "SCHWARZ");
    list.sublist("coarse: params").set("schwarz: overlap level", 8).set("subdomain solver name", "AMESOS2");
    error = -1.0;
    TEST_NOTHROW(error = inverseError(system, list));
    out << "MueLu coarse SCHWARZ/AMESOS2: |M^-1 P x - x| / |x| = " << error << which << "\n";
    TEST_COMPARE(error, >=, 0.0);
    TEST_COMPARE(error, <, 1e-10);
  }
}

std::string rejection(const ParameterList& mueLu) {
  auto pl = Teuchos::rcp(new ParameterList("Implicit Solver"));
  pl->set("Preconditioner", "MUELU");
  pl->set("MueLu", mueLu);
  try {
    impm::NewtonSolver s(pl);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEUCHOS_UNIT_TEST(MueLuBeam, BadMueLuListsAreRefusedNamingTheKey) {
  if (!impm::mueLuAvailable()) return;  // covered above
  ParameterList ok;
  ok.set("smoother: type", "CHEBYSHEV").set("aggregation: drop tol", 0);  // a YAML integer where MueLu wants a double
  TEST_EQUALITY(rejection(ok), "");

  ParameterList misspelt;
  misspelt.set("smoother: tipe", "RELAXATION");
  const std::string m1 = rejection(misspelt);
  out << m1 << "\n";
  TEST_ASSERT(m1.find("'Implicit Solver/MueLu/smoother: tipe'") != std::string::npos);
  TEST_ASSERT(m1.find("smoother: type") != std::string::npos);  // the suggestion
  TEST_ASSERT(m1.find('\n') == std::string::npos);

  ParameterList badValue;
  badValue.set("smoother: type", "MAGIC");
  const std::string m2 = rejection(badValue);
  out << m2 << "\n";
  TEST_ASSERT(m2.find("'Implicit Solver/MueLu'") != std::string::npos);
  TEST_ASSERT(m2.find('\n') == std::string::npos);

  ParameterList ownEquations;
  ownEquations.set("number of equations", 3);
  TEST_ASSERT(rejection(ownEquations).find("'Implicit Solver/MueLu/number of equations'") != std::string::npos);
}

}  // namespace
