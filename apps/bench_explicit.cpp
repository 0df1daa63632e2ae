// impm_bench_explicit: speed and memory of the explicit step (USL, FLIP) on a long bar.
//
// For linear MPM and for uGIMP it runs a 2D bar of 1000 x 5 cells with 5 x 5 particles per cell
// and a 3D bar of 40 x 5 x 5 cells with 5 x 5 x 5 (125,000 particles each) and prints
// particle-steps per second at 1 and 2 OpenMP threads, and bytes per particle (particle views,
// and the process's resident-memory growth).
// Then the MPM bars again with the finite-strain laws (neo-Hookean, J2 plasticity, Drucker-Prager,
// Mohr-Coulomb; plane strain in 2D, and 3D) against the linear one in the same run.
// Targets: >= 40 M particle-steps/s (MPM 2D) and >= 10 M (GIMP) on 2 threads, a 2-thread
// speed-up >= 1.8, <= 300 bytes per particle; neo-Hookean MPM at >= 60% of the linear throughput;
// the soil models at <= 1.3x the cost per particle-step of J2, F-bar at <= 1.2x the same run
// without it. The machine's noise
// is large (runs of one binary spread by 20-40% on a shared host): each case is timed --repeat
// times (default 3) after one warm-up, and the best, median and worst rates are printed; compare
// binaries by the best of several interleaved runs. The parent prints the 2-thread speed-up of
// each case from its children's best rates, and the parent measures the host's core-to-core
// latency before and after the runs (see coreToCoreRoundTripNs): the 2-thread rates depend on it.
//
// Sample run:   build/apps/impm_bench_explicit            (spawns itself once per thread count)
//               build/apps/impm_bench_explicit --case mpm2d --steps 400   (one case: mpm2d, gimp2d,
//                 mpm3d, gimp3d, neohookean2d, j2-2d, dp-2d, mc-2d, j2-3d, dp-3d, mc-3d, contact2d,
//                 apic-gimp2d, tpic-gimp2d, xpic-gimp2d, fbar-j2-2d, fbar-j2-3d)
//               build/apps/impm_bench_explicit --child --kokkos-threads=2 --steps 200
//               build/apps/impm_bench_explicit --case mpm2d --timers   (adds the time of each
//                 phase: p2g, grid update, g2p, ...; Teuchos::TimeMonitor, summed over the repeats)
//               build/apps/impm_bench_explicit --case mpm2d --repeat 5
#include <Tpetra_Core.hpp>

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <iterator>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "core/FloatingPoint.hpp"
#include "core/InputDeck.hpp"
#include "core/PhaseTimer.hpp"
#include "solvers/ExplicitStepper.hpp"
#include "physics/Body.hpp"

