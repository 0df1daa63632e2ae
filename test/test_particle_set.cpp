// The particle container is ready for migration: pack a subset of particles into rows, unpack
// them into another set, and every field (positions, kinematics, mass and volumes, stress, F,
// body, material and global id) arrives bit for bit; resize keeps the leading particles.
#include <Teuchos_UnitTestHarness.hpp>
#include <Teuchos_DefaultSerialComm.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <vector>

#include "physics/Body.hpp"

namespace {

using namespace impm;

TEUCHOS_UNIT_TEST(ParticleSet, PackUnpackRoundTrip) {
  StructuredGrid g;
  g.nx = 6;
  g.ny = 3;
  g.hx = 0.5;
  g.hy = 0.5;
  GridDistribution dist(g, Teuchos::rcp(new Teuchos::SerialComm<int>()));
  ParticleSet ps = createParticles(RectangularBody{0.5, 2.5, 0.0, 1.5, 2, 2, 0.1}, Materials{1e6, 0.25, 1000.0}, dist);
  // Give every field a distinct value.
  auto psv = ps;
  Kokkos::parallel_for(
      "fill", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        for (int d = 0; d < 2; ++d) {
          psv.v(p, d) = 0.1 * p + d;
          psv.a(p, d) = -0.3 * p - d;
        }
        for (int i = 0; i < 4; ++i) psv.stress(p, i) = 1e3 * p + i;
        psv.F(p, 0, 1) = 1e-3 * p;
        psv.body(p) = p % 3;
        psv.material(p) = p % 2;
        psv.id(p) = 1000000000000LL + p;
      });
  // Every other particle, packed and appended to an empty set.
  const int n = ps.count / 2;
  ParticleSet::Ids picked("picked", n);
  Kokkos::parallel_for(
      "pick", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int k) { picked(k) = 2 * k + 1; });
  ParticleSet::Packed buffer("buffer", n, ps.packedWidth());
  ps.pack(picked, buffer);
  ParticleSet other(0);
  other.unpackAppend(buffer);
  TEST_EQUALITY(other.count, n);
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
  g.nx = 6;
  g.ny = 3;
  g.hx = 0.5;
  g.hy = 0.5;
  GridDistribution dist(g, Teuchos::rcp(new Teuchos::SerialComm<int>()));
  ParticleSet ps = createParticles(RectangularBody{0.5, 2.5, 0.0, 1.5, 2, 2, 0.1}, Materials{1e6, 0.25, 1000.0}, dist);
  ps.allocateHistory();
  auto h = ps.history;
  Kokkos::parallel_for(
      "fill_history", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h(p, i) = 10.0 * p + i;
      });
  const int n = 3;
  ParticleSet::Ids picked("picked", n);
  Kokkos::parallel_for(
      "pick", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int k) { picked(k) = 4 + k; });
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

// Every field, read back one by one from the receiving set and compared with the particle it was
// packed from (not with a second packing, which would hide an error made in both directions: two
// fields swapped in pack and unpack alike). Each value encodes its field, particle and component,
// so a field that lands in another, a component that lands in another, or a particle that lands
// at another's index all differ. 2D and 3D, with the fixed positions' u, history and C_p.
template <class View>
std::vector<double> hostValues(const View& view) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  std::vector<double> out;
  const size_t rows = h.extent(0), perRow = h.size() / std::max<size_t>(rows, 1);
  for (size_t i = 0; i < rows * perRow; ++i) out.push_back(static_cast<double>(h.data()[i]));
  return out;
}

template <class View>
void fillEncoded(const View& view, int field) {
  auto h = Kokkos::create_mirror_view(view);
  const size_t rows = h.extent(0), perRow = h.size() / std::max<size_t>(rows, 1);
  for (size_t p = 0; p < rows; ++p)
    for (size_t c = 0; c < perRow; ++c)
      h.data()[p * perRow + c] = static_cast<typename View::value_type>(1000 * field + 10 * p + c);
  Kokkos::deep_copy(view, h);
}

// The number of values of `received` (rows from `first` on) that differ from the source rows picked.
template <class View>
int differingValues(const View& source, const View& received, const std::vector<int>& picked, int first) {
  const auto src = hostValues(source), dst = hostValues(received);
  const size_t perRow = source.size() / std::max<size_t>(source.extent(0), 1);
  int differ = 0;
  for (size_t k = 0; k < picked.size(); ++k)
    for (size_t c = 0; c < perRow; ++c) differ += src[picked[k] * perRow + c] != dst[(first + k) * perRow + c];
  return differ;
}

int packUnpackDifferences(int dim, Teuchos::FancyOStream& out) {
  const int count = 7;
  ParticleSet ps(count, dim);
  ps.u = ps.newVector("u");
  ps.allocateHistory();
  ps.allocateAffine();
  int field = 0;
  for (auto* v : {&ps.x, &ps.x0, &ps.v, &ps.a, &ps.halfSize, &ps.u}) fillEncoded(*v, ++field);
  for (auto* v : {&ps.mass, &ps.volume0, &ps.volume}) fillEncoded(*v, ++field);
  fillEncoded(ps.stress, ++field);
  fillEncoded(ps.history, ++field);
  fillEncoded(ps.F, ++field);
  fillEncoded(ps.affine, ++field);
  fillEncoded(ps.body, ++field);
  fillEncoded(ps.material, ++field);
  fillEncoded(ps.id, ++field);
  const std::vector<int> picked{5, 0, 3};
  ParticleSet::Ids ids("picked", picked.size());
  auto idsHost = Kokkos::create_mirror_view(ids);
  for (size_t k = 0; k < picked.size(); ++k) idsHost(k) = picked[k];
  Kokkos::deep_copy(ids, idsHost);
  ParticleSet::Packed buffer("buffer", picked.size(), ps.packedWidth());
  ps.pack(ids, buffer);
  // A receiver of the same kind that already holds one particle: the rows append after it.
  ParticleSet other(1, dim);
  other.u = other.newVector("u");
  other.allocateHistory();
  other.allocateAffine();
  other.unpackAppend(buffer);
  if (other.count != 1 + (int)picked.size()) return -1;
  int differ = 0;
  for (auto m :
       {&ParticleSet::x, &ParticleSet::x0, &ParticleSet::v, &ParticleSet::a, &ParticleSet::halfSize, &ParticleSet::u})
    differ += differingValues(ps.*m, other.*m, picked, 1);
  for (auto m : {&ParticleSet::mass, &ParticleSet::volume0, &ParticleSet::volume})
    differ += differingValues(ps.*m, other.*m, picked, 1);
  for (auto m : {&ParticleSet::F, &ParticleSet::affine}) differ += differingValues(ps.*m, other.*m, picked, 1);
  differ += differingValues(ps.stress, other.stress, picked, 1) + differingValues(ps.history, other.history, picked, 1);
  differ += differingValues(ps.body, other.body, picked, 1) + differingValues(ps.material, other.material, picked, 1);
  differ += differingValues(ps.id, other.id, picked, 1);
  out << dim << "D: " << differ << " of the received values differ from their source particle's\n";
  return differ;
}

TEUCHOS_UNIT_TEST(ParticleSet, EveryFieldArrivesAtItsParticle) {
  TEST_EQUALITY(packUnpackDifferences(2, out), 0);
  TEST_EQUALITY(packUnpackDifferences(3, out), 0);
}

}  // namespace
