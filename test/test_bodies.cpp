// Bodies, materials and particle identity: several bodies of any shape in one deck, each of its
// own material; global ids independent of the MPI decomposition; the overlap rule; body forces,
// box constraints; and the bad-input messages of the Materials and Bodies sections. Run at np 1
// and 2.
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "core/ParticleMigration.hpp"
#include "core/kernels/Energy.hpp"
#include "solvers/Simulation.hpp"

#include "RunHistory.hpp"

namespace {

using impm::DeckError;
using Teuchos::ParameterList;
const double kPi = std::acos(-1.0);

// A 2 x 1 m grid of 0.1 m cells with a plate (left), a disk (right) and a triangle.
ParameterList shapesDeck(const std::string& outdir) {
  ParameterList d("impm");
  d.sublist("Problem").set("Output Directory", outdir);
  auto& g = d.sublist("Grid");
  g.set("Cells X", 20).set("Cells Y", 10).set("Cell Size X", 0.1).set("Cell Size Y", 0.1).set("Thickness", 0.5);
  auto& ms = d.sublist("Materials");
  ms.sublist("soft").set("Young Modulus", 1e6).set("Poisson Ratio", 0.3).set("Density", 1000.0);
  ms.sublist("stiff").set("Young Modulus", 1e8).set("Poisson Ratio", 0.2).set("Density", 3000.0);
  auto& bs = d.sublist("Bodies");
  bs.sublist("plate")
      .set("Shape", "Rectangle")
      .set("Material", "soft")
      .set("X Min", 0.0)
      .set("X Max", 0.6)
      .set("Y Min", 0.0)
      .set("Y Max", 0.4)
      .set("Particles Per Cell X", 2)
      .set("Particles Per Cell Y", 3);
  bs.sublist("disk")
      .set("Shape", "Ellipse")
      .set("Material", "stiff")
      .set("Center X", 1.5)
      .set("Center Y", 0.5)
      .set("Radius X", 0.3)
      .set("Radius Y", 0.3)
      .set("Velocity X", -1.0);
  bs.sublist("wedge").set("Shape", "Polygon").set("Material", "soft").set("Vertices", "0.1, 0.6; 0.9, 0.6; 0.5, 0.95");
  d.sublist("Integrator").set("Time Step", 1e-5).set("Number of Steps", 10);
  d.sublist("Output").set("Plot", false).set("Progress", false);
  return d;
}

struct HostParticles {
  std::vector<double> x, y, mass, volume, vx;
  std::vector<int> body, material;
  std::vector<long long> id;
};
HostParticles gather(const impm::ParticleSet& ps) {
  HostParticles h;
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  auto V = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.volume0);
  auto b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.body);
  auto mt = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.material);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id);
  for (int p = 0; p < ps.count; ++p) {
    h.x.push_back(x(p, 0));
    h.y.push_back(x(p, 1));
    h.vx.push_back(v(p, 0));
    h.mass.push_back(m(p));
    h.volume.push_back(V(p));
    h.body.push_back(b(p));
    h.material.push_back(mt(p));
    h.id.push_back(id(p));
  }
  return h;
}

std::string problemWith(ParameterList deck) {
  try {
    impm::validateDeck(deck);
    impm::Simulation sim(deck, Tpetra::getDefaultComm());
  } catch (const DeckError& e) {
    return e.what();
  }
  return "";
}
bool mentions(const std::string& msg, const std::string& what) { return msg.find(what) != std::string::npos; }

