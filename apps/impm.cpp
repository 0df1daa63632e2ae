// impm: runs one input deck of the Material Point Method framework.
//
// It reads a deck (Teuchos ParameterList, XML or YAML), checks it against the full list of
// valid parameters (filling in defaults), builds the grid, particles and integrator, runs,
// and writes history.csv, summary.yaml, VTU/PVD files and, with an exact solution, plot.png.
//
// Sample runs (the seed's traveling-wave bar, explicit MPM; its beam, implicit GIMP):
//   build/apps/impm apps/bar_explicit_mpm_plane_stress.yaml --output out/bar
//   build/apps/impm apps/beam_implicit_gimp_plane_strain.yaml
//   OMP_NUM_THREADS=1 mpirun -np 2 build/apps/impm apps/bar_explicit_gimp_plane_strain.yaml
//
// Options:
//   --output DIR        override the deck's Problem/Output Directory
//   --restart DIR       continue from the checkpoint in DIR (Output/Checkpoint Interval writes
//                       OUTPUT/checkpoint); the deck must be the one that wrote it (except Output,
//                       Decomposition, Problem/Output Directory and Integrator/Number of Steps)
//   --timers            time the main phases (Teuchos::TimeMonitor): a table at the end of the
//                       run, and the totals in summary.yaml (Timers)
//   --help              usage and every valid parameter with its documentation
//   --print-defaults    every valid parameter with its default, as YAML
//
// Exit status: 0 completed; 2 the deck, the command line or a path they name is wrong (nothing
// written); 1 the run failed (diverged, Newton not converged, an output not written). Every MPI
// rank exits with the same status; rank 0 prints the one-line message.
#include <Tpetra_Core.hpp>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "core/PhaseTimer.hpp"
#include "solvers/newton/NewtonSolver.hpp"
#include "solvers/Simulation.hpp"
#include "core/FloatingPoint.hpp"

namespace {
// plot_history.py: $IMPM_PLOT_SCRIPT; else the installed one, found from this executable
// (<prefix>/bin/impm -> <prefix>/share/impm/plot_history.py); else the source tree's.
std::string plotScript() {
  if (const char* env = std::getenv("IMPM_PLOT_SCRIPT")) return env;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = (exe.parent_path() / IMPM_PLOT_SCRIPT_FROM_BIN).lexically_normal();
    if (std::filesystem::is_regular_file(installed, ec)) return installed.string();
  }
  return IMPM_PLOT_SCRIPT;
}

void usage(std::ostream& os) {
  os << "usage: impm DECK.{yaml,xml} [--output DIR] [--restart CHECKPOINT_DIR] [--timers]\n"
        "       impm --help | --print-defaults\n";
}

struct CommandLine {
  std::string deckPath, outputDir, restartDir;
  int exitCode = -1;  // >= 0: exit with it (a bad command line, reported on rank 0)
};

// The deck, --output, --restart and --timers; one message for anything else.
CommandLine parseCommandLine(int argc, char** argv, bool root) {
  CommandLine line;
  auto fail = [&](const std::string& message, bool withUsage) {
    if (root && !message.empty()) std::cerr << "impm: error: " << message << "\n";
    if (root && withUsage) usage(std::cerr);
    line.exitCode = 2;
    return line;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--timers") {
      impm::PhaseTimer::enabled() = true;
    } else if (a == "--output") {
      if (i + 1 >= argc) return fail("--output needs a directory", false);
      line.outputDir = argv[++i];
    } else if (a == "--restart") {
      if (i + 1 >= argc) return fail("--restart needs a checkpoint directory", false);
      line.restartDir = argv[++i];
    } else if (a.rfind("--", 0) == 0) {
      return fail("unknown option '" + a + "'", true);
    } else if (line.deckPath.empty()) {
      line.deckPath = a;
    } else {
      return fail("more than one deck given ('" + line.deckPath + "', '" + a + "')", false);
    }
  }
  if (line.deckPath.empty()) return fail("", true);
  return line;
}

// plot.png (rank 0): computed against exact for each monitor, and the energies when recorded.
void plotHistory(const Teuchos::ParameterList& deck, const impm::Simulation& sim) {
  const auto& out = deck.sublist("Output");
  if (!out.get<bool>("Plot") || !(sim.hasExact() || out.get<bool>("Energy And Momentum"))) return;
  const std::string title = deck.sublist("Problem").get<std::string>("Name");
  const std::string cmd =
      "/usr/bin/python3 '" + plotScript() + "' '" + sim.outputDirectory() + "' --title '" + title + "'";
  if (std::system(cmd.c_str()) != 0)
    std::cout << "  warning: the plot could not be written (" << cmd << ")\n";
  else
    std::cout << "  plot: " << sim.outputDirectory() << "/plot.png\n";
}
}  // namespace

int main(int argc, char** argv) {
  // --help and --print-defaults need neither MPI nor Kokkos (whose own --help would answer).
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage(std::cout);
      impm::printHelp(std::cout, {{"Implicit Solver", impm::NewtonSolver::validParameters()}});
      return 0;
    }
    if (a == "--print-defaults") {
      std::cout.setf(std::ios::showpoint);  // keeps doubles distinguishable from ints in the YAML
      impm::printDefaults(std::cout, {{"Implicit Solver", impm::NewtonSolver::validParameters()}});
      return 0;
    }
  }
  impm::flushSubnormalsToZero();  // before Kokkos starts its threads, which inherit it
  // Started without a launcher (mpiexec, or srun's PMI/PMIx), impm is an MPI singleton, beside
  // which Open MPI would start an orted daemon (about 0.13 s) unless told that the process stays
  // alone; impm spawns no processes.
  if (!std::getenv("OMPI_COMM_WORLD_SIZE") && !std::getenv("PMIX_RANK") && !std::getenv("PMI_RANK"))
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  Tpetra::ScopeGuard scope(&argc, &argv);
  auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;

  const CommandLine line = parseCommandLine(argc, argv, root);
  if (line.exitCode >= 0) return line.exitCode;
  const std::string& deckPath = line.deckPath;

  try {
    auto deck = impm::readDeck(deckPath);
    impm::validateDeck(*deck);
    impm::Simulation sim(*deck, comm, line.outputDir);
    if (!line.restartDir.empty()) sim.restartFrom(line.restartDir);
    sim.run(std::cout);
    if (impm::PhaseTimer::enabled()) {
      // Collective; the table is printed by rank 0. Only impm's phases (NOX, Belos keep their own).
      Teuchos::TimeMonitor::summarize(comm.ptr(), std::cout, false, true, false, Teuchos::Union, "impm:");
    }
    if (root) plotHistory(*deck, sim);
  } catch (const impm::DeckError& e) {
    // (A refused checkpoint names --restart itself: solvers/Checkpoint.hpp.)
    const std::string what = e.what();
    if (root && what.rfind("--restart ", 0) == 0)
      std::cerr << "impm: error: " << what << "\n";
    else if (root)
      std::cerr << "impm: error in deck '" << deckPath << "': " << what << "\n";
    return 2;
  } catch (const std::exception& e) {
    if (root) std::cerr << "impm: error: " << e.what() << "\n";
    return 1;
  } catch (...) {
    if (root) std::cerr << "impm: error: unknown exception\n";
    return 1;
  }
  return 0;
}
