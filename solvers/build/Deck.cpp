// The deck's schema (each section's from its file under solvers/build/, in the deck's order), the
// check of a deck against it with one message naming the key, and the single-body form's
// conversion.
#include "solvers/build/Deck.hpp"

#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include <set>
#include <vector>
#include <sstream>
#include <stdexcept>

#include "core/DeckSchema.hpp"
#include "physics/materials/MaterialRegistry.hpp"
#include "solvers/build/Sections.hpp"

namespace impm {

using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

namespace {

const std::set<std::string> kCollections = {"Materials",     "Bodies", "Constraints", "Walls",
                                            "Contact Pairs", "Loads",  "Monitors"};
// Sublists handed unchanged to Trilinos packages, which validate them themselves.
const std::set<std::string> kPassThrough = {"Implicit Solver"};

std::string valueString(const Teuchos::ParameterEntry& e) {
  std::ostringstream os;
  e.leftshift(os, false);
  return os.str();
}

std::string join(const Teuchos::ParameterList& pl) {
  std::string s;
  for (auto it = pl.begin(); it != pl.end(); ++it) s += (s.empty() ? "" : ", ") + ("'" + pl.name(it) + "'");
  return s;
}

void checkList(const ParameterList& deck, const ParameterList& valid, const std::string& path);

void checkEntry(const ParameterList& deck, const ParameterList& valid, const std::string& key,
                const std::string& path) {
  const std::string where = path.empty() ? key : path + "/" + key;
  const Teuchos::ParameterEntry& entry = deck.getEntry(key);
  const Teuchos::ParameterEntry* ve = valid.getEntryPtr(key);
  if (!ve) throw DeckError("unknown key '" + where + "' (valid here: " + join(valid) + ")");
  if (ve->isList()) {
    if (!entry.isList()) throw DeckError("'" + where + "' must be a sublist, not a value");
    const ParameterList& sub = deck.sublist(key);
    if (kCollections.count(key) && path.empty()) {
      auto tmpl = collectionTemplate(key);
      for (auto it = sub.begin(); it != sub.end(); ++it) {
        const std::string item = sub.name(it);
        if (!sub.entry(it).isList())
          throw DeckError("'" + where + "/" + item + "' must be a sublist (one " + key + " entry)");
        checkList(sub.sublist(item), *tmpl, where + "/" + item);
      }
    } else if (!kPassThrough.count(where)) {
      checkList(sub, Teuchos::getValue<ParameterList>(*ve), where);
    }
    return;
  }
  if (entry.isList()) throw DeckError("'" + where + "' must be a value, not a sublist");
  auto validator = ve->validator();
  if (validator != Teuchos::null) {
    try {
      validator->validate(entry, key, path);
    } catch (const std::exception&) {
      std::string msg = "invalid value '" + valueString(entry) + "' for '" + where + "'";
      auto strings = validator->validStringValues();
      if (strings != Teuchos::null) {
        msg += " (valid: ";
        for (size_t k = 0; k < static_cast<size_t>(strings->size()); ++k) msg += (k ? ", " : "") + (*strings)[k];
        msg += ")";
      } else {
        msg += " (expected a number)";
      }
      throw DeckError(msg);
    }
  } else if (entry.getAny().type() != ve->getAny().type()) {
    throw DeckError("wrong type for '" + where + "': expected " + ve->getAny().typeName() + ", got '" +
                    valueString(entry) + "' (" + entry.getAny().typeName() + ")");
  }
}

void checkList(const ParameterList& deck, const ParameterList& valid, const std::string& path) {
  for (auto it = deck.begin(); it != deck.end(); ++it) checkEntry(deck, valid, deck.name(it), path);
}

}  // namespace

RCP<const ParameterList> validParameters() {
  static RCP<ParameterList> valid;
  if (valid != Teuchos::null) return valid;
  valid = rcp(new ParameterList("impm"));
  ParameterList& v = *valid;
  addProblemSchema(v);
  addGridSchema(v);
  v.sublist("Materials", false, "named sublists, each a material (see --print-defaults)").disableRecursiveValidation();
  v.sublist("Bodies", false,
            "named sublists, each a body: a shape filled with particles of one material (see --print-defaults); "
            "a later body replaces the particles of earlier ones inside its shape")
      .disableRecursiveValidation();
  addMethodSchema(v);
  addIntegratorSchema(v);
  addInitialConditionsSchema(v);
  v.sublist("Implicit Solver", false,
            "Newton solver of the implicit step (NOX, Belos, Ifpack2, Amesos2); validated by the solver, "
            "see --print-defaults")
      .disableRecursiveValidation();
  v.sublist("Constraints", false, "named sublists, each a displacement constraint (see --print-defaults)")
      .disableRecursiveValidation();
  v.sublist("Walls", false,
            "named sublists, each a rigid wall the bodies meet, with Coulomb friction (explicit and implicit; see "
            "--print-defaults)")
      .disableRecursiveValidation();
  addContactSchema(v);
  v.sublist("Loads", false, "named sublists, each an external load").disableRecursiveValidation();
  v.sublist("Monitors", false, "named sublists, each a particle quantity recorded in history.csv")
      .disableRecursiveValidation();
  addExactSolutionSchema(v);
  addDecompositionSchema(v);
  addOutputSchema(v);
  return valid;
}

RCP<const ParameterList> collectionTemplate(const std::string& collection) {
  if (collection == "Materials") return materialSchema();
  if (collection == "Bodies") return build::bodiesTemplate();
  if (collection == "Constraints") return build::constraintsTemplate();
  if (collection == "Walls") return build::wallsTemplate();
  if (collection == "Contact Pairs") return build::contactPairsTemplate();
  if (collection == "Loads") return build::loadsTemplate();
  if (collection == "Monitors") return build::monitorsTemplate();
  throw std::logic_error("no collection " + collection);
}

namespace {
// The sections of the single-body form (read, then converted by convertSingleBodyForm).
RCP<const ParameterList> legacyTemplate(const std::string& section) {
  auto pl = rcp(new ParameterList(section));
  if (section == "Material") {
    pl->setParameters(*collectionTemplate("Materials"));
    schema::choice(*pl, "Plane Condition", "Plane Strain", {"Plane Strain", "Plane Stress"}, "2D idealisation");
    schema::number(*pl, "Thickness", 1.0, "out-of-plane thickness b (m)");
  } else if (section == "Body") {
    schema::number(*pl, "X Min", 0.0, "left edge");
    schema::number(*pl, "X Max", 1.0, "right edge");
    schema::number(*pl, "Y Min", 0.0, "bottom edge");
    schema::number(*pl, "Y Max", 1.0, "top edge");
    pl->set("Particles Per Cell X", 2, "particles per cell in x");
    pl->set("Particles Per Cell Y", 2, "particles per cell in y");
    schema::choice(*pl, "Particle Placement", "Uniform", {"Uniform", "Gauss"}, build::kParticlePlacementDoc);
  } else {
    throw std::logic_error("no legacy section " + section);
  }
  return pl;
}

// The single-body form (sections Material and Body, the seed's decks) becomes the Materials
// entry "Material", the Rectangle "Body" in Bodies and the Grid's plane condition and
// thickness, so that everything after validation sees one form (and messages about it name
// 'Materials/Material/...', 'Bodies/Body/...', which contain the keys the user wrote).
void convertSingleBodyForm(ParameterList& deck) {
  for (const char* section : {"Material", "Body", "Materials", "Bodies"})
    if (deck.isParameter(section) && !deck.isSublist(section))
      throw DeckError(std::string("'") + section + "' must be a sublist, not a value");
  const bool legacy = deck.isSublist("Material") || deck.isSublist("Body");
  if (deck.isSublist("Bodies")) {
    for (const char* old : {"Material", "Body"})
      if (deck.isSublist(old))
        throw DeckError(std::string("'") + old +
                        "' is the single-body form and cannot be mixed with 'Bodies' (put it in "
                        "'Materials' / 'Bodies')");
    return;
  }
  if (deck.isSublist("Materials"))
    throw DeckError("'Materials' needs 'Bodies' (the single-body form uses 'Material' and 'Body')");
  if (!legacy)
    throw DeckError(
        "the deck has no body: add 'Materials' and 'Bodies', or the single-body sections 'Material' and 'Body'");
  if (deck.isSublist("Grid"))
    for (const char* key : {"Plane Condition", "Thickness"})
      if (deck.sublist("Grid").isParameter(key))
        throw DeckError(std::string("'Grid/") + key +
                        "' belongs to the 'Materials'/'Bodies' form; the single-body form "
                        "sets 'Material/" +
                        key + "'");
  ParameterList material = deck.isSublist("Material") ? deck.sublist("Material") : ParameterList("Material");
  ParameterList body = deck.isSublist("Body") ? deck.sublist("Body") : ParameterList("Body");
  checkList(material, *legacyTemplate("Material"), "Material");
  checkList(body, *legacyTemplate("Body"), "Body");
  material.validateParametersAndSetDefaults(*legacyTemplate("Material"));
  body.validateParametersAndSetDefaults(*legacyTemplate("Body"));
  if (!(material.get<double>("Thickness") > 0))
    throw DeckError("'Material/Thickness' must be positive, got " + valueString(material.getEntry("Thickness")));
  ParameterList& grid = deck.sublist("Grid");
  grid.set("Plane Condition", material.get<std::string>("Plane Condition"));
  grid.set("Thickness", material.get<double>("Thickness"));
  ParameterList& m = deck.sublist("Materials").sublist("Material");
  std::vector<std::string> keys = {"Young Modulus", "Poisson Ratio", "Density"};
  for (const auto& model : materialModels())
    keys.insert(keys.end(), model.parameterKeys.begin(), model.parameterKeys.end());
  for (const auto& key : keys) m.setEntry(key, material.getEntry(key));
  m.set("Model", material.get<std::string>("Model"));
  ParameterList& b = deck.sublist("Bodies").sublist("Body");
  b.set("Shape", std::string("Rectangle"));
  b.set("Material", std::string("Material"));
  for (const char* key : {"X Min", "X Max", "Y Min", "Y Max"}) b.set(key, body.get<double>(key));
  for (const char* key : {"Particles Per Cell X", "Particles Per Cell Y"}) b.set(key, body.get<int>(key));
  b.set("Particle Placement", body.get<std::string>("Particle Placement"));
  deck.remove("Material");
  deck.remove("Body");
}
}  // namespace

void validateDeck(ParameterList& deck) {
  const RCP<const ParameterList> valid = validParameters();
  // Deck keys name the single-body form in messages (e.g. 'Body/X Min'): check it first.
  for (const char* old : {"Material", "Body"})
    if (deck.isSublist(old) && deck.isSublist("Bodies"))
      throw DeckError(std::string("'") + old +
                      "' is the single-body form and cannot be mixed with 'Bodies' (put it in "
                      "'Materials' / 'Bodies')");
  // A 3D deck has no 2D idealisation: a Plane Condition or Thickness it names would be ignored.
  // And a 2D deck must not name z keys of the grid or of a body (a 3D deck that forgot
  // 'Grid/Dimension' would otherwise run as plane strain without a word).
  const bool hasDimension = deck.isSublist("Grid") && deck.sublist("Grid").isType<int>("Dimension");
  const int dimension = hasDimension ? deck.sublist("Grid").get<int>("Dimension") : 2;
  const bool solid = dimension == 3;
  // (Entries that validation filled in as defaults, in a deck validated before, do not count.)
  auto named = [](const ParameterList& list, const char* key) {
    return list.isParameter(key) && !list.getEntry(key).isDefault();
  };
  if (dimension == 2) {
    if (deck.isSublist("Grid"))
      for (const char* key : {"Cells Z", "Cell Size Z", "Origin Z"})
        if (named(deck.sublist("Grid"), key))
          throw DeckError(std::string("'Grid/") + key +
                          "' is a 3D key: set 'Grid/Dimension' = 3, or remove it for a 2D deck");
    if (deck.isSublist("Bodies")) {
      const ParameterList& bodies = deck.sublist("Bodies");
      for (auto it = bodies.begin(); it != bodies.end(); ++it)
        if (bodies.isSublist(bodies.name(it)))
          for (const char* key : {"Z Min", "Z Max", "Particles Per Cell Z"})
            if (named(bodies.sublist(bodies.name(it)), key))
              throw DeckError("'Bodies/" + bodies.name(it) + "/" + key +
                              "' is a 3D key: set 'Grid/Dimension' = 3, or remove it for a 2D deck");
    }
  }
  if (solid) {
    for (const char* key : {"Plane Condition", "Thickness"})
      if (named(deck.sublist("Grid"), key))
        throw DeckError(std::string("'Grid/") + key +
                        "' is a 2D idealisation; a deck with 'Grid/Dimension' = 3 has none (remove it)");
    if (deck.isSublist("Material") || deck.isSublist("Body"))
      throw DeckError(
          "the single-body form ('Material', 'Body') is 2D; a deck with 'Grid/Dimension' = 3 uses 'Materials' and "
          "'Bodies'");
  }
  convertSingleBodyForm(deck);
  checkList(deck, *valid, "");
  try {
    deck.validateParametersAndSetDefaults(*valid);
    for (const auto& c : kCollections) {
      ParameterList& coll = deck.sublist(c);
      auto tmpl = collectionTemplate(c);
      for (auto it = coll.begin(); it != coll.end(); ++it)
        coll.sublist(coll.name(it)).validateParametersAndSetDefaults(*tmpl);
    }
  } catch (const std::exception& e) {
    std::string what = e.what();
    throw DeckError("invalid deck: " + what.substr(0, what.find('\n')));
  }
}

void printDefaults(std::ostream& os, const std::map<std::string, RCP<const ParameterList>>& extra) {
  ParameterList full(*validParameters());
  for (const auto& [name, list] : extra) full.set(name, *list);
  for (const auto& c : kCollections) full.sublist(c).set("example", *collectionTemplate(c));
  Teuchos::writeParameterListToYamlOStream(full, os);
}

void printHelp(std::ostream& os, const std::map<std::string, RCP<const ParameterList>>& extra) {
  os << "Valid parameters (type, default and meaning); collections take any number of named entries:\n";
  ParameterList full(*validParameters());
  for (const auto& [name, list] : extra) full.set(name, *list);
  for (const auto& c : kCollections) full.sublist(c).set("<name>", *collectionTemplate(c));
  full.print(os, ParameterList::PrintOptions().showDoc(true).indent(2).showTypes(true));
}

}  // namespace impm
