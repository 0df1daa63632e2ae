// The explicit time step impm accepts is stable. The seed's explicit beam with the scheme of the
// smallest measured limit (USL, one particle per cell, 2:1 cells; doc/stability.md) runs 3000 steps
// at the largest step the check accepts and stays bounded (its energy within twice that of the same
// run at a quarter of the step); at the bilinear cells' critical step itself
// (1 / (c_p sqrt(1/hx^2 + 1/hy^2)), 1/0.7 of the accepted one) it diverges.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/InputDeck.hpp"
#include "solvers/ExplicitStepper.hpp"
#include "solvers/Simulation.hpp"
#include "test/RunHistory.hpp"

namespace {

using Teuchos::ParameterList;

// Largest total energy of the run (kinetic + strain), or infinity when the run stopped.
double peakEnergy(double fractionOfCheckedLimit, Teuchos::FancyOStream& out) {
  auto deck = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/beam_explicit_mpm_plane_strain_stable.yaml");
  ParameterList d = *deck;
  const double hx = 0.25, hy = 0.125, E = 200e9, nu = 0.3, rho = 7800;
  const double cp = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho));
  const double checked = impm::kTransferStabilityFraction / (cp * std::sqrt(1 / (hx * hx) + 1 / (hy * hy)));
  const std::string tag = std::to_string(fractionOfCheckedLimit);
  d.sublist("Problem").set("Output Directory", "test_output/explicit_stability_" + tag);
  d.sublist("Body").set("Particles Per Cell X", 1).set("Particles Per Cell Y", 1);
  // The same end time (3000 steps at the checked limit) for every step size.
  d.sublist("Integrator")
      .set("Time Step", fractionOfCheckedLimit * checked)
      .set("Number of Steps", (int)std::lround(3000 / fractionOfCheckedLimit));
  d.sublist("Integrator").sublist("Explicit").set("Update Scheme", "USL").set("Stability Factor", 2.0);
  d.sublist("Output")
      .set("Energy And Momentum", true)
      .set("History Interval", 10)
      .set("VTK Interval", 0)
      .set("Plot", false)
      .set("Progress", false);
  double peak = 0;
  try {
    const impm_test::History h = impm_test::runDeck(d);  // (kept: .at() of a temporary would dangle)
    for (double e : h.at("total_energy")) peak = std::max(peak, e);
  } catch (const impm::DeckError&) {
    throw;  // a bad deck is the test's error, not a diverged run
  } catch (const std::exception& e) {
    out << "run stopped: " << e.what() << "\n";
    peak = std::numeric_limits<double>::infinity();
  }
  out << "dt = " << fractionOfCheckedLimit << " x the checked limit: peak total energy " << peak << " J\n";
  return peak;
}

TEUCHOS_UNIT_TEST(ExplicitStability, CheckedLimitIsStable) {
  const double reference = peakEnergy(0.25, out);
  TEST_COMPARE(reference, >, 0.0);
  TEST_COMPARE(peakEnergy(1.0, out), <, 2.0 * reference);
  // The bilinear cells' critical step (this fraction's inverse): the energy grows without bound.
  TEST_COMPARE(peakEnergy(1.0 / impm::kTransferStabilityFraction, out), >, 100.0 * reference);
}

}  // namespace
