// Cell crossing (doc/method.md, "Cell crossing: MPM against GIMP"): the first mode of a bar fixed at
// both ends, from apps/standing_wave_{mpm,gimp}.yaml, on the deck's grid (1024 cells, where the
// particles near the middle cross cell lines) and on half of it (512 cells, where no particle
// reaches a cell line). GIMP converges there; MPM's error jumps by orders of magnitude once
// particles cross. Also: the exact solution itself, and the deck checks of the standing wave's keys.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <cmath>
#include <map>
#include <sstream>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "physics/ExactSolutions.hpp"
#include "solvers/Simulation.hpp"

namespace {

using Teuchos::ParameterList;

ParameterList standingWaveDeck(const std::string& method) {
  auto d = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/standing_wave_" + method + ".yaml");
  return *d;
}

// The deck on nx cells over the same 1 m bar: dt = h / (2c) (c = 10 m/s) scaled with h, one
// period (0.2 s) in 4 nx steps, history at the same 256 instants on every grid.
std::map<std::string, double> errors(const std::string& method, int nx, Teuchos::FancyOStream& out) {
  ParameterList d = standingWaveDeck(method);
  d.sublist("Problem").set("Output Directory", "test_output/standing_wave_" + method + "_" + std::to_string(nx));
  d.sublist("Grid").set("Cells X", nx).set("Cell Size X", 1.0 / nx);
  d.sublist("Integrator").set("Time Step", 0.05 / nx).set("Number of Steps", 4 * nx);
  d.sublist("Output").set("History Interval", nx / 64).set("Plot", false).set("Progress", false);
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm());
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  out << log.str();
  return r.relativeL2;
}

// Measured, relative L2 errors over one period (the same at 1 and 2 threads to the digits shown):
//                 512 cells   1024 cells   observed order
//   MPM  ux_half   6.69e-06    5.96e-02      -13.1   (particles cross at 1024)
//   GIMP ux_half   9.02e-06    2.61e-06        1.79
//   MPM  sxx_1/4   1.53e-03    7.74e-02       -5.7
//   GIMP sxx_1/4   1.29e-03    5.70e-04        1.18
// The bounds on errors are about 1.3 times these (the runs are deterministic: the margin is for
// compiler and library changes), the ratios about a third of the measured, and each fails for a
// plausible defect: GIMP degraded to first order in displacement or stagnating, GIMP behaving
// like MPM under crossing (ratio ~1), a wrong omega or modulus in the exact solution or initial
// condition (errors of percent).
TEUCHOS_UNIT_TEST(StandingWave, GimpConvergesWhereMpmCrossingFails) {
  const auto mpm1 = errors("mpm", 512, out), mpm2 = errors("mpm", 1024, out);
  const auto gimp1 = errors("gimp", 512, out), gimp2 = errors("gimp", 1024, out);
  const double gimpOrderU = std::log2(gimp1.at("ux_half") / gimp2.at("ux_half"));
  const double gimpOrderS = std::log2(gimp1.at("sxx_quarter") / gimp2.at("sxx_quarter"));
  const double mpmOrderU = std::log2(mpm1.at("ux_half") / mpm2.at("ux_half"));
  out << "GIMP order ux_half " << gimpOrderU << ", sxx_quarter " << gimpOrderS << "; MPM order ux_half " << mpmOrderU
      << "\n";
  // GIMP: displacement order 1.79 measured (2.0 at amplitudes too small to cross; the rest is
  // GIMP's own, much smaller, crossing error); 1.5 fails for first order.
  TEST_COMPARE(gimpOrderU, >, 1.5);
  // Stress at a particle is first order for both methods (the gradient of the linear grid
  // field is exact at cell centres, and the particles sit h/4 off them): 1.18 measured.
  TEST_COMPARE(gimpOrderS, >, 0.8);
  TEST_COMPARE(gimp2.at("ux_half"), <, 3.5e-6);
  TEST_COMPARE(gimp2.at("sxx_quarter"), <, 7.5e-4);
  // MPM: converges while no particle crosses (512), then the error grows by 4 orders.
  TEST_COMPARE(mpm1.at("ux_half"), <, 9.0e-6);
  TEST_COMPARE(mpmOrderU, <, -8.0);
  // On the crossing grid GIMP is 22800x (displacement) and 136x (stress) better than MPM.
  TEST_COMPARE(mpm2.at("ux_half"), >, 5000.0 * gimp2.at("ux_half"));
  TEST_COMPARE(mpm2.at("sxx_quarter"), >, 60.0 * gimp2.at("sxx_quarter"));
}

