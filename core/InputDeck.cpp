#include "core/InputDeck.hpp"

#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Teuchos_XMLParameterListCoreHelpers.hpp>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include <fstream>
#include <set>
#include <sstream>

namespace impm {

using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

namespace {

RCP<Teuchos::AnyNumberParameterEntryValidator> numberValidator() {
  Teuchos::AnyNumberParameterEntryValidator::AcceptedTypes accept(false);
  accept.allowInt(true).allowDouble(true).allowString(false);
  return rcp(new Teuchos::AnyNumberParameterEntryValidator(
      Teuchos::AnyNumberParameterEntryValidator::PREFER_DOUBLE, accept));
}

void number(ParameterList& pl, const std::string& key, double def, const std::string& doc) {
  pl.set(key, def, doc, numberValidator());
}

void choice(ParameterList& pl, const std::string& key, const std::string& def,
            const std::vector<std::string>& values, const std::string& doc) {
  pl.set(key, def, doc, rcp(new Teuchos::StringValidator(Teuchos::Array<std::string>(values.begin(), values.end()))));
}

const std::set<std::string> kCollections = {"Constraints", "Loads", "Monitors"};
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
        for (size_t k = 0; k < strings->size(); ++k) msg += (k ? ", " : "") + (*strings)[k];
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

RCP<const ParameterList> collectionTemplate(const std::string& collection) {
  auto pl = rcp(new ParameterList(collection));
  if (collection == "Constraints") {
    choice(*pl, "Where", "Face", {"Face", "Node"}, "a face of the body, or the grid node at (X, Y)");
    choice(*pl, "Face", "x-", {"x-", "x+", "y-", "y+"}, "face of the body (Where = Face)");
    number(*pl, "X", 0.0, "x of the node (Where = Node)");
    number(*pl, "Y", 0.0, "y of the node (Where = Node)");
    choice(*pl, "Components", "xy", {"x", "y", "xy"}, "displacement components fixed to zero");
  } else if (collection == "Loads") {
    choice(*pl, "Type", "Face Traction", {"Face Traction", "Node Force", "Particle Force"},
           "uniform traction on a face of the body (consistent nodal forces), a force on the grid node at "
           "(X, Y), or a force carried by the particle nearest (X, Y)");
    choice(*pl, "Face", "x+", {"x-", "x+", "y-", "y+"}, "face of the body (Face Traction)");
    number(*pl, "X", 0.0, "x of the point (Node Force, Particle Force)");
    number(*pl, "Y", 0.0, "y of the point (Node Force, Particle Force)");
    number(*pl, "Force X", 0.0, "total force, x component (N)");
    number(*pl, "Force Y", 0.0, "total force, y component (N)");
    choice(*pl, "Time Function", "Step", {"Step", "Sine", "Constant"},
           "Step: F H(t - Start Time); Sine: F sin(omega t); Constant: F");
    number(*pl, "Angular Frequency", 0.0, "omega of the Sine time function (rad/s)");
    number(*pl, "Start Time", 0.0, "time at which a Step load comes on (s)");
  } else if (collection == "Monitors") {
    choice(*pl, "Quantity", "Displacement X",
           {"Displacement X", "Displacement Y", "Velocity X", "Velocity Y", "Stress XX", "Stress YY", "Stress XY"},
           "particle quantity recorded in history.csv");
    number(*pl, "X", 0.0, "the particle nearest (X, Y) at t = 0 is monitored");
    number(*pl, "Y", 0.0, "the particle nearest (X, Y) at t = 0 is monitored");
  } else {
    throw std::logic_error("no collection " + collection);
  }
  return pl;
}

RCP<const ParameterList> validParameters() {
  static RCP<ParameterList> valid;
  if (valid != Teuchos::null) return valid;
  valid = rcp(new ParameterList("impm"));
  {
    ParameterList& p = valid->sublist("Problem", false, "what is run and where its outputs go");
    p.set("Name", "impm run", "a name for the run, copied to summary.yaml");
    p.set("Output Directory", "impm-output", "directory for history.csv, summary.yaml, VTU/PVD and plot.png");
  }
  {
    ParameterList& p = valid->sublist("Grid", false, "structured background grid");
    number(p, "Origin X", 0.0, "x of the lower-left corner");
    number(p, "Origin Y", 0.0, "y of the lower-left corner");
    p.set("Cells X", 10, "number of cells in x");
    p.set("Cells Y", 1, "number of cells in y");
    number(p, "Cell Size X", 1.0, "cell size in x (m)");
    number(p, "Cell Size Y", 1.0, "cell size in y (m)");
  }
  {
    ParameterList& p = valid->sublist("Material", false, "small-strain isotropic linear elasticity");
    choice(p, "Model", "Linear Elastic", {"Linear Elastic"}, "constitutive model");
    number(p, "Young Modulus", 200.0e9, "E (Pa)");
    number(p, "Poisson Ratio", 0.3, "nu, in (-1, 0.5)");
    number(p, "Density", 7800.0, "rho (kg/m^3)");
    choice(p, "Plane Condition", "Plane Strain", {"Plane Strain", "Plane Stress"},
           "2D idealisation; a bar in plane stress has modulus E, in plane strain E/(1 - nu^2)");
    number(p, "Thickness", 1.0, "out-of-plane thickness b (m)");
  }
  {
    ParameterList& p = valid->sublist("Body", false, "rectangle of material; its edges lie on grid lines");
    number(p, "X Min", 0.0, "left edge");
    number(p, "X Max", 1.0, "right edge");
    number(p, "Y Min", 0.0, "bottom edge");
    number(p, "Y Max", 1.0, "top edge");
    p.set("Particles Per Cell X", 2, "particles per cell in x");
    p.set("Particles Per Cell Y", 2, "particles per cell in y");
  }
  {
    ParameterList& p = valid->sublist("Method", false, "spatial discretisation");
    choice(p, "Shape Function", "MPM", {"MPM", "GIMP", "FE Q4", "FE Q9"},
           "MPM: linear tent at particle points; GIMP: uniform GIMP; FE Q4 / FE Q9: the finite-element "
           "reference on the same kernels, particles fixed at the Gauss points (Q4: bilinear, 2 x 2 per cell; "
           "Q9: biquadratic Lagrange elements of 2 x 2 cells, 3 x 3 points; Cells X and Y even), implicit "
           "only; Body/Particles Per Cell is not used");
  }
  {
    ParameterList& p = valid->sublist("Integrator", false, "time integration");
    choice(p, "Type", "Explicit", {"Explicit", "Implicit"},
           "Explicit: USF/USL/MUSL; Implicit: Newmark average acceleration solved by Newton (see Implicit Solver)");
    number(p, "Time Step", 1.0e-8, "dt (s)");
    p.set("Number of Steps", 100, "number of time steps");
    ParameterList& e = p.sublist("Explicit", false, "explicit integrator options");
    choice(e, "Update Scheme", "USL", {"USF", "USL", "MUSL"}, "when the stress is updated");
    number(e, "FLIP Fraction", 1.0, "particle velocity update: 1 = FLIP, 0 = PIC, between = blend");
    e.set("Consistent Projection Iterations", 0,
          "Jacobi iterations towards the consistent-mass projection of particle momentum to grid velocity; "
          "0 = the classic lumped projection p/m, which smooths the velocity field by M_L^-1 M_C every step "
          "and about triples the lumped-mass wave dispersion; 1 removes that to O((kh)^4)");
    number(e, "Stability Factor", 1.0,
           "dt must not exceed this factor times 1 / (P-wave speed sqrt(1/hx^2 + 1/hy^2)), the critical step of "
           "lumped bilinear cells");
    ParameterList& im = p.sublist("Implicit", false, "implicit integrator options");
    im.set("Maximum Step Halvings", 4, "a step whose Newton iteration fails is retried with dt/2, dt/4, ... this many times");
    im.set("Consistent Projection Iterations", 0,
           "Jacobi iterations towards the consistent-mass projection of particle velocity and acceleration to "
           "the grid (0: lumped projection; see Integrator/Explicit); not used with Mass Matrix: Consistent, "
           "whose residual needs no projection");
    im.set("Preconditioner Refresh Interval", 1,
           "steps between numeric refactorisations of the Ifpack2 preconditioner (1: every step); its factors "
           "of a slightly older P remain a good preconditioner while the particles move little");
    choice(im, "Mass Matrix", "Lumped", {"Lumped", "Consistent"},
           "Lumped: Guilkey & Weiss; Consistent: R uses M_C u and particles take their own Newmark update, "
           "which conserves the particles' energy (P then holds the consistent mass too, except with GIMP Stiffness = Integrated)");
    choice(im, "GIMP Stiffness", "Integrated", {"Integrated", "Consistent"},
           "GIMP's assembled stiffness (preconditioner, or Jacobian of Assembled Newton): Integrated = the seed's "
           "D int_Omega_p B^T B, exact per particle-cell overlap; Consistent = V_p B^T D B with the averaged "
           "gradients, the exact derivative of the GIMP internal force");
    im.set("Consistent Initial Acceleration", true,
           "start from a(0) = M^-1 (F_ext(0) + F_int(0)) instead of zero particle accelerations");
  }
  {
    ParameterList& p = valid->sublist("Initial Conditions", false, "initial particle state (default: at rest)");
    choice(p, "Type", "None", {"None", "Standing Wave"},
           "None: particles at rest; Standing Wave: zero displacement and v_x(X, 0) = Amplitude sin(Mode pi "
           "(X - X Min) / L), L = the body's length (one mode of a bar fixed at both ends)");
    number(p, "Amplitude", 0.0, "velocity amplitude V of the Standing Wave (m/s), non-zero");
    p.set("Mode", 1, "mode number n >= 1 of the Standing Wave (n half-waves along the body)");
  }
  valid->sublist("Implicit Solver", false,
                 "Newton solver of the implicit step (NOX, Belos, Ifpack2, Amesos2); validated by the solver, "
                 "see --print-defaults").disableRecursiveValidation();
  valid->sublist("Constraints", false, "named sublists, each a displacement constraint (see --print-defaults)")
      .disableRecursiveValidation();
  valid->sublist("Loads", false, "named sublists, each an external load").disableRecursiveValidation();
  valid->sublist("Monitors", false, "named sublists, each a particle quantity recorded in history.csv")
      .disableRecursiveValidation();
  {
    ParameterList& p = valid->sublist("Exact Solution", false, "exact solution for the monitors, if any");
    choice(p, "Type", "None", {"None", "Bar Step Load", "Simply Supported Beam", "Bar Standing Wave"},
           "Bar Step Load: 1D rod fixed at X Min under the step load named by Load at X Max; "
           "Simply Supported Beam: Euler-Bernoulli beam under the harmonic point load named by Load; "
           "Bar Standing Wave: 1D rod fixed in x at both ends (Constraints on faces x- and x+), no loads, "
           "started by Initial Conditions/Type = Standing Wave: u = (V/omega) sin(n pi X/L) sin(omega t), "
           "omega = c n pi / L (displacement, velocity and stress XX)");
    choice(p, "Modulus", "Plane Condition", {"Plane Condition", "Young Modulus"},
           "modulus of the exact solution: Plane Condition = E in plane stress, E/(1-nu^2) in plane strain");
    p.set("Load", "", "name of the load (in Loads) that the exact solution is driven by (not used by Bar Standing Wave)");
    choice(p, "Form", "Closed", {"Closed", "Series"}, "bar: d'Alembert closed form or Fourier series");
    p.set("Series Terms", 2000, "terms of the series");
    choice(p, "Beam Theory", "Euler-Bernoulli", {"Euler-Bernoulli", "Timoshenko"},
           "beam: Euler-Bernoulli (the benchmark's formula), or Timoshenko (shear deformation and rotary "
           "inertia; deflection only, no stress)");
    number(p, "Shear Coefficient", 5.0 / 6.0, "Timoshenko shear coefficient kappa (5/6 for a rectangle)");
    choice(p, "Time Discretisation", "Exact", {"Exact", "Newmark"},
           "beam: Exact in time, or each mode advanced by the Newmark average-acceleration recurrence at the "
           "run's time step (what an exact-in-space Newmark integration gives: isolates the spatial error)");
  }
  {
    ParameterList& p = valid->sublist("Output", false, "what is written");
    p.set("History Interval", 10, "steps between rows of history.csv");
    p.set("VTK Interval", 0, "steps between VTU particle files (0: first and last step only)");
    p.set("Plot", true, "write plot.png (computed against exact) with python3-matplotlib");
    p.set("Progress", true, "print a progress line with ETA on runs longer than a few seconds");
  }
  return valid;
}

RCP<ParameterList> readDeck(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw DeckError("cannot open deck '" + path + "'");
  const auto dot = path.find_last_of('.');
  const std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  try {
    if (ext == "xml") return Teuchos::getParametersFromXmlFile(path);
    if (ext == "yaml" || ext == "yml") return Teuchos::getParametersFromYamlFile(path);
  } catch (const std::exception& e) {
    std::string what = e.what();
    // Teuchos parser messages can be long: keep the first line.
    throw DeckError("cannot parse deck '" + path + "': " + what.substr(0, what.find('\n')));
  }
  throw DeckError("deck '" + path + "' must end in .xml, .yaml or .yml");
}

void validateDeck(ParameterList& deck) {
  const RCP<const ParameterList> valid = validParameters();
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
