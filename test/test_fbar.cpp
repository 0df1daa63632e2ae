// F-bar's cell averaging (core/kernels/FbarAveraging.hpp) on hand-placed particles (2D, and one
// 3D cell), on one or two ranks. Each rank places the same pattern of particles in two cells on
// either side of the middle of the grid (where two ranks split it), with increments G that differ
// per particle, and two materials in one cell. After the correction:
//   - every particle of a (cell, material) has det(I + G_bar) equal to the volume-weighted mean of
//     det(I + G) over that (cell, material) on all ranks (computed here from the known pattern);
//   - I + G_bar is a positive multiple of I + G (the isochoric part is the particle's own);
//   - a uniform G is left as it is.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/kernels/FbarAveraging.hpp"
#include "core/kernels/StressUpdate.hpp"
#include "physics/Materials.hpp"

namespace {

using namespace impm;

struct Placed {
  double x, y, volume;
  int material;
  double G[2][2];
};

// The pattern every rank places: cells (1, 0) and (2, 0) of a 4 x 2 grid of unit cells; cell
// (1, 0) holds material 0 and 1 particles.
std::vector<Placed> pattern(int rank) {
  const double r = 0.01 * rank;  // ranks' particles differ, so that their sums matter
  return {
      {1.25, 0.25, 0.25, 0, {{0.010 + r, 0.002}, {0.000, -0.004}}},
      {1.75, 0.25, 0.20, 0, {{-0.020, 0.001}, {0.003, 0.015 + r}}},
      {1.25, 0.75, 0.30, 1, {{0.050, 0.000}, {0.000, 0.010}}},
      {1.75, 0.75, 0.25, 1, {{0.000, 0.020}, {-0.010, -0.030 - r}}},
      {2.25, 0.25, 0.25, 0, {{0.030, 0.000}, {0.000, 0.030}}},
      {2.75, 0.75, 0.25, 0, {{0.030 - r, 0.000}, {0.000, 0.030 + r}}},
  };
}

double det2(const double (&G)[2][2]) { return (1 + G[0][0]) * (1 + G[1][1]) - G[0][1] * G[1][0]; }

// Volume-weighted mean det(I + G) of the particles of `material` in the cell of x, over all ranks.
double expectedCellMean(int ranks, int cellX, int material) {
  double sumVJ = 0, sumV = 0;
  for (int rank = 0; rank < ranks; ++rank)
    for (const Placed& q : pattern(rank))
      if (int(q.x) == cellX && int(q.y) == 0 && q.material == material) {
        sumVJ += q.volume * det2(q.G);
        sumV += q.volume;
      }
  return sumVJ / sumV;
}

ParticleSet placeParticles(const std::vector<Placed>& placed) {
  ParticleSet ps(int(placed.size()), 2);
  auto x = Kokkos::create_mirror_view(ps.x);
  auto V = Kokkos::create_mirror_view(ps.volume);
  auto m = Kokkos::create_mirror_view(ps.material);
  auto L = Kokkos::create_mirror_view(ps.gradient);
  for (size_t p = 0; p < placed.size(); ++p) {
    x(p, 0) = placed[p].x;
    x(p, 1) = placed[p].y;
    V(p) = placed[p].volume;
    m(p) = placed[p].material;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) L(p, i, j) = placed[p].G[i][j];
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.volume, V);
  Kokkos::deep_copy(ps.material, m);
  Kokkos::deep_copy(ps.gradient, L);
  return ps;
}

// G_bar of every particle, on the host.
std::vector<std::array<double, 4>> correctedGradients(FbarAveraging<2>& fbar, const ParticleSet& ps) {
  const auto correct = fbar.correction(ps);
  Kokkos::View<double* [4]> out("out", ps.count);
  auto L = FixedParticleViews<2>(ps).gradient;
  Kokkos::parallel_for(
      "corrected", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        double G[2][2] = {{L(p, 0, 0), L(p, 0, 1)}, {L(p, 1, 0), L(p, 1, 1)}};
        correct(p, G);
        out(p, 0) = G[0][0];
        out(p, 1) = G[0][1];
        out(p, 2) = G[1][0];
        out(p, 3) = G[1][1];
      });
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  std::vector<std::array<double, 4>> result(ps.count);
  for (int p = 0; p < ps.count; ++p) result[p] = {h(p, 0), h(p, 1), h(p, 2), h(p, 3)};
  return result;
}

