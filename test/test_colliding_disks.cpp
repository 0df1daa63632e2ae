// Colliding disks (Sulsky, Chen & Schreyer 1994), explicit MPM and GIMP, from the decks in
// apps/: linear momentum is conserved to round-off, total energy stays within a bound, and at
// np 2 the history equals the one of a single rank to 1e-10.
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/Simulation.hpp"

namespace {

using Teuchos::ParameterList;

impm::RunResult runDeck(const std::string& method, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                        const std::string& outdir, Teuchos::FancyOStream& out) {
  auto deck = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/colliding_disks_explicit_" + method + ".yaml");
  impm::validateDeck(*deck);
  deck->sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
  impm::Simulation sim(*deck, comm, outdir);
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  out << log.str();
  return r;
}

void checkDisks(const std::string& method, Teuchos::FancyOStream& out, bool& success) {
  auto comm = Tpetra::getDefaultComm();
  const impm::RunResult r = runDeck(method, comm, "test_output/disks_" + method, out);
  TEST_EQUALITY_CONST(r.status, "completed");
  // The disks' momenta cancel: the total stays zero to round-off of sum m |v| (FLIP moves
  // momentum only through grid forces that sum to zero by partition of unity).
  TEST_COMPARE(r.momentumMaxRelativeChange, <, 1e-12);
  // Energy: a few percent lost in the collision (the single-velocity grid makes the disks
  // stick, which is dissipative), never gained. Measured (MPM / GIMP): drift -2.5% / -2.3%, largest
  // deviation 7.3% / 7.0% (mid-collision), peak strain energy 0.90 of the initial total (the
  // collision turns most kinetic energy into strain). Asserted: drift in (-3%, 0], deviation
  // below 8% (each about 1.2 times the larger of the two measured: the runs are deterministic and
  // agree across rank counts to 1e-10, so the margin covers only compiler and library changes),
  // peak strain energy between 0.5 and 1 of the initial total (a doubled strain energy, or energy
  // created, fails).
  TEST_COMPARE(r.energyRelativeDrift, >, -0.03);
  TEST_COMPARE(r.energyRelativeDrift, <=, 0.0);
  TEST_COMPARE(r.energyMaxRelativeDeviation, <, 0.08);
  double maxStrain = 0;
  for (double s : r.strain) maxStrain = std::max(maxStrain, s);
  const double e0 = r.kinetic.front() + r.strain.front();
  out << method << ": energy drift " << r.energyRelativeDrift << ", max deviation " << r.energyMaxRelativeDeviation
      << ", peak strain energy " << maxStrain / e0 << " of the initial total\n";
  TEST_COMPARE(maxStrain, >, 0.5 * e0);
  TEST_COMPARE(maxStrain, <, 1.0 * e0);
  // Decomposition: at np 2, rank 0 reruns alone and compares the whole history.
  if (comm->getSize() > 1) {
    auto self = comm->split(comm->getRank(), 0);
    const impm::RunResult one =
        runDeck(method, self, "test_output/disks_" + method + "_rank" + std::to_string(comm->getRank()), out);
    double worst = 0;
    for (size_t i = 0; i < r.time.size(); ++i) {
      const double e = std::abs(r.kinetic[i] + r.strain[i] - one.kinetic[i] - one.strain[i]) / e0;
      worst = std::max(worst, e);
    }
    out << "np 2 against np 1: max relative difference of the total energy " << worst << "\n";
    TEST_COMPARE(worst, <, 1e-10);
  }
}

TEUCHOS_UNIT_TEST(CollidingDisks, Mpm) { checkDisks("mpm", out, success); }
TEUCHOS_UNIT_TEST(CollidingDisks, Gimp) { checkDisks("gimp", out, success); }

}  // namespace
