// Main for impm's Teuchos unit tests: initialises MPI and Kokkos (through Tpetra), then runs
// every TEUCHOS_UNIT_TEST linked in.
#include <Teuchos_UnitTestRepository.hpp>
#include <Tpetra_Core.hpp>

int main(int argc, char* argv[]) {
  Tpetra::ScopeGuard scope(&argc, &argv);
  return Teuchos::UnitTestRepository::runUnitTestsFromMain(argc, argv);
}
