// RankGrid: the Cartesian grid of MPI ranks (which factorisation, which cells a rank owns, who
// its neighbours are) and balancedCuts (the tensor split of the load balancer). No MPI: these are
// the pure rules every rank evaluates alike.
#include <Teuchos_UnitTestHarness.hpp>

#include <algorithm>
#include <numeric>
#include <set>

#include "core/InputDeck.hpp"
#include "core/RankGrid.hpp"

namespace {

using impm::RankGrid;
using impm::StructuredGrid;

StructuredGrid grid2d(int nx, int ny) {
  StructuredGrid g;
  g.nx = nx; g.ny = ny;
  return g;
}
StructuredGrid grid3d(int nx, int ny, int nz) {
  StructuredGrid g;
  g.nx = nx; g.ny = ny; g.nz = nz; g.dim = 3;
  return g;
}

// The factorisation with the fewest nodes on the cuts: slabs across a long grid, a 2 x 2 block
// on a square one, and the 3D analogue.
TEUCHOS_UNIT_TEST(RankGrid, ChoosesTheSmallestInterface) {
  const RankGrid bar(grid2d(100, 10), 4);
  TEST_EQUALITY(bar.dims(0), 4); TEST_EQUALITY(bar.dims(1), 1); TEST_EQUALITY(bar.dims(2), 1);
  const RankGrid square(grid2d(20, 20), 4);
  TEST_EQUALITY(square.dims(0), 2); TEST_EQUALITY(square.dims(1), 2);
  const RankGrid tall(grid2d(10, 100), 2);
  TEST_EQUALITY(tall.dims(0), 1); TEST_EQUALITY(tall.dims(1), 2);
  const RankGrid cube(grid3d(8, 8, 8), 8);
  TEST_EQUALITY(cube.dims(0), 2); TEST_EQUALITY(cube.dims(1), 2); TEST_EQUALITY(cube.dims(2), 2);
  const RankGrid primes(grid2d(20, 20), 3);  // a prime count on a square grid: slabs, x first on ties
  TEST_EQUALITY(primes.dims(0), 3); TEST_EQUALITY(primes.dims(1), 1);
  // Requested counts are kept; the free direction takes the rest.
  const RankGrid asked(grid2d(100, 10), 4, {0, 2, 0});
  TEST_EQUALITY(asked.dims(0), 2); TEST_EQUALITY(asked.dims(1), 2);
}

// Every cell has exactly one owner, whose box holds it; boxes cover the grid.
TEUCHOS_UNIT_TEST(RankGrid, OwnersAndBoxesAgree) {
  for (int np : {1, 2, 3, 4, 6, 8}) {
    const StructuredGrid g = grid3d(9, 7, 5);
    const RankGrid rg(g, np, {0, 0, 0}, 1);
    TEST_EQUALITY(rg.dims(0) * rg.dims(1) * rg.dims(2), np);
    std::vector<int> owned(np, 0);
    for (int i = 0; i < g.nx; ++i)
      for (int j = 0; j < g.ny; ++j)
        for (int k = 0; k < g.nz; ++k) {
          const int r = rg.ownerOfCell(i, j, k);
          int lo[3], hi[3];
          rg.cellBox(r, lo, hi);
          TEST_ASSERT(i >= lo[0] && i < hi[0] && j >= lo[1] && j < hi[1] && k >= lo[2] && k < hi[2]);
          ++owned[r];
        }
    TEST_EQUALITY(std::accumulate(owned.begin(), owned.end(), 0), g.nx * g.ny * g.nz);
    for (int r = 0; r < np; ++r) TEST_COMPARE(owned[r], >, 0);
  }
}

// Neighbours: the 8 (2D) or 26 (3D) surrounding blocks inside the rank grid; symmetric.
TEUCHOS_UNIT_TEST(RankGrid, NeighboursAreSymmetric) {
  const RankGrid rg2(grid2d(30, 30), 9);  // 3 x 3
  TEST_EQUALITY(rg2.dims(0), 3); TEST_EQUALITY(rg2.dims(1), 3);
  TEST_EQUALITY(rg2.neighbours(4).size(), 8u);  // the centre
  TEST_EQUALITY(rg2.neighbours(0).size(), 3u);  // a corner
  const RankGrid rg3(grid3d(9, 9, 9), 27);
  TEST_EQUALITY(rg3.neighbours(13).size(), 26u);
  for (const RankGrid* rg : {&rg2, &rg3})
    for (int r = 0; r < rg->ranks(); ++r)
      for (int n : rg->neighbours(r)) {
        const auto back = rg->neighbours(n);
        TEST_ASSERT(std::find(back.begin(), back.end(), r) != back.end());
        TEST_INEQUALITY(n, r);
      }
}

// More ranks than the grid can give cells to: a DeckError naming the grid keys; a requested
// rank grid that does not multiply to the rank count names its keys.
TEUCHOS_UNIT_TEST(RankGrid, TooManyRanksIsADeckError) {
  TEST_THROW(RankGrid(grid2d(2, 1), 3), impm::DeckError);
  try {
    RankGrid(grid2d(2, 1), 3);
  } catch (const impm::DeckError& e) {
    TEST_ASSERT(std::string(e.what()).find("'Grid/Cells X' = 2") != std::string::npos);
    TEST_ASSERT(std::string(e.what()).find("3 MPI ranks") != std::string::npos);
  }
  // A slack of 1 needs 2 cells per rank along a split direction.
  TEST_THROW(RankGrid(grid2d(5, 1), 3, {0, 0, 0}, 2), impm::DeckError);
  TEST_NOTHROW(RankGrid(grid2d(6, 1), 3, {0, 0, 0}, 2));
  try {
    RankGrid(grid2d(20, 20), 4, {3, 1, 0});
    TEST_ASSERT(false);
  } catch (const impm::DeckError& e) {
    TEST_ASSERT(std::string(e.what()).find("'Decomposition/Ranks X'") != std::string::npos);
  }
}

// The tensor split: uniform weights give equal parts; a heavy cell gets a part of its own
// (within the minimum width); the current cuts stay when they are already optimal.
TEUCHOS_UNIT_TEST(RankGrid, BalancedCuts) {
  const std::vector<double> uniform(12, 1.0);
  const std::vector<int> even = impm::balancedCuts(uniform, 3, 1);
  TEST_EQUALITY(even.size(), 4u);
  TEST_EQUALITY(even[1], 4); TEST_EQUALITY(even[2], 8); TEST_EQUALITY(even[3], 12);

  std::vector<double> heavy(12, 1.0);
  heavy[9] = 100.0;
  const std::vector<int> c = impm::balancedCuts(heavy, 3, 2);
  // The part holding cell 9 is exactly 2 cells wide (the minimum): nothing lighter is possible.
  int partOf9 = 0;
  while (!(c[partOf9] <= 9 && 9 < c[partOf9 + 1])) ++partOf9;
  TEST_EQUALITY(c[partOf9 + 1] - c[partOf9], 2);
  for (size_t r = 0; r + 1 < c.size(); ++r) TEST_COMPARE(c[r + 1] - c[r], >=, 2);

  // Particles in the left half only: the right parts grow, the left shrink.
  std::vector<double> left(20, 0.0);
  for (int i = 0; i < 10; ++i) left[i] = 10.0;
  const std::vector<int> l = impm::balancedCuts(left, 2, 1);
  TEST_EQUALITY(l[1], 5);
  // Optimal current cuts are kept (no churn on equal loads): empty cells may go either way.
  const std::vector<double> ends = {1, 0, 0, 1};
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1)[1], 3);             // greedy: as far as it may
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1, {0, 1, 4})[1], 1);  // just as good: kept
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1, {0, 4, 4}).size(), 3u);  // invalid current: ignored
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1, {0, 4, 4})[1], 3);

  RankGrid rg(grid2d(20, 4), 2);
  rg.setCuts(0, l);
  TEST_EQUALITY(rg.ownerOfCell(4, 0), 0);
  TEST_EQUALITY(rg.ownerOfCell(5, 0), 1);
  TEST_THROW(rg.setCuts(0, {0, 0, 20}), std::invalid_argument);
}

}  // namespace
