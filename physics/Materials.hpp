// The materials of a run: one interface, a table of parameter sets indexed by the particle's
// material id, and a switch on each row's model (cb-geo/mpm's compute_stress/compute_dmatrix, as a
// Kokkos functor). The switch is the one closed list of models, deliberately: a device kernel takes
// no virtual calls, and one law type keeps one kernel instantiation for every material. The host
// side of each model (its deck keys, checks, finite strain and history width) is in
// physics/materials/MaterialRegistry.hpp; each law lives in its own file under physics/materials/.
// The kernels in core/ are templated on the law type and call only its device interface:
//   isLinearElastic(m)                small-strain linear elasticity (the kernels' inline fast path)
//   finiteStrain(m)                   the model is written in the current configuration (the
//                                     implicit residual then integrates over the deformed
//                                     domain and the stiffness adds the geometric term)
//   stress<Dim>(m, s0, G, F, h, s)    stress after a displacement-gradient increment G from
//                                     stress s0; F is the deformation gradient after it, h the
//                                     particle's history (hasHistory(m): read and updated)
//   tangent<Dim>(m, G, J, h, D)       dsigma/deps on the Voigt strains (2D: xx, yy, 2xy), for
//                                     K = int B^T D B over the current volume (J = V / V0), at
//                                     the state of stress<Dim> after the increment G from the
//                                     history h (the elastoplastic models: the consistent tangent of the return map)
//   tangent<Dim>(m, J, D)             the same without the particle's state (the elastoplastic models: elastic)
//   energyDensity<Dim>(m, s, F, h)    (elastic) strain energy per unit current volume
#pragma once

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/ParticleSet.hpp"
#include "core/Types.hpp"
#include "physics/materials/DruckerPragerModel.hpp"
#include "physics/materials/J2PlasticityModel.hpp"
#include "physics/materials/LinearElasticModel.hpp"
#include "physics/materials/MohrCoulombModel.hpp"
#include "physics/materials/NeoHookeanModel.hpp"

namespace impm {

// The 2D idealisations, and Solid for 3D.
enum class PlaneCondition { PlaneStrain, PlaneStress, Solid };

enum class MaterialModel { LinearElastic = 0, NeoHookean = 1, J2Plasticity = 2, DruckerPrager = 3, MohrCoulomb = 4 };

// One material's parameters, as the deck gives them. Neo-Hookean and J2 take their Lame
// constants from E and nu (the small-strain limit of both is the linear law).
struct MaterialParameters {
  double E = 1.0, nu = 0.0, density = 1.0;
  MaterialModel model = MaterialModel::LinearElastic;
  double yieldStress = 0.0, hardening = 0.0;  // J2: sigma_y (> 0) and the isotropic modulus H (>= 0)
  // Drucker-Prager and Mohr-Coulomb: c_0 (>= 0), the friction and dilatancy angles (degrees), the
  // cohesion's modulus H (negative: softening) and the residual cohesion c_r; Drucker-Prager's
  // match to Mohr-Coulomb; Mohr-Coulomb's tension cutoff (0: none).
  double cohesion = 0.0, frictionAngle = 0.0, dilatancyAngle = 0.0;
  DruckerPragerCone cone = DruckerPragerCone::PlaneStrain;
  double cohesionModulus = 0.0, residualCohesion = 0.0;
  double tensionCutoff = 0.0;
};

struct MaterialLaw {
  enum : int {
    Model = 0,
    C11,
    C12,
    C33,
    CZZ,
    InvDet,
    Lambda,
    Mu,
    Yield,
    Hardening,
    Eta,
    EtaBar,
    Xi,
    Residual,
    Tension,
    Count
  };
  Kokkos::View<double* [Count], Kokkos::LayoutRight, DeviceType> table;

