// Deck section Materials: each entry read and checked by its model's registry entry
// (physics/materials/MaterialRegistry.hpp), which also holds the schema.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/Collective.hpp"
#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

#include "physics/materials/MaterialRegistry.hpp"

namespace impm {

using build::kParticlePlacementDoc;
using build::onGridLine;
using build::timeFunctionKeys;
using schema::choice;
using schema::number;
using schema::positive;
using schema::positiveInt;
using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

void Simulation::buildMaterials() {
  const ParameterList& ms = deck_.sublist("Materials");
  std::vector<MaterialParameters> params;
  for (auto it = ms.begin(); it != ms.end(); ++it) {
    const std::string name = ms.name(it), key = "Materials/" + name;
    const MaterialParameters p = readMaterial(ms.sublist(name), key, [&](const MaterialModelInfo& model) {
      if (!model.finiteStrain) return;
      if (grid_.dim == 2 && deck_.sublist("Grid").get<std::string>("Plane Condition") == "Plane Stress")
        throw DeckError(
            "'" + key + "/Model' = " + model.name +
            " is plane strain or 3D; 'Grid/Plane Condition' = Plane Stress "
            "would need the out-of-plane stretch solved per particle (use Plane Strain or Grid/Dimension 3)");
      if (shapeInfo(shape_).fixedParticles)
        throw DeckError("'" + key + "/Model' = " + model.name + " needs moving particles; 'Method/Shape Function' = " +
                        shape_ + " is the small-strain finite-element reference (use MPM, GIMP or cpGIMP)");
    });
    params.push_back(p);
    materialNames_.push_back(name);
  }
  const PlaneCondition plane = grid_.dim == 3 ? PlaneCondition::Solid
                               : deck_.sublist("Grid").get<std::string>("Plane Condition") == "Plane Stress"
                                   ? PlaneCondition::PlaneStress
                                   : PlaneCondition::PlaneStrain;
  if (params.empty()) throw DeckError("'Materials' is empty: a deck with Bodies needs at least one material");
  materials_ = Materials(params, plane);
}

}  // namespace impm
