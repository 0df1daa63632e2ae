// The Drucker-Prager model (physics/materials/DruckerPragerModel.hpp) at the material point:
// element tests under mixed stress-strain control against the closed-form Mohr-Coulomb strength
// and dilatancy, and its consistent tangent against central differences.
//
// Closed forms (compression positive, sigma_1 the major principal stress, N = (1 + sin phi) /
// (1 - sin phi)): at failure sigma_1 = N sigma_3 + 2 c sqrt(N), and in steady plastic flow the
// volumetric strain rate over the axial one is -2 sin psi / (1 - sin psi) (dilation for psi > 0).
// The outer cone touches Mohr-Coulomb on the compressive meridian, where triaxial compression
// (sigma_2 = sigma_3) stays, so there both hold from first yield; the plane-strain match gives
// Mohr-Coulomb's plane-strain strength (associated flow) and dilatancy (any psi) once the flow is
// steady (the out-of-plane stress settled). With log strains and Kirchhoff stresses the finite
// strain return is the small-strain one, so the comparison holds to round-off at large strain.
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
using impm_test::principalStretch;
using impm_test::tangentMismatch;

constexpr double kDegree = 3.141592653589793 / 180.0;

MaterialParameters soil(double c, double phi, double psi, DruckerPragerCone cone, double H = 0.0, double cr = 0.0) {
  MaterialParameters p{1.0e7, 0.3, 1800.0, MaterialModel::DruckerPrager};
  p.cohesion = c;
  p.frictionAngle = phi;
  p.dilatancyAngle = psi;
  p.cone = cone;
  p.cohesionModulus = H;
  p.residualCohesion = cr;
  return p;
}

void checkElementTest(bool plane, double c, double phi, double psi, bool assertStrength, Teuchos::FancyOStream& out,
                      bool& success) {
  const double sigma3 = 1.0e5;
  const DruckerPragerCone cone = plane ? DruckerPragerCone::PlaneStrain : DruckerPragerCone::Outer;
  const Materials materials({soil(c, phi, psi, cone)}, plane ? PlaneCondition::PlaneStrain : PlaneCondition::Solid);
  const ElementTest r = plane ? compress<2>(materials, sigma3, -0.30, 300) : compress<3>(materials, sigma3, -0.10, 100);
  const double s = std::sin(phi * kDegree), N = (1 + s) / (1 - s);
  const double strength = N * sigma3 + 2 * c * std::sqrt(N);
  const double sp = std::sin(psi * kDegree), dilatancy = -2 * sp / (1 - sp);
  const double strengthError = std::abs(r.strength - strength) / strength;
  const double dilatancyError = std::abs(r.dilatancy - dilatancy);
  out << (plane ? "plane strain, plane-strain cone" : "triaxial compression, outer cone") << ", c = " << c
      << " Pa, phi = " << phi << ", psi = " << psi << ": sigma_1 = " << r.strength << " Pa against Mohr-Coulomb "
      << strength << " (relative error " << strengthError << "); d(eps_v)/d(eps_1) = " << r.dilatancy << " against "
      << dilatancy << " (error " << dilatancyError << "); alpha = " << r.alpha << "\n";
  TEST_COMPARE(r.alpha, >, 0.05);  // well into plastic flow
  if (assertStrength) TEST_COMPARE(strengthError, <, 1e-8);
  TEST_COMPARE(dilatancyError, <, 1e-6);
}

// Triaxial compression: from first yield, on the compressive meridian.
TEUCHOS_UNIT_TEST(DruckerPrager, TriaxialCompressionMatchesMohrCoulomb) {
  checkElementTest(false, 2.0e4, 30.0, 30.0, true, out, success);
  checkElementTest(false, 2.0e4, 30.0, 10.0, true, out, success);
  checkElementTest(false, 0.0, 35.0, 0.0, true, out, success);
}

// Plane strain, in steady flow: the strength with associated flow, the dilatancy for any psi
// (non-associated: the strength differs from Mohr-Coulomb's, printed).
TEUCHOS_UNIT_TEST(DruckerPrager, PlaneStrainFlowMatchesMohrCoulomb) {
  checkElementTest(true, 2.0e4, 30.0, 30.0, true, out, success);
  checkElementTest(true, 0.0, 35.0, 35.0, true, out, success);
  checkElementTest(true, 2.0e4, 30.0, 10.0, false, out, success);
}

