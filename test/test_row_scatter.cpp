// The P2G's per-thread copies are zeroed and summed by node rows (RowScatterView) rather than by
// Kokkos' flat loops. The sum must be Kokkos::Experimental::contribute's bit for bit (destination
// plus copy 0 plus copy 1 ...), and a reset must clear every copy. Each thread adds inexact values
// to nodes all over the grid, of sizes chosen so that the order of the additions shows in the last
// bits (summing copy 1 before copy 0 changes about a quarter of the sums at 2 threads). With one
// thread there is one copy and nothing to order, so this test runs at two threads whatever the CI
// pass (test/CMakeLists.txt: THREADS 2) and requires them.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include "core/kernels/ParticleToGrid.hpp"

namespace {

using namespace impm;

TEUCHOS_UNIT_TEST(RowScatter, SumsLikeKokkosContribute) {
  out << "threads: " << ExecutionSpace::concurrency() << "\n";
  TEST_COMPARE(ExecutionSpace::concurrency(), >=, 2);
  using GridView = Kokkos::View<double**, Kokkos::LayoutLeft, DeviceType>;
  const int nodes = 3001, columns = 7, hits = 100000;
  GridView ours("ours", nodes, columns), kokkos("kokkos", nodes, columns);
  Kokkos::parallel_for(
      "start_values", Kokkos::RangePolicy<ExecutionSpace>(0, nodes), KOKKOS_LAMBDA(int n) {
        for (int c = 0; c < columns; ++c) ours(n, c) = kokkos(n, c) = 1e-5 * (n + c + 0.3);
      });
  RowScatterView<GridView> rows(ours);
  auto flat = Kokkos::Experimental::create_scatter_view(kokkos);
  for (int round = 0; round < 2; ++round) {  // the second round checks the reset
    if (round > 0) {
      rows.resetRows();
      flat.reset();
    }
    Kokkos::parallel_for(
        "scatter_hits", scatterPolicy<ExecutionSpace>(hits), KOKKOS_LAMBDA(int k) {
          auto a = rows.access();
          auto b = flat.access();
          const int n = int((long(k) * 7919) % nodes), c = k % columns;
          const double value = 1.0 / (1.0 + k % 1013);
          a(n, c) += value;
          b(n, c) += value;
        });
    rows.contributeRows(ours);
    Kokkos::Experimental::contribute(kokkos, flat);
    Kokkos::fence();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ours);
    auto y = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), kokkos);
    int differ = 0;
    for (int n = 0; n < nodes; ++n)
      for (int c = 0; c < columns; ++c) differ += x(n, c) != y(n, c);
    out << "round " << round << ": " << differ
        << " sums differ from Kokkos' (threads: " << ExecutionSpace::concurrency() << ")\n";
    TEST_EQUALITY(differ, 0);
  }
}

}  // namespace
