// Contact between bodies in the implicit step (Contact/Type = Multi Field with Integrator/Type =
// Implicit): the contact law's correction of the end-of-step velocities as a penalty force in the
// Jacobian-free Newton residual (ImplicitNewmark::addContactForces), against closed forms and
// conservation laws:
// - a block on a 30 degree incline on an elastic slab (apps/block_incline_contact_implicit_gimp.yaml)
//   at 40 times the explicit time step: its travel against g (sin 30 - mu cos 30) t^2 / 2 for mu = 0
//   and 0.3, and the slab's normal and friction forces against M g cos 30 and mu times it; with
//   mu = 0.7 > tan 30 it stays, held by the friction force M g sin 30, and with mu = 0.5 just below
//   it slides as the closed form says;
// - two elastic disks that collide and separate (apps/colliding_disks_contact_implicit_gimp.yaml) at
//   10 times the explicit step: momentum conserved, a contact force that only pushes and whose
//   impulse is each disk's change of momentum, velocities reversed, a bounded loss of energy;
// - two bodies that never meet: one field per body gives the single-field answer (the per-field
//   unknowns, internal forces, preconditioner and particle update are the single field's);
// - the assembled P against a finite difference of the residual: the contact's stiffness in P,
//   the fields coupled, is its Jacobian;
// - the deck's refusals, each one message naming the key.
// np 1 and 2: the same assertions at either rank count.
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "core/InputDeck.hpp"
#include "solvers/Simulation.hpp"
#include "solvers/build/Deck.hpp"
#include "BodyMotion.hpp"
#include "ContactJacobian.hpp"
#include "DeckRefusals.hpp"

