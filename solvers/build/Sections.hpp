// The deck's sections: each one's schema, declared here and defined in the file of the section that
// reads it (solvers/build/<Section>Section.cpp, with its part of the Simulation builder), and the
// small readers they share. solvers/build/Deck.cpp assembles the schema in the deck's order.
#pragma once

#include <Teuchos_ParameterList.hpp>

#include <cmath>
#include <string>

#include "core/InputDeck.hpp"

namespace impm {

// The schema of each fixed section, added to the deck's list of valid parameters.
void addProblemSchema(Teuchos::ParameterList& valid);  // ProblemSection.cpp
void addOutputSchema(Teuchos::ParameterList& valid);
void addGridSchema(Teuchos::ParameterList& valid);  // GridSection.cpp
void addMethodSchema(Teuchos::ParameterList& valid);
void addDecompositionSchema(Teuchos::ParameterList& valid);
void addIntegratorSchema(Teuchos::ParameterList& valid);  // IntegratorSection.cpp
void addInitialConditionsSchema(Teuchos::ParameterList& valid);
void addExactSolutionSchema(Teuchos::ParameterList& valid);  // MonitorsSection.cpp
void addContactSchema(Teuchos::ParameterList& valid);        // ContactSection.cpp (Contact, Contact Pairs)

namespace build {

// One entry of each collection (Materials: physics/materials/MaterialRegistry.hpp).
Teuchos::RCP<const Teuchos::ParameterList> bodiesTemplate();       // BodiesSection.cpp
Teuchos::RCP<const Teuchos::ParameterList> constraintsTemplate();  // ConditionsSection.cpp
Teuchos::RCP<const Teuchos::ParameterList> loadsTemplate();
Teuchos::RCP<const Teuchos::ParameterList> wallsTemplate();         // WallsSection.cpp
Teuchos::RCP<const Teuchos::ParameterList> monitorsTemplate();      // MonitorsSection.cpp
Teuchos::RCP<const Teuchos::ParameterList> contactPairsTemplate();  // ContactSection.cpp
// The time-function keys of a load or a prescribed motion (physics/TimeFunction.hpp).
void timeFunctionKeys(Teuchos::ParameterList& pl, const std::string& def, const std::string& what);
// The documentation of Particle Placement (Bodies, and the single-body form's Body).
extern const char* const kParticlePlacementDoc;

// True when x is on a grid line x0 + k h (to round-off).
inline bool onGridLine(double x, double x0, double h) {
  const double k = (x - x0) / h;
  return std::abs(k - std::round(k)) < 1e-6;
}

}  // namespace build
}  // namespace impm
