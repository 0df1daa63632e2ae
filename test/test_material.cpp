// The material laws (physics/Materials.hpp) against finite differences of their own strain
// energy. Linear elastic: for a random small strain, dW/d(eps) = sigma (the stress update and
// the energy density are one law) and d(sigma)/d(eps) = D (the tangent the implicit stiffness
// uses), in plane strain, plane stress and 3D, for two materials of one table. Neo-Hookean, at
// a large random F: the Kirchhoff stress J sigma = dW/dF F^T, and the spatial tangent D is the
// derivative of the Lie (Truesdell) rate of J sigma, the one that with the geometric term makes
// the current-configuration stiffness exact.
#include <Teuchos_UnitTestHarness.hpp>

#include <cmath>
#include <random>

#include "physics/Materials.hpp"
#include "physics/materials/MaterialRegistry.hpp"
#include "test/ElastoplasticDriver.hpp"

namespace {

using namespace impm;
using impm_test::ElastoplasticDriver;
using impm_test::kirchhoffAfter;
using impm_test::tangentMismatch;

template <int Dim>
struct Probe {
  MaterialLaw law;
  int material;
  // Stress from zero after the displacement gradient G (copied to host: the law's table lives
  // on the device memory space, which is the host for OpenMP).
  void stress(const double (&G)[Dim][Dim], double* s) const {
    double s0[StressLayout<Dim>::count] = {};
    double F[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) F[i][j] = (i == j ? 1.0 : 0.0) + G[i][j];
    law.template stress<Dim>(material, s0, G, F, nullptr, s);
  }
  double energy(const double (&G)[Dim][Dim]) const {
    double s[StressLayout<Dim>::count];
    stress(G, s);
    double F[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) F[i][j] = (i == j ? 1.0 : 0.0) + G[i][j];
    return law.template energyDensity<Dim>(material, s, F, nullptr);
  }
};

template <int Dim>
void checkLaw(PlaneCondition plane, Teuchos::FancyOStream& out, bool& success) {
  using SL = StressLayout<Dim>;
  const Materials materials({{200e9, 0.3, 7800}, {1e6, 0.45, 1000}}, plane);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (int m = 0; m < 2; ++m) {
    const Probe<Dim> probe{materials.law(), m};
    double G[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) G[i][j] = u(rng);
    double s[SL::count];
    probe.stress(G, s);
    double D[SL::voigt][SL::voigt];
    materials.law().template tangent<Dim>(m, 1.0, D);
    const double scale = materials.c11(m) * 1e-3;  // a stress of the strains' size
    const double h = 1e-7;
    double worstStress = 0, worstTangent = 0;
    for (int v = 0; v < SL::voigt; ++v) {
      // Perturb the Voigt strain v: a normal strain, or an engineering shear through G_ij.
      const int i = SL::first(v), j = SL::second(v);
      double Gp[Dim][Dim], Gm[Dim][Dim];
      for (int a = 0; a < Dim; ++a)
        for (int b = 0; b < Dim; ++b) Gp[a][b] = Gm[a][b] = G[a][b];
      Gp[i][j] += h;
      Gm[i][j] -= h;
      const double dW = (probe.energy(Gp) - probe.energy(Gm)) / (2 * h);
      worstStress = std::max(worstStress, std::abs(dW - s[v]) / scale);
      TEST_COMPARE(std::abs(dW - s[v]), <, 1e-9 * scale);  // exact for a quadratic W, up to round-off (~1e-12)
      double sp[SL::count], sm[SL::count];
      probe.stress(Gp, sp);
      probe.stress(Gm, sm);
      for (int r = 0; r < SL::voigt; ++r) {
        const double dS = (sp[r] - sm[r]) / (2 * h);
        worstTangent = std::max(worstTangent, std::abs(dS - D[r][v]) / materials.c11(m));
        TEST_COMPARE(std::abs(dS - D[r][v]), <, 1e-9 * materials.c11(m));
      }
    }
    out << Dim << "D " << materials.planeName() << ", material " << m << ": |dW/deps - sigma| <= " << worstStress
        << " of c11 x 1e-3, |dsigma/deps - D| <= " << worstTangent << " of c11\n";
  }
}

// The device law's model flags (the kernels' branches) are copies of the registry's facts: each
// model's finiteStrain and whether it has history (historyWidth > 0) must agree, or a new model
// would be integrated in the wrong configuration or lose its history.
TEUCHOS_UNIT_TEST(Material, DeviceFlagsAgreeWithTheRegistry) {
  for (const impm::MaterialModelInfo& info : impm::materialModels()) {
    MaterialParameters p;
    p.E = 1e6;
    p.nu = 0.3;
    p.model = info.model;
    const Materials materials(std::vector<MaterialParameters>{p}, PlaneCondition::PlaneStrain);
    const auto law = materials.law();
    int flags = 0;
    Kokkos::parallel_reduce(
        "flags", Kokkos::RangePolicy<impm::ExecutionSpace>(0, 1),
        KOKKOS_LAMBDA(int, int& f) {
          f += (law.finiteStrain(0) ? 1 : 0) + (law.hasHistory(0) ? 2 : 0) + (law.isLinearElastic(0) ? 4 : 0);
        },
        flags);
    const bool finite = flags & 1, history = flags & 2, linear = flags & 4;
    out << info.name << ": finite strain " << finite << " (registry " << info.finiteStrain << "), history " << history
        << " (registry width " << info.historyWidth << ")\n";
    TEST_EQUALITY(finite, info.finiteStrain);
    TEST_EQUALITY(history, info.historyWidth > 0);
    TEST_EQUALITY(linear, !info.finiteStrain);
  }
}

TEUCHOS_UNIT_TEST(Material, PlaneStrainEnergyStressTangent) { checkLaw<2>(PlaneCondition::PlaneStrain, out, success); }
TEUCHOS_UNIT_TEST(Material, PlaneStressEnergyStressTangent) { checkLaw<2>(PlaneCondition::PlaneStress, out, success); }
TEUCHOS_UNIT_TEST(Material, SolidEnergyStressTangent) { checkLaw<3>(PlaneCondition::Solid, out, success); }

// 3D uniaxial stress: sigma_xx = E eps_xx when the lateral strains are -nu eps_xx (the bar's
// modulus is E, the one the 3D bar is compared with).
TEUCHOS_UNIT_TEST(Material, SolidUniaxialStressHasModulusE) {
  const double E = 200e9, nu = 0.3;
  const Materials materials({{E, nu, 7800}}, PlaneCondition::Solid);
  const double eps = 1e-4;
  const double G[3][3] = {{eps, 0, 0}, {0, -nu * eps, 0}, {0, 0, -nu * eps}};
  double s0[6] = {}, s[6];
  const double F[3][3] = {{1 + eps, 0, 0}, {0, 1 - nu * eps, 0}, {0, 0, 1 - nu * eps}};
  materials.law().stress<3>(0, s0, G, F, nullptr, s);
  TEST_FLOATING_EQUALITY(s[0], E * eps, 1e-12);
  TEST_COMPARE(std::abs(s[1]), <, 1e-12 * E * eps);
  TEST_COMPARE(std::abs(s[3]), <, 1e-12 * E * eps);
  TEST_FLOATING_EQUALITY(materials.barModulus(0), E, 1e-15);
}

// --- Neo-Hookean at finite strain ---

template <int Dim>
struct NeoHookeanProbe {
  MaterialLaw law;
  int material;
  // Kirchhoff stress tau = J sigma (stored layout) and W = J (W / J) at F.
  void kirchhoff(const double (&F)[Dim][Dim], double* tau) const {
    double s0[StressLayout<Dim>::count] = {}, G[Dim][Dim] = {};
    law.template stress<Dim>(material, s0, G, F, nullptr, tau);
    const double J = determinant<Dim>(F);
    for (int c = 0; c < StressLayout<Dim>::count; ++c) tau[c] *= J;
  }
  double energy(const double (&F)[Dim][Dim]) const {
    double s[StressLayout<Dim>::count] = {};
    return determinant<Dim>(F) * law.template energyDensity<Dim>(material, s, F, nullptr);
  }
};

template <int Dim>
void checkNeoHookean(Teuchos::FancyOStream& out, bool& success) {
  using SL = StressLayout<Dim>;
  const PlaneCondition plane = Dim == 2 ? PlaneCondition::PlaneStrain : PlaneCondition::Solid;
  MaterialParameters rubber{1e6, 0.3, 1000, MaterialModel::NeoHookean};
  MaterialParameters soft{2e4, 0.45, 1100, MaterialModel::NeoHookean};
  const Materials materials({rubber, soft}, plane);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int m = 0; m < 2; ++m) {
    TEST_ASSERT(materials.law().finiteStrain(m));
    const NeoHookeanProbe<Dim> probe{materials.law(), m};
    const double mu = materials.c33(m);
    // A large deformation: stretches and shears of up to 30%, det F well away from 0.
    double F[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) F[i][j] = (i == j ? 1.0 : 0.0) + u(rng);
    TEST_COMPARE(determinant<Dim>(F), >, 0.3);
    double tau[SL::count];
    probe.kirchhoff(F, tau);

    // tau = dW/dF F^T by central differences of W.
    const double h = 1e-6;
    double P[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int J = 0; J < Dim; ++J) {
        double Fp[Dim][Dim], Fm[Dim][Dim];
        for (int a = 0; a < Dim; ++a)
          for (int b = 0; b < Dim; ++b) Fp[a][b] = Fm[a][b] = F[a][b];
        Fp[i][J] += h;
        Fm[i][J] -= h;
        P[i][J] = (probe.energy(Fp) - probe.energy(Fm)) / (2 * h);
      }
    double worstStress = 0;
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        double t = 0;
        for (int k = 0; k < Dim; ++k) t += P[i][k] * F[j][k];
        worstStress = std::max(worstStress, std::abs(t - tau[SL::index(i, j)]) / mu);
      }
    TEST_COMPARE(worstStress, <, 1e-8);  // central differences at h = 1e-6: O(h^2) ~ 1e-12 plus round-off / h ~ 1e-10