namespace {

using Teuchos::ParameterList;

using impm_test::quietAppDeck;

// Runs a deck; `after` (when given) looks at the simulation once it has run.
impm::RunResult runDeck(ParameterList d, const std::string& tag,
                        const std::function<void(const impm::Simulation&)>& after = nullptr) {
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/implicit_contact_" + tag);
  std::ostringstream log;
  impm::RunResult r = sim.run(log);
  if (after) after(sim);
  return r;
}

using impm_test::bodyVelocities;

// The block (0.4 kg per metre of thickness) slides from rest for 0.15 s (150 steps of 1 ms, 40
// explicit steps each). Asserted: the travel within 3% of g (sin 30 - mu cos 30) t^2 / 2 (measured
// 0.002% frictionless, 1.5% with mu = 0.3; the block's elastic settling on the slab at the start is
// the rest), and with mu = 0.3 the mean force of the block on the slab over t >= 0.05 s within 10%
// of its weight M g cos 30 = 3.46 N and of mu times it (the soft block rings on the slab; measured
// 0.7% and 1%).
TEUCHOS_UNIT_TEST(ImplicitContact, BlockSlidesDownInclineOnSlab) {
  const double t = 0.15, M = 0.4, g = 10.0, theta = M_PI / 6;
  for (double mu : {0.0, 0.3}) {
    ParameterList d = quietAppDeck("block_incline_contact_implicit_gimp.yaml");
    d.sublist("Contact").set("Friction", mu);
    d.sublist("Integrator").set("Number of Steps", 150);
    const impm::RunResult r = runDeck(d, "incline_" + std::to_string(mu));
    TEST_EQUALITY_CONST(r.status, "completed");
    if (r.status != "completed") continue;
    const double travel = r.computed.at("block travel").back();
    const double exact = 0.5 * g * (std::sin(theta) - mu * std::cos(theta)) * t * t;
    const double error = std::abs(travel / exact - 1);
    out << "mu = " << mu << ": travel " << travel << " m, exact " << exact << " m, relative error " << error << "\n";
    TEST_COMPARE(error, <, 0.03);
    if (mu == 0) continue;
    const double sx = impm_test::meanFrom(r, "slab_block_contact_x", 0.05);
    const double sy = impm_test::meanFrom(r, "slab_block_contact_y", 0.05);
    const double weight = M * g * std::cos(theta);
    out << "  mean force of the block on the slab (" << sx << ", " << sy << ") N; weight " << weight << " N, friction "
        << mu * weight << " N\n";
    TEST_COMPARE(std::abs(-sy / weight - 1), <, 0.1);
    TEST_COMPARE(std::abs(sx / (mu * weight) - 1), <, 0.1);
  }
}

// Sticking friction: mu = 0.7 > tan 30 holds the block (ContactActiveSet: its contact nodes stick
// in the solve, so Newton sees no kink). Gravity ramps up over 0.05 s (applied at once it rings the
// soft block on the slab, whose rebounds slip it a little each time). Asserted: the block moves less
// than 0.5% of the frictionless travel g sin 30 t^2 / 2 in 0.15 s (measured 0.16%), and over
// t >= 0.1 s the mean force of the block on the slab is its weight: M g sin 30 = 2 N along the
// incline (held by friction) and M g cos 30 = 3.46 N into the slab, within 2% (measured 0.1% and
// 0.3%).
TEUCHOS_UNIT_TEST(ImplicitContact, FrictionHoldsBlockOnIncline) {
  const double t = 0.15, M = 0.4, g = 10.0, theta = M_PI / 6;
  ParameterList d = quietAppDeck("block_incline_contact_implicit_gimp.yaml");
  d.sublist("Contact").set("Friction", 0.7);
  d.sublist("Integrator").set("Number of Steps", 150);
  d.sublist("Loads").sublist("gravity").set("Time Function", std::string("Ramp")).set("Ramp Time", 0.05);
  const impm::RunResult r = runDeck(d, "hold");
  TEST_EQUALITY_CONST(r.status, "completed");
  if (r.status != "completed") return;
  const double travel = r.computed.at("block travel").back(), frictionless = 0.5 * g * std::sin(theta) * t * t;
  const double sx = impm_test::meanFrom(r, "slab_block_contact_x", 0.1);
  const double sy = impm_test::meanFrom(r, "slab_block_contact_y", 0.1);
  const double along = M * g * std::sin(theta), into = M * g * std::cos(theta);
  out << "mu = 0.7: travel " << travel << " m, " << travel / frictionless << " of the frictionless " << frictionless
      << " m; mean force of the block on the slab (" << sx << ", " << sy << ") N, weight (" << along << ", " << -into
      << ") N\n";
  TEST_COMPARE(std::abs(travel), <, 0.005 * frictionless);
  TEST_COMPARE(std::abs(sx / along - 1), <, 0.02);
  TEST_COMPARE(std::abs(-sy / into - 1), <, 0.02);
}

// Just below the threshold, mu = 0.5 < tan 30, the same ramped gravity slides the block with
// a = g (sin 30 - mu cos 30) = 0.67 m/s^2 once ramped: s(t) = a (T^2 / 6 + T (t - T) / 2 +
// (t - T)^2 / 2) for the ramp time T <= t. Asserted within 3% at t = 0.15 s (measured 1.3%), the
// tolerance of the sliding test above; a stick-slip cycle that never settled would creep instead.
TEUCHOS_UNIT_TEST(ImplicitContact, FrictionNearTheThresholdSlides) {
  const double t = 0.15, T = 0.05, g = 10.0, theta = M_PI / 6, mu = 0.5;
  ParameterList d = quietAppDeck("block_incline_contact_implicit_gimp.yaml");
  d.sublist("Contact").set("Friction", mu);
  d.sublist("Integrator").set("Number of Steps", 150);
  d.sublist("Loads").sublist("gravity").set("Time Function", std::string("Ramp")).set("Ramp Time", T);
  const impm::RunResult r = runDeck(d, "threshold");
  TEST_EQUALITY_CONST(r.status, "completed");
  if (r.status != "completed") return;
  const double a = g * (std::sin(theta) - mu * std::cos(theta));
  const double exact = a * (T * T / 6 + T * (t - T) / 2 + (t - T) * (t - T) / 2);
  const double travel = r.computed.at("block travel").back(), error = std::abs(travel / exact - 1);
  out << "mu = 0.5: travel " << travel << " m, exact " << exact << " m, relative error " << error << "\n";
  TEST_COMPARE(error, <, 0.03);
}

// The disks (0.2 m radius, 1000 kg/m^3, +-(0.1, 0.1) m/s; 20 x 20 cells; dt = 10 ms) meet along
// the diagonal. The force of the upper disk on the lower one points down the diagonal whenever it
// acts (it never pulls), is gone once they have parted (t > 2.4 s), and its impulse is the lower
// disk's change of momentum (the history reports the impulse per unit time; measured equal to
// three digits, 33.3 N s): asserted within 5%. Total momentum stays zero to round-off (the
// penalty forces of the two fields at a node are equal and opposite), each disk leaves with its
// velocity reversed, and the contact costs energy as in the explicit step (measured 16.7% with the
// deck's penalty 100, explicit 19%; 24.7% with 30, 14.1% with 300): asserted below 20%.
TEUCHOS_UNIT_TEST(ImplicitContact, DisksCollideAndSeparate) {
  const double M = M_PI * 0.2 * 0.2 * 1000.0, v0 = 0.1 * std::sqrt(2.0), dt = 0.01;
  std::vector<std::array<double, 2>> velocity;
  const impm::RunResult r = runDeck(quietAppDeck("colliding_disks_contact_implicit_gimp.yaml"), "disks",
                                    [&](const impm::Simulation& sim) { velocity = bodyVelocities(sim); });
  TEST_EQUALITY_CONST(r.status, "completed");
  if (r.status != "completed") return;
  const std::vector<double>& fx = r.reactions.at("lower_disk_upper_disk_contact_x");
  const std::vector<double>& fy = r.reactions.at("lower_disk_upper_disk_contact_y");
  double peak = 0, pull = 0, after = 0, momentum = 0, impulse = 0;
  for (size_t i = 0; i < r.time.size(); ++i) {
    peak = std::max(peak, std::hypot(fx[i], fy[i]));
    pull = std::max(pull, (fx[i] + fy[i]) / std::sqrt(2.0));
    if (r.time[i] > 2.4) after = std::max(after, std::hypot(fx[i], fy[i]));
    momentum = std::max(momentum, std::hypot(r.momentumX[i], r.momentumY[i]));
    if (i > 0) impulse -= (fx[i] + fy[i]) / std::sqrt(2.0) * dt;
  }
  const double change = M * (v0 - (velocity[0][0] + velocity[0][1]) / std::sqrt(2.0));
  const double loss = 1 - (r.kinetic.back() + r.strain.back()) / (r.kinetic.front() + r.strain.front());
  out << "peak contact force " << peak << " N, largest pull " << pull << " N, after parting " << after << " N; impulse "
      << impulse << " N s, the lower disk's change of momentum " << change << " N s; momentum " << momentum
      << " (M v0 = " << M * v0 << "); lower disk leaves at (" << velocity[0][0] << ", " << velocity[0][1]
      << "), upper at (" << velocity[1][0] << ", " << velocity[1][1] << "); energy lost " << loss << "\n";
  TEST_COMPARE(peak, >, 10.0);
  TEST_COMPARE(pull, <=, 1e-9 * peak);
  TEST_COMPARE(after, <, 1e-6 * peak);
  TEST_COMPARE(momentum, <, 1e-11 * M * v0);
  TEST_COMPARE(std::abs(impulse / change - 1), <, 0.05);
  for (int d = 0; d < 2; ++d) {
    TEST_COMPARE(velocity[0][d], <, -0.05);
    TEST_COMPARE(velocity[1][d], >, 0.05);
  }
  TEST_COMPARE(loss, >, 0.0);
  TEST_COMPARE(loss, <, 0.20);
}

// A block held above the slab, falling towards it under gravity while the slab settles under its
// own weight (stress waves in it), shares no node with the slab in the first 15 steps: with one
// field per body the implicit step must give what one shared field gives. The unknowns are
// numbered differently (the block's field after all the slab's nodes) and the preconditioner's
// factors differ with them, so the answers agree to the Newton and GMRES tolerances, not bit for
// bit: the block's travel and the energies within 1e-8 relative.
TEUCHOS_UNIT_TEST(ImplicitContact, BodiesApartGiveTheSingleFieldAnswer) {
  auto apart = [](const std::string& type) {
    ParameterList d = quietAppDeck("block_incline_contact_implicit_gimp.yaml");
    d.sublist("Bodies").sublist("block").set("Y Min", 0.015).set("Y Max", 0.025);
    d.sublist("Monitors").sublist("block travel").set("Y", 0.02);
    d.sublist("Integrator").set("Number of Steps", 15);
    d.sublist("Contact").set("Type", type);
    d.sublist("Implicit Solver").set("Linear Tolerance", 1e-10);
    d.sublist("Output").set("History Interval", 1);
    return d;
  };
  const impm::RunResult multi = runDeck(apart("Multi Field"), "apart_multi");
  const impm::RunResult single = runDeck(apart("Single Field"), "apart_single");
  TEST_EQUALITY_CONST(multi.status, "completed");
  TEST_EQUALITY_CONST(single.status, "completed");
  if (multi.status != "completed" || single.status != "completed") return;
  const auto& a = multi.computed.at("block travel");
  const auto& b = single.computed.at("block travel");
  TEST_EQUALITY(a.size(), b.size());
  const double energy = single.kinetic.back() + single.strain.back();
  double worst = 0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]) / std::abs(b.back()));
    worst = std::max(worst, std::abs(multi.kinetic[i] - single.kinetic[i]) / energy);
    worst = std::max(worst, std::abs(multi.strain[i] - single.strain[i]) / energy);
  }
  out << "block travel " << b.back() << " m, strain energy " << single.strain.back()
      << " J; largest relative difference, one field per body against one field: " << worst << "\n";
  TEST_COMPARE(single.strain.back(), >, 0.0);
  TEST_COMPARE(worst, <, 1e-8);
}