// A cohesionless soil pulled apart returns to the apex, the stress-free state; with cohesion to
// p = (xi / eta) c, with no deviatoric stress.
TEUCHOS_UNIT_TEST(DruckerPrager, TensionReturnsToTheApex) {
  for (const double c : {0.0, 2.0e4}) {
    const Materials materials({soil(c, 30.0, 10.0, DruckerPragerCone::Outer)}, PlaneCondition::Solid);
    ElastoplasticDriver<3> d(materials.law());
    const double F[3][3] = {{1.01, 0.002, 0}, {0, 1.02, 0}, {0, 0, 1.015}};
    d.stepTo(F);
    const DruckerPragerModel dp = materials.law().druckerPrager(0);
    const double J = determinant<3>(d.F), p = J * (d.s[0] + d.s[1] + d.s[3]) / 3;
    double dev = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double t = J * d.s[StressLayout<3>::index(i, j)] - (i == j ? p : 0.0);
        dev += t * t;
      }
    out << "c = " << c << ": p = " << p << " (apex " << dp.xi / dp.eta * c << "), |dev tau| = " << std::sqrt(dev)
        << ", alpha = " << d.h[kHenckyInternal] << "\n";
    TEST_COMPARE(std::abs(p - dp.xi / dp.eta * c), <=, 1e-9 * (1e4 + c));
    TEST_COMPARE(std::sqrt(dev), <=, 1e-9 * (1e4 + c));
    TEST_COMPARE(d.h[kHenckyInternal], >, 0.0);  // psi > 0: the apex return is plastic volumetric flow
  }
}

// Cohesion softening: the cohesion falls with the plastic strain and stops at the residual one.
TEUCHOS_UNIT_TEST(DruckerPrager, CohesionSoftensToItsResidual) {
  const double c = 5.0e4, cr = 1.0e4, H = -5.0e5, sigma3 = 5.0e4;
  const Materials materials({soil(c, 30.0, 30.0, DruckerPragerCone::Outer, H, cr)}, PlaneCondition::Solid);
  const ElementTest r = compress<3>(materials, sigma3, -0.15, 150);
  const double s = std::sin(30.0 * kDegree), N = (1 + s) / (1 - s);
  const double residualStrength = N * sigma3 + 2 * cr * std::sqrt(N), peak = N * sigma3 + 2 * c * std::sqrt(N);
  out << "softened: sigma_1 = " << r.strength << " Pa, residual Mohr-Coulomb " << residualStrength << ", peak " << peak
      << ", alpha = " << r.alpha << " (c reaches c_r at alpha = " << (cr - c) / H << ")\n";
  TEST_COMPARE(r.alpha, >, (cr - c) / H);
  TEST_FLOATING_EQUALITY(r.strength, residualStrength, 1e-8);
}

// The consistent tangent against central differences (the J2 check, test/ElastoplasticDriver.hpp):
// from a yielded state (confined, then sheared), elastic unloading, a small and a large plastic
// step on the cone, with hardening, softening and none; a step to the apex.
template <int Dim>
void checkTangent(Teuchos::FancyOStream& out, bool& success) {
  const PlaneCondition plane = Dim == 2 ? PlaneCondition::PlaneStrain : PlaneCondition::Solid;
  for (const double H : {2.0e5, 0.0, -2.0e5}) {
    const Materials materials({soil(2.0e4, 30.0, 10.0, DruckerPragerCone::Outer, H, 0.0)}, plane);
    const double mu = materials.c33(0);
    ElastoplasticDriver<Dim> yielded(materials.law());
    for (int k = 1; k <= 4; ++k) {  // confined (volumetric -0.04), sheared (0.04 k)
      double F[Dim][Dim];
      principalStretch<Dim>(-0.02 * k / 4.0, -0.02 * k / 4.0, F);
      F[0][Dim - 1] += 0.04 * k;
      yielded.stepTo(F);
    }
    TEST_COMPARE(yielded.h[kHenckyInternal], >, 1e-3);
    const ElastoplasticDriver<Dim> virgin(materials.law());
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    struct Case {
      const char* name;
      const ElastoplasticDriver<Dim>* from;
      double G[Dim][Dim];
      bool plastic;
    };
    Case cases[4] = {{"elastic unloading", &yielded, {}, false},
                     {"cone, small step", &yielded, {}, true},
                     {"cone, large step", &yielded, {}, true},
                     {"apex", &virgin, {}, true}};
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        cases[0].G[i][j] = i == j ? -0.002 : 0.0;  // compression with the shear taken back
        cases[1].G[i][j] = 0.003 * u(rng) + (i == 0 && j == Dim - 1 ? 0.01 : 0.0);
        cases[2].G[i][j] = 0.05 * u(rng) + (i == 0 && j == Dim - 1 ? 0.1 : 0.0);
        cases[3].G[i][j] = i == j ? 0.02 : 0.001 * u(rng);
      }
    cases[0].G[0][Dim - 1] = -0.02;
    for (Case& c : cases) {
      bool plastic = false;
      double fromElastic = 0;
      const double worst = tangentMismatch<Dim>(*c.from, c.G, mu, plastic, fromElastic);
      out << Dim << "D Drucker-Prager (H = " << H << "), " << c.name << ": |Lie rate - J D| <= " << worst
          << " mu; |D - D_elastic| J = " << fromElastic << " mu\n";
      TEST_EQUALITY(plastic, c.plastic);
      TEST_COMPARE(worst, <, 1e-6);
      if (c.plastic) TEST_COMPARE(fromElastic, >, 0.1);
    }
  }
}

TEUCHOS_UNIT_TEST(DruckerPrager, PlaneStrainConsistentTangent) { checkTangent<2>(out, success); }
TEUCHOS_UNIT_TEST(DruckerPrager, SolidConsistentTangent) { checkTangent<3>(out, success); }

}  // namespace