// Every body gets its material's density, its own id and its initial velocity; the disk and the
// triangle carry their exact areas (x thickness) as volume, the plate its lattice volume; global
// ids are 0..N-1 over all ranks.
TEUCHOS_UNIT_TEST(Bodies, ShapesMaterialsAndIdentity) {
  auto comm = Tpetra::getDefaultComm();
  ParameterList d = shapesDeck("test_output/bodies_shapes");
  impm::validateDeck(d);
  impm::Simulation sim(d, comm);
  const HostParticles h = gather(sim.particles());
  double volume[3] = {0, 0, 0}, count[3] = {0, 0, 0};
  bool densities = true, velocities = true, materials = true;
  for (size_t p = 0; p < h.id.size(); ++p) {
    const int b = h.body[p];
    volume[b] += h.volume[p];
    count[b] += 1;
    const double rho = b == 1 ? 3000.0 : 1000.0;
    densities = densities && std::abs(h.mass[p] - rho * h.volume[p]) <= 1e-12 * h.mass[p];
    velocities = velocities && h.vx[p] == (b == 1 ? -1.0 : 0.0);
    materials = materials && h.material[p] == (b == 1 ? 1 : 0);
  }
  TEST_ASSERT(densities);
  TEST_ASSERT(velocities);
  TEST_ASSERT(materials);
  double gVolume[3], gCount[3];
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 3, volume, gVolume);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 3, count, gCount);
  // Exact volume assigned: to round-off (the fill sums a few hundred volumes).
  TEST_FLOATING_EQUALITY(gVolume[0], 0.6 * 0.4 * 0.5, 1e-12);
  TEST_FLOATING_EQUALITY(gVolume[1], kPi * 0.09 * 0.5, 1e-12);
  TEST_FLOATING_EQUALITY(gVolume[2], 0.5 * 0.8 * 0.35 * 0.5, 1e-12);
  TEST_EQUALITY_CONST(gCount[0], 6 * 4 * 6);
  // Global ids: a permutation of 0..N-1 over all ranks.
  const long long total = (long long)(gCount[0] + gCount[1] + gCount[2]);
  std::vector<int> seen(total, 0), gSeen(total, 0);
  bool inRange = true;
  for (long long id : h.id) {
    inRange = inRange && id >= 0 && id < total;
    if (id >= 0 && id < total) seen[id] += 1;
  }
  TEST_ASSERT(inRange);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, (int)total, seen.data(), gSeen.data());
  TEST_EQUALITY_CONST(*std::min_element(gSeen.begin(), gSeen.end()), 1);
  TEST_EQUALITY_CONST(*std::max_element(gSeen.begin(), gSeen.end()), 1);
}

// Bodies/<name>/Particle Placement = Gauss through the deck, 2D and 3D (np 1 and 2): the mass is
// rho times the body's volume, and the second moments of the body about its centre are exact,
// as the Gauss pairs integrate cubics (Uniform sub-box centres get them low by 1 - (d/H)^2).
TEUCHOS_UNIT_TEST(Bodies, GaussPlacementKeepsMassAndSecondMoments) {
  auto comm = Tpetra::getDefaultComm();
  for (int dim : {2, 3}) {
    ParameterList d("impm");
    d.sublist("Problem").set("Output Directory", "test_output/bodies_gauss");
    auto& g = d.sublist("Grid");
    g.set("Cells X", 6).set("Cells Y", 4).set("Cell Size X", 0.1).set("Cell Size Y", 0.05);
    if (dim == 3) g.set("Dimension", 3).set("Cells Z", 3).set("Cell Size Z", 0.2);
    d.sublist("Materials").sublist("steel").set("Young Modulus", 2e11).set("Poisson Ratio", 0.3).set("Density", 7800.0);
    auto& b = d.sublist("Bodies").sublist("block");
    b.set("Shape", "Rectangle")
        .set("Material", "steel")
        .set("X Min", 0.1)
        .set("X Max", 0.5)
        .set("Y Min", 0.05)
        .set("Y Max", 0.2)
        .set("Particles Per Cell X", 2)
        .set("Particles Per Cell Y", 4)
        .set("Particle Placement", "Gauss");
    if (dim == 3) b.set("Z Min", 0.2).set("Z Max", 0.6).set("Particles Per Cell Z", 2);
    d.sublist("Integrator").set("Time Step", 1e-7).set("Number of Steps", 1);
    d.sublist("Output").set("Plot", false).set("Progress", false);
    impm::validateDeck(d);
    impm::Simulation sim(d, comm);
    const impm::ParticleSet& ps = sim.particles();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
    auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
    const double lo[3] = {0.1, 0.05, 0.2}, hi[3] = {0.5, 0.2, 0.6};
    double local[4] = {0, 0, 0, 0}, global[4];  // mass, and mass-weighted second moments per direction
    for (int p = 0; p < ps.count; ++p) {
      local[0] += m(p);
      for (int k = 0; k < dim; ++k) {
        const double r = x(p, k) - 0.5 * (lo[k] + hi[k]);
        local[1 + k] += m(p) * r * r;
      }
    }
    Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 4, local, global);
    const double volume = 0.4 * 0.15 * (dim == 3 ? 0.4 : 1.0);  // 2D: Grid/Thickness 1
    TEST_FLOATING_EQUALITY(global[0], 7800.0 * volume, 1e-13);
    for (int k = 0; k < dim; ++k) {
      const double length = hi[k] - lo[k];
      TEST_FLOATING_EQUALITY(global[1 + k], 7800.0 * volume * length * length / 12, 1e-12);
    }
  }
  // An odd count per cell, and an unknown value, are rejected naming the key.
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Bodies").sublist("plate").set("Particle Placement", "Gauss");
    const std::string msg = problemWith(d);
    TEST_ASSERT(mentions(msg, "'Bodies/plate/Particle Placement' = Gauss") &&
                mentions(msg, "'Bodies/plate/Particles Per Cell Y' must be even, got 3"));
  }
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Bodies").sublist("plate").set("Particle Placement", "Gaussian");
    TEST_ASSERT(mentions(problemWith(d), "Bodies/plate/Particle Placement"));
  }
  TEST_ASSERT(!std::filesystem::exists("test_output/bodies_bad"));
}

