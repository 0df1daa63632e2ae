// Particle-to-grid-to-particle transfers conserve mass and linear momentum, for every particle
// shape function (MPM, GIMP, quadratic and cubic B-splines) and on any number of MPI ranks (grid sums travel through
// the Tpetra Import).
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

template <class Shape, int Dim>
void checkConservation(Teuchos::FancyOStream& out, bool& success) {
  using A = AccumColumns<Dim>;
  using K = KinColumns<Dim>;
  auto comm = Tpetra::getDefaultComm();
  StructuredGrid g;
  g.nx = 16;
  g.ny = 6;
  g.hx = 0.25;
  g.hy = 0.5;
  RectangularBody body{0.5, 3.5, 0.5, 2.5, 3, 2, 0.1};
  if (Dim == 3) {
    g.dim = 3;
    g.nz = 4;
    g.hz = 0.3;
    body.zMin = 0.3;
    body.zMax = 0.9;
    body.particlesPerCellZ = 2;
  }
  GridDistribution dist(g, comm);
  Materials mat(std::vector<MaterialParameters>{{1e6, 0.25, 1000.0}},
                Dim == 3 ? PlaneCondition::Solid : PlaneCondition::PlaneStrain);
  ParticleSet ps = createParticles(body, mat, dist);
  TEST_EQUALITY(ps.dim, Dim);

  // Jitter positions (within the cell, keeping ownership) and give random velocities.
  std::mt19937 rng(11 + comm->getRank());
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), vel(-2.0, 2.0);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.halfSize);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  double local[1 + Dim] = {};
  for (int p = 0; p < ps.count; ++p) {
    local[0] += m(p);
    for (int d = 0; d < Dim; ++d) {
      x(p, d) += jitter(rng) * hs(p, d);
      v(p, d) = vel(rng);
      local[1 + d] += m(p) * v(p, d);
    }
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.v, v);
  double particleTotals[1 + Dim];
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, 1 + Dim, local, particleTotals);

  GridFields f(dist, A::Count, K::Count);
  TEST_EQUALITY(f.ghostedIsOwned(), comm->getSize() == 1);  // one rank: no ghost copies
  f.accumGhosted->putScalar(0.0);
  {
    auto grid = f.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
    particleToGridMassMomentum<ExecutionSpace, Shape, Dim>(g, dist.ghostedIndexer(), ps, grid, A::Mass, A::MomX);
  }
  f.exportAccumulated();
  // Grid totals over owned nodes equal the particle totals.
  const Teuchos::Array<double> sums = columnSums(*f.accumOwned);
  TEST_FLOATING_EQUALITY(sums[A::Mass], particleTotals[0], 1e-13);
  for (int d = 0; d < Dim; ++d) TEST_FLOATING_EQUALITY(sums[A::MomX + d], particleTotals[1 + d], 1e-12);

  // Grid velocity, then a PIC transfer back: the particle momentum is unchanged.
  {
    auto acc = f.accumOwned->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto kinv = f.kinOwned->getLocalViewDevice(Tpetra::Access::OverwriteAll);
    Kokkos::parallel_for(
        "test_velocity", Kokkos::RangePolicy<ExecutionSpace>(0, acc.extent(0)), KOKKOS_LAMBDA(int n) {
          const double mn = acc(n, A::Mass);
          for (int d = 0; d < Dim; ++d) {
            kinv(n, K::VelX + d) = mn > 0 ? acc(n, A::MomX + d) / mn : 0.0;
            kinv(n, K::AccX + d) = 0.0;
          }
        });
  }
  f.importKinematics();
  {
    auto kinv = f.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridToParticleExplicit<ExecutionSpace, Shape, Dim>(g, dist.ghostedIndexer(), ps, kinv, 1e-3, 0.0, false, mat.law(),
                                                       false);
  }
  Kokkos::deep_copy(v, ps.v);
  double after[Dim] = {}, afterTotals[Dim];
  for (int p = 0; p < ps.count; ++p)
    for (int d = 0; d < Dim; ++d) after[d] += m(p) * v(p, d);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, Dim, after, afterTotals);
  for (int d = 0; d < Dim; ++d) TEST_FLOATING_EQUALITY(afterTotals[d], particleTotals[1 + d], 1e-12);

  // Internal forces of any stress field sum to zero (no net force from inside the body).
  {
    Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> stress("stress", ps.count, StressLayout<Dim>::count);
    auto sh = Kokkos::create_mirror_view(stress);
    for (int p = 0; p < ps.count; ++p)
      for (int c = 0; c < StressLayout<Dim>::count; ++c) sh(p, c) = vel(rng) * 1e3;
    Kokkos::deep_copy(stress, sh);
    f.accumGhosted->putScalar(0.0);
    {
      auto grid = f.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
      accumulateInternalForce<ExecutionSpace, Shape, Dim>(g, dist.ghostedIndexer(), ps, stress, grid, A::FintX);
    }
    f.exportAccumulated();
    const Teuchos::Array<double> fs = columnSums(*f.accumOwned);
    Teuchos::Array<double> mags(A::Count);
    f.accumOwned->norm1(mags());
    for (int d = 0; d < Dim; ++d) {
      TEST_COMPARE(std::abs(fs[A::FintX + d]), <, 1e-12 * mags[A::FintX + d]);
      TEST_COMPARE(mags[A::FintX + d], >, 0.0);
    }
  }
}

TEUCHOS_UNIT_TEST(Transfer, MpmConservesMassAndMomentum) { checkConservation<LinearMpm, 2>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, GimpConservesMassAndMomentum) { checkConservation<UniformGimp, 2>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, Mpm3dConservesMassAndMomentum) { checkConservation<LinearMpm, 3>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, Gimp3dConservesMassAndMomentum) { checkConservation<UniformGimp, 3>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, BSplineConservesMassAndMomentum) { checkConservation<QuadraticBSpline, 2>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, BSpline3dConservesMassAndMomentum) { checkConservation<QuadraticBSpline, 3>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, CubicBSplineConservesMassAndMomentum) { checkConservation<CubicBSpline, 2>(out, success); }
TEUCHOS_UNIT_TEST(Transfer, CubicBSpline3dConservesMassAndMomentum) {
  checkConservation<CubicBSpline, 3>(out, success);
}

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
