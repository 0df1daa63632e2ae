// impm_consumer DECK OUTPUT_DIR [STEPS]: runs an impm deck through impm's library, as a program
// of another project would: read and validate the deck, build the Simulation, run it (for STEPS
// steps if given, without the plot) and print how the run ended. Exit 0 when it completed.
#include <Tpetra_Core.hpp>

#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include "core/InputDeck.hpp"
#include "solvers/Simulation.hpp"
#include "solvers/build/Deck.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: impm_consumer DECK OUTPUT_DIR [STEPS]\n";
    return 2;
  }
  const std::string deckPath = argv[1], outputDir = argv[2];
  const int steps = argc > 3 ? std::atoi(argv[3]) : 0;

  Tpetra::ScopeGuard scope(&argc, &argv);  // MPI and Kokkos
  auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;
  try {
    auto deck = impm::readDeck(deckPath);
    if (steps > 0) deck->sublist("Integrator").set("Number of Steps", steps);
    deck->sublist("Output").set("Plot", false);
    impm::validateDeck(*deck);
    impm::Simulation sim(*deck, comm, outputDir);
    const impm::RunResult r = sim.run(std::cout);
    if (root)
      std::cout << "impm_consumer: run " << r.status << " after " << r.steps << " steps, " << r.particles
                << " particles, output in " << sim.outputDirectory() << "\n";
    return r.status == "completed" ? 0 : 1;
  } catch (const std::exception& e) {
    if (root) std::cerr << "impm_consumer: error: " << e.what() << "\n";
    return 1;
  }
}
