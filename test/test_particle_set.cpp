// The particle container is ready for migration: pack a subset of particles into rows, unpack
// them into another set, and every field (positions, kinematics, mass and volumes, stress, F,
// body, material and global id) arrives bit for bit; resize keeps the leading particles.
#include <Teuchos_UnitTestHarness.hpp>
#include <Teuchos_DefaultSerialComm.hpp>
#include <Tpetra_Core.hpp>

#include "physics/Body.hpp"

namespace {

using namespace impm;

TEUCHOS_UNIT_TEST(ParticleSet, PackUnpackRoundTrip) {
  StructuredGrid g;
  g.nx = 6; g.ny = 3; g.hx = 0.5; g.hy = 0.5;
  GridDistribution dist(g, Teuchos::rcp(new Teuchos::SerialComm<int>()));
  ParticleSet ps = createParticles(RectangularBody{0.5, 2.5, 0.0, 1.5, 2, 2, 0.1}, Materials{1e6, 0.25, 1000.0}, dist);
  // Give every field a distinct value.
  auto psv = ps;
  Kokkos::parallel_for(
      "fill", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        for (int d = 0; d < 2; ++d) { psv.v(p, d) = 0.1 * p + d; psv.a(p, d) = -0.3 * p - d; }
        for (int i = 0; i < 4; ++i) psv.stress(p, i) = 1e3 * p + i;
        psv.F(p, 0, 1) = 1e-3 * p;
        psv.body(p) = p % 3; psv.material(p) = p % 2; psv.id(p) = 1000000000000LL + p;
      });
  // Every other particle, packed and appended to an empty set.
  const int n = ps.count / 2;
  ParticleSet::Ids picked("picked", n);
  Kokkos::parallel_for("pick", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int k) { picked(k) = 2 * k + 1; });
  ParticleSet::Packed buffer("buffer", n, ps.packedWidth());
  ps.pack(picked, buffer);
  ParticleSet other(0);
  other.unpackAppend(buffer);
  TEST_EQUALITY(other.count, n);
  auto src = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), buffer);
  ParticleSet::Packed again("again", n, ps.packedWidth());
  ParticleSet::Ids all("all", n);
  Kokkos::parallel_for("iota", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int k) { all(k) = k; });
  other.pack(all, again);
  auto dst = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), again);
  int differ = 0;
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < ps.packedWidth(); ++c) differ += src(k, c) != dst(k, c);
  TEST_EQUALITY_CONST(differ, 0);
  // Spot checks against the original particle 2k+1.
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), other.id);
  auto s = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), other.stress);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), other.material);
  TEST_EQUALITY(id(n - 1), 1000000000000LL + 2 * (n - 1) + 1);
  TEST_EQUALITY(s(n - 1, 3), 1e3 * (2 * (n - 1) + 1) + 3);
  TEST_EQUALITY(m(0), 1);
  // resize keeps the leading particles.
  other.resize(n + 5);
  auto id2 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), other.id);
  TEST_EQUALITY(other.count, n + 5);
  TEST_EQUALITY(id2(n - 1), id(n - 1));
}

// A set with history (J2 plasticity): the history travels with its particle, also into a set
// that was empty when it allocated its history (a rank without particles receiving some).
TEUCHOS_UNIT_TEST(ParticleSet, HistoryTravelsWithItsParticle) {
  StructuredGrid g;
  g.nx = 6; g.ny = 3; g.hx = 0.5; g.hy = 0.5;
  GridDistribution dist(g, Teuchos::rcp(new Teuchos::SerialComm<int>()));
  ParticleSet ps = createParticles(RectangularBody{0.5, 2.5, 0.0, 1.5, 2, 2, 0.1}, Materials{1e6, 0.25, 1000.0}, dist);
  ps.allocateHistory();
  auto h = ps.history;
  Kokkos::parallel_for("fill_history", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
    for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h(p, i) = 10.0 * p + i;
  });
  const int n = 3;
  ParticleSet::Ids picked("picked", n);
  Kokkos::parallel_for("pick", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int k) { picked(k) = 4 + k; });
  ParticleSet::Packed buffer("buffer", n, ps.packedWidth());
  ps.pack(picked, buffer);
  ParticleSet empty(0);
  empty.allocateHistory();
  TEST_EQUALITY(empty.packedWidth(), ps.packedWidth());
  empty.unpackAppend(buffer);
  auto hh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), empty.history);
  TEST_EQUALITY(empty.count, n);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < ParticleSet::kHistoryCount; ++i) TEST_EQUALITY(hh(k, i), 10.0 * (4 + k) + i);
}

}  // namespace
