// The particle-grid transfers beyond FLIP/PIC (Integrator/Explicit/Transfer = APIC, TPIC, XPIC;
// core/kernels/AffineTransfer.hpp):
//   - one P2G + G2P round trip of an affine velocity field v = v0 + A x with C_p = A gives back
//     v_p and C_p to round-off, for every shape function of the explicit stepper, 2D and 3D;
//   - APIC's D_p summed over a B-spline stencil is the constant the kernel uses (h^2/4, h^2/3);
//   - a free neo-Hookean disk spinning at 1 rad/s keeps its angular momentum over one revolution
//     with APIC and TPIC (PIC loses far more; FLIP's is printed), on any number of ranks, and the
//     same to 1e-10 at np 2 as at np 1 (migration carries C_p);
//   - XPIC(m) (solvers/XpicExtrapolation.hpp): order 1 is PIC; orders 2 and 5 keep the spin
//     far better than PIC; np 2 as np 1.
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "core/InputDeck.hpp"
#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "physics/Body.hpp"
#include "solvers/Simulation.hpp"
#include "solvers/build/Deck.hpp"

namespace {

using namespace impm;
using Teuchos::ParameterList;
using Comm = Teuchos::RCP<const Teuchos::Comm<int>>;

// --- round trip of an affine field ---

// A = the affine field's gradient, v0 its value at the origin.
constexpr double kA[3][3] = {{0.3, -1.1, 0.7}, {0.9, -0.2, 0.4}, {-0.5, 0.8, 0.6}};
constexpr double kV0[3] = {1.0, -2.0, 0.5};

template <int Dim>
double affineVelocity(const double* x, int i) {
  double v = kV0[i];
  for (int j = 0; j < Dim; ++j) v += kA[i][j] * x[j];
  return v;
}

// Writes v = v0 + A x and C_p = A on jittered particles of a block three cells away from the grid's
// edges (no edge-modified functions), maps them to the grid and back with `transfer`, and
// returns the largest errors of v_p (relative to max |v|) and C_p (relative to max |A_ij|).
template <class Shape, int Dim>
std::pair<double, double> affineRoundTrip(ParticleTransfer transfer) {
  using A = AccumColumns<Dim>;
  using K = KinColumns<Dim>;
  auto comm = Tpetra::getDefaultComm();
  StructuredGrid g;
  g.nx = 12;
  g.ny = 10;
  g.hx = 0.25;
  g.hy = 0.2;
  RectangularBody body{0.75, 2.25, 0.6, 1.4, 2, 2, 0.1};
  if (Dim == 3) {
    g.dim = 3;
    g.nz = 9;
    g.hz = 0.3;
    body.zMin = 0.9;
    body.zMax = 1.8;
    body.particlesPerCellZ = 2;
  }
  GridDistribution dist(g, comm);
  Materials mat(std::vector<MaterialParameters>{{1e6, 0.25, 1000.0}},
                Dim == 3 ? PlaneCondition::Solid : PlaneCondition::PlaneStrain);
  ParticleSet ps = createParticles(body, mat, dist);
  ps.allocateAffine();
  std::mt19937 rng(7 + comm->getRank());
  std::uniform_real_distribution<double> jitter(-0.4, 0.4);
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto hs = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.halfSize);
  auto v = Kokkos::create_mirror_view(ps.v);
  auto C = Kokkos::create_mirror_view(ps.affine);
  for (int p = 0; p < ps.count; ++p) {
    double xp[Dim];
    for (int d = 0; d < Dim; ++d) xp[d] = x(p, d) += jitter(rng) * hs(p, d);
    for (int i = 0; i < Dim; ++i) {
      v(p, i) = affineVelocity<Dim>(xp, i);
      for (int j = 0; j < Dim; ++j) C(p, i, j) = kA[i][j];
    }
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.v, v);
  Kokkos::deep_copy(ps.affine, C);