    // Lie derivative: tau(F + h G F) - tau(F) - h (G tau + tau G^T) = h J D sym(G) + O(h^2), per
    // Voigt direction (a normal stretch, or an engineering shear through G_ij = G_ji = 1/2).
    double D[SL::voigt][SL::voigt];
    materials.law().template tangent<Dim>(m, determinant<Dim>(F), D);
    const double J = determinant<Dim>(F);
    double worstTangent = 0;
    for (int v = 0; v < SL::voigt; ++v) {
      double G[Dim][Dim] = {};
      const int i = SL::first(v), j = SL::second(v);
      if (i == j)
        G[i][i] = 1.0;
      else
        G[i][j] = G[j][i] = 0.5;
      double Fp[Dim][Dim], Fm[Dim][Dim], tp[SL::count], tm[SL::count];
      for (int a = 0; a < Dim; ++a)
        for (int b = 0; b < Dim; ++b) {
          double gf = 0;
          for (int k = 0; k < Dim; ++k) gf += G[a][k] * F[k][b];
          Fp[a][b] = F[a][b] + h * gf;
          Fm[a][b] = F[a][b] - h * gf;
        }
      probe.kirchhoff(Fp, tp);
      probe.kirchhoff(Fm, tm);
      for (int r = 0; r < SL::voigt; ++r) {
        const int a = SL::first(r), b = SL::second(r);
        double convected = 0;  // (G tau + tau G^T)_ab
        for (int k = 0; k < Dim; ++k) convected += G[a][k] * tau[SL::index(k, b)] + tau[SL::index(a, k)] * G[b][k];
        const double lie = (tp[r] - tm[r]) / (2 * h) - convected;
        worstTangent = std::max(worstTangent, std::abs(lie - J * D[r][v]) / mu);
      }
    }
    TEST_COMPARE(worstTangent, <, 1e-8);
    out << Dim << "D neo-Hookean, material " << m << ", det F = " << J << ": |dW/dF F^T - J sigma| <= " << worstStress
        << " mu, |Lie rate - J D| <= " << worstTangent << " mu\n";

