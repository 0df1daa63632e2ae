// Preconditioner: MUELU (smoothed-aggregation AMG, solvers/MueLuPreconditioner.cpp). On the seed
// beam (apps/beam_implicit_mpm_plane_strain.yaml: implicit MPM, Jacobian-free Newton-Krylov,
// linear tolerance 1e-8) at 40 x 4 and 80 x 8 cells: at most 10 GMRES iterations per Newton
// iteration on average, and the mid-span deflection of the direct solve (AMESOS2) to the Newton
// tolerance. And the deck checks of the 'Implicit Solver/MueLu' list.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include "RunHistory.hpp"
#include "core/InputDeck.hpp"
#include "solvers/MueLuPreconditioner.hpp"
#include "solvers/NewtonSolver.hpp"
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
  deck->sublist("Grid").set("Cells X", nx).set("Cells Y", ny).set("Cell Size X", 10.0 / nx).set("Cell Size Y", 0.5 / ny);
  deck->sublist("Integrator").set("Number of Steps", steps);
  ParameterList& solver = deck->sublist("Implicit Solver");
  solver.set("Preconditioner", preconditioner);
  solver.remove("Ifpack2");  // the deck's ILU level of fill
  deck->sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
  const std::string dir = "test_output/muelu_beam_" + preconditioner + "_" + std::to_string(nx);
  impm::Simulation sim(*deck, Tpetra::getDefaultComm(), dir);
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  TEUCHOS_TEST_FOR_EXCEPTION(r.status != "completed", std::runtime_error, "beam run: " + r.status);
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
  for (int nx : {40, 80}) {
    const BeamRun amg = runBeam(nx, "MUELU", 10, out);
    const BeamRun direct = runBeam(nx, "AMESOS2", 10, out);
    TEST_COMPARE(amg.gmresPerNewton, <=, 10.0);
    TEST_COMPARE(amg.newtonPerStep, <=, direct.newtonPerStep + 0.5);
    // The deck's Newton tolerance: a second Newton step changes w(L/2) by ~2.5e-8 of its amplitude.
    TEST_COMPARE(std::abs(amg.w - direct.w), <=, 1e-7 * direct.wMax);
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
