// Contact between bodies (Contact/Type = Multi Field; physics/MultiFieldContact.hpp), explicit,
// against closed forms and conservation laws:
// - two elastic disks that collide and separate (apps/colliding_disks_contact_explicit_gimp.yaml):
//   momentum conserved, the contact force only ever pushes, the disks part with their velocities
//   reversed, and the kinetic energy the contact costs falls with the cell size;
// - a block on a 30 degree incline (apps/block_incline_contact_explicit_gimp.yaml) on an elastic
//   slab: its travel against g (sin 30 - mu cos 30) t^2 / 2 for mu = 0 and 0.3, no motion for
//   mu = 0.7 > tan 30 or a No Slip pair; the same on a rough rigid wall instead of the slab;
// - a disk on the incline (apps/disk_incline_contact_explicit_gimp.yaml), rolling (mu = 0.5) and
//   slipping (mu = 0.1): its centroid travel and spin against the rigid-body closed forms;
// - two cubes colliding in 3D: momentum, a push along the normal only, the rebound;
// - the deck's refusals, each one message naming the key.
// np 1 and 2: the same figures at any rank count (test_partition_independence compares them to 1e-10).
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
#include "DeckRefusals.hpp"

namespace {

using Teuchos::ParameterList;

using impm_test::quietAppDeck;

using impm_test::bodyVelocities;

struct DiskRun {
  impm::RunResult result;
  std::vector<std::array<double, 2>> velocity;  // per disk, at the end
};

DiskRun runDisks(int refine) {
  ParameterList d = quietAppDeck("colliding_disks_contact_explicit_gimp.yaml");
  ParameterList& g = d.sublist("Grid");
  g.set("Cells X", 20 * refine)
      .set("Cells Y", 20 * refine)
      .set("Cell Size X", 0.05 / refine)
      .set("Cell Size Y", 0.05 / refine);
  d.sublist("Integrator").set("Time Step", 1e-3 / refine).set("Number of Steps", 3500 * refine);
  d.sublist("Output").set("History Interval", 10 * refine);
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/contact_disks_" + std::to_string(refine));
  std::ostringstream log;
  DiskRun run;
  run.result = sim.run(log);
  run.velocity = bodyVelocities(sim);
  return run;
}

// The disks (0.2 m radius, 1000 kg/m^3, +-(0.1, 0.1) m/s) meet along the diagonal. The contact
// force on the lower disk, F, points down the diagonal whenever it acts (F . (1, 1) <= 0: it never
// pulls), vanishes once they have parted (t > 2.3 s; a last graze of 1e-8 of the peak at h), and is
// exactly the upper disk's reaction: total momentum stays zero to round-off. Each disk leaves with its velocity
// reversed. The contact is detected when the fields approach, up to a cell before the surfaces meet, and costs kinetic
// energy: measured 19% of it at 20 x 20 cells and 6.5% at 40 x 40. Asserted: below 25% at h, and at h / 2 less than
// half of that at h (the loss falls with h, about linearly: 3.5% at 80 x 80 cells,
// apps/colliding_disks_contact_explicit_gimp.yaml).
TEUCHOS_UNIT_TEST(Contact, DisksCollideAndSeparate) {
  const double M = 2 * M_PI * 0.2 * 0.2 * 1000.0, v0 = 0.1 * std::sqrt(2.0);
  double loss[2] = {0, 0};
  for (int refine : {1, 2}) {
    const DiskRun run = runDisks(refine);
    const impm::RunResult& r = run.result;
    TEST_EQUALITY_CONST(r.status, "completed");
    const std::vector<double>& fx = r.reactions.at("lower_disk_upper_disk_contact_x");
    const std::vector<double>& fy = r.reactions.at("lower_disk_upper_disk_contact_y");
    double peak = 0, pull = 0, after = 0, momentum = 0;
    for (size_t i = 0; i < r.time.size(); ++i) {
      peak = std::max(peak, std::hypot(fx[i], fy[i]));
      pull = std::max(pull, (fx[i] + fy[i]) / std::sqrt(2.0));
      if (r.time[i] > 2.3) after = std::max(after, std::hypot(fx[i], fy[i]));
      momentum = std::max(momentum, std::hypot(r.momentumX[i], r.momentumY[i]));
    }
    loss[refine - 1] = 1 - (r.kinetic.back() + r.strain.back()) / (r.kinetic.front() + r.strain.front());
    const auto& lower = run.velocity[0];
    const auto& upper = run.velocity[1];
    out << "refine " << refine << ": peak contact force " << peak << " N, largest pull " << pull << " N, after parting "
        << after << " N; momentum " << momentum << " (M v0 = " << M * v0 << "); lower disk leaves at (" << lower[0]
        << ", " << lower[1] << "), upper at (" << upper[0] << ", " << upper[1] << "); energy lost " << loss[refine - 1]
        << "\n";
    TEST_COMPARE(peak, >, 10.0);  // the disks did meet (the peak force is about 27 N)
    TEST_COMPARE(pull, <=, 1e-9 * peak);
    TEST_COMPARE(after, <, 1e-6 * peak);  // (a graze of 1e-8 peak at h)
    TEST_COMPARE(momentum, <, 1e-11 * M * v0);
    for (int d = 0; d < 2; ++d) {
      TEST_COMPARE(lower[d], <, -0.05);  // reversed, and most of the speed kept
      TEST_COMPARE(upper[d], >, 0.05);
    }
  }
  TEST_COMPARE(loss[0], >, 0.0);
  TEST_COMPARE(loss[0], <, 0.25);
  TEST_COMPARE(loss[1], <, 0.5 * loss[0]);
}

// The block's travel at t = 0.25 s (the centre particle's displacement along the incline).
double inclineTravel(const std::function<void(ParameterList&)>& edit, const std::string& tag,
                     impm::RunResult* result = nullptr) {
  ParameterList d = quietAppDeck("block_incline_contact_explicit_gimp.yaml");
  edit(d);
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/contact_incline_" + tag);
  std::ostringstream log;
  impm::RunResult r = sim.run(log);
  if (r.status != "completed") return std::nan("");
  const double travel = r.computed.at("block travel").back();
  if (result) *result = r;
  return travel;
}

double slidingTravel(double mu, double t = 0.25) {
  const double g = 10.0, theta = M_PI / 6;
  return std::max(0.0, 0.5 * g * (std::sin(theta) - mu * std::cos(theta)) * t * t);
}

// Frictionless and mu = 0.3: the travel within 3% of g (sin 30 - mu cos 30) t^2 / 2 (measured
// 0.04% and 1.2%; the block's elastic settling on the slab at the start is the rest). With
// mu = 0.3 the slab also carries the block's weight across the contact, M g cos 30 = 3.46 N, and
// its friction mu times that (means over the sliding, within 10%: the soft block rings on the slab).
TEUCHOS_UNIT_TEST(Contact, BlockSlidesDownInclineOnSlab) {
  for (double mu : {0.0, 0.3}) {
    impm::RunResult r;
    const double travel = inclineTravel([&](ParameterList& d) { d.sublist("Contact").set("Friction", mu); },
                                        "slab_" + std::to_string(mu), &r);
    const double exact = slidingTravel(mu), error = std::abs(travel / exact - 1);
    out << "mu = " << mu << ": travel " << travel << " m, exact " << exact << " m, relative error " << error << "\n";
    TEST_COMPARE(error, <, 0.03);
    if (mu > 0) {
      const double sx = impm_test::meanFrom(r, "slab_block_contact_x", 0.05);
      const double sy = impm_test::meanFrom(r, "slab_block_contact_y", 0.05);
      const double weight = 0.4 * 10.0 * std::cos(M_PI / 6);  // M g cos 30 (0.4 kg per metre of thickness)
      out << "  mean force of the block on the slab (" << sx << ", " << sy << ") N; weight " << weight
          << " N, friction " << mu * weight << " N\n";
      TEST_COMPARE(std::abs(-sy / weight - 1), <, 0.1);
      TEST_COMPARE(std::abs(sx / (mu * weight) - 1), <, 0.1);
    }
  }
}

// mu = 0.7 > tan 30 = 0.577, or a No Slip pair: the block stays. Gravity comes on over 0.05 s:
// switched on at once it makes the soft block ring on the slab, the normal force dips to a quarter
// of the weight, and the block ratchets down the slope in those dips (4% of the frictionless travel
// in 0.25 s with mu = 0.7: what a ringing block does). Loaded so, the block moves below 0.1% of
// the frictionless travel (measured 0.02%, its elastic deformation), and the slab carries its
// weight: the mean force of the slab on the block over the hold is M g (-sin 30, cos 30) within 2%
// (measured 0.1%; friction holds the whole downhill pull). The mu = 0.7 pair names the block
// first, so its force column is the one on the block.
TEUCHOS_UNIT_TEST(Contact, BlockHoldsOnInclineWhenFrictionSuffices) {
  const double frictionless = slidingTravel(0.0), M = 0.4, g = 10.0, theta = M_PI / 6;
  auto ramped = [](ParameterList& d) {
    d.sublist("Loads").sublist("gravity").set("Time Function", "Ramp").set("Ramp Time", 0.05);
  };
  impm::RunResult r;
  // (The rough pair named block first: its force is the one on the block, the slab's reversed.)
  const double rough = inclineTravel(
      [&](ParameterList& d) {
        ramped(d);
        d.sublist("Contact Pairs").sublist("rough").set("Bodies", "block, slab").set("Friction", 0.7);
      },
      "rough", &r);
  const double bonded = inclineTravel(
      [&](ParameterList& d) {
        ramped(d);
        d.sublist("Contact Pairs").sublist("glued").set("Bodies", "slab, block").set("Law", "No Slip");
      },
      "bonded");
  out << "travel with mu = 0.7: " << rough << " m; No Slip: " << bonded << " m; frictionless " << frictionless
      << " m\n";
  TEST_COMPARE(std::abs(rough), <, 1e-3 * frictionless);
  TEST_COMPARE(std::abs(bonded), <, 1e-3 * frictionless);
  // (the force of the slab on the block: minus the block's on the slab)
  const double sx = impm_test::meanFrom(r, "rough_contact_x", 0.1), sy = impm_test::meanFrom(r, "rough_contact_y", 0.1);
  out << "mean force of the slab on the block (" << sx << ", " << sy << ") N; M g (-sin 30, cos 30) = ("
      << -M * g * std::sin(theta) << ", " << M * g * std::cos(theta) << ") N\n";
  TEST_COMPARE(std::abs(-sx / (M * g * std::sin(theta)) - 1), <, 0.02);
  TEST_COMPARE(std::abs(sy / (M * g * std::cos(theta)) - 1), <, 0.02);
}

// The block on a rough rigid floor (Walls) instead of the slab, mu = 0.3: the same travel within 3%.
TEUCHOS_UNIT_TEST(Contact, BlockSlidesDownInclineOnRoughWall) {
  const double travel = inclineTravel(
      [](ParameterList& d) {
        d.sublist("Bodies").remove("slab");
        d.sublist("Bodies").sublist("block").set("Y Min", 0.0).set("Y Max", 0.01);
        d.sublist("Monitors").sublist("block travel").set("Y", 0.005);
        d.remove("Constraints");
        d.sublist("Contact").set("Type", "Single Field");
        d.sublist("Walls").sublist("incline").set("Normal", "y+").set("Position", 0.0).set("Friction", 0.3);
      },
      "wall");
  const double exact = slidingTravel(0.3), error = std::abs(travel / exact - 1);
  out << "on a rough wall, mu = 0.3: travel " << travel << " m, exact " << exact << " m, relative error " << error
      << "\n";
  TEST_COMPARE(error, <, 0.03);
}

// The centroid x and the spin (angular momentum over moment of inertia about the centroid, z) of a
// body's particles, over all ranks.
std::array<double, 2> centroidAndSpin(const impm::Simulation& sim, int body) {
  const impm::ParticleSet& ps = sim.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  auto b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.body);
  const auto comm = Tpetra::getDefaultComm();
  double local[3] = {0, 0, 0}, sums[3];
  for (int p = 0; p < ps.count; ++p)
    if (b(p) == body) {
      local[0] += m(p);
      local[1] += m(p) * x(p, 0);
      local[2] += m(p) * x(p, 1);
    }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 3, local, sums);
  const double cx = sums[1] / sums[0], cy = sums[2] / sums[0];
  double spin[2] = {0, 0}, spinSums[2];
  for (int p = 0; p < ps.count; ++p)
    if (b(p) == body) {
      const double rx = x(p, 0) - cx, ry = x(p, 1) - cy;
      spin[0] += m(p) * (rx * v(p, 1) - ry * v(p, 0));
      spin[1] += m(p) * (rx * rx + ry * ry);
    }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 2, spin, spinSums);
  return {cx, spinSums[0] / spinSums[1]};
}