// The particle with a given global id sits at the same place whatever the decomposition: each
// rank re-runs the set-up alone (a communicator of one) and finds its own particles there.
TEUCHOS_UNIT_TEST(Bodies, GlobalIdsIndependentOfRanks) {
  auto comm = Tpetra::getDefaultComm();
  ParameterList d = shapesDeck("test_output/bodies_ids");
  impm::validateDeck(d);
  impm::Simulation distributed(d, comm);
  auto self = comm->split(comm->getRank(), 0);
  impm::Simulation alone(d, self);
  const HostParticles a = gather(distributed.particles()), b = gather(alone.particles());
  std::map<long long, std::pair<double, double>> where;
  for (size_t p = 0; p < b.id.size(); ++p) where[b.id[p]] = {b.x[p], b.y[p]};
  bool same = true;
  for (size_t p = 0; p < a.id.size(); ++p) {
    auto it = where.find(a.id[p]);
    same = same && it != where.end() && it->second.first == a.x[p] && it->second.second == a.y[p];
  }
  TEST_ASSERT(same);
}

// Migration: shift every particle by 3 cells to the right (across the slab boundary at np 2,
// one slab is 10 columns), migrate, and every particle sits in its rank's slab, with the same
// set of global ids and masses over all ranks.
TEUCHOS_UNIT_TEST(Bodies, ParticlesMigrateToTheirSlab) {
  auto comm = Tpetra::getDefaultComm();
  ParameterList d = shapesDeck("test_output/bodies_migrate");
  d.sublist("Bodies").sublist("disk").set("Center X", 1.2);
  impm::validateDeck(d);
  impm::Simulation sim(d, comm);
  impm::ParticleSet ps = sim.particles();  // shares the views
  // A path-dependent material's history travels with its particle: alpha = global id / 1000.
  ps.allocateHistory();
  auto x = ps.x;
  auto history = ps.history;
  auto ids = ps.id;
  Kokkos::parallel_for(
      "shift", Kokkos::RangePolicy<impm::ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        x(p, 0) += 0.3;
        history(p, impm::ParticleSet::kHistoryCount - 1) = 1e-3 * (double)ids(p);
      });
  const HostParticles before = gather(ps);
  double sums[3] = {0, 0, 0}, gBefore[3], gAfter[3];
  for (size_t p = 0; p < before.id.size(); ++p) {
    sums[0] += 1;
    sums[1] += (double)before.id[p];
    sums[2] += before.mass[p];
  }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 3, sums, gBefore);
  const long long moved = impm::migrateParticles(ps, sim.distribution());
  if (comm->getSize() == 1) {
    TEST_EQUALITY_CONST(moved, 0);
  } else {
    TEST_COMPARE(moved, >, 0);
  }
  const HostParticles after = gather(ps);
  sums[0] = sums[1] = sums[2] = 0;
  bool inSlab = true;
  for (size_t p = 0; p < after.id.size(); ++p) {
    sums[0] += 1;
    sums[1] += (double)after.id[p];
    sums[2] += after.mass[p];
    const double xp[3] = {after.x[p], after.y[p], 0.0};
    inSlab = inSlab && sim.distribution().ownsPoint(xp);
  }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 3, sums, gAfter);
  TEST_ASSERT(inSlab);
  TEST_ASSERT(ps.hasHistory());
  if (ps.hasHistory()) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.history);
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id);
    bool historyFollows = h.extent(0) == (size_t)ps.count;
    for (int p = 0; historyFollows && p < ps.count; ++p)
      historyFollows = h(p, impm::ParticleSet::kHistoryCount - 1) == 1e-3 * (double)id(p) && h(p, 0) == 1.0;
    TEST_ASSERT(historyFollows);
  }
  TEST_EQUALITY(gAfter[0], gBefore[0]);
  TEST_EQUALITY(gAfter[1], gBefore[1]);
  TEST_FLOATING_EQUALITY(gAfter[2], gBefore[2], 1e-14);
}

