#include "physics/materials/MaterialRegistry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/DeckSchema.hpp"
#include "core/InputDeck.hpp"

namespace impm {

using Teuchos::ParameterList;

namespace {

void noParameters(ParameterList&) {}
void readNothing(const ParameterList&, const std::string&, MaterialParameters&) {}

void addJ2Parameters(ParameterList& pl) {
  schema::number(pl, "Yield Stress", 0.0, "J2 Plasticity: initial yield stress sigma_y (Pa, > 0)");
  schema::number(pl, "Hardening Modulus", 0.0, "J2 Plasticity: linear isotropic hardening modulus H (Pa, >= 0)");
}

void readJ2(const ParameterList& m, const std::string& key, MaterialParameters& p) {
  p.yieldStress = schema::positive(m, key, "Yield Stress");
  p.hardening = m.get<double>("Hardening Modulus");
  if (!(p.hardening >= 0))
    throw DeckError("'" + key + "/Hardening Modulus' must not be negative, got " + formatNumber(p.hardening));
}

const char* const kConeNames[] = {"Plane Strain", "Outer", "Inner"};

// The keys Drucker-Prager and Mohr-Coulomb share (schema order: Cone after Dilatancy Angle).
void addFrictionParameters(ParameterList& pl, bool withCone) {
  const std::string both = "Drucker-Prager, Mohr-Coulomb: ";
  schema::number(pl, "Cohesion", 0.0, both + "cohesion c_0 (Pa, >= 0)");
  schema::number(
      pl, "Friction Angle", 0.0,
      both + "friction angle phi (degrees, in (0, 90); Mohr-Coulomb also 0: Tresca, with c the undrained strength)");
  schema::number(pl, "Dilatancy Angle", 0.0,
                 both + "dilatancy angle psi (degrees, in [0, Friction Angle]; = phi: associated flow)");
  if (withCone)
    schema::choice(
        pl, "Cone", kConeNames[0], {kConeNames[0], kConeNames[1], kConeNames[2]},
        "Drucker-Prager: the cone's match to Mohr-Coulomb. Plane Strain: the Mohr-Coulomb collapse load in plane "
        "strain (associated flow); Outer: the compressive meridian (triaxial compression); Inner: the extensive "
        "meridian (triaxial extension)");
  schema::number(pl, "Cohesion Modulus", 0.0,
                 both +
                     "dc/dalpha, the cohesion's linear change with the equivalent plastic strain (Pa; negative: "
                     "softening, down to Residual Cohesion)");
  schema::number(pl, "Residual Cohesion", 0.0, both + "the cohesion softening stops at (Pa, in [0, Cohesion])");
}

void addDruckerPragerParameters(ParameterList& pl) { addFrictionParameters(pl, true); }

void addMohrCoulombParameters(ParameterList& pl) {
  addFrictionParameters(pl, true);  // the shared keys keep their place (set again, same values)
  schema::number(pl, "Tension Cutoff", 0.0,
                 "Mohr-Coulomb: the largest principal stress the soil carries, t (Pa, in (0, Cohesion cot(Friction "
                 "Angle))); 0: no cutoff but Mohr-Coulomb's apex c cot(phi)");
}

[[noreturn]] void failKey(const std::string& key, const std::string& k, const std::string& what, double v) {
  throw DeckError("'" + key + "/" + k + "' " + what + ", got " + formatNumber(v));
}

// The shared keys read and checked (Mohr-Coulomb takes phi = 0: Tresca).
void readFriction(const ParameterList& m, const std::string& key, MaterialParameters& p, bool zeroFriction) {
  p.cohesion = m.get<double>("Cohesion");
  p.frictionAngle = m.get<double>("Friction Angle");
  p.dilatancyAngle = m.get<double>("Dilatancy Angle");
  p.cohesionModulus = m.get<double>("Cohesion Modulus");
  p.residualCohesion = m.get<double>("Residual Cohesion");
  if (!(p.cohesion >= 0)) failKey(key, "Cohesion", "must not be negative", p.cohesion);
  if (!((zeroFriction ? p.frictionAngle >= 0 : p.frictionAngle > 0) && p.frictionAngle < 90))
    failKey(key, "Friction Angle", zeroFriction ? "must lie in [0, 90) degrees" : "must lie in (0, 90) degrees",
            p.frictionAngle);
  if (!(p.dilatancyAngle >= 0 && p.dilatancyAngle <= p.frictionAngle))
    failKey(key, "Dilatancy Angle", "must lie in [0, Friction Angle = " + formatNumber(p.frictionAngle) + "] degrees",
            p.dilatancyAngle);
  if (!(p.residualCohesion >= 0 && p.residualCohesion <= p.cohesion))
    failKey(key, "Residual Cohesion", "must lie in [0, Cohesion = " + formatNumber(p.cohesion) + "]",
            p.residualCohesion);
  if (!std::isfinite(p.cohesionModulus)) failKey(key, "Cohesion Modulus", "must be a number", p.cohesionModulus);
}

// Softening steeper than `limit` has no unique return (the yield surface would shrink faster than
// the elastic trial state relaxes).
void checkSoftening(const std::string& key, double modulus, double limit) {
  if (!(modulus > limit))
    failKey(key, "Cohesion Modulus",
            "softens faster than the returns allow (must exceed " + formatNumber(limit) + " Pa)", modulus);
}

void readDruckerPrager(const ParameterList& m, const std::string& key, MaterialParameters& p) {
  readFriction(m, key, p, false);
  const std::string cone = m.get<std::string>("Cone");
  for (int c = 0; c < 3; ++c)
    if (cone == kConeNames[c]) p.cone = DruckerPragerCone(c);
  // The cone's return divides by mu + K eta etaBar + xi^2 H, the apex's (etaBar > 0) by K + xi^2 H /
  // (eta etaBar).
  const double degree = 3.141592653589793 / 180.0, mu = p.E / (2 * (1 + p.nu)), K = p.E / (3 * (1 - 2 * p.nu));
  double eta = 0, xi = 0, etaBar = 0, xiBar = 0;
  DruckerPragerModel::coneSlopes(p.cone, p.frictionAngle * degree, eta, xi);
  DruckerPragerModel::coneSlopes(p.cone, p.dilatancyAngle * degree, etaBar, xiBar);
  const double coneLimit = -(mu + K * eta * etaBar) / (xi * xi);
  const double apexLimit = etaBar > 0 ? -K * eta * etaBar / (xi * xi) : coneLimit;
  checkSoftening(key, p.cohesionModulus, std::max(coneLimit, apexLimit));
}

void readMohrCoulomb(const ParameterList& m, const std::string& key, MaterialParameters& p) {
  readFriction(m, key, p, true);
  // The main plane's return divides by 4 (lambda sin phi sin psi + mu (1 + sin phi sin psi)) +
  // 4 cos^2(phi) H, the apex's (psi > 0) by K + H cos(phi) cot(phi) / sin(psi).
  const double degree = 3.141592653589793 / 180.0, mu = p.E / (2 * (1 + p.nu)), K = p.E / (3 * (1 - 2 * p.nu));
  const double lambda = K - 2 * mu / 3, sp = std::sin(p.frictionAngle * degree),
               cp = std::cos(p.frictionAngle * degree);
  const double sd = std::sin(p.dilatancyAngle * degree);
  const double planeLimit = -(lambda * sp * sd + mu * (1 + sp * sd)) / (cp * cp);
  const double apexLimit = sd > 0 ? -K * sd * sp / (cp * cp) : planeLimit;
  checkSoftening(key, p.cohesionModulus, std::max(planeLimit, apexLimit));
  p.tensionCutoff = m.get<double>("Tension Cutoff");
  const double apex = sp > 0 ? p.cohesion * cp / sp : std::numeric_limits<double>::infinity();
  if (!(p.tensionCutoff >= 0 && p.tensionCutoff < apex) && p.tensionCutoff != 0.0)
    failKey(key, "Tension Cutoff",
            "must lie in (0, Cohesion cot(Friction Angle) = " + formatNumber(apex) + ") Pa, or be 0 (no cutoff)",
            p.tensionCutoff);
}

}  // namespace

const std::vector<MaterialModelInfo>& materialModels() {
  static const std::vector<MaterialModelInfo> models = {
      {MaterialModel::LinearElastic,
       "Linear Elastic",
       "small strain (the seed problems)",
       false,
       0,
       noParameters,
       {},
       readNothing},
      {MaterialModel::NeoHookean,
       "Neo-Hookean",
       "compressible hyperelastic at finite strain, W = mu/2 (tr b - 3) - mu ln J + lambda/2 (ln J)^2 with the Lame "
       "constants of Young Modulus and Poisson Ratio",
       true,
       0,
       noParameters,
       {},
       readNothing},
      {MaterialModel::J2Plasticity,
       "J2 Plasticity",
       "von Mises elastoplasticity at finite strain (multiplicative split, Hencky elasticity, radial return, linear "
       "isotropic hardening: Yield Stress, Hardening Modulus)",
       true,
       J2PlasticityModel::historyCount,
       addJ2Parameters,
       {"Yield Stress", "Hardening Modulus"},
       readJ2},
      {MaterialModel::DruckerPrager,
       "Drucker-Prager",
       "pressure-dependent elastoplasticity for soils at finite strain (the J2 model's Hencky elasticity; a cone "
       "matched "
       "to Mohr-Coulomb, non-associated flow through the dilatancy angle, cone and apex returns, linear cohesion "
       "hardening or softening: Cohesion, Friction Angle, Dilatancy Angle, Cone, Cohesion Modulus, Residual Cohesion)",
       true,
       DruckerPragerModel::historyCount,
       addDruckerPragerParameters,
       {"Cohesion", "Friction Angle", "Dilatancy Angle", "Cone", "Cohesion Modulus", "Residual Cohesion"},
       readDruckerPrager},
      {MaterialModel::MohrCoulomb,
       "Mohr-Coulomb",
       "Mohr-Coulomb elastoplasticity for soils at finite strain (the J2 model's Hencky elasticity; the six planes "
       "with "
       "their edge and apex returns, non-associated flow through the dilatancy angle, an optional tension cutoff, "
       "linear cohesion hardening or softening: Cohesion, Friction Angle, Dilatancy Angle, Cohesion Modulus, Residual "
       "Cohesion, Tension Cutoff)",
       true,
       MohrCoulombModel::historyCount,
       addMohrCoulombParameters,
       {"Cohesion", "Friction Angle", "Dilatancy Angle", "Cohesion Modulus", "Residual Cohesion", "Tension Cutoff"},
       readMohrCoulomb},
  };
  static const bool historyFits = std::all_of(models.begin(), models.end(), [](const MaterialModelInfo& m) {
    return m.historyWidth <= ParticleSet::kHistoryCount;
  });
  if (!historyFits) throw std::logic_error("a material model's history is wider than ParticleSet::kHistoryCount");
  return models;
}

const MaterialModelInfo& materialModel(MaterialModel model) {
  for (const auto& m : materialModels())
    if (m.model == model) return m;
  throw std::logic_error("material model " + std::to_string(int(model)) + " is not registered");
}

const MaterialModelInfo* findMaterialModel(const std::string& name) {
  for (const auto& m : materialModels())
    if (m.name == name) return &m;
  return nullptr;
}

Teuchos::RCP<const ParameterList> materialSchema() {
  auto pl = Teuchos::rcp(new ParameterList("Materials"));
  std::vector<std::string> names;
  std::string doc = "constitutive model. ";
  for (const auto& m : materialModels()) {
    names.push_back(m.name);
    doc += m.name + ": " + m.summary + (&m == &materialModels().back() ? ". " : "; ");
  }
  doc += "The finite-strain models are plane strain or 3D, not with FE Q4/Q9";
  schema::choice(*pl, "Model", "Linear Elastic", names, doc);
  for (const auto& m : materialModels()) m.addParameters(*pl);
  schema::number(*pl, "Young Modulus", 200.0e9, "E (Pa)");
  schema::number(*pl, "Poisson Ratio", 0.3, "nu, in (-1, 0.5)");
  schema::number(*pl, "Density", 7800.0, "rho (kg/m^3)");
  return pl;
}

bool Materials::anyFiniteStrain() const {
  return std::any_of(params_.begin(), params_.end(),
                     [](const MaterialParameters& p) { return materialModel(p.model).finiteStrain; });
}

bool Materials::anyHistory() const {
  return std::any_of(params_.begin(), params_.end(),
                     [](const MaterialParameters& p) { return materialModel(p.model).historyWidth > 0; });
}

std::string Materials::modelName(MaterialModel m) { return materialModel(m).name; }

void Materials::initializeHistory(ParticleSet& ps) const {
  if (!anyHistory()) return;
  ps.allocateHistory();
  auto h = ps.history;
  auto material = ps.material;
  const Law law = law_;
  Kokkos::parallel_for(
      "initial_history", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        double row[ParticleSet::kHistoryCount];
        law.initialHistory(material(p), row);
        for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h(p, i) = row[i];
      });
}