// A disk (R = 20 mm, 8 cells) on the slab of a 30 degree incline
// (apps/disk_incline_contact_explicit_gimp.yaml, Contact Distance 0.8), at t = 0.2 s.
// mu = 0.5 >= tan 30 / 3: it rolls, its centroid travels 2/3 g sin 30 t^2 / 2 and it spins at
// a t / R (clockwise); measured 5.7% and 6.1% short, asserted within 8%. mu = 0.1: it slips and
// travels g (sin 30 - mu cos 30) t^2 / 2, within 5% (measured +0.7%); the friction torque should
// spin it at 2 mu g cos 30 t / R, measured 30% short. Both deficits come from where the contact
// carries the disk's weight: at the grid nodes next to the contact point where the disk approaches
// the slab, the ones just ahead of it as it turns, so the normal force acts about a quarter cell
// ahead, a torque against the spin (e / (mu R) of the slipping spin, e / (R tan 30) of the rolling
// acceleration). They halve with the cell: at 16 and 32 cells per radius the slipping spin is 14%
// and 2% short and the rolling travel 1.2% and 0.1% (the verification report). Asserted here: the
// slipping spin between half and all of the closed form, and well below the rolling spin.
TEUCHOS_UNIT_TEST(Contact, DiskRollsOrSlipsDownIncline) {
  const double g = 10.0, theta = M_PI / 6, R = 0.02, t = 0.2;
  double rollingSpin = 0;
  for (double mu : {0.5, 0.1}) {
    ParameterList d = quietAppDeck("disk_incline_contact_explicit_gimp.yaml");
    d.sublist("Contact").set("Friction", mu);
    impm::validateDeck(d);
    impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/contact_disk_" + std::to_string(mu));
    const std::array<double, 2> start = centroidAndSpin(sim, 1);
    std::ostringstream log;
    const impm::RunResult r = sim.run(log);
    TEST_EQUALITY_CONST(r.status, "completed");
    const std::array<double, 2> end = centroidAndSpin(sim, 1);
    const bool rolls = mu >= std::tan(theta) / 3;
    const double a = rolls ? 2.0 / 3.0 * g * std::sin(theta) : g * (std::sin(theta) - mu * std::cos(theta));
    const double spin = rolls ? -a * t / R : -2 * mu * g * std::cos(theta) * t / R;
    const double travel = end[0] - start[0];
    const double travelError = travel / (0.5 * a * t * t) - 1, spinError = end[1] / spin - 1;
    out << "mu = " << mu << (rolls ? " (rolls)" : " (slips)") << ": travel " << travel << " m (exact "
        << 0.5 * a * t * t << ", error " << travelError << "), spin " << end[1] << " rad/s (exact " << spin
        << ", error " << spinError << ")\n";
    TEST_COMPARE(std::abs(start[1]), <, 1e-12);
    if (rolls) {
      TEST_COMPARE(std::abs(travelError), <, 0.08);
      TEST_COMPARE(std::abs(spinError), <, 0.08);
      rollingSpin = end[1];
    } else {
      TEST_COMPARE(std::abs(travelError), <, 0.05);
      TEST_COMPARE(end[1] / spin, >, 0.5);
      TEST_COMPARE(end[1] / spin, <, 1.0);
      TEST_COMPARE(std::abs(end[1]), <, 0.6 * std::abs(rollingSpin));
    }
  }
}

