// StiffnessAssembler (solvers/implicit/): the assembled P is the sum of the stiffness kernel's
// blocks taken in block order, bit for bit, at any thread count (the suite runs this at 1 and 2
// OpenMP threads), with the sequential fill (the host's) and with the parallel gather (a device's).
// A fill that summed in the order threads happen to reach an entry would differ in the last bits
// where contributions of particles handled by different threads meet.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <map>
#include <random>
#include <utility>

#include "core/kernels/Stiffness.hpp"
#include "physics/Body.hpp"
#include "solvers/implicit/ImplicitNewmark.hpp"

namespace {

using namespace impm;

void checkFill(StiffnessFill fill, Teuchos::FancyOStream& out, bool& success) {
  auto comm = Tpetra::getDefaultComm();
  if (comm->getSize() != 1) return;  // the reference below is one rank's (the Export sums ranks)
  StructuredGrid g;
  g.nx = 12;
  g.ny = 6;
  g.hx = 1e-3;
  g.hy = 1e-3;
  GridDistribution dist(g, comm);
  RectangularBody body{1e-3, 11e-3, 1e-3, 5e-3, 3, 3, 1e-3};
  Materials mat{200e9, 0.3, 7800.0, PlaneCondition::PlaneStrain};
  ParticleSet ps = createParticles(body, mat, dist);
  {
    // Irregular positions (within a third of a sub-cell), so that the order of a sum matters.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-1e-4, 1e-4);
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
    for (int p = 0; p < ps.count; ++p)
      for (int d = 0; d < 2; ++d) x(p, d) += jitter(rng);
    Kokkos::deep_copy(ps.x, x);
  }
  GridConditions bc({ConstraintSpec::onFace("left", body, "x-", true, true)}, dist);
  LoadSet loads({}, dist, {}, 1);
  ImplicitOptions opt;
  opt.consistentMass = true;  // the mass in the blocks too: P is the blocks' sum alone
  opt.stiffnessFill = fill;
  opt.solverParams = Teuchos::rcp(new Teuchos::ParameterList("Implicit Solver"));
  opt.solverParams->set("Jacobian", "Assembled");
  const double dt = 1e-7;
  ImplicitNewmark<UniformGimp> model(ps, dist, mat, bc, loads, opt);
  model.prepareStep(0.0, dt);
  Vector u(model.unknownMap(), true);
  const auto P = model.jacobianMatrix(u);

  // The reference: the kernel's blocks summed sequentially, block after block, into zero.
  const BlockMatrices Kb =
      stencilStiffness<ExecutionSpace, UniformGimp, 2>(g, ps, mat.law(), opt.newmark.c1(dt), false);
  auto O = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kb.origin);
  auto K = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kb.K);
  const auto rows = P->getRowMap();
  const auto nodes = dist.ghostedNodeMap();
  const LocalNodeIndexer& ix = dist.ghostedIndexer();
  const int bn0 = Kb.blockNodes[0], nd = Kb.dofs();
  std::map<std::pair<GO, GO>, double> reference;
  for (int k = 0; k < Kb.count; ++k) {
    std::vector<GO> gid(nd);
    for (int a = 0; a < Kb.nodes(); ++a)
      for (int d = 0; d < 2; ++d)
        gid[2 * a + d] = FreeDofMap<2>::gid(nodes->getGlobalElement(ix(O(k, 0) + a % bn0, O(k, 1) + a / bn0)), d);
    for (int r = 0; r < nd; ++r)
      for (int c = 0; c < nd; ++c)
        if (rows->isNodeGlobalElement(gid[r]) && rows->isNodeGlobalElement(gid[c]))
          reference[{gid[r], gid[c]}] += K(k, r, c);
  }

  size_t entries = 0, differing = 0, missing = 0;
  double largestDifference = 0.0;
  typename CrsMatrix::local_inds_host_view_type cols;
  typename CrsMatrix::values_host_view_type values;
  const auto colMap = P->getColMap();
  std::map<std::pair<GO, GO>, double> assembled;
  for (size_t r = 0; r < rows->getNodeNumElements(); ++r) {
    const GO row = rows->getGlobalElement(LO(r));
    P->getLocalRowView(LO(r), cols, values);
    for (size_t e = 0; e < cols.extent(0); ++e) {
      assembled[{row, colMap->getGlobalElement(cols(e))}] = values(e);
      const auto it = reference.find({row, colMap->getGlobalElement(cols(e))});
      const double expected = it == reference.end() ? 0.0 : it->second;
      ++entries;
      if (values(e) != expected) {
        ++differing;
        largestDifference = std::max(largestDifference, std::abs(values(e) - expected) / std::abs(expected));
      }
    }
  }
  for (const auto& [rc, value] : reference)
    if (value != 0.0 && assembled.find(rc) == assembled.end()) ++missing;
  out << (fill == StiffnessFill::Parallel ? "parallel" : "sequential") << " fill, " << entries << " entries of P ("
      << Kb.count << " blocks, " << Kokkos::DefaultExecutionSpace().concurrency() << " thread(s)): " << differing
      << " differ from the sequential block-order sum (largest relative difference " << largestDifference << "), "
      << missing << " of the reference missing\n";
  TEST_COMPARE(entries, >, 1000);
  TEST_EQUALITY(differing, 0);
  TEST_EQUALITY(missing, 0);
}

TEUCHOS_UNIT_TEST(StiffnessAssembler, SequentialFillSumsBlocksInBlockOrder) {
  checkFill(StiffnessFill::Sequential, out, success);
}
TEUCHOS_UNIT_TEST(StiffnessAssembler, ParallelFillSumsBlocksInBlockOrder) {
  checkFill(StiffnessFill::Parallel, out, success);
}

}  // namespace
