// Particle-to-grid-to-particle transfers conserve mass and linear momentum, for both shape
// functions and on any number of MPI ranks (grid sums travel through the Tpetra Import).
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <random>

#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/InternalForce.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "physics/Body.hpp"

namespace {

using namespace impm;

// Sum over the owned nodes (all ranks) of each column.
Teuchos::Array<double> columnSums(const MultiVector& mv) {
  Vector ones(mv.getMap());
  ones.putScalar(1.0);
  Teuchos::Array<double> sums(mv.getNumVectors());
  for (size_t j = 0; j < mv.getNumVectors(); ++j) sums[j] = mv.getVector(j)->dot(ones);
  return sums;
}

template <class Shape>
void checkConservation(Teuchos::FancyOStream& out, bool& success) {
  auto comm = Tpetra::getDefaultComm();
  StructuredGrid g;
  g.nx = 16; g.ny = 6; g.hx = 0.25; g.hy = 0.5;
  GridDistribution dist(g, comm);
  RectangularBody body{0.5, 3.5, 0.5, 2.5, 3, 2, 0.1};
  LinearElastic mat{1e6, 0.25, 1000.0};
  ParticleSet ps = createParticles(body, mat, dist);

  // Jitter positions (within the cell, keeping ownership) and give random velocities.
  std::mt19937 rng(11 + comm->getRank());
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), vel(-2.0, 2.0);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.halfSize);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  double local[3] = {0, 0, 0};
  for (int p = 0; p < ps.count; ++p) {
    x(p, 0) += jitter(rng) * hs(p, 0);
    x(p, 1) += jitter(rng) * hs(p, 1);
    v(p, 0) = vel(rng); v(p, 1) = vel(rng);
    local[0] += m(p); local[1] += m(p) * v(p, 0); local[2] += m(p) * v(p, 1);
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.v, v);
  double particleTotals[3];
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 3, local, particleTotals);

  GridFields f(dist);
  f.accumGhosted->putScalar(0.0);
  {
    auto grid = f.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
    particleToGridMassMomentum<ExecutionSpace, Shape>(g, dist.ghostedIndexer(), ps, grid, accum::Mass, accum::MomX);
  }
  f.exportAccumulated();
  // Grid totals over owned nodes equal the particle totals.
  const Teuchos::Array<double> sums = columnSums(*f.accumOwned);
  TEST_FLOATING_EQUALITY(sums[accum::Mass], particleTotals[0], 1e-13);
  TEST_FLOATING_EQUALITY(sums[accum::MomX], particleTotals[1], 1e-12);
  TEST_FLOATING_EQUALITY(sums[accum::MomY], particleTotals[2], 1e-12);

  // Grid velocity, then a PIC transfer back: the particle momentum is unchanged.
  {
    auto acc = f.accumOwned->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto kinv = f.kinOwned->getLocalViewDevice(Tpetra::Access::OverwriteAll);
    Kokkos::parallel_for("test_velocity", Kokkos::RangePolicy<ExecutionSpace>(0, acc.extent(0)), KOKKOS_LAMBDA(int n) {
      const double mn = acc(n, accum::Mass);
      kinv(n, kin::VelX) = mn > 0 ? acc(n, accum::MomX) / mn : 0.0;
      kinv(n, kin::VelY) = mn > 0 ? acc(n, accum::MomY) / mn : 0.0;
      kinv(n, kin::AccX) = 0.0;
      kinv(n, kin::AccY) = 0.0;
    });
  }
  f.importKinematics();
  {
    auto kinv = f.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridToParticleExplicit<ExecutionSpace, Shape>(g, dist.ghostedIndexer(), ps, kinv, 1e-3, 0.0, false,
                                                  LinearElastic{}.law(), false);
  }
  Kokkos::deep_copy(v, ps.v);
  double after[2] = {0, 0}, afterTotals[2];
  for (int p = 0; p < ps.count; ++p) { after[0] += m(p) * v(p, 0); after[1] += m(p) * v(p, 1); }
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 2, after, afterTotals);
  TEST_FLOATING_EQUALITY(afterTotals[0], particleTotals[1], 1e-12);
  TEST_FLOATING_EQUALITY(afterTotals[1], particleTotals[2], 1e-12);

  // Internal forces of any stress field sum to zero (no net force from inside the body).
  {
    Kokkos::View<double* [4], Kokkos::LayoutRight, DeviceType> stress("stress", ps.count);
    auto sh = Kokkos::create_mirror_view(stress);
    for (int p = 0; p < ps.count; ++p) for (int c = 0; c < 3; ++c) sh(p, c) = vel(rng) * 1e3;
    Kokkos::deep_copy(stress, sh);
    f.accumGhosted->putScalar(0.0);
    {
      auto grid = f.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
      accumulateInternalForce<ExecutionSpace, Shape>(g, dist.ghostedIndexer(), ps, stress, grid, accum::FintX);
    }
    f.exportAccumulated();
    const Teuchos::Array<double> fs = columnSums(*f.accumOwned);
    Teuchos::Array<double> mags(accum::Count);
    f.accumOwned->norm1(mags());
    TEST_COMPARE(std::abs(fs[accum::FintX]), <, 1e-12 * mags[accum::FintX]);
    TEST_COMPARE(std::abs(fs[accum::FintY]), <, 1e-12 * mags[accum::FintY]);
    TEST_COMPARE(mags[accum::FintX], >, 0.0);
  }
}

TEUCHOS_UNIT_TEST(Transfer, MpmConservesMassAndMomentum) { checkConservation<LinearMpm>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, GimpConservesMassAndMomentum) { checkConservation<UniformGimp>(out, success); }

}  // namespace

namespace {
// The tests run on Kokkos' OpenMP backend, with the thread count OMP_NUM_THREADS asks for.
TEUCHOS_UNIT_TEST(Backend, IsOpenMP) {
  TEST_ASSERT((std::is_same<impm::ExecutionSpace, Kokkos::OpenMP>::value));
  if (const char* n = std::getenv("OMP_NUM_THREADS")) {
    TEST_EQUALITY(impm::ExecutionSpace::concurrency(), std::atoi(n));
  }
  out << "execution space " << impm::ExecutionSpace::name() << " with " << impm::ExecutionSpace::concurrency()
      << " threads\n";
}
}  // namespace
