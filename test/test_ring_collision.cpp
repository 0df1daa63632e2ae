// The two-ring collision of Tesserae.jl's transfer tutorial (apps/ring_collision_explicit_bspline.yaml):
// the total energy (kinetic + strain) at t = 0.2 s for each particle-grid transfer against
// Tesserae's regression values. Tesserae samples the rings by Poisson disks and steps at CFL 0.8
// of the current wave speed; impm fills them with a 2 x 2 lattice at a fixed step, so the two
// codes integrate the same problem with different particles, and impm's energies lie 2.5-4.5%
// above Tesserae's (compared to 5%). Their ratio to the FLIP run's energy agrees to 0.2% (PIC
// 1.6%): PIC keeps 58% of FLIP's energy, XPIC(5) 96%, APIC, TPIC and FLIP 0.99 98%.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <cmath>
#include <string>

#include "core/ParticleSet.hpp"
#include "test/RunHistory.hpp"

namespace {

using Teuchos::ParameterList;

struct Energies {
  double initial = 0.0, final = 0.0;  // impm's history: kinetic + sum V0 psi(F)
  double tesseraeFinal = 0.0;         // Tesserae's measure: kinetic + sum V psi(F), V = J V0
};

// Tesserae's total energy of the particles: sum m |v|^2 / 2 + V psi(F) with the current volume V
// (impm's history.csv weighs psi, an energy per reference volume, by V0). The rings' neo-Hookean
// psi = mu/2 (tr C - 2) - mu ln J + lambda/2 (ln J)^2 in plane strain.
double tesseraeEnergy(const impm::ParticleSet& ps) {
  const double E = 100e6, nu = 0.2;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  auto F = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.F);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  auto V0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.volume0);
  double total = 0.0;
  for (int p = 0; p < ps.count; ++p) {
    const double J = F(p, 0, 0) * F(p, 1, 1) - F(p, 0, 1) * F(p, 1, 0), lnJ = std::log(J);
    double trC = 0.0;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) trC += F(p, i, j) * F(p, i, j);
    const double psi = 0.5 * mu * (trC - 2.0) - mu * lnJ + 0.5 * lambda * lnJ * lnJ;
    total += 0.5 * m(p) * (v(p, 0) * v(p, 0) + v(p, 1) * v(p, 1)) + J * V0(p) * psi;
  }
  return total;
}

Energies collide(const std::string& transfer, double flip, int xpicOrder, const std::string& name) {
  auto deck = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/ring_collision_explicit_bspline.yaml");
  ParameterList& ex = deck->sublist("Integrator").sublist("Explicit");
  ex.set("Transfer", transfer).set("FLIP Fraction", flip);
  if (xpicOrder > 0) ex.set("XPIC Order", xpicOrder);
  deck->sublist("Output").set("VTK Interval", 0).set("Plot", false).set("Progress", false);
  impm::validateDeck(*deck);
  impm::Simulation sim(*deck, Tpetra::getDefaultComm(), "test_output/ring_collision_" + name);
  const impm::RunResult r = impm_test::runToCompletion(sim, name);
  Energies e;
  e.initial = r.kinetic.front() + r.strain.front();
  e.final = r.kinetic.back() + r.strain.back();
  e.tesseraeFinal = tesseraeEnergy(sim.particles());
  return e;
}

struct Case {
  const char* name;
  const char* transfer;
  double flip;
  int xpicOrder;
  double tesserae;  // Tesserae's total energy at 0.2 s, J per metre of thickness
};

// Every transfer against Tesserae: the energy at 0.2 s (Tesserae's measure) to 5%, and its ratio
// to FLIP's energy, which the sampling and the time step shift far less, to 0.5% (PIC 2.5%).
TEUCHOS_UNIT_TEST(RingCollision, EnergyAtPointTwoSecondsPerTransfer) {
  const Case cases[] = {{"flip", "FLIP/PIC", 1.0, 0, 1.567e7},     {"pic", "FLIP/PIC", 0.0, 0, 9.114e6},
                        {"flip099", "FLIP/PIC", 0.99, 0, 1.543e7}, {"apic", "APIC", 1.0, 0, 1.539e7},
                        {"tpic", "TPIC", 1.0, 0, 1.537e7},         {"xpic5", "XPIC", 1.0, 5, 1.502e7}};
  // Two rings of area pi (4^2 - 3^2) at 30 m/s: E0 = 1.979e7 J/m (the lattice fill keeps the exact area).
  const double e0 = 2.0 * M_PI * (16.0 - 9.0) * 1000.0 * 0.5 * 30.0 * 30.0;
  double flipEnergy = 0.0;
  for (const Case& c : cases) {
    const Energies e = collide(c.transfer, c.flip, c.xpicOrder, c.name);
    if (flipEnergy == 0.0) flipEnergy = e.tesseraeFinal;
    const double error = (e.tesseraeFinal - c.tesserae) / c.tesserae;
    const double ratio = e.tesseraeFinal / flipEnergy, tesseraeRatio = c.tesserae / 1.567e7;
    out << c.name << ": E(0.2 s) = " << e.final << " J/m (E/E0 " << e.final / e0 << "); measured as Tesserae does, "
        << e.tesseraeFinal << " against Tesserae's " << c.tesserae << ": relative difference " << error << "; E/E_FLIP "
        << ratio << " against " << tesseraeRatio << " (" << ratio / tesseraeRatio - 1.0 << ")\n";
    TEST_FLOATING_EQUALITY(e.initial, e0, 1e-10);
    TEST_COMPARE(std::abs(error), <, 5e-2);
    // PIC's loss grows with the number of steps, which Tesserae's adaptive step sets a little
    // differently: 2.5% (measured 1.6%); the others 0.5% (measured at most 0.2%), finer than the
    // 2% between APIC and XPIC(5).
    TEST_COMPARE(std::abs(ratio / tesseraeRatio - 1.0), <, c.flip == 0.0 ? 2.5e-2 : 5e-3);
  }
}

}  // namespace