  GridFields f(dist, A::Count, K::Count);
  f.accumGhosted->putScalar(0.0);
  {
    auto grid = f.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
    particleToGridMassMomentum<ExecutionSpace, Shape, Dim>(g, dist.ghostedIndexer(), ps, grid, A::Mass, A::MomX, -1, -1,
                                                           SingleField(), true);
  }
  f.exportAccumulated();
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
    gridToParticleExplicit<ExecutionSpace, Shape, Dim>(g, dist.ghostedIndexer(), ps, kinv, 1e-3, 1.0, false, mat.law(),
                                                       false, SingleField(), transfer);
  }
  Kokkos::deep_copy(v, ps.v);
  Kokkos::deep_copy(C, ps.affine);
  double local[2] = {0.0, 0.0}, worst[2];
  double vmax = 0.0, amax = 0.0;
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) amax = std::max(amax, std::abs(kA[i][j]));
  for (int p = 0; p < ps.count; ++p) {
    double xp[Dim];
    for (int d = 0; d < Dim; ++d) xp[d] = x(p, d);
    for (int i = 0; i < Dim; ++i) {
      const double exact = affineVelocity<Dim>(xp, i);
      vmax = std::max(vmax, std::abs(exact));
      local[0] = std::max(local[0], std::abs(v(p, i) - exact));
      for (int j = 0; j < Dim; ++j) local[1] = std::max(local[1], std::abs(C(p, i, j) - kA[i][j]));
    }
  }
  double vmaxAll = 0.0;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, 2, local, worst);
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, vmax, Teuchos::outArg(vmaxAll));
  return {worst[0] / vmaxAll, worst[1] / amax};
}

template <class Shape, int Dim>
void checkAffineRoundTrip(Teuchos::FancyOStream& out, bool& success) {
  for (ParticleTransfer t : {ParticleTransfer::Apic, ParticleTransfer::Tpic}) {
    const auto [verr, cerr] = affineRoundTrip<Shape, Dim>(t);
    out << Shape::name << " " << Dim << "D " << (t == ParticleTransfer::Apic ? "APIC" : "TPIC")
        << ": round trip of an affine field, relative error of v_p " << verr << ", of C_p " << cerr << "\n";
    TEST_COMPARE(verr, <, 1e-13);
    TEST_COMPARE(cerr, <, 1e-11);
  }
}

TEUCHOS_UNIT_TEST(AffineRoundTrip, Mpm2d) { checkAffineRoundTrip<LinearMpm, 2>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, Mpm3d) { checkAffineRoundTrip<LinearMpm, 3>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, Gimp2d) { checkAffineRoundTrip<UniformGimp, 2>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, Gimp3d) { checkAffineRoundTrip<UniformGimp, 3>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, CpGimp2d) { checkAffineRoundTrip<ConvectedGimp, 2>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, CpGimp3d) { checkAffineRoundTrip<ConvectedGimp, 3>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, Cpdi2d) { checkAffineRoundTrip<Cpdi, 2>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, Cpdi3d) { checkAffineRoundTrip<Cpdi, 3>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, QuadraticBSpline2d) { checkAffineRoundTrip<QuadraticBSpline, 2>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, QuadraticBSpline3d) { checkAffineRoundTrip<QuadraticBSpline, 3>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, CubicBSpline2d) { checkAffineRoundTrip<CubicBSpline, 2>(out, success); }
TEUCHOS_UNIT_TEST(AffineRoundTrip, CubicBSpline3d) { checkAffineRoundTrip<CubicBSpline, 3>(out, success); }

// APIC with B-splines uses D_p = factor h_d^2 I (ApicInertia); the sum over the stencil gives it
// at any position away from the grid's edge.
template <class Shape, int Dim>
void checkConstantInertia(Teuchos::FancyOStream& out, bool& success) {
  StructuredGrid g;
  g.nx = 12;
  g.ny = 12;
  g.hx = 0.25;
  g.hy = 0.2;
  if (Dim == 3) {
    g.dim = 3;
    g.nz = 12;
    g.hz = 0.3;
  }
  const double fractions[4][3] = {{4.0, 5.0, 6.0}, {4.3, 5.71, 6.05}, {5.5, 4.999, 6.5}, {6.87, 7.12, 4.41}};
  double worst = 0.0;
  for (const auto& frac : fractions) {
    double xp[Dim], l[Dim];
    for (int d = 0; d < Dim; ++d) {
      xp[d] = g.origin(d) + frac[d] * g.spacing(d);
      l[d] = 0.25 * g.spacing(d);
    }
    const ParticleStencil<Shape, Dim> st(g, xp, l);
    double D[Dim][Dim];
    apicInertia(st, g, xp, D);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        const double constant = i == j ? ApicInertia<Shape>::factor * g.spacing(i) * g.spacing(i) : 0.0;
        worst = std::max(worst, std::abs(D[i][j] - constant) / (g.spacing(i) * g.spacing(j)));
      }
  }
  out << Shape::name << " " << Dim << "D: largest |D_p - factor h^2 I| / h^2 " << worst << "\n";
  TEST_COMPARE(worst, <, 1e-14);
}

