// The Mohr-Coulomb model (physics/materials/MohrCoulombModel.hpp) at the material point: element
// tests under mixed stress-strain control against the closed-form strength and dilatancy on the
// main plane and on both edges, the apex and the tension cutoff, softening, and the consistent
// tangent against central differences.
//
// Closed forms (compression positive, N = (1 + sin phi) / (1 - sin phi)): at failure the major and
// minor principal stresses satisfy sigma_1 = N sigma_3 + 2 c sqrt(N) whatever the intermediate one
// (triaxial compression sits on one edge, triaxial extension on the other, plane strain on the main
// plane), from first yield. In steady plastic flow the volumetric strain rate over the axial one is
// -2 sin psi / (1 - sin psi) when the axial stress is the major one (compression, plane strain) and
// 2 sin psi / (1 + sin psi) when it is the minor one (extension). With log strains and Kirchhoff
// stresses the finite-strain return is the small-strain one, so these hold to round-off at large
// strain.
#include <Teuchos_UnitTestHarness.hpp>

#include <cmath>
#include <random>

#include "physics/Materials.hpp"
#include "test/ElastoplasticDriver.hpp"

namespace {

using namespace impm;
using impm_test::compress;
using impm_test::ElastoplasticDriver;
using impm_test::ElementTest;
using impm_test::tangentMismatch;

constexpr double kDegree = 3.141592653589793 / 180.0;

MaterialParameters soil(double c, double phi, double psi, double H = 0.0, double cr = 0.0, double t = 0.0) {
  MaterialParameters p{1.0e7, 0.3, 1800.0, MaterialModel::MohrCoulomb};
  p.cohesion = c;
  p.frictionAngle = phi;
  p.dilatancyAngle = psi;
  p.cohesionModulus = H;
  p.residualCohesion = cr;
  p.tensionCutoff = t;
  return p;
}

double flowFactor(double phi) {
  const double s = std::sin(phi * kDegree);
  return (1 + s) / (1 - s);
}

// Kirchhoff stress tau = J sigma of the driver's state, component (i, j).
template <int Dim>
double tauOf(const ElastoplasticDriver<Dim>& d, int i, int j) {
  return determinant<Dim>(d.F) * d.s[StressLayout<Dim>::index(i, j)];
}

// Triaxial compression (3D, lateral stresses equal: the compression edge), triaxial extension (the
// extension edge, the axial stress the minor one) and plane strain (the main plane).
void checkElementTest(const char* name, int dim, double axialEnd, double c, double phi, double psi,
                      Teuchos::FancyOStream& out, bool& success) {
  const double sigma3 = 1.0e5, N = flowFactor(phi), sp = std::sin(psi * kDegree);
  const Materials materials({soil(c, phi, psi)}, dim == 2 ? PlaneCondition::PlaneStrain : PlaneCondition::Solid);
  const int steps = int(std::abs(axialEnd) * 1000);
  const ElementTest r =
      dim == 2 ? compress<2>(materials, sigma3, axialEnd, steps) : compress<3>(materials, sigma3, axialEnd, steps);
  const bool extension = axialEnd > 0;
  // Extension: the lateral stress sigma3 is the major one and the axial one the minor.
  const double strength = extension ? (sigma3 - 2 * c * std::sqrt(N)) / N : N * sigma3 + 2 * c * std::sqrt(N);
  const double dilatancy = extension ? 2 * sp / (1 + sp) : -2 * sp / (1 - sp);
  const double strengthError = std::abs(r.strength - strength) / strength;
  const double dilatancyError = std::abs(r.dilatancy - dilatancy);
  out << name << ", c = " << c << " Pa, phi = " << phi << ", psi = " << psi << ": axial stress " << r.strength
      << " Pa against Mohr-Coulomb " << strength << " (relative error " << strengthError
      << "); d(eps_v)/d(eps_axial) = " << r.dilatancy << " against " << dilatancy << " (error " << dilatancyError
      << "); alpha = " << r.alpha << "\n";
  TEST_COMPARE(r.alpha, >, 0.02);  // well into plastic flow
  TEST_COMPARE(strengthError, <, 1e-8);
  TEST_COMPARE(dilatancyError, <, 1e-6);
}

TEUCHOS_UNIT_TEST(MohrCoulomb, TriaxialCompressionOnTheCompressionEdge) {
  checkElementTest("triaxial compression", 3, -0.10, 2.0e4, 30.0, 30.0, out, success);
  checkElementTest("triaxial compression", 3, -0.10, 2.0e4, 30.0, 10.0, out, success);
  checkElementTest("triaxial compression", 3, -0.10, 0.0, 35.0, 0.0, out, success);
  checkElementTest("triaxial compression, Tresca (phi = 0)", 3, -0.10, 2.0e4, 0.0, 0.0, out, success);
}

TEUCHOS_UNIT_TEST(MohrCoulomb, TriaxialExtensionOnTheExtensionEdge) {
  checkElementTest("triaxial extension", 3, 0.10, 2.0e4, 30.0, 30.0, out, success);
  checkElementTest("triaxial extension", 3, 0.10, 0.0, 35.0, 5.0, out, success);
}

// Plane strain: the out-of-plane stress is the intermediate one, so the strength is Mohr-Coulomb's
// for any dilatancy (unlike a Drucker-Prager cone); the flow is steady once the out-of-plane
// stress has settled.
TEUCHOS_UNIT_TEST(MohrCoulomb, PlaneStrainOnTheMainPlane) {
  checkElementTest("plane strain", 2, -0.30, 2.0e4, 30.0, 30.0, out, success);
  checkElementTest("plane strain", 2, -0.30, 2.0e4, 30.0, 10.0, out, success);
  checkElementTest("plane strain", 2, -0.30, 0.0, 35.0, 0.0, out, success);
  checkElementTest("plane strain, Tresca (phi = 0)", 2, -0.30, 2.0e4, 0.0, 0.0, out, success);
}

// Stretched equally in every direction: without a cutoff the state returns to the apex
// p = c cot(phi) (c = 0: stress-free), with no deviatoric stress; with a cutoff t to p = t.
TEUCHOS_UNIT_TEST(MohrCoulomb, IsotropicTensionReturnsToAnApex) {
  const double phi = 30.0;
  for (const double c : {0.0, 2.0e4})
    for (const double t : {0.0, 1.0e4}) {
      if (c == 0.0 && t > 0.0) continue;  // a cutoff lies below the apex
      const Materials materials({soil(c, phi, 10.0, 0.0, 0.0, t)}, PlaneCondition::Solid);
      ElastoplasticDriver<3> d(materials.law());
      const double F[3][3] = {{1.01, 0.002, 0}, {0, 1.02, 0}, {0, 0, 1.015}};
      d.stepTo(F);
      const double apex = t > 0 ? t : c * std::cos(phi * kDegree) / std::sin(phi * kDegree);
      const double p = (tauOf(d, 0, 0) + tauOf(d, 1, 1) + tauOf(d, 2, 2)) / 3;
      double dev = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) dev += std::pow(tauOf(d, i, j) - (i == j ? p : 0.0), 2);
      out << "c = " << c << ", cutoff " << t << ": p = " << p << " (apex " << apex
          << "), |dev tau| = " << std::sqrt(dev) << ", alpha = " << d.h[kHenckyInternal] << "\n";
      TEST_COMPARE(std::abs(p - apex), <=, 1e-9 * (1e4 + c));
      TEST_COMPARE(std::sqrt(dev), <=, 1e-9 * (1e4 + c));
      // psi > 0: the Mohr-Coulomb apex is plastic volumetric flow; the cutoff leaves alpha alone.
      if (t == 0.0) TEST_COMPARE(d.h[kHenckyInternal], >, 0.0);
      if (t > 0.0) TEST_EQUALITY(d.h[kHenckyInternal], 0.0);
    }
}

