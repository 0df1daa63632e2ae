// RankGrid: the Cartesian grid of MPI ranks (which factorisation, which cells a rank owns, who
// its neighbours are) and balancedCuts (the tensor split of the load balancer). No MPI: these are
// the pure rules every rank evaluates alike.
#include <Teuchos_UnitTestHarness.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include "core/InputDeck.hpp"
#include "core/RankGrid.hpp"

namespace {

using impm::RankGrid;
using impm::StructuredGrid;

StructuredGrid grid2d(int nx, int ny) {
  StructuredGrid g;
  g.nx = nx;
  g.ny = ny;
  return g;
}
StructuredGrid grid3d(int nx, int ny, int nz) {
  StructuredGrid g;
  g.nx = nx;
  g.ny = ny;
  g.nz = nz;
  g.dim = 3;
  return g;
}

// The factorisation with the fewest nodes on the cuts: slabs across a long grid, a 2 x 2 block
// on a square one, and the 3D analogue.
TEUCHOS_UNIT_TEST(RankGrid, ChoosesTheSmallestInterface) {
  const RankGrid bar(grid2d(100, 10), 4);
  TEST_EQUALITY(bar.dims(0), 4);
  TEST_EQUALITY(bar.dims(1), 1);
  TEST_EQUALITY(bar.dims(2), 1);
  const RankGrid square(grid2d(20, 20), 4);
  TEST_EQUALITY(square.dims(0), 2);
  TEST_EQUALITY(square.dims(1), 2);
  const RankGrid tall(grid2d(10, 100), 2);
  TEST_EQUALITY(tall.dims(0), 1);
  TEST_EQUALITY(tall.dims(1), 2);
  const RankGrid cube(grid3d(8, 8, 8), 8);
  TEST_EQUALITY(cube.dims(0), 2);
  TEST_EQUALITY(cube.dims(1), 2);
  TEST_EQUALITY(cube.dims(2), 2);
  const RankGrid primes(grid2d(20, 20), 3);  // a prime count on a square grid: slabs, x first on ties
  TEST_EQUALITY(primes.dims(0), 3);
  TEST_EQUALITY(primes.dims(1), 1);
  // Requested counts are kept; the free direction takes the rest.
  const RankGrid asked(grid2d(100, 10), 4, {0, 2, 0});
  TEST_EQUALITY(asked.dims(0), 2);
  TEST_EQUALITY(asked.dims(1), 2);
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
  TEST_EQUALITY(rg2.dims(0), 3);
  TEST_EQUALITY(rg2.dims(1), 3);
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
  TEST_EQUALITY(even[1], 4);
  TEST_EQUALITY(even[2], 8);
  TEST_EQUALITY(even[3], 12);

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
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1)[1], 3);                  // greedy: as far as it may
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1, {0, 1, 4})[1], 1);       // just as good: kept
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1, {0, 4, 4}).size(), 3u);  // invalid current: ignored
  TEST_EQUALITY(impm::balancedCuts(ends, 2, 1, {0, 4, 4})[1], 3);

  RankGrid rg(grid2d(20, 4), 2);
  rg.setCuts(0, l);
  TEST_EQUALITY(rg.ownerOfCell(4, 0), 0);
  TEST_EQUALITY(rg.ownerOfCell(5, 0), 1);
  TEST_THROW(rg.setCuts(0, {0, 0, 20}), std::invalid_argument);
}

// The load balancer's cuts are optimal: on random histograms (5 to 12 cells, 2 to 4 parts, parts
// at least 1 to 3 cells wide, some cells empty), the largest part's weight equals the smallest
// achievable, found by trying every valid set of cuts, to the bisection's 1e-9. A balancer that
// left 1.73 at 1.72 (any cut short of the optimum) fails. Every part is at least minCells wide.
double largestPartWeight(const std::vector<double>& w, const std::vector<int>& cuts) {
  double worst = 0;
  for (size_t r = 0; r + 1 < cuts.size(); ++r)
    worst = std::max(worst, std::accumulate(w.begin() + cuts[r], w.begin() + cuts[r + 1], 0.0));
  return worst;
}

// The smallest largest-part weight over every way to cut cells [from, n) into `parts` parts.
double bestLargestPart(const std::vector<double>& w, int from, int parts, int minCells) {
  const int n = (int)w.size();
  if (parts == 1) return std::accumulate(w.begin() + from, w.end(), 0.0);
  double best = INFINITY;
  for (int end = from + minCells; end <= n - (parts - 1) * minCells; ++end)
    best = std::min(best, std::max(std::accumulate(w.begin() + from, w.begin() + end, 0.0),
                                   bestLargestPart(w, end, parts - 1, minCells)));
  return best;
}

TEUCHOS_UNIT_TEST(RankGrid, BalancedCutsAreOptimal) {
  std::mt19937 random(12345);
  int checked = 0, worse = 0, invalid = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = 5 + (int)(random() % 8), parts = 2 + (int)(random() % 3), minCells = 1 + (int)(random() % 3);
    if (parts * minCells > n) continue;
    std::vector<double> w(n);
    for (double& x : w) x = (random() % 4 == 0) ? 0.0 : double(random() % 1000);
    const std::vector<int> cuts = impm::balancedCuts(w, parts, minCells);
    bool valid = (int)cuts.size() == parts + 1 && cuts.front() == 0 && cuts.back() == n;
    for (size_t r = 0; valid && r + 1 < cuts.size(); ++r) valid = cuts[r + 1] - cuts[r] >= minCells;
    invalid += !valid;
    if (!valid) continue;
    const double got = largestPartWeight(w, cuts), best = bestLargestPart(w, 0, parts, minCells);
    if (got > best * (1 + 1e-9) + 1e-12) {
      ++worse;
      out << "  parts " << parts << ", min " << minCells << ", weights";
      for (double x : w) out << " " << x;
      out << ": cuts";
      for (int c : cuts) out << " " << c;
      out << ", largest " << got << " against " << best << "\n";
    }
    ++checked;
  }
  out << checked << " random histograms, " << worse << " with a largest part above the optimum, " << invalid
      << " with invalid cuts\n";
  TEST_COMPARE(checked, >, 200);
  TEST_EQUALITY(worse, 0);
  TEST_EQUALITY(invalid, 0);
}

}  // namespace