// 3D: two elastic cubes (40 mm, 4 cells a side, c = 10 m/s) approach along x at +-0.5 m/s, meet
// frictionlessly and bounce apart. The contact force on the first cube only ever pushes it back
// (F_x <= 0), it has no y or z part (the faces meet square on: 5e-15 of the push; 0.1 of it before
// equal gradients were given to one side on both), and each cube leaves with its velocity reversed,
// at 0.354 m/s (half the kinetic energy is lost at this resolution, against 7% with one field,
// where the cubes stick and spring apart). Momentum: 9e-11 of M v0 with the Larger Gradient
// normals (3e-14 with Average; the source of the difference is not found), asserted below 1e-9.
TEUCHOS_UNIT_TEST(Contact, CubesCollideAndSeparateIn3d) {
  ParameterList d("impm");
  d.sublist("Problem").set("Name", "cubes").set("Output Directory", "test_output/contact_cubes");
  d.sublist("Grid").set("Dimension", 3).set("Cells X", 16).set("Cells Y", 6).set("Cells Z", 6);
  d.sublist("Grid").set("Cell Size X", 0.01).set("Cell Size Y", 0.01).set("Cell Size Z", 0.01);
  d.sublist("Materials").sublist("soft").set("Young Modulus", 1.0e5).set("Poisson Ratio", 0.3).set("Density", 1000.0);
  auto cube = [&](const std::string& name, double x0, double v) {
    ParameterList& b = d.sublist("Bodies").sublist(name);
    b.set("Material", "soft").set("X Min", x0).set("X Max", x0 + 0.04).set("Y Min", 0.01).set("Y Max", 0.05);
    b.set("Z Min", 0.01).set("Z Max", 0.05).set("Velocity X", v);
    b.set("Particles Per Cell X", 2).set("Particles Per Cell Y", 2).set("Particles Per Cell Z", 2);
  };
  cube("left", 0.03, 0.5);
  cube("right", 0.09, -0.5);
  d.sublist("Method").set("Shape Function", "GIMP");
  d.sublist("Integrator").set("Type", "Explicit").set("Time Step", 2.0e-4).set("Number of Steps", 300);
  d.sublist("Contact").set("Type", "Multi Field");
  d.sublist("Output").set("History Interval", 5).set("VTK Interval", 0).set("Plot", false).set("Progress", false);
  d.sublist("Output").set("Energy And Momentum", true);
  impm::validateDeck(d);
  impm::Simulation sim(d, Tpetra::getDefaultComm(), "test_output/contact_cubes");
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  TEST_EQUALITY_CONST(r.status, "completed");
  const std::vector<double>& fx = r.reactions.at("left_right_contact_x");
  const std::vector<double>& fy = r.reactions.at("left_right_contact_y");
  const std::vector<double>& fz = r.reactions.at("left_right_contact_z");
  double push = 0, pull = 0, side = 0, momentum = 0;
  for (size_t i = 0; i < r.time.size(); ++i) {
    push = std::min(push, fx[i]);
    pull = std::max(pull, fx[i]);
    side = std::max({side, std::abs(fy[i]), std::abs(fz[i])});
    momentum = std::max({momentum, std::abs(r.momentumX[i]), std::abs(r.momentumY[i]), std::abs(r.momentumZ[i])});
  }
  const double M = 1000.0 * 0.04 * 0.04 * 0.04, v0 = 0.5;
  const auto& pm = sim.particles();
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pm.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pm.mass);
  auto body = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pm.body);
  double local[4] = {0, 0, 0, 0}, sums[4];
  for (int p = 0; p < pm.count; ++p) {
    local[2 * body(p)] += m(p);
    local[2 * body(p) + 1] += m(p) * v(p, 0);
  }
  Teuchos::reduceAll(*Tpetra::getDefaultComm(), Teuchos::REDUCE_SUM, 4, local, sums);
  const double left = sums[1] / sums[0], right = sums[3] / sums[2];
  out << "peak push " << -push << " N, largest pull " << pull << " N, largest side force " << side << " N, momentum "
      << momentum << " (M v0 = " << M * v0 << "); the cubes leave at " << left << " and " << right << " m/s\n";
  TEST_COMPARE(-push, >, 1.0);
  TEST_COMPARE(pull, <=, 1e-9 * -push);
  TEST_COMPARE(side, <, 1e-9 * -push);
  TEST_COMPARE(momentum, <, 1e-9 * M * v0);
  TEST_COMPARE(left, <, -0.3);
  TEST_COMPARE(right, >, 0.3);
}