// Walls and contact together: the block of BlockSlidesDownInclineOnSlab (mu = 0.3 between the
// bodies) on a slab that is not pinned but rests on a rough rigid wall (mu = 1 > tan 30: friction
// holds the slab; each body's field meets the wall on its own), for 0.15 s. Asserted: the block's
// travel within 3% of the closed form, as on the pinned slab (measured +1.5%); the wall carries
// both bodies, its normal force over t >= 0.05 s within 2% of (M_block + M_slab) g cos 30 = 25.1 N
// (measured +0.4%), and its friction within 3% of their weight along the incline less the block's
// inertia, (M_slab + M_block) g sin 30 - M_block a (the slab stays, the block accelerates at
// a = g (sin 30 - mu cos 30); measured +1.5%: the slab rings on the wall).
TEUCHOS_UNIT_TEST(ImplicitContact, SlabOnARoughWallCarriesTheSlidingBlock) {
  const double t = 0.15, M = 0.4, slab = 2.5, g = 10.0, theta = M_PI / 6, mu = 0.3;
  ParameterList d = quietAppDeck("block_incline_contact_implicit_gimp.yaml");
  d.remove("Constraints");
  d.sublist("Walls").sublist("floor").set("Normal", "y+").set("Position", 0.0).set("Friction", 1.0);
  d.sublist("Integrator").set("Number of Steps", 150);
  const impm::RunResult r = runDeck(d, "slab_on_wall");
  TEST_EQUALITY_CONST(r.status, "completed");
  if (r.status != "completed") return;
  const double a = g * (std::sin(theta) - mu * std::cos(theta));
  const double travel = r.computed.at("block travel").back(), exact = 0.5 * a * t * t;
  const double normal = impm_test::meanFrom(r, "floor_reaction_y", 0.05);
  const double along = impm_test::meanFrom(r, "floor_reaction_x", 0.05);
  const double weight = (M + slab) * g * std::cos(theta), pull = (M + slab) * g * std::sin(theta) - M * a;
  out << "travel " << travel << " m, exact " << exact << " m; wall force (" << along << ", " << normal
      << ") N against (" << -pull << ", " << weight << ")\n";
  TEST_COMPARE(std::abs(travel / exact - 1), <, 0.03);
  TEST_COMPARE(std::abs(normal / weight - 1), <, 0.02);
  TEST_COMPARE(std::abs(-along / pull - 1), <, 0.03);
}

