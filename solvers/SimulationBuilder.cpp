// Simulation, part 1: from the validated deck to the objects of a run. Every semantic check of the
// deck happens before anything is written: a DeckError names the key. Each deck section's schema
// and the code that reads it live together in solvers/build/<Section>Section.cpp; this file is
// the order in which they run.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/InputDeck.hpp"
#include "physics/InitialConditions.hpp"

namespace impm {

using Teuchos::ParameterList;

// The deck's sections in the order their checks must run (a later one needs the objects of an
// earlier one: the bodies need the grid and the materials, the conditions the particles, the
// exact solution the loads), each in its section's file under solvers/build/.
Simulation::Simulation(const ParameterList& deck, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                       const std::string& outputOverride)
    : deck_(deck), comm_(comm) {
  readProblem(outputOverride);  // ProblemSection.cpp
  readGrid();                   // GridSection.cpp
  readMethod();
  buildMaterials();      // MaterialsSection.cpp
  buildBodies();         // BodiesSection.cpp
  readTime();            // IntegratorSection.cpp
  readOutputSettings();  // ProblemSection.cpp
  checkProblemSize(deck_.sublist("Integrator").get<std::string>("Type") == "Implicit");
  std::vector<ConstraintSpec> cspecs = buildConstraints();  // ConditionsSection.cpp
  distribute();                                             // GridSection.cpp (Decomposition)
  createParticlesAndConditions(cspecs);
  readManufacturedSolution();                   // MonitorsSection.cpp (Exact Solution)
  applyInitialConditions();                     // IntegratorSection.cpp
  std::vector<LoadSpec> lspecs = buildLoads();  // ConditionsSection.cpp
  buildMonitors();                              // MonitorsSection.cpp
  buildExactSolution(cspecs, lspecs);
  buildIntegrator();  // IntegratorSection.cpp
}

// The bodies' particles on their ranks, then the grid conditions on them.
void Simulation::createParticlesAndConditions(const std::vector<ConstraintSpec>& cspecs) {
  try {
    particles_ = createParticles(bodies_, materials_, *dist_, placement_, thickness_);
    materials_.initializeHistory(particles_);
  } catch (const std::invalid_argument& e) {
    throw DeckError(e.what());
  }
  applyGeostaticStresses();
  checkConditionsReached(cspecs);
  wallSpecs_ = buildWalls();  // WallsSection.cpp
  checkParticlesBesideWalls(wallSpecs_);
  contactSpec_ = buildContact();  // ContactSection.cpp
  constraints_ = GridConditions(cspecs, *dist_, wallSpecs_, contactSpec_);
  constraintSpecs_ = cspecs;  // rebuilt for a new rank grid (load balance)
}

// Initial Stress = Geostatic: each such body's particles start at rest under their overburden.
void Simulation::applyGeostaticStresses() {
  for (int b = 0; b < (int)bodies_.size(); ++b) {
    const BodySpec& body = bodies_[b];
    if (!body.geostatic) continue;
    const std::string key = "Bodies/" + body.name;
    const double local = applyGeostaticStress(particles_, materials_, b, geostaticGravity(key), body.surfaceY, body.k0);
    double highest = local;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, local, Teuchos::outArg(highest));
    if (highest > body.surfaceY)
      throw DeckError("'" + key + "/Surface Y' = " + formatNumber(body.surfaceY) +
                      " lies below the body's highest particle at y = " + formatNumber(highest) +
                      " (the overburden would pull)");
  }
}

}  // namespace impm
