// Deck sections Contact and Contact Pairs: contact between bodies (physics/MultiFieldContact.hpp).
// Contact chooses the grid's velocity fields (one shared field, where bodies that touch stick, or
// one per body) and the law of every pair of bodies; Contact Pairs gives a pair its own law and a
// name for its force in history.csv.
#include "solvers/Simulation.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

namespace impm {

using schema::choice;
using schema::number;
using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

namespace {
const char* const kLawDoc =
    "Coulomb: the bodies stop approaching and slide against each other with Coulomb friction mu = Friction "
    "(0: frictionless), and separate freely; No Slip: they move as one velocity field (bonded)";
const char* const kFrictionDoc = "Coulomb friction coefficient mu >= 0 (Law = Coulomb)";
}  // namespace

void addContactSchema(ParameterList& valid) {
  ParameterList& c = valid.sublist("Contact", false, "contact between bodies");
  choice(c, "Type", "Single Field", {"Single Field", "Multi Field"},
         "Single Field: the bodies share one grid velocity field, so bodies that touch stick together; Multi Field: "
         "each body has its own velocity field and bodies meet by the contact law (Bardenhagen et al. 2001), "
         "explicit and implicit (there as a penalty in the residual; see Implicit Penalty). The force of each pair of "
         "bodies on the first is in history.csv "
         "(<pair>_contact_<x|y|z>; a pair not in Contact Pairs: <first>_<second> in the deck's body order) and "
         "summary.yaml");
  choice(c, "Law", "Coulomb", {"Coulomb", "No Slip"},
         std::string("the law of every pair not in Contact Pairs. ") + kLawDoc);
  number(c, "Friction", 0.0, std::string(kFrictionDoc) + " of every pair not in Contact Pairs");
  choice(c, "Normals", "Larger Gradient", {"Larger Gradient", "Average"},
         "the contact normal at a node: Larger Gradient: the normal of the side with the larger volume gradient; "
         "Average: from the difference of the two sides' volume gradients, which tilts the normal at a body's "
         "corners (a block sliding on a slab then plows: 6% short of its frictionless travel, against 0.04% with "
         "Larger Gradient). Both give the two bodies opposite normals (momentum is conserved)");
  number(c, "Contact Distance", 0.0,
         "0: bodies are in contact at a node when they approach there (Bardenhagen), which may be up to a cell before "
         "their surfaces meet; > 0: also only where the centroids of their mass seen by the node lie closer along the "
         "normal than this many cell sizes (0.8 suits 2 particles per cell: touching surfaces are about 0.75 cells "
         "apart in this measure). The check keeps contact from braking a rolling body; a collision it detects later "
         "costs more energy");
  number(c, "Implicit Penalty", 30.0,
         "implicit integrator: the penalty factor alpha > 0 of the contact force in the residual, alpha r m (v* - "
         "v_new) / c_v with v* the contact law's velocity, r = c1 + c_p^2 / h^2 a node's stiffness per unit mass. "
         "The bodies' remaining approach is of order 1 / alpha of the one without contact (the preconditioner "
         "carries the penalty's stiffness, so a larger alpha costs no more GMRES iterations)");
  number(c, "Mass Screen", 1.0e-5,
         "a node where a body holds less than this fraction of the mass (or more than 1 minus it) is not a contact "
         "node for it: the far edge of a stencil carries too little mass for a reliable normal");
  valid
      .sublist("Contact Pairs", false,
               "named sublists, each a pair of bodies with its own contact law (Contact/Type = Multi Field)")
      .disableRecursiveValidation();
}

RCP<const ParameterList> build::contactPairsTemplate() {
  auto pl = rcp(new ParameterList("Contact Pairs"));
  pl->set("Bodies", "",
          "the two bodies, 'first, second' (names in Bodies, in either order); the pair's force in "
          "history.csv is the force of the second on the first");
  choice(*pl, "Law", "Coulomb", {"Coulomb", "No Slip"}, kLawDoc);
  number(*pl, "Friction", 0.0, kFrictionDoc);
  return pl;
}

namespace {
// The friction of a law entry (ContactSpec::kNoSlip for No Slip), checked.
double frictionOf(const ParameterList& l, const std::string& key) {
  const double mu = l.get<double>("Friction");
  if (!(mu >= 0) || !std::isfinite(mu))
    throw DeckError("'" + key + "/Friction' must be a finite coefficient >= 0, got " + formatNumber(mu));
  return l.get<std::string>("Law") == "No Slip" ? ContactSpec::kNoSlip : mu;
}

std::string trimmed(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}
}  // namespace

// The pair of bodies a Contact Pairs entry names, as body indices (first, second).
std::pair<int, int> Simulation::contactPairBodies(const std::string& key, const std::string& value) const {
  const size_t comma = value.find(',');
  const std::string first = trimmed(value.substr(0, comma));
  const std::string second = comma == std::string::npos ? "" : trimmed(value.substr(comma + 1));
  if (comma == std::string::npos || first.empty() || second.empty() || second.find(',') != std::string::npos)
    throw DeckError("'" + key + "' = '" + value + "' must name two bodies, 'first, second'");
  const int a = int(&bodyNamed(key, first) - bodies_.data()), b = int(&bodyNamed(key, second) - bodies_.data());
  if (a == b) throw DeckError("'" + key + "' = '" + value + "' names body '" + first + "' twice; a pair is two bodies");
  return {a, b};
}

// The contact of the deck: none (Single Field), or one field per body and a law per pair.
ContactSpec Simulation::buildContact() const {
  const ParameterList& c = deck_.sublist("Contact");
  const ParameterList& pairs = deck_.sublist("Contact Pairs");
  ContactSpec spec;
  if (c.get<std::string>("Type") != "Multi Field") {
    for (const BodySpec& b : bodies_)
      if (b.rigid)
        throw DeckError("'Bodies/" + b.name +
                        "/Rigid' = true needs 'Contact/Type' = Multi Field (a rigid body meets "
                        "the others through contact)");
    if (pairs.numParams() > 0)
      throw DeckError("'Contact Pairs/" + pairs.name(pairs.begin()) + "' needs 'Contact/Type' = Multi Field");
    return spec;
  }
  checkContactUsable();
  spec.massScreen = c.get<double>("Mass Screen");
  if (!(spec.massScreen >= 0 && spec.massScreen < 0.5))
    throw DeckError("'Contact/Mass Screen' must lie in [0, 0.5), got " + formatNumber(spec.massScreen));
  spec.contactDistance = c.get<double>("Contact Distance");
  if (!(spec.contactDistance >= 0) || !std::isfinite(spec.contactDistance))
    throw DeckError("'Contact/Contact Distance' must be a finite number of cells >= 0, got " +
                    formatNumber(spec.contactDistance));
  spec.normals =
      c.get<std::string>("Normals") == "Average" ? ContactSpec::Normals::Average : ContactSpec::Normals::LargerGradient;
  const int n = (int)bodies_.size();
  for (const BodySpec& b : bodies_) spec.bodies.push_back(b.name);
  readRigidBodies(spec);
  const double law = frictionOf(c, "Contact");
  std::vector<std::string> entry(n * (n - 1) / 2);  // the Contact Pairs entry of each pair
  spec.pairFriction.assign(n * (n - 1) / 2, law);
  spec.pairSign.assign(n * (n - 1) / 2, 1.0);
  spec.pairNames.resize(n * (n - 1) / 2);
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      spec.pairNames[ContactSpec::pairIndex(a, b, n)] = bodies_[a].name + "_" + bodies_[b].name;
  for (auto it = pairs.begin(); it != pairs.end(); ++it) {
    const std::string name = pairs.name(it), key = "Contact Pairs/" + name;
    const ParameterList& p = pairs.sublist(name);
    const auto [a, b] = contactPairBodies(key + "/Bodies", p.get<std::string>("Bodies"));
    const int k = ContactSpec::pairIndex(a, b, n);
    if (!entry[k].empty())
      throw DeckError("'" + key + "' and 'Contact Pairs/" + entry[k] + "' name the same pair of bodies");
    entry[k] = name;
    spec.pairSign[k] = a < b ? 1.0 : -1.0;  // the force on the body named first
    spec.pairFriction[k] = frictionOf(p, key);
    spec.pairNames[k] = name;
  }
  return spec;
}

// The rigid bodies' motions; at least one body must be free to move.
void Simulation::readRigidBodies(ContactSpec& spec) const {
  bool anyFree = false;
  for (const BodySpec& b : bodies_) {
    spec.rigid.push_back(b.rigid);
    spec.rigidVelocity.push_back(b.rigidVelocity);
    spec.rigidTime.push_back(b.motion);
    spec.rigidNormal.push_back(b.rigidNormal);
    anyFree = anyFree || !b.rigid;
  }
  if (!anyFree)
    throw DeckError("'Bodies/" + bodies_.front().name +
                    "/Rigid': every body is rigid; contact needs a body that is not");
}

// Multi-field contact: two bodies or more (at most MultiFieldContact::kMaxFields), no projection
// correction, no load applied at grid nodes (it would belong to no body). The implicit step
// refuses what it does not take (ImplicitNewmark::checkContactUsable).
void Simulation::checkContactUsable() const {
  const ParameterList& integrator = deck_.sublist("Integrator");
  if (shapeInfo(shape_).fixedParticles)
    throw DeckError("'Contact/Type' = Multi Field needs material points; 'Method/Shape Function' = " + shape_ +
                    " is a finite-element reference without contact");
  const double penalty = deck_.sublist("Contact").get<double>("Implicit Penalty");
  if (!(penalty > 0) || !std::isfinite(penalty))
    throw DeckError("'Contact/Implicit Penalty' must be a finite number > 0, got " + formatNumber(penalty));
  if (bodies_.size() < 2)
    throw DeckError("'Contact/Type' = Multi Field needs two bodies or more in Bodies, got " +
                    std::to_string(bodies_.size()));
  if ((int)bodies_.size() > MultiFieldContact::kMaxFields)
    throw DeckError("'Contact/Type' = Multi Field takes at most " + std::to_string(MultiFieldContact::kMaxFields) +
                    " bodies, got " + std::to_string(bodies_.size()));
  if (integrator.sublist("Explicit").get<int>("Consistent Projection Iterations") > 0)
    throw DeckError(
        "'Integrator/Explicit/Consistent Projection Iterations' must be 0 with 'Contact/Type' = Multi Field "
        "(the projection correction works on one velocity field)");
  const ParameterList& loads = deck_.sublist("Loads");
  for (auto it = loads.begin(); it != loads.end(); ++it) {
    const std::string type = loads.sublist(loads.name(it)).get<std::string>("Type");
    if (type == "Face Traction" || type == "Node Force")
      throw DeckError("'Loads/" + loads.name(it) + "/Type' = " + type +
                      " acts on grid nodes, which belong to no single body with 'Contact/Type' = Multi Field; use a "
                      "Particle Force or a Body Force");
  }
}

}  // namespace impm