TEUCHOS_UNIT_TEST(ApicInertia, QuadraticBSpline2d) { checkConstantInertia<QuadraticBSpline, 2>(out, success); }
TEUCHOS_UNIT_TEST(ApicInertia, QuadraticBSpline3d) { checkConstantInertia<QuadraticBSpline, 3>(out, success); }
TEUCHOS_UNIT_TEST(ApicInertia, CubicBSpline2d) { checkConstantInertia<CubicBSpline, 2>(out, success); }
TEUCHOS_UNIT_TEST(ApicInertia, CubicBSpline3d) { checkConstantInertia<CubicBSpline, 3>(out, success); }

// --- the spinning disk ---

// A free neo-Hookean disk (radius 1 m, E = 1 MPa, nu = 0.3, rho = 1000 kg/m^3; plane strain) on
// cells of 0.1 m with 2 x 2 particles per cell, spinning rigidly at 1 rad/s about its centre (the
// origin), explicit GIMP USL for one revolution. P-wave speed 36.7 m/s: the stable step is
// 0.7 / (36.7 sqrt(2) / 0.1) = 1.35 ms; 5000 steps of 1.26 ms make t = 2 pi s.
const char* const kDiskDeck = R"(
impm:
  Problem:
    Name: spinning disk
    Output Directory: test_output/spinning_disk
  Grid:
    Origin X: -1.5
    Origin Y: -1.5
    Cells X: 30
    Cells Y: 30
    Cell Size X: 0.1
    Cell Size Y: 0.1
    Plane Condition: Plane Strain
  Materials:
    rubber:
      Model: Neo-Hookean
      Young Modulus: 1.0e6
      Poisson Ratio: 0.3
      Density: 1000.0
  Bodies:
    disk:
      Shape: Ellipse
      Material: rubber
      Center X: 0.0
      Center Y: 0.0
      Radius X: 1.0
      Radius Y: 1.0
      Particles Per Cell X: 2
      Particles Per Cell Y: 2
      Angular Velocity: 1.0
  Method:
    Shape Function: GIMP
  Integrator:
    Type: Explicit
    Number of Steps: 5000
    Explicit:
      Update Scheme: USL
  Output:
    History Interval: 100
    VTK Interval: 0
    Plot: false
    Progress: false
    Energy And Momentum: true
)";

ParameterList diskDeck(const std::string& transfer, double flip, int steps, int xpicOrder = 5) {
  ParameterList deck = *Teuchos::getParametersFromYamlString(kDiskDeck);
  deck.sublist("Integrator").set("Time Step", 2.0 * M_PI / 5000).set("Number of Steps", steps);
  deck.sublist("Integrator").sublist("Explicit").set("Transfer", transfer).set("FLIP Fraction", flip);
  if (transfer == "XPIC") deck.sublist("Integrator").sublist("Explicit").set("XPIC Order", xpicOrder);
  return deck;
}

// Component `axis` of the particles' angular momentum sum m (x - c) x v about the centre c = 0
// (all ranks); about z (2) in 2D.
double angularMomentum(const ParticleSet& ps, const Teuchos::Comm<int>& comm, int axis = 2) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  double local = 0.0, total = 0.0;
  for (int p = 0; p < ps.count; ++p) local += m(p) * (x(p, b) * v(p, c) - x(p, c) * v(p, b));
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, local, Teuchos::outArg(total));
  return total;
}

struct Spin {
  double initial = 0.0, final = 0.0, kinetic = 0.0;
  std::string status;
  double relativeLoss() const { return (initial - final) / initial; }
};

