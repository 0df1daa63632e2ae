// Verification: the seed beam (Problem 2) on its own 40 x 4 grid with implicit
// quadratic B-spline MPM, apps/beam_implicit_bspline_plane_strain.yaml as shipped (1000 steps of
// 1e-3 s; the cubic deck likewise), against the Timoshenko beam at E/(1 - nu^2) whose modes are advanced by the same
// Newmark rule (so that only the spatial error is measured): w(L/2, t) within 2% (relative L2
// over the run, from summary.yaml). The deck's Gauss pairs are what gets it there: the same run
// with the Uniform lattice, whose midpoint rule puts the second moment of area 0.39% low and the
// first bending frequency 0.2% low, is several times further off.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <cmath>
#include <sstream>
#include <string>

#include "RunHistory.hpp"
#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/Simulation.hpp"

namespace {

using Teuchos::ParameterList;

// Runs a B-spline beam deck ("" quadratic, "_cubic") with `placement`; returns the relative L2
// error of w_mid.
double beamError(const std::string& placement, Teuchos::FancyOStream& out, const std::string& order = "") {
  auto deck =
      impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/beam_implicit_bspline" + order + "_plane_strain.yaml");
  const std::string dir = "test_output/bspline" + order + "_beam_" + placement;
  deck->sublist("Problem").set("Output Directory", dir);
  deck->sublist("Body").set("Particle Placement", placement);
  deck->sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
  impm::validateDeck(*deck);
  // The comparison the verification asks for; the deck must name it (not the test).
  const ParameterList& exact = deck->sublist("Exact Solution");
  TEUCHOS_TEST_FOR_EXCEPTION(exact.get<std::string>("Beam Theory") != "Timoshenko" ||
                                 exact.get<std::string>("Time Discretisation") != "Newmark" ||
                                 exact.get<std::string>("Modulus") != "Plane Condition",
                             std::runtime_error,
                             "the beam deck no longer compares with the Newmark-advanced Timoshenko beam");
  impm::Simulation sim(*deck, Tpetra::getDefaultComm());
  const impm::RunResult r = impm_test::runToCompletion(sim, "beam");
  const double error = impm_test::summaryValue(dir, "w_mid");
  out << (order.empty() ? "quadratic" : "cubic") << " B-spline beam, " << placement
      << " placement: w(L/2, t) relative L2 error " << error << "\n";
  return error;
}

// Measured 0.73% (Gauss) against 7.95% (Uniform), both with the deck's 3 consistent-projection
// iterations. Bound 1% (1.37 times the measured; the seed's criterion is 2%).
TEUCHOS_UNIT_TEST(BSplineBeam, QuadraticGaussWithinTwoPercentOfTimoshenko) {
  const double gauss = beamError("Gauss", out);
  TEST_COMPARE(gauss, <, 0.01);
  TEST_COMPARE(beamError("Uniform", out), >, 3 * gauss);
}

// The cubic deck (Gauss pairs and the consistent mass): measured 1.99%, at the limit (with 6 x 6
// or 8 x 8 pairs per cell 2.02%, 2.03%: the cubic splines' own stiffness, see the deck).
TEUCHOS_UNIT_TEST(BSplineBeam, CubicGaussWithinTwoPercentOfTimoshenko) {
  TEST_COMPARE(beamError("Gauss", out, "_cubic"), <, 0.02);
}

}  // namespace