    // Small strain: at F = I the tangent is the linear law's.
    double D0[SL::voigt][SL::voigt];
    materials.law().template tangent<Dim>(m, 1.0, D0);
    TEST_FLOATING_EQUALITY(D0[0][0], materials.c11(m), 1e-13);
    TEST_FLOATING_EQUALITY(D0[0][1], materials.c12(m), 1e-13);
    TEST_FLOATING_EQUALITY(D0[2][2], materials.c33(m), 1e-13);
  }
}

TEUCHOS_UNIT_TEST(Material, NeoHookeanPlaneStrainStressAndTangent) { checkNeoHookean<2>(out, success); }
TEUCHOS_UNIT_TEST(Material, NeoHookeanSolidStressAndTangent) { checkNeoHookean<3>(out, success); }

// --- J2 plasticity at finite strain ---

// Proportional loading in fixed principal axes, rotated by R: with logarithmic strains the
// return map is exactly the small-strain one, so the Kirchhoff stress must equal the closed-form
// small-strain J2 solution evaluated at the log strains, K tr(e) I + q n with
//   q = 2 mu |dev e| (elastic) or 2 mu (|dev e| - Gamma), Gamma = (2 mu |dev e| - sqrt(2/3) sigma_y) / (2 mu + 2 H /
//   3),
// and alpha = sqrt(2/3) Gamma: to round-off, after 40 steps that cross the yield point.
template <int Dim>
void checkJ2Proportional(Teuchos::FancyOStream& out, bool& success) {
  using SL = StressLayout<Dim>;
  const double E = 200e9, nu = 0.3, sy = 250e6, H = 2e9;
  MaterialParameters steel{E, nu, 7800, MaterialModel::J2Plasticity, sy, H};
  const Materials materials({steel}, Dim == 2 ? PlaneCondition::PlaneStrain : PlaneCondition::Solid);
  const double mu = materials.c33(0), lambda = materials.c12(0), K = lambda + 2 * mu / 3;
  // Final log strains: a 30% compression with lateral flow (plane strain: e_zz = 0).
  const double eFinal[3] = {-0.3, Dim == 2 ? 0.25 : 0.12, Dim == 2 ? 0.0 : 0.14};
  const double angle = 0.4;
  const double R[3][3] = {{std::cos(angle), -std::sin(angle), 0}, {std::sin(angle), std::cos(angle), 0}, {0, 0, 1}};
  ElastoplasticDriver<Dim> driver(materials.law());
  const int steps = 40;
  for (int k = 1; k <= steps; ++k) {
    const double t = double(k) / steps;
    double F[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        double v = 0;
        for (int a = 0; a < Dim; ++a) v += R[i][a] * std::exp(eFinal[a] * t) * R[j][a];  // R U (R^T): a rotated stretch
        F[i][j] = v;
      }
    driver.stepTo(F);
  }
  // Closed form.
  const double vol = eFinal[0] + eFinal[1] + eFinal[2];
  double dev[3], norm = 0;
  for (int a = 0; a < 3; ++a) {
    dev[a] = eFinal[a] - vol / 3;
    norm += dev[a] * dev[a];
  }
  norm = std::sqrt(norm);
  const double root23 = std::sqrt(2.0 / 3.0);
  const double Gamma = std::max(0.0, (2 * mu * norm - root23 * sy) / (2 * mu + 2 * H / 3));
  TEST_COMPARE(Gamma, >, 0.1);  // well into the plastic range
  const double q = 2 * mu * (norm - Gamma);
  const double J = std::exp(vol);
  double worst = 0;
  for (int i = 0; i < Dim; ++i)
    for (int j = i; j < Dim; ++j) {
      double tau = 0;
      for (int a = 0; a < Dim; ++a) tau += R[i][a] * (K * vol + q * dev[a] / norm) * R[j][a];
      worst = std::max(worst, std::abs(J * driver.s[SL::index(i, j)] - tau) / sy);
    }
  if (Dim == 2) worst = std::max(worst, std::abs(J * driver.s[3] - (K * vol + q * dev[2] / norm)) / sy);
  out << Dim << "D J2, 30% compression in " << steps << " rotated steps: |J sigma - closed form| <= " << worst
      << " sigma_y, alpha = " << driver.h[6] << " (closed form " << root23 * Gamma << ")\n";
  TEST_COMPARE(worst, <, 1e-8);
  TEST_FLOATING_EQUALITY(driver.h[6], root23 * Gamma, 1e-10);
}