// P carries the contact penalty's stiffness (ImplicitNewmark::contactStiffness), the block's and
// the slab's fields coupled at each contact node through the centre-of-mass velocity they meet at:
// with the active set held, P is the Jacobian of the residual as for a single body. The incline
// with linear MPM after 20 steps (the block sliding, mu = 0.3; held, mu = 0.7; a frictionless
// approach, mu = 0, whose law kinks only where the bodies start or stop approaching, away from
// the random u of the check): measured 3e-12, asserted below 1e-5 (the finite difference's
// round-off, as in test_implicit). With P leaving the contact out the mismatch is 0.3 to 2.
TEUCHOS_UNIT_TEST(ImplicitContact, ContactStiffnessInPIsTheJacobianBetweenBodies) {
  for (double mu : {0.3, 0.7, 0.0}) {
    ParameterList d = quietAppDeck("block_incline_contact_implicit_gimp.yaml");
    d.sublist("Contact").set("Friction", mu);
    d.sublist("Method").set("Shape Function", "MPM");
    d.sublist("Integrator").set("Number of Steps", 20);
    out << "mu = " << mu << ", ";
    const double mismatch = impm_test::contactJacobianMismatch(d, "test_output/implicit_contact_jacobian", out);
    TEST_COMPARE(mismatch, <, 1e-5);
  }
}

// Each refusal: one DeckError naming the key.
TEUCHOS_UNIT_TEST(ImplicitContact, RefusesWhatTheImplicitStepDoesNotTake) {
  const std::vector<impm_test::DeckRefusal> cases = {
      {"penalty", "Contact/Implicit Penalty", "must be a finite number > 0",
       [](ParameterList& d) { d.sublist("Contact").set("Implicit Penalty", 0.0); }},
      {"consistent mass", "Contact/Type", "Mass Matrix",
       [](ParameterList& d) { d.sublist("Integrator").sublist("Implicit").set("Mass Matrix", "Consistent"); }},
      {"projected", "Contact/Type", "Grid Acceleration",
       [](ParameterList& d) { d.sublist("Integrator").sublist("Implicit").set("Grid Acceleration", "Projected"); }},
      {"apic", "Contact/Type", "Transfer",
       [](ParameterList& d) { d.sublist("Integrator").sublist("Implicit").set("Transfer", "APIC"); }},
  };
  impm_test::checkRefusals(quietAppDeck("block_incline_contact_implicit_gimp.yaml"), cases,
                           "test_output/implicit_contact_bad", out, success);
}

}  // namespace
