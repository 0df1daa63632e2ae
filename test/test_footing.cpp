// Strip footing on undrained clay under displacement control (apps/footing_displacement_implicit_
// gimp_j2.yaml): a rough rigid footing, B = 1 m, pushed 3 cm into a weightless von Mises clay
// (c_u = 10 kPa, E / c_u = 1000), half model, implicit GIMP with Jacobian-free Newton. The bearing
// pressure is the footing nodes' reaction over B/2. Prandtl's collapse pressure is (2 + pi) c_u
// for a smooth or rough footing on a weightless Tresca soil.
// Asserted, at 4 and 8 cells under the half footing (h = B/8, B/16):
//   - with F-bar the plateau (the pressure over the last fifth of the push, where it has stopped
//     rising) lies within 5% of 5.14 c_u;
//   - without volumetric-locking control the same clay carries more: the particles' volumes are
//     held under isochoric plastic flow (printed; asserted above the F-bar plateau by 5%);
//   - the pressure has levelled off: its rise over the last fifth is below 1% of it.
// Newton and GMRES iterations per step are printed for each run.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include "RunHistory.hpp"

namespace {

using Teuchos::ParameterList;

constexpr double kCohesion = 1.0e4;                  // c_u (Pa): sigma_y = sqrt(3) c_u in the deck
constexpr double kPrandtl = 2.0 + 3.14159265358979;  // collapse pressure / c_u

struct Plateau {
  double pressure, rise, newtonPerStep, gmresPerNewton;
};

Plateau pushFooting(int cellsUnderHalfFooting, bool fbar, const std::string& outdir) {
  ParameterList d = *impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/footing_displacement_implicit_gimp_j2.yaml");
  const double h = 0.5 / cellsUnderHalfFooting;
  auto& g = d.sublist("Grid");
  g.set("Cell Size X", h).set("Cell Size Y", h);
  g.set("Cells X", int(std::lround(2.5 / h))).set("Cells Y", int(std::lround(2.0 / h)) + 1);
  d.sublist("Method").set("Volumetric Locking", std::string(fbar ? "F-bar" : "None"));
  d.sublist("Output").set("Plot", false).set("Progress", false);
  d.sublist("Problem").set("Output Directory", outdir);
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm());
  impm_test::runToCompletion(sim, outdir);
  const impm_test::History hist = impm_test::readHistory(outdir + "/history.csv");
  const std::vector<double>& R = hist.at("footing_reaction_y");
  // The plateau: the mean pressure over the last fifth of the push (the reaction jumps by a few
  // per cent from step to step as particles cross cells); its rise: the last fifth's mean against
  // the fifth before it.
  const int n = int(R.size()) - 1, fifth = n / 5;
  auto meanPressure = [&](int first) {
    double sum = 0;
    for (int k = first; k < first + fifth; ++k) sum += -R[k + 1] / 0.5;
    return sum / fifth;
  };
  std::ostringstream curve;
  for (int k = 1; k <= n; ++k) curve << " " << std::setprecision(3) << -R[k] / 0.5 / kCohesion;
  std::cout << outdir << ": q / c_u per step:" << curve.str() << "\n";
  const double last = meanPressure(n - fifth), before = meanPressure(n - 2 * fifth);
  return {last / kCohesion, (last - before) / last, impm_test::summaryValue(outdir, "Newton Iterations Mean"),
          impm_test::summaryValue(outdir, "Krylov Iterations Per Newton Mean")};
}

void report(Teuchos::FancyOStream& out, const char* what, int cells, const Plateau& p) {
  out << what << ", " << cells << " cells under the half footing: q / c_u = " << p.pressure << " ("
      << 100 * (p.pressure / kPrandtl - 1) << "% from 2 + pi), rise over the last fifth " << 100 * p.rise
      << "%, Newton per step " << p.newtonPerStep << ", GMRES per Newton " << p.gmresPerNewton << "\n";
}

TEUCHOS_UNIT_TEST(StripFooting, FbarPlateauIsPrandtlsAndLockingOverestimates) {
  for (int cells : {4, 8}) {
    const Plateau fbar = pushFooting(cells, true, "test_output/footing_fbar_" + std::to_string(cells));
    const Plateau locked = pushFooting(cells, false, "test_output/footing_none_" + std::to_string(cells));
    report(out, "F-bar", cells, fbar);
    report(out, "no locking control", cells, locked);
    TEST_ASSERT(std::abs(fbar.pressure / kPrandtl - 1) < 0.05);
    TEST_ASSERT(fbar.rise < 0.01);
    TEST_ASSERT(locked.pressure > 1.05 * fbar.pressure);
  }
}

}  // namespace