namespace {

long residentKiB() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

template <class Shape, int Dim>
void runCase(int steps, int repeats, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
             impm::MaterialModel model = impm::MaterialModel::LinearElastic, bool contact = false,
             impm::ParticleTransfer transfer = impm::ParticleTransfer::FlipPic, bool fbar = false) {
  using namespace impm;
  const long rss0 = residentKiB();
  StructuredGrid g;
  g.nx = 1000;
  g.ny = 5;
  g.hx = 1e-3;
  g.hy = 1e-3;
  RectangularBody body{0.0, 1.0, 0.0, 5e-3, 5, 5, 1e-3};
  if (Dim == 3) {  // 40 x 5 x 5 cells, 5 x 5 x 5 particles per cell: 125,000 particles too
    g.nx = 40;
    g.dim = 3;
    g.nz = 5;
    g.hz = 1e-3;
    body.xMax = 0.04;
    body.zMin = 0.0;
    body.zMax = 5e-3;
    body.particlesPerCellZ = 5;
  }
  GridDistribution dist(g, comm);
  const bool linear = model == MaterialModel::LinearElastic;
  // J2 and the soil models stay elastic under the bar's small traction: each pays its return
  // map's trial state (an eigen-decomposition and logs) on every particle and step.
  MaterialParameters parameters{200e9, 0.3, 7800.0, model, 250e6, 1e9};
  if (model == MaterialModel::DruckerPrager || model == MaterialModel::MohrCoulomb) {
    parameters.cohesion = 250e6;
    parameters.frictionAngle = 30.0;
    parameters.dilatancyAngle = 10.0;
  }
  Materials mat(std::vector<MaterialParameters>{parameters}, Dim == 3 ? PlaneCondition::Solid
                                                             : linear ? PlaneCondition::PlaneStress
                                                                      : PlaneCondition::PlaneStrain);
  ParticleSet ps = createParticles(body, mat, dist);
  if (mat.anyHistory()) ps.allocateHistory();
  // The contact case: the same particles as two bodies (the bar's halves), each its own grid
  // field, meeting frictionlessly at mid-length.
  ContactSpec fields;
  if (contact) {
    fields.bodies = {"left half", "right half"};
    fields.pairNames = {"halves"};
    fields.pairFriction = {0.0};
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
    auto id = Kokkos::create_mirror_view(ps.body);
    for (int p = 0; p < ps.count; ++p) id(p) = x(p, 0) > 0.5 * (body.xMin + body.xMax) ? 1 : 0;
    Kokkos::deep_copy(ps.body, id);
  }
  GridConditions bc({ConstraintSpec::onFace("left", body, "x-", true, false)}, dist, {}, fields);
  const LoadSpec load = LoadSpec::faceTraction("end", body, "x+", 1.0, 0.0);
  LoadSet loads({load}, dist, {-1}, 1);
  ExplicitOptions opt;
  opt.transfer = transfer;
  opt.fbar = fbar;
  ExplicitStepper<Shape, Dim> stepper(ps, dist, mat, bc, loads, opt);
  const double dt = 0.2 * g.hx / mat.pWaveSpeed(0);
  for (int n = 0; n < 5; ++n) stepper.step(n * dt, dt);  // warm-up (first-touch, allocations)
  Kokkos::fence();
  const long rss1 = residentKiB();
  Teuchos::TimeMonitor::zeroOutTimers();  // the phase table counts the timed steps only
  // Each repeat continues the same run (the bar keeps moving); a step's cost does not depend on
  // the time it is taken at.
  std::vector<double> seconds;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int n = 0; n < steps; ++n) stepper.step((5 + r * steps + n) * dt, dt);
    Kokkos::fence();
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(seconds.begin(), seconds.end());
  const auto rate = [&](double sec) { return double(ps.count) * steps / sec / 1e6; };
  std::printf(
      "%-5s %dD %-14s%s threads=%d particles=%d steps=%d time=%.3f s  %.2f M particle-steps/s "
      "(best of %d; median %.2f, worst %.2f)  view bytes/particle=%zu  RSS bytes/particle=%.0f\n",
      Shape::name, Dim, Materials::modelName(model).c_str(),
      contact                              ? " 2 fields"
      : fbar                               ? " F-bar"
      : transfer == ParticleTransfer::Apic ? " APIC"
      : transfer == ParticleTransfer::Tpic ? " TPIC"
      : transfer == ParticleTransfer::Xpic ? " XPIC(5)"
                                           : "",
      (int)ExecutionSpace::concurrency(), ps.count, steps, seconds.front(), rate(seconds.front()), repeats,
      rate(seconds[seconds.size() / 2]), rate(seconds.back()), ParticleSet::bytesPerParticle(Dim),
      1024.0 * (rss1 - rss0) / ps.count);
  if (impm::PhaseTimer::enabled())
    Teuchos::TimeMonitor::summarize(comm.ptr(), std::cout, false, true, false, Teuchos::Union, "impm:");
  std::fflush(stdout);
}

// The round trip of a cache line between the first two CPUs this process may run on, in ns
// (best of 5 x 100,000 ping-pongs through one atomic), or -1 with fewer than two CPUs. On a
// shared host it tells the host's state apart: about 100 ns when the two vCPUs share a last-level
// cache, 400-500 ns when they sit on different core complexes, where every grid line one thread
// writes and the other reads costs a cross-complex transfer.
double coreToCoreRoundTripNs() {
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) return -1.0;
  int cpus[2], found = 0;
  for (int c = 0; c < CPU_SETSIZE && found < 2; ++c)
    if (CPU_ISSET(c, &allowed)) cpus[found++] = c;
  if (found < 2) return -1.0;
  const auto pin = [](int cpu) {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    pthread_setaffinity_np(pthread_self(), sizeof one, &one);
  };
  constexpr int kTrips = 100000;
  double best = 1e30;
  for (int round = 0; round < 5; ++round) {
    alignas(128) std::atomic<int> ball{0};
    std::thread partner([&] {
      pin(cpus[1]);
      for (int i = 0; i < kTrips; ++i) {
        while (ball.load(std::memory_order_acquire) != 2 * i + 1) {
        }
        ball.store(2 * i + 2, std::memory_order_release);
      }
    });
    pin(cpus[0]);
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kTrips; ++i) {
      ball.store(2 * i + 1, std::memory_order_release);
      while (ball.load(std::memory_order_acquire) != 2 * i + 2) {
      }
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    partner.join();
  }
  sched_setaffinity(0, sizeof allowed, &allowed);  // the children inherit the parent's mask
  return best / kTrips * 1e9;
}