TEUCHOS_UNIT_TEST(Material, J2PlaneStrainProportionalLoadingMatchesClosedForm) { checkJ2Proportional<2>(out, success); }
TEUCHOS_UNIT_TEST(Material, J2SolidProportionalLoadingMatchesClosedForm) { checkJ2Proportional<3>(out, success); }

// A random large step: the returned stress lies on the yield surface of the updated alpha, and
// plastic flow is isochoric (det b_e = J^2).
TEUCHOS_UNIT_TEST(Material, J2ReturnIsOnTheYieldSurfaceAndIsochoric) {
  const double sy = 1e6, H = 1e7;
  MaterialParameters clay{1e8, 0.35, 2000, MaterialModel::J2Plasticity, sy, H};
  const Materials materials({clay}, PlaneCondition::Solid);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  ElastoplasticDriver<3> driver(materials.law());
  for (int k = 0; k < 5; ++k) {
    double F[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F[i][j] = driver.F[i][j] + u(rng);
    driver.stepTo(F);
    const double J = determinant<3>(driver.F);
    TEST_COMPARE(J, >, 0.2);
    // |dev tau| against sqrt(2/3) (sigma_y + H alpha).
    double tau[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) tau[i][j] = J * driver.s[StressLayout<3>::index(i, j)];
    const double p = (tau[0][0] + tau[1][1] + tau[2][2]) / 3;
    double q2 = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) q2 += std::pow(tau[i][j] - (i == j ? p : 0.0), 2);
    const double radius = std::sqrt(2.0 / 3.0) * (sy + H * driver.h[6]);
    TEST_COMPARE(std::sqrt(q2), <=, radius * (1 + 1e-10));
    TEST_COMPARE(driver.h[6], >, 0.0);  // steps of 20% strain on a 1% yield strain all flow
    double be[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) be[i][j] = driver.h[StressLayout<3>::index(i, j)];
    TEST_FLOATING_EQUALITY(std::sqrt(determinant<3>(be)), J, 1e-10);
    out << "step " << k << ": J = " << J << ", |dev tau| / radius = " << std::sqrt(q2) / radius
        << ", alpha = " << driver.h[6] << "\n";
  }
}

