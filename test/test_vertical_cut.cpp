// A vertical cut in undrained clay brought to collapse by increasing gravity
// (apps/vertical_cut_implicit_gimp_tresca.yaml): Mohr-Coulomb with phi = 0 (Tresca, c_u = 10 kPa),
// H = 2 m, implicit GIMP, Jacobian-free Newton with the polynomial line search. Gravity rises
// linearly, the stability number N = rho g H / c_u by 0.1 per step up to 5. The implicit step is
// dynamic, so past the limit load Newton still converges: the cut's crest runs away instead. The
// computed limit load is where the crest's settlement per step first exceeds 10 times its elastic
// one (the first step's), bracketed by that step's N and the one before.
// Reference: the limit analysis bounds 3.7752 <= N <= 3.7776 (Kammoun, Pastor, Smaoui & Pastor
// 2010, their static bound and the kinematic one they cite), N = 3.776 to 0.03%; Taylor's (1937)
// circular slip gives 3.83. Asserted at h = H/8: with F-bar the bracket lies within 7% of 3.776
// (a coarse mesh overestimates a limit load; the strip footing at the same resolution is 2.6%
// high), and without volumetric-locking control the cut stands longer (locking). Newton and
// GMRES counts are printed.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <cmath>
#include <sstream>
#include <string>

#include "RunHistory.hpp"

namespace {

using Teuchos::ParameterList;

constexpr double kLimit = 3.776;  // gamma H / c_u of a vertical Tresca cut
constexpr double kHeight = 2.0, kCohesion = 1.0e4, kDensity = 2000.0;

struct Collapse {
  double below, above;     // N of the last step before the runaway and of the first in it
  double crestSettlement;  // at the end (N = 5)
  double newtonPerStep, gmresPerNewton, halvings;
};

Collapse raiseGravity(bool fbar, const std::string& outdir) {
  ParameterList d = *impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/vertical_cut_implicit_gimp_tresca.yaml");
  d.sublist("Method").set("Volumetric Locking", std::string(fbar ? "F-bar" : "None"));
  d.sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
  d.sublist("Problem").set("Output Directory", outdir);
  const double gravityEnd = -d.sublist("Loads").sublist("gravity").get<double>("Acceleration Y");
  const double rampTime = d.sublist("Loads").sublist("gravity").get<double>("Ramp Time");
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm());
  impm_test::runToCompletion(sim, outdir);
  const impm_test::History hist = impm_test::readHistory(outdir + "/history.csv");
  const std::vector<double>& t = hist.at("time");
  const std::vector<double>& uy = hist.at("crest y");
  const auto number = [&](double time) { return kDensity * gravityEnd * time / rampTime * kHeight / kCohesion; };
  const double elastic = std::abs(uy[1] - uy[0]);
  Collapse c{-1,
             -1,
             -uy.back(),
             impm_test::summaryValue(outdir, "Newton Iterations Mean"),
             impm_test::summaryValue(outdir, "Krylov Iterations Per Newton Mean"),
             impm_test::summaryValue(outdir, "Step Halvings")};
  for (size_t k = 1; k < uy.size(); ++k)
    if (std::abs(uy[k] - uy[k - 1]) > 10 * elastic) {
      c.below = number(t[k - 1]);
      c.above = number(t[k]);
      break;
    }
  return c;
}

void report(Teuchos::FancyOStream& out, const char* what, const Collapse& c) {
  out << what << ": collapse between N = " << c.below << " and " << c.above << " (" << 100 * (c.below / kLimit - 1)
      << "% to " << 100 * (c.above / kLimit - 1) << "% from " << kLimit
      << "), crest settlement at N = 5: " << c.crestSettlement << " m; Newton per step " << c.newtonPerStep
      << ", GMRES per Newton " << c.gmresPerNewton << ", step halvings " << c.halvings << "\n";
}

TEUCHOS_UNIT_TEST(VerticalCut, GravityIncreaseCollapsesAtTheLimitLoad) {
  const Collapse fbar = raiseGravity(true, "test_output/vertical_cut_fbar");
  const Collapse locked = raiseGravity(false, "test_output/vertical_cut_none");
  report(out, "F-bar", fbar);
  report(out, "no locking control", locked);
  TEST_COMPARE(fbar.below, >, 0.0);  // the runaway was found
  TEST_COMPARE(std::abs(fbar.below / kLimit - 1), <, 0.07);
  TEST_COMPARE(std::abs(fbar.above / kLimit - 1), <, 0.07);
  TEST_COMPARE(fbar.crestSettlement, >, 0.05 * kHeight);  // a mechanism, not elastic settlement
  // Without control: a runaway later, or none up to N = 5.
  TEST_COMPARE(locked.below > 0 ? locked.below : 5.0, >=, fbar.above);
}

}  // namespace
