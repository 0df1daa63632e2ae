// impm_bench_implicit: solver figures of the implicit step on the seed's beam (Problem 2:
// 40 x 4 cells, 16 particles per cell, dt = 1e-3), MPM and GIMP.
//
// For each preconditioner (and for assembled Newton with a direct solve) it runs the beam deck
// and prints the mean Newton iterations per step, the mean GMRES iterations per Newton
// iteration, and the wall time, with the whole-run time projected to the deck's 1000 steps.
// Slow configurations (no preconditioner, Jacobi, Chebyshev) run fewer steps.
// Targets (issue 3): <= 2 Newton iterations and <= 10 Krylov iterations per Newton iteration
// on average, the whole 1000-step run within 2 s on 2 threads.
//
// Sample run:   OMP_NUM_THREADS=2 build/apps/impm_bench_implicit [--steps N]
#include <Tpetra_Core.hpp>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include "core/InputDeck.hpp"
#include "solvers/Simulation.hpp"

#ifndef IMPM_SOURCE_DIR
#define IMPM_SOURCE_DIR "."
#endif

int main(int argc, char** argv) {
  Tpetra::ScopeGuard scope(&argc, &argv);
  auto comm = Tpetra::getDefaultComm();
  int fullSteps = 1000;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) fullSteps = std::atoi(argv[i + 1]);

  struct Config { const char* label; const char* jacobian; const char* prec; int fill; double linTol; int steps; };
  const Config configs[] = {
      {"JFNK + RILUK(4) [deck]", "Jacobian-Free", "RILUK", 4, 1e-8, fullSteps},
      {"JFNK + RILUK(0)", "Jacobian-Free", "RILUK", 0, 1e-8, fullSteps / 4},
      {"JFNK + ILUT", "Jacobian-Free", "ILUT", 0, 1e-8, fullSteps / 4},
      {"JFNK + Jacobi", "Jacobian-Free", "RELAXATION", 0, 1e-8, fullSteps / 20},
      {"JFNK + Chebyshev", "Jacobian-Free", "CHEBYSHEV", 0, 1e-8, fullSteps / 20},
      {"JFNK, no preconditioner", "Jacobian-Free", "None", 0, 1e-8, fullSteps / 20},
      {"assembled Newton, KLU2", "Assembled", "None", 0, 1e-8, fullSteps},
  };
  if (comm->getRank() == 0)
    std::printf("impm implicit benchmark: seed beam (40 x 4 cells, 16 ppc, dt = 1e-3), %d thread(s), %d rank(s)\n"
                "%-8s %-26s %6s %8s %10s %9s %10s %12s\n",
                (int)impm::ExecutionSpace::concurrency(), comm->getSize(), "method", "solver", "steps",
                "Newton", "Krylov/N", "wall s", "ms/step", "1000 steps s");
  for (const char* method : {"mpm", "gimp"}) {
    for (const Config& c : configs) {
      auto deck = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/beam_implicit_" + method + "_plane_strain.yaml");
      deck->sublist("Integrator").set("Number of Steps", std::max(1, c.steps));
      auto& solver = deck->sublist("Implicit Solver");
      solver.set("Jacobian", std::string(c.jacobian));
      solver.set("Preconditioner", std::string(c.prec));
      solver.set("Linear Tolerance", c.linTol);
      solver.remove("Ifpack2", false);
      if (std::string(c.prec) == "RILUK") solver.sublist("Ifpack2").set("fact: iluk level-of-fill", c.fill);
      deck->sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
      impm::validateDeck(*deck);
      impm::Simulation sim(*deck, comm, std::string("output/bench_implicit/") + method);
      std::ostringstream log;
      const impm::RunResult r = sim.run(log);
      auto summary = Teuchos::getParametersFromYamlFile(std::string("output/bench_implicit/") + method + "/summary.yaml");
      const auto& s = summary->sublist("Solver");
      if (comm->getRank() == 0)
        std::printf("%-8s %-26s %6d %8.2f %10.2f %9.2f %10.2f %12.1f\n", method, c.label, r.steps,
                    s.get<double>("Newton Iterations Mean"), s.get<double>("Krylov Iterations Per Newton Mean"),
                    r.wallSeconds, 1e3 * r.wallSeconds / r.steps, r.wallSeconds / r.steps * 1000);
      std::fflush(stdout);
    }
  }
  return 0;
}
