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

namespace {

using namespace impm;

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
    law.template stress<Dim>(material, s0, G, F, s);
  }
  double energy(const double (&G)[Dim][Dim]) const {
    double s[StressLayout<Dim>::count];
    stress(G, s);
    double F[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) F[i][j] = (i == j ? 1.0 : 0.0) + G[i][j];
    return law.template energyDensity<Dim>(material, s, F);
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
  materials.law().stress<3>(0, s0, G, F, s);
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
    law.template stress<Dim>(material, s0, G, F, tau);
    const double J = determinant<Dim>(F);
    for (int c = 0; c < StressLayout<Dim>::count; ++c) tau[c] *= J;
  }
  double energy(const double (&F)[Dim][Dim]) const {
    double s[StressLayout<Dim>::count] = {};
    return determinant<Dim>(F) * law.template energyDensity<Dim>(material, s, F);
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
      if (i == j) G[i][i] = 1.0;
      else G[i][j] = G[j][i] = 0.5;
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
        for (int k = 0; k < Dim; ++k)
          convected += G[a][k] * tau[SL::index(k, b)] + tau[SL::index(a, k)] * G[b][k];
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

}  // namespace
