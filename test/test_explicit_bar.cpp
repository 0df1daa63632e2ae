// A short explicit run of the seed's bar (Problem 1): the tip displacement follows the exact
// solution over the first reflection, for MPM and GIMP, with the modulus of the plane condition.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <sstream>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/Simulation.hpp"
#include "RunHistory.hpp"

namespace {

using Teuchos::ParameterList;

// The seed's bar on its seed grid (30 x 1 cells, 1 mm), 3 x 3 particles per cell, 4000 steps of
// 1e-8 s (t_end = 4e-5 s: the wave crosses the bar almost seven times).
ParameterList barDeck(const std::string& method, const std::string& plane, const std::string& outdir) {
  ParameterList d("impm");
  d.sublist("Problem").set("Name", "unit test bar").set("Output Directory", outdir);
  auto& g = d.sublist("Grid");
  g.set("Cells X", 30).set("Cells Y", 1).set("Cell Size X", 1e-3).set("Cell Size Y", 0.5e-3);
  auto& m = d.sublist("Material");
  m.set("Young Modulus", 200e9).set("Poisson Ratio", 0.3).set("Density", 7800.0).set("Thickness", 1e-3);
  m.set("Plane Condition", plane);
  auto& b = d.sublist("Body");
  b.set("X Max", 0.03).set("Y Max", 0.5e-3).set("Particles Per Cell X", 3).set("Particles Per Cell Y", 3);
  d.sublist("Method").set("Shape Function", method);
  d.sublist("Integrator").set("Time Step", 1e-8).set("Number of Steps", 4000);
  d.sublist("Constraints").sublist("fixed").set("Face", "x-").set("Components", "x");
  d.sublist("Constraints").sublist("pin").set("Where", "Node").set("Components", "y");
  d.sublist("Loads").sublist("end force").set("Face", "x+").set("Force X", 1.0);
  d.sublist("Monitors").sublist("ux_L").set("X", 0.03).set("Y", 0.25e-3);
  d.sublist("Exact Solution").set("Type", "Bar Step Load").set("Load", "end force");
  d.sublist("Output").set("Plot", false).set("Progress", false).set("History Interval", 20);
  return d;
}

// The tip's relative L2 error; at np 2 (two ranks across the bar, the front crossing the cut)
// also the same history as one rank's to 1e-12, so that the np 2 entry tests the decomposition.
double tipError(const std::string& method, const std::string& plane, Teuchos::FancyOStream& out, bool& success) {
  const std::string dir = "test_output/explicit_bar_" + method + "_" + plane.substr(6);
  ParameterList d = barDeck(method, plane, dir);
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm());
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  out << log.str();
  const double npDifference = impm_test::rankCountDifference(d, r, dir);
  if (npDifference >= 0) {
    out << "np " << Tpetra::getDefaultComm()->getSize() << " against one rank: max relative difference " << npDifference
        << "\n";
    TEST_COMPARE(npDifference, <, 1e-12);
  }
  return r.relativeL2.at("ux_L");
}

// Tolerance: measured 1.51% for both (np 1 and 2), set by the lumped-mass dispersion of the
// step front on 1 mm cells (a 1D lumped-mass FE model of the bar has 1.5% at t = 1e-4). The run
// is deterministic and the same at np 1 and 2 (asserted above), so 1.8% (1.2 times the
// measured) leaves room only for compiler and library changes, and fails for a wrong modulus
// (plane strain against stress differ by 9%) or a misplaced load.
TEUCHOS_UNIT_TEST(ExplicitBar, MpmPlaneStress) {
  TEST_COMPARE(tipError("MPM", "Plane Stress", out, success), <, 0.018);
}
TEUCHOS_UNIT_TEST(ExplicitBar, GimpPlaneStrain) {
  TEST_COMPARE(tipError("GIMP", "Plane Strain", out, success), <, 0.018);
}

// Against the wrong modulus the error must be large: the test can tell plane strain from stress.
TEUCHOS_UNIT_TEST(ExplicitBar, WrongModulusIsDetected) {
  ParameterList d = barDeck("MPM", "Plane Strain", "test_output/explicit_bar_wrong_modulus");
  d.sublist("Exact Solution").set("Modulus", "Young Modulus");
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm());
  std::ostringstream log;
  TEST_COMPARE(sim.run(log).relativeL2.at("ux_L"), >, 0.05);
}

}  // namespace
