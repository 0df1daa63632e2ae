// The particle-cell pairs tile each particle domain, and integrating the grid shape functions
// exactly over the overlap boxes reproduces the uGIMP weights and gradient weights: the pairs
// are what the implicit GIMP stiffness integrates over.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <map>
#include <random>

#include "core/ParticleCellPairs.hpp"
#include "core/ParticleStencil.hpp"
#include "physics/Body.hpp"

namespace {

using namespace impm;

TEUCHOS_UNIT_TEST(ParticleCellPairs, OverlapIntegralsGiveGimpWeights) {
  auto comm = Tpetra::getDefaultComm();
  StructuredGrid g;
  g.nx = 8;
  g.ny = 5;
  g.hx = 0.4;
  g.hy = 0.3;
  GridDistribution dist(g, comm);
  RectangularBody body{0.4, 2.8, 0.3, 1.2, 3, 2, 1.0};
  ParticleSet ps = createParticles(body, Materials{1.0, 0.2, 1.0}, dist);
  // Move particles by up to half their domain so that domains straddle cell lines.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.halfSize);
  for (int p = 0; p < ps.count; ++p) {
    x(p, 0) += jitter(rng) * hs(p, 0);
    x(p, 1) += jitter(rng) * hs(p, 1);
  }
  Kokkos::deep_copy(ps.x, x);

  const ParticleCellPairs pairs = buildParticleCellPairs<ExecutionSpace>(g, ps, false);
  auto P = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pairs.particle);
  auto C = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pairs.cell);
  auto B = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pairs.box);
  TEST_COMPARE(pairs.count, >, ps.count);  // some domains straddle cell lines

  // Per particle and node: weight, gradient x, gradient y from the overlap boxes.
  std::vector<std::map<std::pair<int, int>, std::array<double, 3>>> fromPairs(ps.count);
  std::vector<double> area(ps.count, 0.0);
  auto tent = [](double r, double h) { return std::max(0.0, 1.0 - std::abs(r) / h); };
  for (int k = 0; k < pairs.count; ++k) {
    const int p = P(k);
    const double a = B(k, 0), b = B(k, 1), c = B(k, 2), d = B(k, 3);
    TEST_COMPARE(b, >=, a);
    TEST_COMPARE(d, >=, c);
    area[p] += (b - a) * (d - c);
    const double V = 4 * hs(p, 0) * hs(p, 1);
    for (int di = 0; di < 2; ++di)
      for (int dj = 0; dj < 2; ++dj) {
        const int i = C(k, 0) + di, j = C(k, 1) + dj;
        const double xi = g.nodeX(i), yj = g.nodeY(j);
        // Within one cell a tent is linear: int N = length * N(midpoint), int N' = N(end) - N(start).
        const double Ix = (b - a) * tent(0.5 * (a + b) - xi, g.hx), Iy = (d - c) * tent(0.5 * (c + d) - yj, g.hy);
        const double Dx = tent(b - xi, g.hx) - tent(a - xi, g.hx), Dy = tent(d - yj, g.hy) - tent(c - yj, g.hy);
        auto& e = fromPairs[p][{i, j}];
        e[0] += Ix * Iy / V;
        e[1] += Dx * Iy / V;
        e[2] += Ix * Dy / V;
      }
  }
  for (int p = 0; p < ps.count; ++p) {
    TEST_FLOATING_EQUALITY(area[p], 4 * hs(p, 0) * hs(p, 1), 1e-12);
    const ParticleStencil<UniformGimp> st(g, x(p, 0), x(p, 1), hs(p, 0), hs(p, 1));
    for (int a = 0; a < st.count[0]; ++a)
      for (int b = 0; b < st.count[1]; ++b) {
        const auto it = fromPairs[p].find({st.first[0] + a, st.first[1] + b});
        const std::array<double, 3> e = it == fromPairs[p].end() ? std::array<double, 3>{0, 0, 0} : it->second;
        TEST_COMPARE(std::abs(e[0] - st.weight(a, b)), <, 1e-12);
        TEST_COMPARE(std::abs(e[1] - st.gradX(a, b)), <, 1e-10 / g.hx);
        TEST_COMPARE(std::abs(e[2] - st.gradY(a, b)), <, 1e-10 / g.hy);
      }
  }
}

TEUCHOS_UNIT_TEST(ParticleCellPairs, MpmHasOnePairPerParticle) {
  auto comm = Tpetra::getDefaultComm();
  StructuredGrid g;
  g.nx = 6;
  g.ny = 3;
  g.hx = 1.0;
  g.hy = 1.0;
  GridDistribution dist(g, comm);
  ParticleSet ps = createParticles(RectangularBody{1, 5, 0, 3, 2, 2, 1.0}, Materials{1.0, 0.2, 1.0}, dist);
  const ParticleCellPairs pairs = buildParticleCellPairs<ExecutionSpace>(g, ps, true);
  TEST_EQUALITY(pairs.count, ps.count);
}

}  // namespace
