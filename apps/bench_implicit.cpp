// impm_bench_implicit: solver figures of the implicit step on the seed's beam (Problem 2:
// 40 x 4 cells, 16 particles per cell, dt = 1e-3), MPM and GIMP.
//
// For each preconditioner (and for assembled Newton with a direct solve) it runs the beam deck
// and prints the mean Newton iterations per step, the mean GMRES iterations per Newton
// iteration, and the wall time, with the whole-run time projected to the deck's 1000 steps.
// Slow configurations (no preconditioner, Jacobi, Chebyshev) run fewer steps. The deck's own
// configuration runs three times and prints the median wall time (this machine's timings vary
// by 20-30% from run to run). For GIMP, "consistent K" assembles P from the averaged gradients
// (Integrator/Implicit/GIMP Stiffness: Consistent), the exact Jacobian of the GIMP residual,
// instead of the seed's integrated stiffness.
// Targets: <= 2 Newton iterations and <= 10 Krylov iterations per Newton iteration
// on average, the whole 1000-step run within 2 s on 2 threads.
//
// Sample run:   OMP_NUM_THREADS=2 build/apps/impm_bench_implicit [--steps N]
#include <Tpetra_Core.hpp>

#include <cstdio>
#include <algorithm>
#include <cstring>
#include <vector>
#include <iostream>
#include <sstream>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/Simulation.hpp"
#include "core/FloatingPoint.hpp"

#ifndef IMPM_SOURCE_DIR
#define IMPM_SOURCE_DIR "."
#endif

int main(int argc, char** argv) {
  impm::flushSubnormalsToZero();  // before Kokkos starts its threads, which inherit it
  Tpetra::ScopeGuard scope(&argc, &argv);
  auto comm = Tpetra::getDefaultComm();
  int fullSteps = 1000;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) fullSteps = std::atoi(argv[i + 1]);

  struct Config {
    const char* label;
    const char* jacobian;
    const char* prec;
    int fill;
    double linTol;
    int steps;
    bool gimpOnly = false;
    const char* gimpStiffness = nullptr;
    int repeats = 1;
  };
  const Config configs[] = {
      {"JFNK + RILUK(4) [deck]", "Jacobian-Free", "RILUK", 4, 1e-8, fullSteps, false, nullptr, 3},
      {"JFNK + RILUK(4), cons. K", "Jacobian-Free", "RILUK", 4, 1e-8, fullSteps, true, "Consistent", 3},
      {"JFNK + RILUK(0)", "Jacobian-Free", "RILUK", 0, 1e-8, fullSteps / 4},
      {"JFNK + ILUT", "Jacobian-Free", "ILUT", 0, 1e-8, fullSteps / 4},
      {"JFNK + Jacobi", "Jacobian-Free", "RELAXATION", 0, 1e-8, fullSteps / 20},
      {"JFNK + Chebyshev", "Jacobian-Free", "CHEBYSHEV", 0, 1e-8, fullSteps / 20},
      {"JFNK, no preconditioner", "Jacobian-Free", "None", 0, 1e-8, fullSteps / 20},
      {"assembled Newton, KLU2", "Assembled", "None", 0, 1e-8, fullSteps},
      {"assembled Newton, cons. K", "Assembled", "None", 0, 1e-8, fullSteps, true, "Consistent"},
  };
  if (comm->getRank() == 0)
    std::printf(
        "impm implicit benchmark: seed beam (40 x 4 cells, 16 ppc, dt = 1e-3), %d thread(s), %d rank(s)\n"
        "%-8s %-26s %6s %8s %10s %9s %10s %12s\n",
        (int)impm::ExecutionSpace::concurrency(), comm->getSize(), "method", "solver", "steps", "Newton", "Krylov/N",
        "wall s", "ms/step", "1000 steps s");
  for (const char* method : {"mpm", "gimp"}) {
    for (const Config& c : configs) {
      if (c.gimpOnly && std::string(method) != "gimp") continue;
      std::vector<double> walls;
      impm::RunResult r;
      double newton = 0, krylov = 0;
      for (int rep = 0; rep < c.repeats; ++rep) {
        auto deck =
            impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/beam_implicit_" + method + "_plane_strain.yaml");
        deck->sublist("Integrator").set("Number of Steps", std::max(1, c.steps));
        auto& solver = deck->sublist("Implicit Solver");
        solver.set("Jacobian", std::string(c.jacobian));
        solver.set("Preconditioner", std::string(c.prec));
        solver.set("Linear Tolerance", c.linTol);
        solver.remove("Ifpack2", false);
        if (std::string(c.prec) == "RILUK") solver.sublist("Ifpack2").set("fact: iluk level-of-fill", c.fill);
        if (c.gimpStiffness)
          deck->sublist("Integrator").sublist("Implicit").set("GIMP Stiffness", std::string(c.gimpStiffness));
        deck->sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
        impm::validateDeck(*deck);
        impm::Simulation sim(*deck, comm, std::string("output/bench_implicit/") + method);
        std::ostringstream log;
        r = sim.run(log);
        auto summary =
            Teuchos::getParametersFromYamlFile(std::string("output/bench_implicit/") + method + "/summary.yaml");
        const auto& s = summary->sublist("Solver");
        newton = s.get<double>("Newton Iterations Mean");
        krylov = s.get<double>("Krylov Iterations Per Newton Mean");
        walls.push_back(r.wallSeconds);
      }
      std::sort(walls.begin(), walls.end());
      const double wall = walls[walls.size() / 2];  // median
      if (comm->getRank() == 0)
        std::printf("%-8s %-26s %6d %8.2f %10.2f %9.2f %10.2f %12.2f%s\n", method, c.label, r.steps, newton, krylov,
                    wall, 1e3 * wall / r.steps, wall / r.steps * 1000, c.repeats > 1 ? "  (median of 3)" : "");
      std::fflush(stdout);
    }
  }
  return 0;
}