  KOKKOS_FORCEINLINE_FUNCTION int model(int m) const { return (int)table(m, Model); }
  KOKKOS_FORCEINLINE_FUNCTION bool isLinearElastic(int m) const {
    return model(m) == (int)MaterialModel::LinearElastic;
  }
  // The device's copies of the registry's finiteStrain and historyWidth > 0 (test_material checks
  // that they agree for every model).
  KOKKOS_INLINE_FUNCTION bool finiteStrain(int m) const { return model(m) != (int)MaterialModel::LinearElastic; }
  // The elastoplastic models (J2, Drucker-Prager, Mohr-Coulomb): b_e and the equivalent plastic strain.
  KOKKOS_INLINE_FUNCTION bool hasHistory(int m) const {
    const int kind = model(m);
    return kind == (int)MaterialModel::J2Plasticity || kind == (int)MaterialModel::DruckerPrager ||
           kind == (int)MaterialModel::MohrCoulomb;
  }
  KOKKOS_FORCEINLINE_FUNCTION LinearElasticModel linearElastic(int m) const {  // inline: a 40-byte return
    return LinearElasticModel{table(m, C11), table(m, C12), table(m, C33), table(m, CZZ), table(m, InvDet)};
  }
  KOKKOS_INLINE_FUNCTION NeoHookeanModel neoHookean(int m) const {
    return NeoHookeanModel{table(m, Lambda), table(m, Mu)};
  }
  KOKKOS_INLINE_FUNCTION J2PlasticityModel j2(int m) const {
    return J2PlasticityModel{table(m, Lambda), table(m, Mu), table(m, Yield), table(m, Hardening)};
  }
  // Yield holds the cohesion c_0 and Hardening its modulus.
  KOKKOS_INLINE_FUNCTION DruckerPragerModel druckerPrager(int m) const {
    return DruckerPragerModel{table(m, Lambda), table(m, Mu),    table(m, Eta),       table(m, EtaBar),
                              table(m, Xi),     table(m, Yield), table(m, Hardening), table(m, Residual)};
  }
  // Mohr-Coulomb: Eta, Xi and EtaBar hold sin(phi), cos(phi) and sin(psi).
  KOKKOS_INLINE_FUNCTION MohrCoulombModel mohrCoulomb(int m) const {
    return MohrCoulombModel{table(m, Lambda),    table(m, Mu),       table(m, Eta),
                            table(m, Xi),        table(m, EtaBar),   table(m, Yield),
                            table(m, Hardening), table(m, Residual), table(m, Tension)};
  }

  // s may alias s0.
  template <int Dim>
  KOKKOS_FORCEINLINE_FUNCTION void stress(int m, const double* s0, const double (&G)[Dim][Dim],
                                          const double (&F)[Dim][Dim], double* h, double* s) const {
    const int kind = model(m);
    if (kind == (int)MaterialModel::LinearElastic)
      linearElastic(m).template stress<Dim>(s0, G, s);
    else if (kind == (int)MaterialModel::NeoHookean)
      neoHookean(m).template stress<Dim>(F, s);
    else if (kind == (int)MaterialModel::J2Plasticity)
      j2(m).template stress<Dim>(G, determinant<Dim>(F), h, s);
    else if (kind == (int)MaterialModel::DruckerPrager)
      druckerPrager(m).template stress<Dim>(G, determinant<Dim>(F), h, s);
    else
      mohrCoulomb(m).template stress<Dim>(G, determinant<Dim>(F), h, s);
  }
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void tangent(int m, double J,
                                      double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    const int kind = model(m);
    if (kind == (int)MaterialModel::LinearElastic)
      isotropicTangent<Dim>(table(m, C11), table(m, C12), table(m, C33), D);
    else if (kind == (int)MaterialModel::NeoHookean)
      neoHookean(m).template tangent<Dim>(J, D);
    else if (kind == (int)MaterialModel::J2Plasticity)
      j2(m).template tangent<Dim>(J, D);
    else if (kind == (int)MaterialModel::DruckerPrager)
      druckerPrager(m).template tangent<Dim>(J, D);
    else
      mohrCoulomb(m).template tangent<Dim>(J, D);
  }
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void tangent(int m, const double (&G)[Dim][Dim], double J, const double* h,
                                      double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    if (model(m) == (int)MaterialModel::J2Plasticity)
      j2(m).template tangent<Dim>(G, J, h, D);
    else if (model(m) == (int)MaterialModel::DruckerPrager)
      druckerPrager(m).template tangent<Dim>(G, J, h, D);
    else if (model(m) == (int)MaterialModel::MohrCoulomb)
      mohrCoulomb(m).template tangent<Dim>(G, J, h, D);
    else
      tangent<Dim>(m, J, D);
  }
  // The history a particle of material m starts with (zeros for a model without history).
  KOKKOS_INLINE_FUNCTION void initialHistory(int m, double* h) const {
    for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = 0.0;
    if (hasHistory(m)) henckyInitialHistory(h);
  }
  template <int Dim>
  KOKKOS_INLINE_FUNCTION double energyDensity(int m, const double* s, const double (&F)[Dim][Dim],
                                              const double* h) const {
    const int kind = model(m);
    if (kind == (int)MaterialModel::LinearElastic) return linearElastic(m).template energyDensity<Dim>(s);
    if (kind == (int)MaterialModel::NeoHookean) return neoHookean(m).template energyDensity<Dim>(F);
    if (kind == (int)MaterialModel::J2Plasticity) return j2(m).energyDensity(h, determinant<Dim>(F));
    if (kind == (int)MaterialModel::DruckerPrager) return druckerPrager(m).energyDensity(h, determinant<Dim>(F));
    return mohrCoulomb(m).energyDensity(h, determinant<Dim>(F));
  }
};

// The host side: the parameter sets (material id = index), the plane condition, and the
// device law built from them.
class Materials {
 public:
  using Law = MaterialLaw;
  Materials() : Materials(std::vector<MaterialParameters>{MaterialParameters{}}, PlaneCondition::PlaneStrain) {}
  Materials(const std::vector<MaterialParameters>& materials, PlaneCondition plane)
      : params_(materials), plane_(plane) {
    law_.table = decltype(law_.table)("material_constants", materials.size());
    auto h = Kokkos::create_mirror_view(law_.table);
    for (int m = 0; m < (int)materials.size(); ++m) {
      const double E = params_[m].E, nu = params_[m].nu;
      h(m, Law::Model) = (double)params_[m].model;
      h(m, Law::C11) = c11(m);
      h(m, Law::C12) = c12(m);
      h(m, Law::C33) = c33(m);
      h(m, Law::CZZ) = czz(m);
      h(m, Law::InvDet) = 1.0 / (c11(m) * c11(m) - c12(m) * c12(m));
      h(m, Law::Lambda) = E * nu / ((1 + nu) * (1 - 2 * nu));
      h(m, Law::Mu) = E / (2 * (1 + nu));
      h(m, Law::Yield) = params_[m].yieldStress;
      h(m, Law::Hardening) = params_[m].hardening;
      if (params_[m].model == MaterialModel::DruckerPrager) {
        const double degree = 3.141592653589793 / 180.0;
        double eta = 0, etaBar = 0, xi = 0, xiBar = 0;
        DruckerPragerModel::coneSlopes(params_[m].cone, params_[m].frictionAngle * degree, eta, xi);
        DruckerPragerModel::coneSlopes(params_[m].cone, params_[m].dilatancyAngle * degree, etaBar, xiBar);
        h(m, Law::Eta) = eta;
        h(m, Law::EtaBar) = etaBar;
        h(m, Law::Xi) = xi;
        h(m, Law::Yield) = params_[m].cohesion;
        h(m, Law::Hardening) = params_[m].cohesionModulus;
        h(m, Law::Residual) = params_[m].residualCohesion;
      }
      if (params_[m].model == MaterialModel::MohrCoulomb) {
        const double degree = 3.141592653589793 / 180.0;
        h(m, Law::Eta) = std::sin(params_[m].frictionAngle * degree);
        h(m, Law::Xi) = std::cos(params_[m].frictionAngle * degree);
        h(m, Law::EtaBar) = std::sin(params_[m].dilatancyAngle * degree);
        h(m, Law::Yield) = params_[m].cohesion;
        h(m, Law::Hardening) = params_[m].cohesionModulus;
        h(m, Law::Residual) = params_[m].residualCohesion;
        h(m, Law::Tension) = params_[m].tensionCutoff;
      }
    }
    Kokkos::deep_copy(law_.table, h);
  }
  // One linear-elastic material (id 0).
  Materials(double E, double nu, double density, PlaneCondition plane = PlaneCondition::PlaneStrain)
      : Materials(std::vector<MaterialParameters>{MaterialParameters{E, nu, density}}, plane) {}