StructuredGrid fourByTwo() {
  StructuredGrid g;
  g.nx = 4;
  g.ny = 2;
  return g;
}

TEUCHOS_UNIT_TEST(Fbar, VolumeChangeIsTheCellsOnEveryRank) {
  auto comm = Tpetra::getDefaultComm();
  const int rank = comm->getRank(), ranks = comm->getSize();
  const GridDistribution dist(fourByTwo(), comm);
  const std::vector<Placed> placed = pattern(rank);
  ParticleSet ps = placeParticles(placed);
  FbarAveraging<2> fbar(dist, 2);
  fbar.accumulate<ExecutionSpace>(ps, 1.0);
  const auto bar = correctedGradients(fbar, ps);
  double worstJ = 0, worstShape = 0;
  for (size_t p = 0; p < placed.size(); ++p) {
    const Placed& q = placed[p];
    const double Gb[2][2] = {{bar[p][0], bar[p][1]}, {bar[p][2], bar[p][3]}};
    const double expected = expectedCellMean(ranks, int(q.x), q.material);
    worstJ = std::max(worstJ, std::abs(det2(Gb) - expected));
    // I + G_bar = s (I + G): the ratio is the same for every entry.
    const double s = (1 + Gb[0][0]) / (1 + q.G[0][0]);
    worstShape = std::max({worstShape, std::abs(Gb[0][1] - s * q.G[0][1]), std::abs(Gb[1][0] - s * q.G[1][0]),
                           std::abs(1 + Gb[1][1] - s * (1 + q.G[1][1]))});
  }
  // Cell (1, 0)'s two materials are averaged apart: their means differ by far more than round-off.
  out << "ranks " << ranks << ": worst |det(I + G_bar) - cell mean| " << worstJ << ", worst departure from s (I + G) "
      << worstShape << "\n";
  TEST_ASSERT(std::abs(expectedCellMean(ranks, 1, 0) - expectedCellMean(ranks, 1, 1)) > 1e-3);
  TEST_ASSERT(worstJ < 1e-14);
  TEST_ASSERT(worstShape < 1e-15);
}

TEUCHOS_UNIT_TEST(Fbar, UniformIncrementIsLeftAlone) {
  auto comm = Tpetra::getDefaultComm();
  const GridDistribution dist(fourByTwo(), comm);
  std::vector<Placed> placed = pattern(comm->getRank());
  for (Placed& q : placed) q = {q.x, q.y, q.volume, q.material, {{0.02, 0.01}, {-0.005, -0.03}}};
  ParticleSet ps = placeParticles(placed);
  FbarAveraging<2> fbar(dist, 2);
  fbar.accumulate<ExecutionSpace>(ps, 1.0);
  const auto bar = correctedGradients(fbar, ps);
  double worst = 0;
  for (size_t p = 0; p < placed.size(); ++p)
    for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(bar[p][c] - placed[p].G[c / 2][c % 2]));
  out << "worst change of a uniform G: " << worst << "\n";
  TEST_ASSERT(worst < 1e-15);
}