// --- The consistent tangent of J2 at finite strain ---

// States: a rotated, stretched history that has yielded (alpha > 0, b_e != I), then from it an
// elastic unloading step, a plastic step in a random direction, and a large plastic step; and from
// the virgin state a uniaxial stretch past yield (two equal trial eigenvalues: the x coth x limit);
// with linear hardening and without (H = 0).
// Central differences at e = 1e-6 (measured: at most 2e-9 mu). Bound 1e-7 mu: the smallest terms
// of the tangent, the stress terms -2 tau_A, are of order sigma_y / mu ~ 3e-3, and the plastic
// tangent differs from the elastic one by O(mu). At the step's start after a plastic step (G = 0,
// on the yield surface), the tangent is the continuum one: the one-sided derivative of a step
// that goes on loading (forward differences along the last step's rate).
template <int Dim>
void checkJ2Tangent(Teuchos::FancyOStream& out, bool& success) {
  const PlaneCondition plane = Dim == 2 ? PlaneCondition::PlaneStrain : PlaneCondition::Solid;
  for (const double H : {2e9, 0.0}) {
    MaterialParameters steel{200e9, 0.3, 7800, MaterialModel::J2Plasticity, 250e6, H};
    const Materials materials({steel}, plane);
    const double mu = materials.c33(0);
    ElastoplasticDriver<Dim> yielded(materials.law());
    const double angle = 0.7;
    const double R[3][3] = {{std::cos(angle), -std::sin(angle), 0}, {std::sin(angle), std::cos(angle), 0}, {0, 0, 1}};
    const double stretch[3] = {std::exp(0.08), std::exp(-0.05), std::exp(-0.02)};
    for (int k = 1; k <= 4; ++k) {  // R U in four steps, with a shear
      double F[Dim][Dim];
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) {
          F[i][j] = 0;
          for (int a = 0; a < Dim; ++a) F[i][j] += R[i][a] * std::pow(stretch[a], k / 4.0) * (a == j ? 1.0 : 0.0);
        }
      F[0][Dim - 1] += 0.03 * k;
      yielded.stepTo(F);
    }
    TEST_COMPARE(yielded.h[6], >, 0.01);
    const ElastoplasticDriver<Dim> virgin(materials.law());

    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    struct Case {
      const char* name;
      const ElastoplasticDriver<Dim>* from;
      double G[Dim][Dim];
      bool plastic;
    };
    Case cases[4];
    cases[0] = {"elastic unloading", &yielded, {}, false};  // back by a 25th of the last step
    cases[1] = {"plastic, random direction", &yielded, {}, true};
    cases[2] = {"plastic, large step", &yielded, {}, true};
    cases[3] = {"plastic, uniaxial from virgin", &virgin, {}, true};
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        cases[0].G[i][j] = 0.0;
        cases[1].G[i][j] = 0.01 * u(rng);
        cases[2].G[i][j] = 0.15 * u(rng);
      }
    {
      double Fback[Dim][Dim], inv[Dim][Dim], f[Dim][Dim];
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) {
          Fback[i][j] = 0;
          for (int a = 0; a < Dim; ++a) Fback[i][j] += R[i][a] * std::pow(stretch[a], 0.99) * (a == j ? 1.0 : 0.0);
        }
      Fback[0][Dim - 1] += 0.03 * 3.96;
      inverse<Dim>(yielded.F, determinant<Dim>(yielded.F), inv);
      multiply<Dim>(Fback, inv, f);
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) cases[0].G[i][j] = f[i][j] - (i == j ? 1.0 : 0.0);
    }
    cases[3].G[0][0] = 0.02;
    for (Case& c : cases) {
      bool plastic = false;
      double fromElastic = 0;
      const double worst = tangentMismatch<Dim>(*c.from, c.G, mu, plastic, fromElastic);
      out << Dim << "D J2 (H = " << H << "), " << c.name << ": |Lie rate - J D| <= " << worst
          << " mu; |D - D_elastic| J = " << fromElastic << " mu\n";
      TEST_EQUALITY(plastic, c.plastic);
      TEST_COMPARE(worst, <, 1e-7);
      // The plastic tangent differs from the elastic one at order mu (the test can tell them apart).
      if (c.plastic) TEST_COMPARE(fromElastic, >, 0.1);
    }
    {
      // At the step's start: G = 0 from the yielded state, loading along the last step's rate L.
      using SL = StressLayout<Dim>;
      double Fprev[Dim][Dim], inv[Dim][Dim], fLast[Dim][Dim], L[Dim][Dim];
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) {
          Fprev[i][j] = 0;
          for (int a = 0; a < Dim; ++a) Fprev[i][j] += R[i][a] * std::pow(stretch[a], 0.75) * (a == j ? 1.0 : 0.0);
        }
      Fprev[0][Dim - 1] += 0.03 * 3;
      inverse<Dim>(Fprev, determinant<Dim>(Fprev), inv);
      multiply<Dim>(yielded.F, inv, fLast);
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) L[i][j] = 0.5 * (fLast[i][j] + fLast[j][i]) - (i == j ? 1.0 : 0.0);
      const double zero[Dim][Dim] = {}, J = determinant<Dim>(yielded.F), e = 1e-7;
      double D[SL::voigt][SL::voigt], De[SL::voigt][SL::voigt], tau0[SL::count], tau1[SL::count], Ge[Dim][Dim];
      materials.law().template tangent<Dim>(0, zero, J, yielded.h, D);
      materials.law().template tangent<Dim>(0, J, De);
      kirchhoffAfter(yielded, zero, tau0);
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) Ge[i][j] = e * L[i][j];
      kirchhoffAfter(yielded, Ge, tau1);
      double worst = 0, elasticWorst = 0;
      for (int r = 0; r < SL::voigt; ++r) {
        const int a = SL::first(r), b = SL::second(r);
        double convected = 0, cd = 0, cde = 0;
        for (int k = 0; k < Dim; ++k) convected += L[a][k] * tau0[SL::index(k, b)] + tau0[SL::index(a, k)] * L[b][k];
        for (int v = 0; v < SL::voigt; ++v) {
          const double strain =
              SL::first(v) == SL::second(v) ? L[SL::first(v)][SL::first(v)] : 2 * L[SL::first(v)][SL::second(v)];
          cd += J * D[r][v] * strain;
          cde += J * De[r][v] * strain;
        }
        const double lie = (tau1[r] - tau0[r]) / e - convected;
        worst = std::max(worst, std::abs(lie - cd) / mu);
        elasticWorst = std::max(elasticWorst, std::abs(lie - cde) / mu);
      }
      out << Dim << "D J2 (H = " << H << "), step start on the yield surface, loading: |Lie rate - J D L| <= " << worst
          << " mu (elastic tangent: " << elasticWorst << " mu)\n";
      TEST_COMPARE(worst, <, 1e-7);  // measured 1.2e-8 at e = 1e-7
      TEST_COMPARE(elasticWorst, >, 1e-3);
    }
  }
}

TEUCHOS_UNIT_TEST(Material, J2PlaneStrainConsistentTangent) { checkJ2Tangent<2>(out, success); }
TEUCHOS_UNIT_TEST(Material, J2SolidConsistentTangent) { checkJ2Tangent<3>(out, success); }

}  // namespace
