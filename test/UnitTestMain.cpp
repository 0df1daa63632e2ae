// Main for impm's Teuchos unit tests: initialises MPI and Kokkos (through Tpetra), then runs
// every TEUCHOS_UNIT_TEST linked in. Each test's result is reduced over the ranks: only rank 0
// prints, and ctest reads its "End Result" line, so without the reduction a check that fails on
// rank 1 alone would pass the ctest entry.
#include <Teuchos_UnitTestRepository.hpp>
#include <Tpetra_Core.hpp>

#include "core/FloatingPoint.hpp"

int main(int argc, char* argv[]) {
  impm::flushSubnormalsToZero();  // before Kokkos starts its threads, which inherit it
  Tpetra::ScopeGuard scope(&argc, &argv);
  Teuchos::UnitTestRepository::setGloballyReduceTestResult(true);  // the default; the command line may override
  return Teuchos::UnitTestRepository::runUnitTestsFromMain(argc, argv);
}