// A later body replaces the earlier bodies' particles inside its shape: a disk inclusion in a
// plate leaves the plate's particles outside the disk only.
TEUCHOS_UNIT_TEST(Bodies, LaterBodyReplacesEarlierInside) {
  auto comm = Tpetra::getDefaultComm();
  ParameterList d = shapesDeck("test_output/bodies_inclusion");
  auto& bs = d.sublist("Bodies");
  bs.remove("wedge");
  bs.sublist("disk").set("Center X", 0.3).set("Center Y", 0.2).set("Radius X", 0.15).set("Radius Y", 0.15);
  impm::validateDeck(d);
  impm::Simulation sim(d, comm);
  const HostParticles h = gather(sim.particles());
  int plateInside = 0, plate = 0;
  for (size_t p = 0; p < h.id.size(); ++p)
    if (h.body[p] == 0) {
      ++plate;
      if (std::hypot(h.x[p] - 0.3, h.y[p] - 0.2) < 0.15) ++plateInside;
    }
  int gInside = 0, gPlate = 0;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, plateInside, Teuchos::outArg(gInside));
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, plate, Teuchos::outArg(gPlate));
  TEST_EQUALITY_CONST(gInside, 0);
  TEST_COMPARE(gPlate, <, 6 * 4 * 6);
  TEST_COMPARE(gPlate, >, 6 * 4 * 6 - 60);
}

// Gravity on one free body: nothing else acts, so its momentum grows as M g t exactly (the grid
// forces sum to M g by partition of unity; internal forces sum to zero), the other body's
// stays zero.
TEUCHOS_UNIT_TEST(Bodies, BodyForceOnOneBody) {
  auto comm = Tpetra::getDefaultComm();
  ParameterList d = shapesDeck("test_output/bodies_gravity");
  d.sublist("Bodies").sublist("disk").set("Velocity X", 0.0);
  d.sublist("Loads")
      .sublist("gravity")
      .set("Type", "Body Force")
      .set("Body", "disk")
      .set("Acceleration Y", -9.81)
      .set("Time Function", "Constant");
  impm::validateDeck(d);
  impm::Simulation sim(d, comm);
  std::ostringstream log;
  sim.run(log);
  const HostParticles h = gather(sim.particles());
  double p[2] = {0, 0}, m = 0;  // momentum of the disk and of the others, disk mass
  for (size_t k = 0; k < h.id.size(); ++k) {
    if (h.body[k] == 1) m += h.mass[k];
  }
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sim.particles().v);
  for (size_t k = 0; k < h.id.size(); ++k) p[h.body[k] == 1 ? 0 : 1] += h.mass[k] * v(k, 1);
  double gp[2], gm;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 2, p, gp);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, m, Teuchos::outArg(gm));
  const double t = 10 * 1e-5;
  TEST_FLOATING_EQUALITY(gp[0], -9.81 * gm * t, 1e-10);
  TEST_COMPARE(std::abs(gp[1]), <, 1e-12 * std::abs(gp[0]));
}