// updateStress with the correction: a cell's particles keep its total volume change exactly.
TEUCHOS_UNIT_TEST(Fbar, StressUpdateKeepsTheCellVolume) {
  auto comm = Tpetra::getDefaultComm();
  const GridDistribution dist(fourByTwo(), comm);
  std::vector<Placed> placed = pattern(0);
  for (Placed& q : placed) q.material = 0;
  ParticleSet ps = placeParticles(placed);
  Kokkos::deep_copy(ps.volume0, ps.volume);
  const Materials law;  // (linear elastic)
  FbarAveraging<2> fbar(dist, 1);
  fbar.accumulate<ExecutionSpace>(ps, 1.0);
  updateStress<ExecutionSpace, 2>(ps, law.law(), 1.0, true, DomainConvection(), fbar.correction(ps));
  auto V = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.volume);
  double before[4] = {}, after[4] = {};
  for (size_t p = 0; p < placed.size(); ++p) {
    before[int(placed[p].x)] += placed[p].volume * det2(placed[p].G);
    after[int(placed[p].x)] += V(p);
  }
  for (int c = 1; c <= 2; ++c) {
    out << "cell " << c << ": sum V det(I + G) " << before[c] << ", sum V after the update " << after[c] << "\n";
    TEST_FLOATING_EQUALITY(after[c], before[c], 1e-14);
  }
}

// 3D: eight particles in one cell of a 2 x 2 x 2 grid with different G: each ends with the
// cell's volume-weighted mean det(I + G) (the exponent is 1/3), a multiple of its own I + G.
TEUCHOS_UNIT_TEST(Fbar, VolumeChangeIsTheCellsIn3d) {
  auto comm = Tpetra::getDefaultComm();
  StructuredGrid g;
  g.dim = 3;
  g.nx = g.ny = g.nz = 2;
  const GridDistribution dist(g, comm);
  const int n = 8;
  ParticleSet ps(n, 3);
  auto x = Kokkos::create_mirror_view(ps.x);
  auto V = Kokkos::create_mirror_view(ps.volume);
  auto L = Kokkos::create_mirror_view(ps.gradient);
  double sumVJ = 0, sumV = 0;
  std::vector<std::array<double, 9>> G(n);
  for (int p = 0; p < n; ++p) {
    for (int d = 0; d < 3; ++d) x(p, d) = 0.25 + 0.5 * ((p >> d) & 1);
    V(p) = 0.1 + 0.01 * p;
    for (int c = 0; c < 9; ++c) G[p][c] = 0.01 * std::sin(1.0 + 3 * p + c) + (c % 4 == 0 ? 0.02 * p : 0.0);
    for (int c = 0; c < 9; ++c) L(p, c / 3, c % 3) = G[p][c];
    double F[3][3];
    for (int c = 0; c < 9; ++c) F[c / 3][c % 3] = G[p][c] + (c % 4 == 0 ? 1 : 0);
    sumVJ += V(p) * determinant<3>(F);
    sumV += V(p);
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.volume, V);
  Kokkos::deep_copy(ps.gradient, L);
  FbarAveraging<3> fbar(dist, 1);
  fbar.accumulate<ExecutionSpace>(ps, 1.0);
  fbar.correctGradients<ExecutionSpace>(ps);
  auto Lbar = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.gradient);
  // Every rank places the same eight particles: the mean over all ranks is this rank's.
  const double mean = sumVJ / sumV;
  double worstJ = 0, worstShape = 0;
  for (int p = 0; p < n; ++p) {
    double Fb[3][3];
    for (int c = 0; c < 9; ++c) Fb[c / 3][c % 3] = Lbar(p, c / 3, c % 3) + (c % 4 == 0 ? 1 : 0);
    worstJ = std::max(worstJ, std::abs(determinant<3>(Fb) - mean));
    const double s = Fb[0][0] / (1 + G[p][0]);
    for (int c = 0; c < 9; ++c)
      worstShape = std::max(worstShape, std::abs(Fb[c / 3][c % 3] - s * (G[p][c] + (c % 4 == 0 ? 1 : 0))));
  }
  out << "3D: worst |det(I + G_bar) - cell mean| " << worstJ << ", worst departure from s (I + G) " << worstShape
      << "\n";
  TEST_ASSERT(worstJ < 1e-14);
  TEST_ASSERT(worstShape < 1e-14);
}

}  // namespace