void printHostState(const char* when) {
  const double ns = coreToCoreRoundTripNs();
  if (ns < 0) return;
  std::printf("host %s: core-to-core round trip %.0f ns (%s)\n", when, ns,
              ns < 250 ? "the two cores share a cache" : "the two cores do not share a cache");
  std::fflush(stdout);
}

void printUsage() {
  std::printf(
      "usage: impm_bench_explicit [--case "
      "mpm2d|gimp2d|mpm3d|gimp3d|neohookean2d|j2-2d|dp-2d|mc-2d|j2-3d|dp-3d|mc-3d|contact2d|apic-gimp2d|tpic-gimp2d|"
      "xpic-gimp2d|fbar-j2-2d|fbar-j2-3d|cpgimp2d|bspline2d|bspline3-2d|cpdi2d] [--steps N] "
      "[--repeat N] [--timers]\n"
      "  runs each case at 1 and 2 OpenMP threads (one child process per thread count) and prints\n"
      "  M particle-steps/s (best, median and worst of N timed repeats, default 3) and bytes per\n"
      "  particle, then each case's 2-thread speed-up; --timers adds the time of each phase.\n");
}

}  // namespace

int main(int argc, char** argv) {
  bool child = false, timers = false;
  int steps = 200, repeats = 3;
  std::string only;
  const char* cases[] = {"mpm2d",       "gimp2d",      "mpm3d",       "gimp3d",     "neohookean2d", "j2-2d",
                         "dp-2d",       "mc-2d",       "j2-3d",       "dp-3d",      "mc-3d",        "contact2d",
                         "apic-gimp2d", "tpic-gimp2d", "xpic-gimp2d", "fbar-j2-2d", "fbar-j2-3d",   "cpgimp2d",
                         "bspline2d",   "bspline3-2d", "cpdi2d"};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--child")) child = true;
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--case") && i + 1 < argc) only = argv[i + 1];
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeats = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--timers")) timers = true;
    if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      printUsage();
      return 0;
    }
  }
  if (steps < 1) {
    std::fprintf(stderr, "impm_bench_explicit: --steps must be a positive integer\n");
    return 2;
  }
  if (repeats < 1) {
    std::fprintf(stderr, "impm_bench_explicit: --repeat must be a positive integer\n");
    return 2;
  }
  if (!only.empty() && std::find(std::begin(cases), std::end(cases), only) == std::end(cases)) {
    std::fprintf(
        stderr,
        "impm_bench_explicit: unknown --case '%s' (mpm2d, gimp2d, mpm3d, gimp3d, neohookean2d, j2-2d, dp-2d, mc-2d, "
        "j2-3d, dp-3d, mc-3d, contact2d, apic-gimp2d, tpic-gimp2d, xpic-gimp2d, fbar-j2-2d, fbar-j2-3d, cpgimp2d, "
        "bspline2d, bspline3-2d, cpdi2d)\n",
        only.c_str());
    return 2;
  }
  if (!child) {
    // One process per thread count: Kokkos fixes its thread count at initialisation.
    std::printf(
        "impm explicit-step benchmark (USL, FLIP; 2D: bar of 1000 x 5 cells, 5 x 5 particles per cell; "
        "3D: 40 x 5 x 5 cells, 5 x 5 x 5 per cell; 125,000 particles each)\n");
    std::fflush(stdout);
    printHostState("before");
    // The children run as MPI singletons; ess_singleton_isolated keeps Open MPI from starting an
    // orted daemon beside each of them (it polled the PCI configuration on the timed cores).
    int status = 0;
    std::vector<std::string> order;             // case labels, in the order they ran
    std::map<std::string, double> bestRate[2];  // label -> best M particle-steps/s at 1, 2 threads
    for (int threads : {1, 2}) {
      const std::string cmd =
          "OMPI_MCA_ess_singleton_isolated=1 OMP_PROC_BIND=false OMP_NUM_THREADS=" + std::to_string(threads) + " '" +
          argv[0] + "' --child --steps " + std::to_string(steps) + " --repeat " + std::to_string(repeats) +
          (only.empty() ? "" : " --case " + only) + (timers ? " --timers" : "") +
          " --kokkos-threads=" + std::to_string(threads);
      FILE* child = popen(cmd.c_str(), "r");
      if (!child) {
        std::fprintf(stderr, "impm_bench_explicit: could not start '%s'\n", cmd.c_str());
        return 1;
      }
      char line[4096];
      while (std::fgets(line, sizeof line, child)) {
        std::fputs(line, stdout);
        std::fflush(stdout);
        const std::string text(line);
        const auto at = text.find(" threads="), rateEnd = text.find(" M particle-steps/s");
        if (at == std::string::npos || rateEnd == std::string::npos) continue;
        const std::string label = text.substr(0, at);
        const auto rateStart = text.rfind(' ', rateEnd - 1) + 1;
        bestRate[threads - 1][label] = std::atof(text.substr(rateStart, rateEnd - rateStart).c_str());
        if (threads == 1) order.push_back(label);
      }
      status |= pclose(child);
    }
    printHostState("after");
    for (const auto& label : order)
      if (bestRate[1].count(label) && bestRate[0][label] > 0.0)
        std::printf("speed-up  %s  2 threads / 1 thread = %.2f  (best rates %.2f / %.2f M particle-steps/s)\n",
                    label.c_str(), bestRate[1][label] / bestRate[0][label], bestRate[1][label], bestRate[0][label]);
    return status == 0 ? 0 : 1;
  }
  impm::flushSubnormalsToZero();
  impm::PhaseTimer::enabled() = timers;
  Tpetra::ScopeGuard scope(&argc, &argv);
  auto comm = Tpetra::getDefaultComm();
  const auto wanted = [&](const char* name) { return only.empty() || only == name; };
  if (wanted("mpm2d")) runCase<impm::LinearMpm, 2>(steps, repeats, comm);
  if (wanted("gimp2d")) runCase<impm::UniformGimp, 2>(steps, repeats, comm);
  if (wanted("mpm3d")) runCase<impm::LinearMpm, 3>(steps, repeats, comm);
  if (wanted("gimp3d")) runCase<impm::UniformGimp, 3>(steps, repeats, comm);
  if (wanted("neohookean2d")) runCase<impm::LinearMpm, 2>(steps, repeats, comm, impm::MaterialModel::NeoHookean);
  if (wanted("j2-2d")) runCase<impm::LinearMpm, 2>(steps, repeats, comm, impm::MaterialModel::J2Plasticity);
  if (wanted("dp-2d")) runCase<impm::LinearMpm, 2>(steps, repeats, comm, impm::MaterialModel::DruckerPrager);
  if (wanted("mc-2d")) runCase<impm::LinearMpm, 2>(steps, repeats, comm, impm::MaterialModel::MohrCoulomb);
  if (wanted("j2-3d")) runCase<impm::LinearMpm, 3>(steps, repeats, comm, impm::MaterialModel::J2Plasticity);
  if (wanted("dp-3d")) runCase<impm::LinearMpm, 3>(steps, repeats, comm, impm::MaterialModel::DruckerPrager);
  if (wanted("mc-3d")) runCase<impm::LinearMpm, 3>(steps, repeats, comm, impm::MaterialModel::MohrCoulomb);
  if (wanted("contact2d"))  // gimp2d's particles as two bodies with multi-field contact
    runCase<impm::UniformGimp, 2>(steps, repeats, comm, impm::MaterialModel::LinearElastic, true);
  if (wanted("apic-gimp2d"))  // gimp2d with the affine transfers
    runCase<impm::UniformGimp, 2>(steps, repeats, comm, impm::MaterialModel::LinearElastic, false,
                                  impm::ParticleTransfer::Apic);
  if (wanted("tpic-gimp2d"))
    runCase<impm::UniformGimp, 2>(steps, repeats, comm, impm::MaterialModel::LinearElastic, false,
                                  impm::ParticleTransfer::Tpic);
  if (wanted("xpic-gimp2d"))  // gimp2d with XPIC(5): four more passes over the particles
    runCase<impm::UniformGimp, 2>(steps, repeats, comm, impm::MaterialModel::LinearElastic, false,
                                  impm::ParticleTransfer::Xpic);
  // j2-2d and j2-3d with F-bar (a cell pass that averages det F, and the modified F per particle).
  if (wanted("fbar-j2-2d"))
    runCase<impm::LinearMpm, 2>(steps, repeats, comm, impm::MaterialModel::J2Plasticity, false,
                                impm::ParticleTransfer::FlipPic, true);
  if (wanted("fbar-j2-3d"))
    runCase<impm::LinearMpm, 3>(steps, repeats, comm, impm::MaterialModel::J2Plasticity, false,
                                impm::ParticleTransfer::FlipPic, true);
  // The other shapes on the 2D bar: cpGIMP (9 nodes), the quadratic and cubic B-splines (9 and 16
  // nodes) and CPDI (the corners' tents, up to 16 nodes).
  if (wanted("cpgimp2d")) runCase<impm::ConvectedGimp, 2>(steps, repeats, comm);
  if (wanted("bspline2d")) runCase<impm::QuadraticBSpline, 2>(steps, repeats, comm);
  if (wanted("bspline3-2d")) runCase<impm::CubicBSpline, 2>(steps, repeats, comm);
  if (wanted("cpdi2d")) runCase<impm::Cpdi, 2>(steps, repeats, comm);
  return 0;
}