// summary.yaml's peak memory: the largest rank's and the sum over ranks (each rank holds Kokkos,
// Trilinos and MPI, well over a megabyte, so with more ranks the sum must exceed the largest).
TEUCHOS_UNIT_TEST(Bodies, SummaryReportsPeakMemoryOfEveryRank) {
  auto comm = Tpetra::getDefaultComm();
  ParameterList d = shapesDeck("test_output/bodies_memory");
  impm::validateDeck(d);
  impm::Simulation sim(d, comm);
  const impm::RunResult r = impm_test::runToCompletion(sim, "bodies");
  out << "peak resident bytes: largest rank " << r.peakResidentBytesMax << ", total " << r.peakResidentBytesTotal
      << " over " << comm->getSize() << " rank(s)\n";
  TEST_COMPARE(r.peakResidentBytesMax, >, 1e6);
  TEST_COMPARE(r.peakResidentBytesTotal, >=, r.peakResidentBytesMax + (comm->getSize() - 1) * 1e6);
  TEST_COMPARE(r.peakResidentBytesTotal, <=, comm->getSize() * r.peakResidentBytesMax);
  TEST_FLOATING_EQUALITY(impm_test::summaryValue(sim.outputDirectory(), "Peak Resident Bytes Total"),
                         r.peakResidentBytesTotal, 1e-12);
}

// A Box constraint fixes every node in the box: a plate whose left column of nodes is held
// in x and y does not move there, while the pulled right end does.
TEUCHOS_UNIT_TEST(Bodies, BoxConstraint) {
  // The plate (0.6 m, c = 32 m/s) pulled at its right face for 0.05 s, 2.6 transits of the wave:
  // the pull reaches the clamped left end. With the clamp, its reaction peaks at the order of the
  // pull (the ringing plate), and the particle nearest the clamped line, 1/4 cell in (its nodes
  // on the right are free), moves far less than the pulled end. The control without the clamp
  // (the plate flies off: its left end moves with its right) fails both.
  auto run = [&](bool clamped, double& left, double& right, double& peak) {
    ParameterList d = shapesDeck("test_output/bodies_box");
    d.sublist("Bodies").remove("disk");
    d.sublist("Bodies").remove("wedge");
    if (clamped)
      d.sublist("Constraints")
          .sublist("clamp")
          .set("Where", "Box")
          .set("X Min", -0.01)
          .set("X Max", 0.01)
          .set("Y Min", 0.0)
          .set("Y Max", 1.0)
          .set("Components", "xy");
    d.sublist("Loads")
        .sublist("pull")
        .set("Type", "Face Traction")
        .set("Body", "plate")
        .set("Face", "x+")
        .set("Force X", 1e3);
    d.sublist("Monitors").sublist("left").set("X", 0.0).set("Y", 0.2);
    d.sublist("Monitors").sublist("right").set("X", 0.6).set("Y", 0.2);
    d.sublist("Integrator").set("Time Step", 1e-4).set("Number of Steps", 500);
    impm::validateDeck(d);
    impm::Simulation sim(d, Tpetra::getDefaultComm());
    std::ostringstream log;
    const impm::RunResult r = sim.run(log);
    left = std::abs(r.computed.at("left").back());
    right = std::abs(r.computed.at("right").back());
    peak = 0;
    if (clamped)
      for (double f : r.reactions.at("clamp_reaction_x")) peak = std::max(peak, std::abs(f));
  };
  double left = 0, right = 0, peak = 0;
  run(true, left, right, peak);
  out << "clamped: left end " << left << " m, right end " << right << " m, clamp reaction peak " << peak << " N\n";
  TEST_COMPARE(right, >, 0.0);
  TEST_COMPARE(left, <, 0.3 * right);
  TEST_COMPARE(peak, >, 0.5e3);
  run(false, left, right, peak);
  out << "control, no clamp: left end " << left << " m, right end " << right << " m\n";
  TEST_COMPARE(left, >, 0.3 * right);
}