Spin spinDisk(ParameterList deck, const Comm& comm, const std::string& outdir, int steps = 5000, int axis = 2) {
  deck.sublist("Integrator").set("Number of Steps", steps);
  impm::validateDeck(deck);
  impm::Simulation sim(deck, comm, outdir);
  Spin s;
  s.initial = angularMomentum(sim.particles(), *comm, axis);
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  s.status = r.status;
  s.final = angularMomentum(sim.particles(), *comm, axis);
  s.kinetic = r.kinetic.empty() ? 0.0 : r.kinetic.back();
  return s;
}

TEUCHOS_UNIT_TEST(SpinningDisk, AngularMomentumOverOneRevolution) {
  auto comm = Tpetra::getDefaultComm();
  if (comm->getSize() > 1) {  // the revolution is the same on any rank count (RankCountIndependent)
    out << "several ranks: run at np 1\n";
    return;
  }
  const Spin apic = spinDisk(diskDeck("APIC", 1.0, 5000), comm, "test_output/spinning_disk_apic");
  const Spin tpic = spinDisk(diskDeck("TPIC", 1.0, 5000), comm, "test_output/spinning_disk_tpic");
  const Spin pic = spinDisk(diskDeck("FLIP/PIC", 0.0, 5000), comm, "test_output/spinning_disk_pic");
  const Spin flip = spinDisk(diskDeck("FLIP/PIC", 1.0, 5000), comm, "test_output/spinning_disk_flip");
  const Spin xpic = spinDisk(diskDeck("XPIC", 1.0, 5000, 5), comm, "test_output/spinning_disk_xpic5");
  out << "spinning disk, one revolution, initial angular momentum " << apic.initial << " kg m^2/s; relative loss: APIC "
      << apic.relativeLoss() << ", TPIC " << tpic.relativeLoss() << ", PIC " << pic.relativeLoss() << ", FLIP "
      << flip.relativeLoss() << ", XPIC(5) " << xpic.relativeLoss() << "\n";
  for (const Spin* s : {&apic, &tpic, &pic, &flip, &xpic}) TEST_EQUALITY_CONST(s->status, "completed");
  // XPIC(5) (measured 0.41) keeps much more of the spin than PIC (all lost), less than FLIP: a
  // grid filter still sees the disk's edge, where the lumped projection of a rotation is one-sided.
  TEST_COMPARE(xpic.relativeLoss(), <, 0.5 * pic.relativeLoss());
  TEST_COMPARE(xpic.relativeLoss(), >, flip.relativeLoss());
  // Rigid rotation of a unit disk: L = (pi rho) omega / 2 per metre of thickness.
  TEST_FLOATING_EQUALITY(apic.initial, M_PI * 1000.0 / 2.0, 2e-2);
  // Measured 4.7e-6 (APIC) and 1.7e-7 (TPIC): round-off of the affine / linear split over 5000
  // steps. FLIP loses 1.6e-2 here, so 1e-4 still tells an affine transfer from FLIP.
  TEST_COMPARE(std::abs(apic.relativeLoss()), <, 1e-4);
  TEST_COMPARE(std::abs(tpic.relativeLoss()), <, 1e-4);
  TEST_COMPARE(flip.relativeLoss(), >, 10.0 * std::abs(apic.relativeLoss()));
  // A transfer that fell back to PIC would lose as much as PIC.
  TEST_COMPARE(pic.relativeLoss(), >, 10.0 * std::abs(apic.relativeLoss()));
  TEST_COMPARE(pic.relativeLoss(), >, 10.0 * std::abs(tpic.relativeLoss()));
}

// At np 2 the disk crosses the ranks' cut twice per revolution: its particles migrate with their
// C_p, and the angular momentum is that of one rank to 1e-10 (XPIC: its grid passes exchange ghosts).
TEUCHOS_UNIT_TEST(SpinningDisk, RankCountIndependent) {
  auto comm = Tpetra::getDefaultComm();
  if (comm->getSize() == 1) {
    out << "one rank: nothing to compare (run at np 2)\n";
    return;
  }
  for (const std::string transfer : {"APIC", "TPIC", "XPIC"}) {
    const std::string name = "test_output/spinning_disk_ranks_" + transfer;
    const Spin all = spinDisk(diskDeck(transfer, 1.0, 1500), comm, name);
    auto self = comm->split(comm->getRank(), 0);
    const Spin one = spinDisk(diskDeck(transfer, 1.0, 1500), self, name + "_rank" + std::to_string(comm->getRank()));
    const double difference = std::abs(all.final - one.final) / all.initial;
    out << transfer << ": angular momentum after 1500 steps, np " << comm->getSize()
        << " against np 1: relative difference " << difference << "\n";
    TEST_COMPARE(difference, <, 1e-10);
  }
}

