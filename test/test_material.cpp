// The material law (physics/LinearElastic.hpp) against finite differences of its own strain
// energy: for a random small strain, dW/d(eps) = sigma (the stress update and the energy
// density are one law) and d(sigma)/d(eps) = D (the tangent the implicit stiffness uses), in
// plane strain, plane stress and 3D, for two materials of one table.
#include <Teuchos_UnitTestHarness.hpp>

#include <cmath>
#include <random>

#include "physics/LinearElastic.hpp"

namespace {

using namespace impm;

template <int Dim>
struct Probe {
  LinearElasticLaw law;
  int material;
  // Stress from zero after the displacement gradient G (copied to host: the law's table lives
  // on the device memory space, which is the host for OpenMP).
  void stress(const double (&G)[Dim][Dim], double* s) const {
    double s0[StressLayout<Dim>::count] = {};
    law.template stress<Dim>(material, s0, G, s);
  }
  double energy(const double (&G)[Dim][Dim]) const {
    double s[StressLayout<Dim>::count];
    stress(G, s);
    return law.template energyDensity<Dim>(material, s);
  }
};

template <int Dim>
void checkLaw(PlaneCondition plane, Teuchos::FancyOStream& out, bool& success) {
  using SL = StressLayout<Dim>;
  const LinearElastic materials({{200e9, 0.3, 7800}, {1e6, 0.45, 1000}}, plane);
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
    materials.law().template tangent<Dim>(m, D);
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
  const LinearElastic materials({{E, nu, 7800}}, PlaneCondition::Solid);
  const double eps = 1e-4;
  const double G[3][3] = {{eps, 0, 0}, {0, -nu * eps, 0}, {0, 0, -nu * eps}};
  double s0[6] = {}, s[6];
  materials.law().stress<3>(0, s0, G, s);
  TEST_FLOATING_EQUALITY(s[0], E * eps, 1e-12);
  TEST_COMPARE(std::abs(s[1]), <, 1e-12 * E * eps);
  TEST_COMPARE(std::abs(s[3]), <, 1e-12 * E * eps);
  TEST_FLOATING_EQUALITY(materials.barModulus(0), E, 1e-15);
}

}  // namespace