// Uniaxial strain in tension: the axial stress rises elastically to the cutoff and stays there; the
// lateral stresses (lambda / (lambda + 2 mu) of it while elastic) stay below it.
TEUCHOS_UNIT_TEST(MohrCoulomb, UniaxialTensionStopsAtTheCutoff) {
  const double c = 5.0e4, t = 1.0e4;
  const Materials materials({soil(c, 30.0, 30.0, 0.0, 0.0, t)}, PlaneCondition::Solid);
  ElastoplasticDriver<3> d(materials.law());
  double worst = 0;
  for (int k = 1; k <= 20; ++k) {
    const double F[3][3] = {{1.0 + 1e-4 * k, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    d.stepTo(F);
    worst = std::max(worst, tauOf(d, 0, 0) - t);
  }
  out << "axial tau = " << tauOf(d, 0, 0) << " Pa (cutoff " << t << "), lateral " << tauOf(d, 1, 1) << ", "
      << tauOf(d, 2, 2) << "; largest excess over the steps " << worst << " Pa\n";
  TEST_COMPARE(std::abs(tauOf(d, 0, 0) - t), <=, 1e-9 * t);
  TEST_COMPARE(worst, <=, 1e-9 * t);
  TEST_COMPARE(tauOf(d, 1, 1), <, t);
  TEST_COMPARE(std::abs(tauOf(d, 1, 1) - tauOf(d, 2, 2)), <=, 1e-9 * t);
}

// Cohesion softening: the strength falls to the residual cohesion's.
TEUCHOS_UNIT_TEST(MohrCoulomb, CohesionSoftensToItsResidual) {
  const double c = 5.0e4, cr = 1.0e4, H = -5.0e5, sigma3 = 5.0e4;
  const Materials materials({soil(c, 30.0, 30.0, H, cr)}, PlaneCondition::Solid);
  const ElementTest r = compress<3>(materials, sigma3, -0.15, 150);
  const double N = flowFactor(30.0), residualStrength = N * sigma3 + 2 * cr * std::sqrt(N);
  out << "softened: sigma_1 = " << r.strength << " Pa, residual Mohr-Coulomb " << residualStrength << ", peak "
      << N * sigma3 + 2 * c * std::sqrt(N) << ", alpha = " << r.alpha << " (c reaches c_r at alpha = " << (cr - c) / H
      << ")\n";
  TEST_COMPARE(r.alpha, >, (cr - c) / H);
  TEST_FLOATING_EQUALITY(r.strength, residualStrength, 1e-8);
}

// The consistent tangent against central differences (test/ElastoplasticDriver.hpp): from a
// yielded state (confined, then sheared), elastic unloading and small and large plastic steps; from
// the virgin state axial compression with lateral stretch (3D: onto the compression edge), an
// isotropic stretch to the apex, a uniaxial stretch, a stretch with strong axial compression, and
// a pure shear; with and without a cutoff (with one, the isotropic and uniaxial stretches end on
// cutoffs, the pure shear on the cutoff and the main plane); hardening, softening and none.
template <int Dim>
void checkTangent(Teuchos::FancyOStream& out, bool& success) {
  const PlaneCondition plane = Dim == 2 ? PlaneCondition::PlaneStrain : PlaneCondition::Solid;
  for (const double t : {0.0, 1.0e4})
    for (const double H : {2.0e5, 0.0, -2.0e5}) {
      const Materials materials({soil(2.0e4, 30.0, 10.0, H, 0.0, t)}, plane);
      const double mu = materials.c33(0);
      ElastoplasticDriver<Dim> yielded(materials.law());
      for (int k = 1; k <= 4; ++k) {  // confined (volumetric -0.04), sheared (0.04 k)
        double F[Dim][Dim];
        impm_test::principalStretch<Dim>(-0.02 * k / 4.0, -0.02 * k / 4.0, F);
        F[0][Dim - 1] += 0.04 * k;
        yielded.stepTo(F);
      }
      TEST_COMPARE(yielded.h[kHenckyInternal], >, 1e-3);
      const ElastoplasticDriver<Dim> virgin(materials.law());
      std::mt19937 rng(11);
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      struct Case {
        const char* name;
        const ElastoplasticDriver<Dim>* from;
        double G[Dim][Dim];
        bool hardens;
      };
      // The cutoff does not change alpha: with one, the stretches harden only with a plane active.
      Case cases[8] = {{"elastic unloading", &yielded, {}, false},
                       {"planes, small step", &yielded, {}, true},
                       {"planes, large step", &yielded, {}, true},
                       {"axial compression, lateral stretch", &virgin, {}, true},
                       {"isotropic stretch", &virgin, {}, t == 0.0},
                       {"uniaxial stretch", &virgin, {}, t == 0.0},
                       {"stretch and axial compression", &virgin, {}, true},
                       {"shear (cutoff with the main plane)", &virgin, {}, true}};
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) {
          const bool axial = i == Dim - 1, diagonal = i == j;
          cases[0].G[i][j] = diagonal ? -0.002 : 0.0;  // compression with the shear taken back
          cases[1].G[i][j] = 0.003 * u(rng) + (i == 0 && j == Dim - 1 ? 0.01 : 0.0);
          cases[2].G[i][j] = 0.05 * u(rng) + (i == 0 && j == Dim - 1 ? 0.1 : 0.0);
          cases[3].G[i][j] = diagonal ? (axial ? -0.02 : 0.005) : 0.0;  // the laterals equal
          cases[4].G[i][j] = diagonal ? 0.02 : 0.001 * u(rng);
          cases[5].G[i][j] = diagonal && i == 0 ? 0.004 : 0.0;
          cases[6].G[i][j] = diagonal ? (i == 0 ? 0.02 : axial ? -0.03 : 0.0) : 0.0;
          cases[7].G[i][j] = diagonal ? (i == 0 ? 0.004 : axial ? -0.004 : 0.0) : 0.0;
        }
      cases[0].G[0][Dim - 1] = -0.02;
      cases[5].G[0][1] = 0.0005;
      for (Case& c : cases) {
        bool hardens = false;
        double fromElastic = 0;
        const double worst = tangentMismatch<Dim>(*c.from, c.G, mu, hardens, fromElastic);
        out << Dim << "D Mohr-Coulomb (H = " << H << ", cutoff " << t << "), " << c.name
            << ": |Lie rate - J D| <= " << worst << " mu; |D - D_elastic| J = " << fromElastic << " mu\n";
        TEST_EQUALITY(hardens, c.hardens);
        TEST_COMPARE(worst, <, 1e-6);
        if (&c != &cases[0]) TEST_COMPARE(fromElastic, >, 0.1);  // every other step is plastic
      }
    }
}

TEUCHOS_UNIT_TEST(MohrCoulomb, PlaneStrainConsistentTangent) { checkTangent<2>(out, success); }
TEUCHOS_UNIT_TEST(MohrCoulomb, SolidConsistentTangent) { checkTangent<3>(out, success); }

}  // namespace