// Bad input: one DeckError naming the key.
TEUCHOS_UNIT_TEST(Bodies, BadInputNamesTheKey) {
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Bodies").sublist("disk").set("Material", "steel");
    const std::string msg = problemWith(d);
    TEST_ASSERT(mentions(msg, "Bodies/disk/Material") && mentions(msg, "steel"));
  }
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Bodies").sublist("wedge").set("Vertices", "0.1, 0.6; 0.9, 0.9; 0.9, 0.6; 0.1, 0.9");
    const std::string msg = problemWith(d);
    TEST_ASSERT(mentions(msg, "Bodies/wedge/Vertices") && mentions(msg, "cross"));
  }
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Bodies").sublist("wedge").set("Vertices", "");
    TEST_ASSERT(mentions(problemWith(d), "Bodies/wedge/Vertices"));
  }
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Bodies").sublist("disk").set("Center X", 1.9);
    const std::string msg = problemWith(d);
    TEST_ASSERT(mentions(msg, "Bodies/disk") && mentions(msg, "outside the grid"));
  }
  {
    // A particles file with a bad row: the message has the key and the line number.
    const std::string path = "test_output/bodies_bad_" + std::to_string(Tpetra::getDefaultComm()->getRank()) + ".csv";
    std::filesystem::create_directories("test_output");
    std::ofstream(path) << "x,y,volume\n0.1,0.1,0.001\n0.2,0.1\n";
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Bodies").sublist("cloud").set("Shape", "Particles File").set("Material", "soft").set("File", path);
    const std::string msg = problemWith(d);
    TEST_ASSERT(mentions(msg, "Bodies/cloud/File") && mentions(msg, "line 3"));
  }
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Body").set("X Max", 0.5);
    TEST_ASSERT(mentions(problemWith(d), "'Body' is the single-body form"));
  }
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Loads").sublist("g").set("Type", "Body Force").set("Body", "moon");
    TEST_ASSERT(mentions(problemWith(d), "Loads/g/Body"));
  }
  {
    ParameterList d = shapesDeck("test_output/bodies_bad");
    d.sublist("Constraints").sublist("side").set("Where", "Face").set("Body", "disk");
    TEST_ASSERT(mentions(problemWith(d), "Constraints/side") && mentions(problemWith(d), "Rectangle"));
  }
  TEST_ASSERT(!std::filesystem::exists("test_output/bodies_bad"));
}

// A Particles File body: the particles of the file, with their volumes, one body id.
TEUCHOS_UNIT_TEST(Bodies, ParticlesFileBody) {
  auto comm = Tpetra::getDefaultComm();
  const std::string path = "test_output/bodies_cloud_" + std::to_string(comm->getRank()) + ".csv";
  std::filesystem::create_directories("test_output");
  {
    std::ofstream f(path);
    f << "# x, y, volume\n";
    for (int k = 0; k < 40; ++k) f << 0.05 + 0.045 * k << "," << 0.75 + 0.001 * k << "," << 0.002 + 1e-5 * k << "\n";
  }
  ParameterList d = shapesDeck("test_output/bodies_file");
  d.sublist("Bodies").sublist("cloud").set("Shape", "Particles File").set("Material", "stiff").set("File", path);
  impm::validateDeck(d);
  impm::Simulation sim(d, comm);
  const HostParticles h = gather(sim.particles());
  double volume = 0, count = 0;
  for (size_t p = 0; p < h.id.size(); ++p)
    if (h.body[p] == 3) {
      volume += h.volume[p];
      count += 1;
    }
  double gv, gc;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, volume, Teuchos::outArg(gv));
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, count, Teuchos::outArg(gc));
  TEST_EQUALITY_CONST(gc, 40);
  TEST_FLOATING_EQUALITY(gv, 40 * 0.002 + 1e-5 * 780, 1e-12);
}

}  // namespace