// XPIC(1) is PIC: v* = v^n, and v_p = S v^n + dt S a against PIC's S (v^n + dt a), the same to
// round-off. (Order 1 runs no extrapolation pass: this checks the wiring and the update.)
TEUCHOS_UNIT_TEST(Xpic, OrderOneIsPic) {
  auto comm = Tpetra::getDefaultComm();
  const Spin xpic1 = spinDisk(diskDeck("XPIC", 1.0, 400, 1), comm, "test_output/spinning_disk_xpic1", 400);
  const Spin pic = spinDisk(diskDeck("FLIP/PIC", 0.0, 400), comm, "test_output/spinning_disk_pic400", 400);
  const Spin xpic2 = spinDisk(diskDeck("XPIC", 1.0, 400, 2), comm, "test_output/spinning_disk_xpic2", 400);
  out << "400 steps: angular momentum XPIC(1) " << xpic1.final << ", PIC " << pic.final << ", XPIC(2) " << xpic2.final
      << " (initial " << pic.initial << "); kinetic energy XPIC(1) " << xpic1.kinetic << ", PIC " << pic.kinetic
      << "\n";
  TEST_FLOATING_EQUALITY(xpic1.final, pic.final, 1e-10);
  TEST_FLOATING_EQUALITY(xpic1.kinetic, pic.kinetic, 1e-10);
  // A second order keeps measurably more of the spin than PIC.
  TEST_COMPARE(xpic2.relativeLoss(), <, 0.75 * pic.relativeLoss());
}

// USF and MUSL take the transfers too: 500 steps (a tenth of a revolution) of the disk.
TEUCHOS_UNIT_TEST(SpinningDisk, EveryUpdateScheme) {
  auto comm = Tpetra::getDefaultComm();
  for (const std::string scheme : {"USF", "MUSL"}) {
    auto run = [&](const std::string& transfer, double flip) {
      ParameterList deck = diskDeck(transfer, flip, 500);
      deck.sublist("Integrator").sublist("Explicit").set("Update Scheme", scheme);
      return spinDisk(deck, comm, "test_output/spinning_disk_" + scheme + "_" + transfer + std::to_string(int(flip)),
                      500);
    };
    const Spin apic = run("APIC", 1.0), tpic = run("TPIC", 1.0), xpic = run("XPIC", 1.0), pic = run("FLIP/PIC", 0.0);
    out << scheme << ", 500 steps: relative loss of angular momentum APIC " << apic.relativeLoss() << ", TPIC "
        << tpic.relativeLoss() << ", XPIC(5) " << xpic.relativeLoss() << ", PIC " << pic.relativeLoss() << "\n";
    for (const Spin* s : {&apic, &tpic, &xpic, &pic}) TEST_EQUALITY_CONST(s->status, "completed");
    TEST_COMPARE(std::abs(apic.relativeLoss()), <, 1e-4);
    TEST_COMPARE(std::abs(tpic.relativeLoss()), <, 1e-4);
    TEST_COMPARE(xpic.relativeLoss(), <, 0.5 * pic.relativeLoss());
  }
}

// 3D: a box (0.8 m a side, GIMP, 4096 particles) spinning about the x axis from `Angular
// Velocity X`, for 300 steps of 1 ms (0.3 rad): APIC and TPIC keep L_x, PIC does not, XPIC(5)
// keeps most of it.
const char* const kBoxDeck = R"(
impm:
  Problem:
    Name: spinning box
    Output Directory: test_output/spinning_box
  Grid:
    Dimension: 3
    Origin X: -0.6
    Origin Y: -0.6
    Origin Z: -0.6
    Cells X: 12
    Cells Y: 12
    Cells Z: 12
    Cell Size X: 0.1
    Cell Size Y: 0.1
    Cell Size Z: 0.1
  Materials:
    rubber:
      Model: Neo-Hookean
      Young Modulus: 1.0e6
      Poisson Ratio: 0.3
      Density: 1000.0
  Bodies:
    box:
      Shape: Rectangle
      Material: rubber
      X Min: -0.4
      X Max: 0.4
      Y Min: -0.4
      Y Max: 0.4
      Z Min: -0.4
      Z Max: 0.4
      Particles Per Cell X: 2
      Particles Per Cell Y: 2
      Particles Per Cell Z: 2
      Angular Velocity X: 1.0
  Method:
    Shape Function: GIMP
  Integrator:
    Type: Explicit
    Time Step: 1.0e-3
    Number of Steps: 300
  Output:
    History Interval: 50
    VTK Interval: 0
    Plot: false
    Progress: false
    Energy And Momentum: true
)";