// The exact solution solves rho u_tt = E u_xx with u = 0 at both ends, u(x, 0) = 0,
// u_t(x, 0) = V sin(n pi x / L), and its stress is E u_x (central differences).
TEUCHOS_UNIT_TEST(StandingWave, ExactSolution) {
  const impm::BarStandingWaveExact w{2.0, 100.0, 4.0, 0.3, 3};
  TEST_FLOATING_EQUALITY(w.waveSpeed(), 5.0, 1e-14);
  TEST_FLOATING_EQUALITY(w.omega(), 5.0 * 3 * std::acos(-1.0) / 2.0, 1e-14);
  TEST_COMPARE(std::abs(w.displacement(0.0, 0.37)) + std::abs(w.displacement(2.0, 0.37)), <, 1e-14);
  TEST_COMPARE(std::abs(w.displacement(0.7, 0.0)), <, 1e-14);
  TEST_FLOATING_EQUALITY(w.velocity(0.7, 0.0), 0.3 * std::sin(3 * std::acos(-1.0) * 0.7 / 2.0), 1e-14);
  const double x = 0.61, t = 0.173, hx = 1e-4, ht = 1e-5;
  const double uxx = (w.displacement(x + hx, t) - 2 * w.displacement(x, t) + w.displacement(x - hx, t)) / (hx * hx);
  const double utt = (w.displacement(x, t + ht) - 2 * w.displacement(x, t) + w.displacement(x, t - ht)) / (ht * ht);
  TEST_FLOATING_EQUALITY(4.0 * utt, 100.0 * uxx, 1e-5);
  const double ux = (w.displacement(x + hx, t) - w.displacement(x - hx, t)) / (2 * hx);
  TEST_FLOATING_EQUALITY(w.stress(x, t), 100.0 * ux, 1e-6);
  const double ut = (w.displacement(x, t + ht) - w.displacement(x, t - ht)) / (2 * ht);
  TEST_FLOATING_EQUALITY(w.velocity(x, t), ut, 1e-6);
}

std::string problemWith(ParameterList deck) {
  try {
    impm::validateDeck(deck);
    impm::Simulation sim(deck, Tpetra::getDefaultComm());
  } catch (const impm::DeckError& e) {
    return e.what();
  }
  return "";
}
bool mentions(const std::string& msg, const std::string& what) { return msg.find(what) != std::string::npos; }

TEUCHOS_UNIT_TEST(StandingWave, DeckChecks) {
  ParameterList ok = standingWaveDeck("gimp");
  ok.sublist("Problem").set("Output Directory", "test_output/standing_wave_deck_checks");
  TEST_EQUALITY_CONST(problemWith(ok), "");
  {
    ParameterList d = ok;
    d.sublist("Initial Conditions").set("Type", "Sine");
    const std::string msg = problemWith(d);
    TEST_ASSERT(mentions(msg, "Initial Conditions/Type") && mentions(msg, "Standing Wave"));
  }
  {
    ParameterList d = ok;
    d.sublist("Initial Conditions").set("Mode", 0);
    TEST_ASSERT(mentions(problemWith(d), "Initial Conditions/Mode"));
  }
  {
    ParameterList d = ok;
    d.sublist("Initial Conditions").set("Mode", 1.5);
    TEST_ASSERT(mentions(problemWith(d), "Initial Conditions/Mode"));
  }
  {
    ParameterList d = ok;
    d.sublist("Initial Conditions").set("Amplitude", 0.0);
    TEST_ASSERT(mentions(problemWith(d), "Initial Conditions/Amplitude"));
  }
  {
    ParameterList d = ok;
    d.sublist("Initial Conditions").set("Amplitude", std::string("fast"));
    TEST_ASSERT(mentions(problemWith(d), "Initial Conditions/Amplitude"));
  }
  {
    ParameterList d = ok;
    d.sublist("Initial Conditions").set("Type", "None");
    TEST_ASSERT(mentions(problemWith(d), "Initial Conditions/Type"));
  }
  {
    ParameterList d = ok;
    d.sublist("Constraints").remove("right end");
    TEST_ASSERT(mentions(problemWith(d), "face x+"));
  }
  {
    ParameterList d = ok;
    d.sublist("Loads").sublist("pull").set("Face", "x+").set("Force X", 1.0);
    TEST_ASSERT(mentions(problemWith(d), "Loads"));
  }
}

}  // namespace