MaterialParameters readMaterial(const ParameterList& m, const std::string& key,
                                const std::function<void(const MaterialModelInfo&)>& admissible) {
  MaterialParameters p;
  p.E = schema::positive(m, key, "Young Modulus");
  p.density = schema::positive(m, key, "Density");
  p.nu = m.get<double>("Poisson Ratio");
  if (!(p.nu > -1.0 && p.nu < 0.5))
    throw DeckError("'" + key + "/Poisson Ratio' must lie in (-1, 0.5), got " + formatNumber(p.nu));
  const std::string name = m.get<std::string>("Model");
  const MaterialModelInfo* model = findMaterialModel(name);
  if (!model) throw DeckError("'" + key + "/Model' = " + name + " is not a material model");
  p.model = model->model;
  admissible(*model);
  model->read(m, key, p);
  // Another model's key with a value (not whether it was written: a validated deck written out
  // and read back has its defaults written too).
  for (const auto& other : materialModels()) {
    if (&other == model) continue;
    for (const auto& k : other.parameterKeys)
      if (std::find(model->parameterKeys.begin(), model->parameterKeys.end(), k) == model->parameterKeys.end() &&
          m.isParameter(k) &&
          (m.isType<double>(k) ? m.get<double>(k) != 0.0
                               : m.get<std::string>(k) != materialSchema()->get<std::string>(k)))
        throw DeckError("'" + key + "/" + k + "' is a " + other.name + " parameter; 'Model' = " + name +
                        " does not use it");
  }
  return p;
}

}  // namespace impm