TEUCHOS_UNIT_TEST(SpinningBox, ThreeDimensionsAboutX) {
  auto comm = Tpetra::getDefaultComm();
  auto run = [&](const std::string& transfer, double flip) {
    ParameterList deck = *Teuchos::getParametersFromYamlString(kBoxDeck);
    deck.sublist("Integrator").sublist("Explicit").set("Transfer", transfer).set("FLIP Fraction", flip);
    return spinDisk(deck, comm, "test_output/spinning_box_" + transfer + std::to_string(int(flip)), 300, 0);
  };
  const Spin apic = run("APIC", 1.0), tpic = run("TPIC", 1.0), pic = run("FLIP/PIC", 0.0), xpic = run("XPIC", 1.0);
  out << "3D box about x, 300 steps: L_x(0) " << apic.initial << " kg m^2/s; relative loss APIC " << apic.relativeLoss()
      << ", TPIC " << tpic.relativeLoss() << ", PIC " << pic.relativeLoss() << ", XPIC(5) " << xpic.relativeLoss()
      << "\n";
  TEST_EQUALITY_CONST(xpic.status, "completed");
  TEST_COMPARE(xpic.relativeLoss(), <, 0.5 * pic.relativeLoss());
  // L_x = omega sum m (y^2 + z^2): the box's m (b^2 + c^2) / 12 = 54.6, less the midpoint rule's
  // 1/256 on 8 particles per 0.8 m.
  TEST_FLOATING_EQUALITY(apic.initial, 512.0 * 1.28 / 12.0 * (1.0 - 1.0 / 256.0), 1e-10);
  TEST_COMPARE(std::abs(apic.relativeLoss()), <, 1e-4);
  TEST_COMPARE(std::abs(tpic.relativeLoss()), <, 1e-4);
  TEST_COMPARE(pic.relativeLoss(), >, 10.0 * std::abs(apic.relativeLoss()));
}

// --- the implicit integrator (Integrator/Implicit/Transfer) ---

// The disk for a quarter revolution with implicit Newmark (average acceleration, the lumped grid
// with the Equilibrium acceleration) at steps of 2 pi / 1000 s (5 times the explicit ones).
Spin spinDiskImplicit(const std::string& transfer, const std::string& outdir, int xpicOrder = 5) {
  ParameterList deck = diskDeck("FLIP/PIC", 1.0, 250);
  deck.sublist("Integrator").set("Type", "Implicit").set("Time Step", 2.0 * M_PI / 1000);
  deck.sublist("Integrator").sublist("Implicit").set("Transfer", transfer).set("XPIC Order", xpicOrder);
  return spinDisk(deck, Tpetra::getDefaultComm(), outdir, 250);
}

