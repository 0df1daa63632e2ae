// The material models by deck name. Each model declares here what the rest of impm needs to know
// of it: its deck keys (with defaults, documentation and checks), whether it is written at finite
// strain, and the width of its per-particle history (its initial history is the device law's,
// MaterialLaw::initialHistory). The "Materials" schema, the builder's checks and the run's set-up
// come from this one list; the device side is the switch of MaterialLaw (physics/Materials.hpp).
//
// Adding a model: its law in physics/materials/<Name>Model.hpp (stress, tangent, energy, and
// initialHistory when it has history), one MaterialModel value, one case in each switch of
// MaterialLaw and in its flags (finiteStrain, hasHistory: test_material checks them against this
// list), and one entry of materialModels() in MaterialRegistry.cpp.
#pragma once

#include <Teuchos_ParameterList.hpp>

#include <functional>
#include <string>
#include <vector>

#include "physics/Materials.hpp"

namespace impm {

struct MaterialModelInfo {
  MaterialModel model;
  std::string name;     // the deck's 'Model'
  std::string summary;  // its part of the 'Model' documentation
  bool finiteStrain;    // written in the current configuration (plane strain or 3D, moving particles)
  int historyWidth;     // history values per particle (<= ParticleSet::kHistoryCount)
  // Its own keys (beyond Young Modulus, Poisson Ratio and Density), in schema order.
  void (*addParameters)(Teuchos::ParameterList& schema);
  std::vector<std::string> parameterKeys;
  // Reads and checks its own keys of the deck entry `key` (a DeckError naming the key).
  void (*read)(const Teuchos::ParameterList& entry, const std::string& key, MaterialParameters& p);
};

// Every model, in the order of the schema's choices.
const std::vector<MaterialModelInfo>& materialModels();
const MaterialModelInfo& materialModel(MaterialModel model);
// Null when no model has this name.
const MaterialModelInfo* findMaterialModel(const std::string& name);

// The schema of one entry of "Materials".
Teuchos::RCP<const Teuchos::ParameterList> materialSchema();

// One deck entry `Materials/<name>` read and checked: E, nu, density; then `admissible` (the
// run's checks of the model, e.g. finite strain in plane stress, throwing a DeckError); then the
// model's keys; a key of another model with a value other than zero is refused.
MaterialParameters readMaterial(const Teuchos::ParameterList& entry, const std::string& key,
                                const std::function<void(const MaterialModelInfo&)>& admissible);

}  // namespace impm