  const Law& law() const { return law_; }
  int count() const { return (int)params_.size(); }
  const MaterialParameters& parameters(int m) const { return params_[m]; }
  PlaneCondition plane() const { return plane_; }
  // From the registry of models (physics/materials/MaterialRegistry.cpp).
  bool anyFiniteStrain() const;
  bool anyHistory() const;
  static std::string modelName(MaterialModel m);
  // Allocates the particles' history (when a material has one) and gives each particle its
  // material's initial history.
  void initializeHistory(ParticleSet& ps) const;
  double density(int m) const { return params_[m].density; }
  double c11(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ != PlaneCondition::PlaneStress ? E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) : E / (1 - nu * nu);
  }
  double c12(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ != PlaneCondition::PlaneStress ? E * nu / ((1 + nu) * (1 - 2 * nu)) : E * nu / (1 - nu * nu);
  }
  double c33(int m) const { return params_[m].E / (2 * (1 + params_[m].nu)); }
  double czz(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ == PlaneCondition::PlaneStrain ? E * nu / ((1 + nu) * (1 - 2 * nu)) : 0.0;
  }
  // The modulus a slender 1D bar of this model sees: E in plane stress and in 3D (lateral faces
  // free), E/(1 - nu^2) in plane strain.
  double barModulus(int m = 0) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ != PlaneCondition::PlaneStrain ? E : E / (1 - nu * nu);
  }
  // P-wave speed of the model at small strain (2D or 3D), for the explicit stable time step; the
  // fastest over the table.
  double pWaveSpeed(int m) const { return std::sqrt(c11(m) / density(m)); }
  double maxPWaveSpeed() const {
    double c = 0;
    for (int m = 0; m < count(); ++m) c = std::max(c, pWaveSpeed(m));
    return c;
  }
  std::string planeName() const {
    return plane_ == PlaneCondition::PlaneStrain   ? "plane strain"
           : plane_ == PlaneCondition::PlaneStress ? "plane stress"
                                                   : "3D";
  }

 private:
  std::vector<MaterialParameters> params_;
  PlaneCondition plane_ = PlaneCondition::PlaneStrain;
  Law law_;
};

}  // namespace impm