TEUCHOS_UNIT_TEST(ImplicitTransfers, SpinningDiskQuarterRevolution) {
  const Spin flip = spinDiskImplicit("FLIP", "test_output/spinning_disk_implicit_flip");
  const Spin apic = spinDiskImplicit("APIC", "test_output/spinning_disk_implicit_apic");
  const Spin tpic = spinDiskImplicit("TPIC", "test_output/spinning_disk_implicit_tpic");
  out << "implicit spinning disk, a quarter revolution: relative loss of angular momentum FLIP " << flip.relativeLoss()
      << ", APIC " << apic.relativeLoss() << ", TPIC " << tpic.relativeLoss() << "; kinetic energy FLIP "
      << flip.kinetic << ", APIC " << apic.kinetic << ", TPIC " << tpic.kinetic << "\n";
  for (const Spin* s : {&flip, &apic, &tpic}) TEST_EQUALITY_CONST(s->status, "completed");
  // Measured: FLIP 3.6e-3, APIC 3.8e-5, TPIC 4.1e-5 (the affine transfers' loss is the Newton
  // tolerance's, not the transfers').
  TEST_COMPARE(std::abs(apic.relativeLoss()), <, 1e-4);
  TEST_COMPARE(std::abs(tpic.relativeLoss()), <, 1e-4);
  TEST_COMPARE(flip.relativeLoss(), >, 10.0 * std::abs(apic.relativeLoss()));
  // XPIC: order 1 is PIC's update (v_p = sum S v_i(t + dt)); order 5 keeps more of the spin.
  const Spin xpic1 = spinDiskImplicit("XPIC", "test_output/spinning_disk_implicit_xpic1", 1);
  const Spin xpic5 = spinDiskImplicit("XPIC", "test_output/spinning_disk_implicit_xpic5", 5);
  out << "implicit XPIC(1) " << xpic1.relativeLoss() << ", XPIC(5) " << xpic5.relativeLoss() << "\n";
  TEST_EQUALITY_CONST(xpic5.status, "completed");
  TEST_COMPARE(xpic5.relativeLoss(), <, 0.5 * xpic1.relativeLoss());
  TEST_COMPARE(xpic5.relativeLoss(), >, flip.relativeLoss());
}

// --- the seed bar (Problem 1, apps/bar_explicit_mpm_plane_stress.yaml) with each transfer ---

// Relative L2 error of u_x(L) over the run against the exact solution, without the projection
// correction (which only FLIP/PIC takes).
double seedBarError(const std::string& transfer, double flip, const std::string& name, int projectionIterations = 0) {
  auto deck = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/bar_explicit_mpm_plane_stress.yaml");
  ParameterList& ex = deck->sublist("Integrator").sublist("Explicit");
  ex.set("Transfer", transfer).set("FLIP Fraction", flip).set("Consistent Projection Iterations", projectionIterations);
  deck->sublist("Output").set("VTK Interval", 0).set("Plot", false).set("Progress", false);
  impm::validateDeck(*deck);
  impm::Simulation sim(*deck, Tpetra::getDefaultComm(), "test_output/seed_bar_" + name);
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  return r.status == "completed" ? r.relativeL2.at("ux_L") : HUGE_VAL;
}

// Measured: FLIP 2.48%, PIC 34.8%, APIC and TPIC 1.29% (the same for linear MPM, whose APIC is
// TPIC's formula), XPIC(5) 2.20%; FLIP with one projection correction (the deck) 1.46%.
TEUCHOS_UNIT_TEST(SeedBar, ErrorPerTransfer) {
  const double flip = seedBarError("FLIP/PIC", 1.0, "flip");
  const double pic = seedBarError("FLIP/PIC", 0.0, "pic");
  const double apic = seedBarError("APIC", 1.0, "apic");
  const double tpic = seedBarError("TPIC", 1.0, "tpic");
  const double xpic = seedBarError("XPIC", 1.0, "xpic5");
  const double corrected = seedBarError("FLIP/PIC", 1.0, "flip_projected", 1);
  out << "seed bar, relative L2 error of u_x(L): FLIP " << flip << ", PIC " << pic << ", APIC " << apic << ", TPIC "
      << tpic << ", XPIC(5) " << xpic << "; FLIP with one projection correction " << corrected << "\n";
  // The projection correction (the deck as shipped) takes FLIP from 2.48% to 1.46%, the 1D
  // lumped-mass rod's figure: asserted below 0.7 of FLIP (measured 0.59), and FLIP itself below
  // 2.8% (1.13 times the measured: the run is deterministic).
  TEST_COMPARE(corrected, <, 0.7 * flip);
  TEST_COMPARE(flip, <, 0.028);
  // The affine transfers keep the wave better than FLIP; XPIC(5) lies between FLIP and PIC's
  // smearing, near FLIP; PIC smears the front.
  TEST_COMPARE(apic, <, 0.6 * flip);
  TEST_COMPARE(tpic, <, 0.6 * flip);
  TEST_FLOATING_EQUALITY(apic, tpic, 1e-8);
  TEST_COMPARE(xpic, <, flip);
  TEST_COMPARE(xpic, >, apic);
  TEST_COMPARE(pic, >, 10.0 * flip);
}

}  // namespace
