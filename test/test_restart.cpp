// Checkpoint and restart (Output/Checkpoint Interval, Simulation::restartFrom): a run restarted
// from its checkpoint at step k ends with the same history.csv as the uninterrupted run, bit for
// bit at the same rank and thread count, whether it writes into a new output directory or into
// the one that holds the checkpoint; at np 2 a checkpoint of one rank continues on two (and one
// of two ranks on one) to 1e-10 relative. Explicit: the colliding disks (MPM, energy and
// momentum columns; also with APIC); implicit: the beam of Problem 2 (Newmark, assembled Newton).
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/Simulation.hpp"

namespace {

using Teuchos::ParameterList;
using Comm = Teuchos::RCP<const Teuchos::Comm<int>>;

struct Run {
  impm::RunResult result;
  std::string csv;  // history.csv, byte for byte
};

std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `deck` into `dir` (removed first unless `keepDir`), with checkpoints every `interval`
// steps, from the checkpoint `restart` when not empty.
Run run(ParameterList deck, const Comm& comm, const std::string& dir, int interval, const std::string& restart,
        bool keepDir = false) {
  deck.sublist("Output").set("Checkpoint Interval", interval).set("Plot", false).set("Progress", false);
  impm::validateDeck(deck);
  if (!keepDir && comm->getRank() == 0) std::filesystem::remove_all(dir);
  comm->barrier();
  impm::Simulation sim(deck, comm, dir);
  if (!restart.empty()) sim.restartFrom(restart);
  std::ostringstream log;
  Run r{sim.run(log), ""};
  comm->barrier();
  r.csv = fileText(dir + "/history.csv");
  return r;
}

// Largest difference between two recorded histories over the time, monitor and energy columns,
// relative to each column's largest magnitude. (Not the momentum: the disks' total momentum is
// zero, and its recorded round-off depends on the order of the particles on each rank, which
// another rank count changes; bit for bit at the same rank count, history.csv compares it too.)
double relativeDifference(const impm::RunResult& a, const impm::RunResult& b) {
  double worst = a.time.size() == b.time.size() ? 0.0 : HUGE_VAL;
  auto compare = [&](const std::vector<double>& x, const std::vector<double>& y) {
    if (x.size() != y.size()) {
      worst = HUGE_VAL;
      return;
    }
    double scale = 0;
    for (double v : y) scale = std::max(scale, std::abs(v));
    for (size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(x[i] - y[i]) / (scale > 0 ? scale : 1.0));
  };
  compare(a.time, b.time);
  for (const auto& [name, values] : b.computed) compare(a.computed.at(name), values);
  compare(a.kinetic, b.kinetic);
  compare(a.strain, b.strain);
  return worst;
}

// The checks of the file's header comment for one deck: `steps` steps, a checkpoint at `k`.
void checkRestart(const ParameterList& deck, const std::string& name, int steps, int k, Teuchos::FancyOStream& out,
                  bool& success, bool acrossRanks = true) {
  auto comm = Tpetra::getDefaultComm();
  const int np = comm->getSize();
  const std::string base = "test_output/restart_" + name + "_np" + std::to_string(np);
  ParameterList d = deck;
  d.sublist("Integrator").set("Number of Steps", steps);

  const Run reference = run(d, comm, base + "_reference", 0, "");
  // A history with something happening in it: strain energy (or a stress monitor) away from zero.
  double strain = 0;
  for (double e : reference.result.strain) strain = std::max(strain, e);
  for (const auto& [monitor, values] : reference.result.computed)
    for (double v : values) strain = std::max(strain, std::abs(v));
  TEST_COMPARE(strain, >, 0.0);
  const Run written = run(d, comm, base + "_checkpointed", k, "");
  // Checkpoints do not disturb the run; the latest (step k) is there.
  TEST_ASSERT(written.csv == reference.csv);
  TEST_ASSERT(std::filesystem::exists(base + "_checkpointed/checkpoint/header.xml"));
  TEST_ASSERT(std::filesystem::exists(base + "_checkpointed/checkpoint_" + [&] {
    char s[16];
    std::snprintf(s, sizeof s, "%09d", k);
    return std::string(s);
  }()));

  // Restarted into a new directory, and into the checkpoint's own (its history.csv rewritten).
  const Run restarted = run(d, comm, base + "_restarted", 0, base + "_checkpointed/checkpoint");
  TEST_ASSERT(!reference.csv.empty());
  TEST_ASSERT(restarted.csv == reference.csv);
  // Resumed where the checkpoint was taken, not from step 0.
  TEST_EQUALITY(reference.result.firstStep, 1);
  TEST_EQUALITY(restarted.result.firstStep, k + 1);
  TEST_EQUALITY(relativeDifference(restarted.result, reference.result), 0.0);
  TEST_EQUALITY(restarted.result.energyRelativeDrift, reference.result.energyRelativeDrift);
  const Run inPlace = run(d, comm, base + "_checkpointed", 0, base + "_checkpointed/checkpoint", true);
  TEST_ASSERT(inPlace.csv == reference.csv);
  out << name << " np " << np << ": restarted at step " << k << " of " << steps << ", history.csv ("
      << reference.csv.size() << " bytes) identical\n";

  if (np > 1 && acrossRanks) {
    // Each rank alone (np 1): a reference and a checkpoint. Then the np 1 checkpoint continues on
    // np ranks, and the np checkpoint on one rank.
    auto self = comm->split(comm->getRank(), 0);
    const std::string solo = base + "_solo_r" + std::to_string(comm->getRank());
    const Run soloReference = run(d, self, solo + "_reference", 0, "");
    run(d, self, solo + "_checkpointed", k, "");
    comm->barrier();
    const Run upward =
        run(d, comm, base + "_from_np1", 0,
            "test_output/restart_" + name + "_np" + std::to_string(np) + "_solo_r0_checkpointed/checkpoint");
    const Run downward = run(d, self, solo + "_from_np" + std::to_string(np), 0, base + "_checkpointed/checkpoint");
    const double up = relativeDifference(upward.result, reference.result);
    const double down = relativeDifference(downward.result, soloReference.result);
    const double ranks = relativeDifference(soloReference.result, reference.result);
    out << name << ": np 1 checkpoint on np " << np << " against the np " << np << " run: " << up << "; np " << np
        << " checkpoint on np 1 against the np 1 run: " << down << " (np 1 against np " << np
        << " uninterrupted: " << ranks << ")\n";
    TEST_COMPARE(up, <, 1e-10);
    TEST_COMPARE(down, <, 1e-10);
  }
}

ParameterList deckOf(const std::string& file) {
  auto deck = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/" + file);
  return *deck;
}

// History every step, no particle files or plot: the runs compare their history.csv.
void everyStepHistory(ParameterList& deck) {
  deck.sublist("Output").set("VTK Interval", 0).set("History Interval", 1).set("Plot", false);
}

// Newton and GMRES converged well beyond their defaults, so that the rank count does not move the
// solution (user guide, contact in the implicit step).
void tightSolver(ParameterList& deck) {
  ParameterList& s = deck.sublist("Implicit Solver");
  s.set("Linear Tolerance", 1e-12).set("Residual Tolerance", 1e-13).set("Residual Magnitude Tolerance", 0.0);
  s.set("Maximum Newton Iterations", 30);
}

TEUCHOS_UNIT_TEST(Restart, ExplicitCollidingDisks) {
  ParameterList deck = deckOf("colliding_disks_explicit_mpm.yaml");
  // The disks start 1 cm apart, so that they are in contact (stresses, strain energy) before the
  // checkpoint; the upper one straddles the np 2 slab boundary x = 0.5, so particles migrate.
  deck.sublist("Bodies").sublist("lower disk").set("Center X", 0.355).set("Center Y", 0.355);
  deck.sublist("Bodies").sublist("upper disk").set("Center X", 0.645).set("Center Y", 0.645);
  deck.sublist("Output").set("VTK Interval", 50).set("History Interval", 5);
  checkRestart(deck, "disks", 120, 70, out, success);
}

// Multi-field contact: the disks (each its own grid field, frictional contact) start 1 cm apart,
// collide before the checkpoint and go on pushing after it; the contact force columns are part of
// the history compared bit for bit. The fields come from each particle's body, which the
// checkpoint carries.
TEUCHOS_UNIT_TEST(Restart, MultiFieldContactDisks) {
  ParameterList deck = deckOf("colliding_disks_contact_explicit_gimp.yaml");
  deck.sublist("Bodies").sublist("lower disk").set("Center X", 0.355).set("Center Y", 0.355);
  deck.sublist("Bodies").sublist("upper disk").set("Center X", 0.645).set("Center Y", 0.645);
  deck.sublist("Contact").set("Friction", 0.3);
  deck.sublist("Output").set("VTK Interval", 0).set("History Interval", 5).set("Plot", false);
  checkRestart(deck, "contact_disks", 160, 90, out, success);
}

// Multi-field contact in the implicit step: the same frictional disks at 10 explicit steps, in
// contact from the first steps on. The unknowns per field, the contact active set (each node's
// stick or slip: without it the restart differs at 6e-16) and the lagged preconditioner's P (its
// rows numbered per field) come back from the checkpoint; across rank counts GMRES and Newton are
// converged far enough (as in test_partition_independence) for 1e-10.
TEUCHOS_UNIT_TEST(Restart, ImplicitMultiFieldContactDisks) {
  ParameterList deck = deckOf("colliding_disks_contact_implicit_gimp.yaml");
  deck.sublist("Bodies").sublist("lower disk").set("Center X", 0.355).set("Center Y", 0.355);
  deck.sublist("Bodies").sublist("upper disk").set("Center X", 0.645).set("Center Y", 0.645);
  deck.sublist("Contact").set("Friction", 0.3);
  everyStepHistory(deck);
  tightSolver(deck);
  checkRestart(deck, "implicit_contact_disks", 40, 25, out, success);
}

// Implicit frictional walls: the block of test_walls' ImplicitRoughFloorAtTheStickThreshold held
// by friction (mu = 0.7, gravity tilted by 30 degrees and ramped over 0.05 s), restarted at step
// 25. Each wall node's hold, stick or slip and slip direction carry over from step to step and come
// back from the checkpoint; without them the restarted run starts its nodes from their start
// motion and differs by 2% (measured).
TEUCHOS_UNIT_TEST(Restart, ImplicitFrictionalWall) {
  ParameterList deck = deckOf("block_sliding_friction_explicit_gimp.yaml");
  deck.sublist("Bodies").sublist("block").set("Velocity X", 0.0);
  deck.sublist("Walls").sublist("floor").set("Friction", 0.7);
  deck.sublist("Grid").set("Cells X", 40).set("Cells Y", 4);
  deck.sublist("Decomposition").set("Ranks X", 1);
  deck.sublist("Integrator").set("Type", "Implicit").set("Time Step", 2.5e-3);
  deck.sublist("Integrator").sublist("Implicit").set("Newmark Gamma", 0.6).set("Newmark Beta", 0.3025);
  deck.sublist("Loads")
      .sublist("gravity")
      .set("Time Function", "Ramp")
      .set("Ramp Time", 0.05)
      .set("Acceleration X", 5.0)
      .set("Acceleration Y", -10.0 * std::cos(M_PI / 6));
  everyStepHistory(deck);
  tightSolver(deck);
  checkRestart(deck, "implicit_frictional_wall", 40, 25, out, success);
}

// Walls and contact together, implicit: the block sliding on the slab that rests on a rough wall
// (test_implicit_contact, SlabOnARoughWallCarriesTheSlidingBlock), restarted at step 7 of 12: the
// walls' set per body field and the contact's active set both come back.
TEUCHOS_UNIT_TEST(Restart, ImplicitContactOnARoughWall) {
  ParameterList deck = deckOf("block_incline_contact_implicit_gimp.yaml");
  deck.remove("Constraints");
  deck.sublist("Walls").sublist("floor").set("Normal", "y+").set("Position", 0.0).set("Friction", 1.0);
  everyStepHistory(deck);
  tightSolver(deck);
  checkRestart(deck, "implicit_contact_wall", 12, 7, out, success);
}

// Rigid bodies, implicit: the press of test_rigid_bodies (ImplicitPlatenCompressesBlock) restarted
// at step 20 of 30, the platen moving: the contact force carried from step to step at the rigid
// bodies' nodes comes back from the checkpoint with the active set. With the tight tolerances the
// rank counts agree as well; that needs the contact's stiffness in P (without it Newton at np 2
// stalled near 1e-10 of its first residual where the block meets the platen, halved a step np 1
// solves whole, and the runs parted at 1e-3).
TEUCHOS_UNIT_TEST(Restart, ImplicitRigidPlaten) {
  ParameterList deck = deckOf("platen_compression_rigid_explicit_gimp.yaml");
  deck.sublist("Integrator").remove("Explicit");
  deck.sublist("Integrator").set("Type", "Implicit").set("Time Step", 1e-2);
  everyStepHistory(deck);
  tightSolver(deck);
  checkRestart(deck, "implicit_rigid_platen", 30, 20, out, success);
}

// APIC: each particle's affine velocity C_p is part of the checkpoint (and migrates at np 2); a
// restart without it would start from C_p = 0 and differ from the first step on.
TEUCHOS_UNIT_TEST(Restart, ApicCollidingDisks) {
  ParameterList deck = deckOf("colliding_disks_explicit_mpm.yaml");
  deck.sublist("Bodies").sublist("lower disk").set("Center X", 0.355).set("Center Y", 0.355);
  deck.sublist("Bodies").sublist("upper disk").set("Center X", 0.645).set("Center Y", 0.645);
  deck.sublist("Integrator").sublist("Explicit").set("Transfer", "APIC");
  deck.sublist("Output").set("VTK Interval", 0).set("History Interval", 5);
  checkRestart(deck, "apic_disks", 120, 70, out, success);
}

// Load balance moves the cuts between ranks before the checkpoint; a restart at the same rank
// count takes the cuts back from it (bit for bit), another rank count starts from its own.
TEUCHOS_UNIT_TEST(Restart, LoadBalancedDisks) {
  ParameterList deck = deckOf("colliding_disks_explicit_cpgimp_neohookean.yaml");
  deck.sublist("Bodies").sublist("lower disk").set("Center X", 0.3).set("Center Y", 0.3);
  deck.sublist("Bodies")
      .sublist("upper disk")
      .set("Center X", 0.62)
      .set("Center Y", 0.62)
      .set("Radius X", 0.12)
      .set("Radius Y", 0.12);
  deck.sublist("Decomposition").set("Load Balance Interval", 10);
  deck.sublist("Output").set("VTK Interval", 0).set("History Interval", 5);
  checkRestart(deck, "balanced_disks", 400, 230, out, success);
  // The same rank count in another rank grid (slabs across y): the particles go to their ranks
  // in it, and the history agrees with the uninterrupted run to 1e-10.
  auto comm = Tpetra::getDefaultComm();
  const int np = comm->getSize();
  if (np > 1) {
    ParameterList d = deck;
    d.sublist("Integrator").set("Number of Steps", 400);
    const std::string base = "test_output/restart_balanced_disks_np" + std::to_string(np);
    const Run reference = run(d, comm, base + "_reference", 0, "");
    d.sublist("Decomposition").set("Ranks X", 1).set("Ranks Y", np);
    const Run regrid = run(d, comm, base + "_regrid", 0, base + "_checkpointed/checkpoint");
    const double e = relativeDifference(regrid.result, reference.result);
    out << "balanced_disks: restarted in 1 x " << np << " against the uninterrupted run: " << e << "\n";
    TEST_COMPARE(e, <, 1e-10);
  }
}

TEUCHOS_UNIT_TEST(Restart, ImplicitBeam) {
  ParameterList deck = deckOf("beam_implicit_mpm_plane_strain.yaml");
  // Assembled Newton with the direct solver: np 1 and np 2 then agree to round-off, so that the
  // 1e-10 across rank counts tests the restart and not the Krylov tolerance.
  ParameterList& solver = deck.sublist("Implicit Solver");
  solver.remove("Preconditioner");
  solver.remove("Linear Tolerance");
  solver.remove("Ifpack2");
  solver.set("Jacobian", "Assembled");
  deck.sublist("Integrator").sublist("Implicit").set("Preconditioner Refresh Interval", 1);
  deck.sublist("Output").set("VTK Interval", 0);
  checkRestart(deck, "beam", 12, 7, out, success);
  // Projected grid acceleration: the first step takes a(0) from the forces and every later one
  // projects the particles' a, so the restarted run must know it is past its first step (the
  // integrator's own state, not only the particles').
  deck.sublist("Integrator").sublist("Implicit").set("Grid Acceleration", "Projected");
  checkRestart(deck, "beam_projected", 12, 7, out, success);
}

// The beam as its deck runs it: Jacobian-free Newton-Krylov whose ILU preconditioner is refreshed
// every few steps. The checkpoint (step 7) falls between refreshes (steps 1, 4, 7 and 10 assemble
// P here, and step 8 reuses step 7's): the restart takes the checkpoint's P, and continues bit for
// bit. (At another rank count P is assembled afresh, and the runs then differ at the level of the
// linear and Newton tolerances: not checked here.)
TEUCHOS_UNIT_TEST(Restart, ImplicitBeamLaggedPreconditioner) {
  ParameterList deck = deckOf("beam_implicit_mpm_plane_strain.yaml");
  deck.sublist("Integrator").sublist("Implicit").set("Preconditioner Refresh Interval", 3);
  deck.sublist("Output").set("VTK Interval", 0);
  checkRestart(deck, "beam_lagged", 12, 7, out, success, false);
}

}  // namespace
