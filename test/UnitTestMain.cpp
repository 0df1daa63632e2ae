// Main for impm's Teuchos unit tests: initialises MPI and Kokkos (through Tpetra), then runs
// every TEUCHOS_UNIT_TEST linked in.
#include <Teuchos_UnitTestRepository.hpp>
#include <Tpetra_Core.hpp>

#include "core/FloatingPoint.hpp"

int main(int argc, char* argv[]) {
  impm::flushSubnormalsToZero();  // before Kokkos starts its threads, which inherit it
  Tpetra::ScopeGuard scope(&argc, &argv);
  return Teuchos::UnitTestRepository::runUnitTestsFromMain(argc, argv);
}