// Each refusal: one DeckError naming the key.
TEUCHOS_UNIT_TEST(Contact, RefusesBadContact) {
  auto pair = [](ParameterList& d, const std::string& bodies) {
    return &d.sublist("Contact Pairs").sublist("pair").set("Bodies", bodies);
  };
  const std::vector<impm_test::DeckRefusal> cases = {
      {"negative friction", "Contact/Friction", "must be a finite coefficient >= 0",
       [](ParameterList& d) { d.sublist("Contact").set("Friction", -0.1); }},
      {"unknown body", "Contact Pairs/pair/Bodies", "names no entry of Bodies",
       [&](ParameterList& d) { pair(d, "slab, brick"); }},
      {"one body twice", "Contact Pairs/pair/Bodies", "twice", [&](ParameterList& d) { pair(d, "block, block"); }},
      {"one body only", "Contact Pairs/pair/Bodies", "must name two bodies",
       [&](ParameterList& d) { pair(d, "block"); }},
      {"pair friction", "Contact Pairs/pair/Friction", "must be a finite coefficient >= 0",
       [&](ParameterList& d) { pair(d, "slab, block")->set("Friction", -1.0); }},
      {"pairs without fields", "Contact Pairs/pair", "needs 'Contact/Type' = Multi Field",
       [&](ParameterList& d) {
         pair(d, "slab, block");
         d.sublist("Contact").set("Type", "Single Field");
       }},
      {"nodal load", "Loads/push/Type", "belong to no single body",
       [](ParameterList& d) {
         d.sublist("Loads").sublist("push").set("Type", "Node Force").set("X", 0.03).set("Y", 0.02).set("Force X", 1.0);
       }},
      {"projection", "Integrator/Explicit/Consistent Projection Iterations", "must be 0",
       [](ParameterList& d) {
         d.sublist("Integrator").sublist("Explicit").set("Consistent Projection Iterations", 1);
       }},
      {"finite elements", "Contact/Type", "finite-element reference",
       [](ParameterList& d) {
         d.sublist("Method").set("Shape Function", "FE Q4");
         d.sublist("Integrator").set("Type", "Implicit");
       }},
      {"one body", "Contact/Type", "needs two bodies or more",
       [](ParameterList& d) {
         d.sublist("Bodies").remove("slab");
         d.remove("Constraints");
       }},
  };
  impm_test::checkRefusals(quietAppDeck("block_incline_contact_explicit_gimp.yaml"), cases, "test_output/contact_bad",
                           out, success);
}

}  // namespace
