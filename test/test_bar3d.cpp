// The seed's bar in 3D (apps/bar3d_*.yaml): a 30 mm steel bar with a 0.5 x 0.5 mm
// section, free lateral faces, under a step end force, explicit and implicit, MPM and GIMP,
// against the 1D exact solution at the Young modulus E (uniaxial stress). Shortened here to
// 2 x 2 x 2 particles per cell and the first 4e-5 s explicit (the wave crosses the bar six
// times), 2e-5 s implicit. On
// more than one rank the same deck is also run on each rank alone (MPI_COMM_SELF) and the
// two histories must agree to 1e-10 relative: the answer does not depend on the decomposition.
#include <Teuchos_DefaultSerialComm.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "physics/GridConditions.hpp"
#include "solvers/Simulation.hpp"

namespace {

using Teuchos::ParameterList;

ParameterList bar3dDeck(const std::string& kind, const std::string& shape, const std::string& outdir) {
  auto deck =
      Teuchos::getParametersFromYamlFile(std::string(IMPM_SOURCE_DIR) + "/apps/bar3d_" + kind + "_" + shape + ".yaml");
  ParameterList d = *deck;
  d.sublist("Problem").set("Output Directory", outdir);
  auto& b = d.sublist("Bodies").sublist("bar");
  b.set("Particles Per Cell X", 2).set("Particles Per Cell Y", 2).set("Particles Per Cell Z", 2);
  // Implicit: steps of 4e-8 s to t = 2e-5 s (the wave crosses the bar three times; the step
  // front still takes 5 steps per cell).
  const bool implicit = kind == "implicit";
  d.sublist("Integrator").set("Time Step", implicit ? 4e-8 : 1e-8).set("Number of Steps", implicit ? 500 : 4000);
  d.sublist("Output")
      .set("Plot", false)
      .set("Progress", false)
      .set("VTK Interval", 0)
      .set("History Interval", implicit ? 5 : 20);
  return d;
}

impm::RunResult run(ParameterList d, const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {
  impm::validateDeck(d);
  impm::Simulation sim(d, comm);
  std::ostringstream log;
  return sim.run(log);
}

// Relative L2 error of the tip displacement against the 1D exact solution at E, and, on more
// than one rank, the largest difference between the distributed and the one-rank histories.
void check(const std::string& kind, const std::string& shape, double tolerance, Teuchos::FancyOStream& out,
           bool& success) {
  auto comm = Tpetra::getDefaultComm();
  const std::string tag = kind + "_" + shape;
  const impm::RunResult r = run(bar3dDeck(kind, shape, "test_output/bar3d_" + tag), comm);
  const double error = r.relativeL2.at("ux_L");
  out << "3D bar, " << kind << " " << shape << ", " << r.particles << " particles: relative L2 error of u_x(L) against "
      << "the 1D exact solution at E: " << 100 * error << " %\n";
  TEST_COMPARE(error, <, tolerance);
  if (comm->getSize() > 1) {
    auto self = Teuchos::rcp(new Teuchos::SerialComm<int>());
    const impm::RunResult serial =
        run(bar3dDeck(kind, shape, "test_output/bar3d_" + tag + "_rank" + std::to_string(comm->getRank())), self);
    double worst = 0;
    for (const auto& [name, values] : r.computed) {
      const auto& ref = serial.computed.at(name);
      TEST_EQUALITY(values.size(), ref.size());
      double scale = 0;
      for (double v : ref) scale = std::max(scale, std::abs(v));
      for (size_t k = 0; k < std::min(values.size(), ref.size()); ++k)
        worst = std::max(worst, std::abs(values[k] - ref[k]) / scale);
    }
    out << "  np " << comm->getSize() << " against np 1: largest difference " << worst
        << " of each monitor's amplitude\n";
    TEST_COMPARE(worst, <, 1e-10);
  }
}

// Tolerance: measured 0.88% explicit, 0.53% implicit (np 1 and 2; 1.4% on the full apps decks to 1e-4 s),
// the lumped-mass dispersion of the step front on 1 mm cells, as in 2D. The runs are
// deterministic and np 2 equals np 1 to 1e-10, so the bounds (1.1% and 0.7%, about 1.25 times
// the measured) leave room only for compiler and library changes; a wrong modulus (E/(1 - nu^2):
// 9% stiffer, the front 4.5% early) or a lost cross-section dimension fails them.
TEUCHOS_UNIT_TEST(Bar3d, ExplicitMpm) { check("explicit", "mpm", 0.011, out, success); }
TEUCHOS_UNIT_TEST(Bar3d, ExplicitGimp) { check("explicit", "gimp", 0.011, out, success); }
TEUCHOS_UNIT_TEST(Bar3d, ImplicitMpm) { check("implicit", "mpm", 0.007, out, success); }
TEUCHOS_UNIT_TEST(Bar3d, ImplicitGimp) { check("implicit", "gimp", 0.007, out, success); }

}  // namespace

namespace {

// A Box constraint in 3D without Z Min / Z Max covers the whole grid in z (its defaults are
// -+1e300, beyond an int node index: boxNodes clamps before converting): every node of the box's
// x-y range at every z, and none outside it.
TEUCHOS_UNIT_TEST(Bar3d, BoxWithDefaultZSpansTheGrid) {
  impm::StructuredGrid g;
  g.dim = 3;
  g.nx = 4;
  g.ny = 3;
  g.nz = 5;
  g.hx = g.hy = g.hz = 0.5;
  const auto all = impm::boxNodes(g, 0.0, 0.0, 0.0, 1.5, -1e300, 1e300);
  TEST_EQUALITY_CONST(all.size(), size_t(1 * 4 * 6));  // x = 0, 4 nodes in y, 6 in z
  for (const auto& n : all) {
    TEST_EQUALITY_CONST(n[0], 0);
  }
  const auto beyond = impm::boxNodes(g, 0.0, 2.0, 0.0, 1.5, 1e300, 2e300);
  TEST_EQUALITY_CONST(beyond.size(), size_t(0));
}

}  // namespace

namespace {

// apps/rod_impact_3d_explicit_gimp.yaml with `shape` and `scheme`: the run's status, and its
// failure message if it stopped.
std::pair<std::string, std::string> rodImpact(const std::string& shape, const std::string& scheme,
                                              Teuchos::FancyOStream& out) {
  auto deck =
      Teuchos::getParametersFromYamlFile(std::string(IMPM_SOURCE_DIR) + "/apps/rod_impact_3d_explicit_gimp.yaml");
  ParameterList d = *deck;
  d.sublist("Method").set("Shape Function", shape);
  d.sublist("Integrator").sublist("Explicit").set("Update Scheme", scheme);
  d.sublist("Output").set("Progress", false).set("VTK Interval", 0);
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/rod_impact_" + shape + "_" + scheme);
  std::ostringstream log;
  try {
    const impm::RunResult r = sim.run(log);
    out << shape << " " << scheme << ": " << r.status << "\n";
    return {r.status, ""};
  } catch (const std::runtime_error& e) {
    out << shape << " " << scheme << ": " << e.what() << "\n";
    return {"stopped", e.what()};
  }
}

// Linear MPM with USL inverts a particle that crosses alone into a cell beyond the rod's free
// surface (the cell-crossing weakness, doc/method.md, "Cell crossing: MPM against GIMP"), within the stable step; the
// failure names the inverted particle and points to GIMP and MUSL. GIMP and MPM with MUSL run the
// same 150 steps through.
TEUCHOS_UNIT_TEST(Bar3d, RodImpactLinearMpmUslInvertsGimpAndMuslDoNot) {
  const auto usl = rodImpact("MPM", "USL", out);
  TEST_EQUALITY_CONST(usl.first, "stopped");
  TEST_ASSERT(usl.second.find("is inverted: det F = -") != std::string::npos);
  TEST_ASSERT(usl.second.find("'Integrator/Explicit/Update Scheme' = MUSL") != std::string::npos);
  TEST_EQUALITY_CONST(rodImpact("GIMP", "USL", out).first, "completed");
  TEST_EQUALITY_CONST(rodImpact("MPM", "MUSL", out).first, "completed");
}

}  // namespace
