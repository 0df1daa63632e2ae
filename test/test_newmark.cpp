// The Newmark family of the implicit integrator (Integrator/Implicit/Newmark Beta, Newmark Gamma):
// a free body under constant gravity falls exactly (u = g t^2 / 2, v = g t) for any beta and gamma,
// which a wrong c1, c2 or c3 (a_new = c1 u - c2 v - c3 a) or velocity update would break; and
// gamma > 1/2 damps the undamped sawtooth the average-acceleration rule carries at omega dt >> 1.
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

ParameterList blockDeck(double beta, double gamma) {
  ParameterList d("impm");
  d.sublist("Grid")
      .set("Origin X", -0.5)
      .set("Origin Y", -2.0)
      .set("Cells X", 8)
      .set("Cells Y", 12)
      .set("Cell Size X", 0.25)
      .set("Cell Size Y", 0.25);
  d.sublist("Material")
      .set("Young Modulus", 1.0e6)
      .set("Poisson Ratio", 0.3)
      .set("Density", 1.0)
      .set("Plane Condition", "Plane Strain")
      .set("Thickness", 1.0);
  d.sublist("Body")
      .set("X Min", 0.0)
      .set("X Max", 1.0)
      .set("Y Min", 0.0)
      .set("Y Max", 0.5)
      .set("Particles Per Cell X", 2)
      .set("Particles Per Cell Y", 2);
  d.sublist("Integrator").set("Type", "Implicit").set("Time Step", 0.05).set("Number of Steps", 10);
  d.sublist("Integrator").sublist("Implicit").set("Newmark Beta", beta).set("Newmark Gamma", gamma);
  d.sublist("Implicit Solver").set("Jacobian", "Assembled");
  d.sublist("Output").set("History Interval", 1).set("Plot", false).set("Progress", false);
  return d;
}

impm::RunResult run(ParameterList d) {
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/newmark");
  std::ostringstream log;
  return sim.run(log);
}

// 10 steps of 0.05 s under g = -10 m/s^2, no constraint: every particle has fallen g t^2 / 2 =
// 1.25 m and moves at g t = -5 m/s, to round-off and the Newton tolerance (measured below 2e-11;
// bound 1e-9), for average acceleration, a damped scheme (beta 0.3025, gamma 0.6) and one off the
// optimal line (beta 0.4, gamma 0.7). At t = 0.25 s the lowest particles sit on a grid line to
// within round-off: a node their stencil reaches with a weight of 1e-16 must stay an unknown (a
// void-node cut-off of 1e-12 of a particle's mass would hold it at u = 0 and give the body a
// spurious strain of u / h: 1 m of error by the end).
TEUCHOS_UNIT_TEST(Newmark, FreeFallIsExactForAnyBetaAndGamma) {
  const double g = -10.0, T = 0.5;
  for (const auto& [beta, gamma] : {std::pair{0.25, 0.5}, std::pair{0.3025, 0.6}, std::pair{0.4, 0.7}}) {
    ParameterList d = blockDeck(beta, gamma);
    d.sublist("Loads")
        .sublist("gravity")
        .set("Type", "Body Force")
        .set("Acceleration Y", g)
        .set("Time Function", "Constant");
    impm::validateDeck(d);
    impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/newmark_fall");
    std::ostringstream log;
    const std::string status = sim.run(log).status;
    TEST_EQUALITY_CONST(status, "completed");
    const impm::ParticleSet& ps = sim.particles();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
    auto x0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x0);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
    double du = 0, dv = 0;
    for (int p = 0; p < ps.count; ++p) {
      du = std::max({du, std::abs(x(p, 1) - x0(p, 1) - 0.5 * g * T * T), std::abs(x(p, 0) - x0(p, 0))});
      dv = std::max({dv, std::abs(v(p, 1) - g * T), std::abs(v(p, 0))});
    }
    out << "beta " << beta << " gamma " << gamma << ": displacement error " << du << " m, velocity error " << dv
        << " m/s\n";
    TEST_COMPARE(du, <, 1e-9);
    TEST_COMPARE(dv, <, 1e-9);
  }
}

// The block on a fixed base, gravity ramped over two steps of 1 s (omega dt ~ 1e3) and held for
// 28 more: the base reaction alternates about the weight from step to step. Average acceleration
// keeps that sawtooth (spectral radius 1 at omega dt -> infinity): its last amplitude is at least
// half of its first. gamma = 0.6, beta = 0.3025 damps it by |gamma - 3/2| / (gamma + 1/2) = 0.82
// per step (a double eigenvalue: (a + b n) 0.82^n): after 28 steps below 2% of its first amplitude.
TEUCHOS_UNIT_TEST(Newmark, GammaAboveOneHalfDampsTheSawtooth) {
  double ratio[2];
  int k = 0;
  for (const auto& [beta, gamma] : {std::pair{0.25, 0.5}, std::pair{0.3025, 0.6}}) {
    ParameterList d = blockDeck(beta, gamma);
    d.sublist("Grid").set("Origin Y", -0.25).set("Cells Y", 4);
    d.sublist("Integrator").set("Time Step", 1.0).set("Number of Steps", 30);
    d.sublist("Constraints")
        .sublist("base")
        .set("Where", "Box")
        .set("X Min", -1.0)
        .set("X Max", 2.0)
        .set("Y Min", 0.0)
        .set("Y Max", 0.0)
        .set("Components", "all");
    d.sublist("Loads")
        .sublist("gravity")
        .set("Type", "Body Force")
        .set("Acceleration Y", -10.0)
        .set("Time Function", "Ramp")
        .set("Ramp Time", 2.0);
    const impm::RunResult r = run(d);
    TEST_EQUALITY_CONST(r.status, "completed");
    const auto& R = r.reactions.at("base_reaction_y");
    const size_t n = R.size();
    const double first = std::abs(R[4] - R[3]), last = std::abs(R[n - 1] - R[n - 2]);
    ratio[k++] = last / first;
    out << "beta " << beta << " gamma " << gamma << ": sawtooth " << first << " N at step 4, " << last
        << " N at the end (ratio " << last / first << "); mean reaction " << 0.5 * (R[n - 1] + R[n - 2])
        << " N against the weight 5 N\n";
  }
  TEST_COMPARE(ratio[0], >, 0.5);
  TEST_COMPARE(ratio[1], <, 0.02);
}

}  // namespace
