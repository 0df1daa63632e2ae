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
//   --help              usage and every valid parameter with its documentation
//   --print-defaults    every valid parameter with its default, as YAML
#include <Tpetra_Core.hpp>

#include <cstring>
#include <iostream>
#include <string>

#include "core/InputDeck.hpp"
#include "solvers/NewtonSolver.hpp"
#include "solvers/Simulation.hpp"

namespace {
void usage(std::ostream& os) {
  os << "usage: impm DECK.{yaml,xml} [--output DIR]\n"
        "       impm --help | --print-defaults\n";
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
  Tpetra::ScopeGuard scope(&argc, &argv);
  auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;

  std::string deckPath, outputDir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--output") {
      if (i + 1 >= argc) { if (root) std::cerr << "impm: error: --output needs a directory\n"; return 2; }
      outputDir = argv[++i];
    } else if (a.rfind("--", 0) == 0) {
      if (root) { std::cerr << "impm: error: unknown option '" << a << "'\n"; usage(std::cerr); }
      return 2;
    } else if (deckPath.empty()) {
      deckPath = a;
    } else {
      if (root) { std::cerr << "impm: error: more than one deck given ('" << deckPath << "', '" << a << "')\n"; }
      return 2;
    }
  }
  if (deckPath.empty()) { if (root) usage(std::cerr); return 2; }

  try {
    auto deck = impm::readDeck(deckPath);
    impm::validateDeck(*deck);
    impm::Simulation sim(*deck, comm, outputDir);
    sim.run(std::cout);
  } catch (const impm::DeckError& e) {
    if (root) std::cerr << "impm: error in deck '" << deckPath << "': " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    if (root) std::cerr << "impm: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
