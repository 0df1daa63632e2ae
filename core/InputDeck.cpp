#include "core/InputDeck.hpp"
#include "core/ShapeRegistry.hpp"

#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Teuchos_XMLParameterListCoreHelpers.hpp>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include <fstream>
#include <iomanip>
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

// The time-function keys of a load or a prescribed motion (physics/TimeFunction.hpp).
void timeFunctionKeys(ParameterList& pl, const std::string& def, const std::string& what) {
  choice(pl, "Time Function", def, {"Step", "Sine", "Constant", "Ramp", "Table"},
         what + ". Step: H(t - Start Time); Sine: sin(omega t); Constant: 1; Ramp: min(max(t - Start Time, 0) / Ramp "
         "Time, 1), for quasi-static loading; Table: linear between the (t, value) pairs of Table, the end values held "
         "outside them");
  number(pl, "Ramp Time", 0.0, "duration of the rise of a Ramp (s)");
  number(pl, "Angular Frequency", 0.0, "omega of the Sine time function (rad/s)");
  number(pl, "Start Time", 0.0, "time at which a Step comes on, or a Ramp starts rising (s)");
  pl.set("Table", "", "Time Function = Table: 't0, v0; t1, v1; ...' (as Bodies/Vertices), the times increasing (s)");
}

const char* const kParticlePlacementDoc =
    "where the lattice fill puts the Particles Per Cell in a cell, per direction, all of equal volume (the cell's over "
    "the particles per cell; total mass rho x the body's volume). Uniform: the centres of n equal sub-cells (the "
    "midpoint rule: a rectangle's second moment of area through its depth H comes out low by the factor "
    "1 - (d/H)^2, d = the sub-cell size); Gauss: n/2 equal sub-cells, each holding the 2-point Gauss-Legendre pair "
    "(its centre +- half width / sqrt(3), equal weights), which integrates cubics exactly, so the second moment "
    "exactly; with 4 per cell the sub-cells are the half cells, on which quadratic B-splines are polynomials "
    "(the beam decks apps/beam_implicit_bspline_*). Gauss needs even Particles Per Cell; not for Particles File "
    "bodies or FE Q4 / FE Q9 (which place their own Gauss points)";

const std::set<std::string> kCollections = {"Materials", "Bodies", "Constraints", "Loads", "Monitors"};
// Sublists handed unchanged to Trilinos packages, which validate them themselves.
const std::set<std::string> kPassThrough = {"Implicit Solver"};

}  // namespace

std::string formatNumber(double value) {
  std::ostringstream os;
  os << std::setprecision(6) << value;
  return os.str();
}

namespace {

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
  if (collection == "Materials") {
    choice(*pl, "Model", "Linear Elastic", {"Linear Elastic", "Neo-Hookean", "J2 Plasticity"},
           "constitutive model. Linear Elastic: small strain (the seed problems); Neo-Hookean: compressible "
           "hyperelastic at finite strain, W = mu/2 (tr b - 3) - mu ln J + lambda/2 (ln J)^2 with the Lame "
           "constants of Young Modulus and Poisson Ratio; J2 Plasticity: von Mises elastoplasticity at finite "
           "strain (multiplicative split, Hencky elasticity, radial return, linear isotropic hardening: Yield "
           "Stress, Hardening Modulus). The finite-strain models are plane strain or 3D, not with FE Q4/Q9");
    number(*pl, "Yield Stress", 0.0, "J2 Plasticity: initial yield stress sigma_y (Pa, > 0)");
    number(*pl, "Hardening Modulus", 0.0, "J2 Plasticity: linear isotropic hardening modulus H (Pa, >= 0)");
    number(*pl, "Young Modulus", 200.0e9, "E (Pa)");
    number(*pl, "Poisson Ratio", 0.3, "nu, in (-1, 0.5)");
    number(*pl, "Density", 7800.0, "rho (kg/m^3)");
  } else if (collection == "Bodies") {
    choice(*pl, "Shape", "Rectangle", {"Rectangle", "Ellipse", "Polygon", "Particles File"},
           "Rectangle: X/Y Min/Max on grid lines; Ellipse: Center X/Y and Radius X/Y (a disk when equal); "
           "Polygon: Vertices; Particles File: File. Lattice-filled shapes keep the sub-box centres inside the "
           "shape; Ellipse and Polygon particles share the shape's exact area as volume. In 3D (Grid/Dimension 3) "
           "a Rectangle is the box X/Y/Z Min/Max, and Particles File rows are x, y, z, volume; Ellipse and "
           "Polygon are 2D shapes");
    pl->set("Material", "", "name of the material (an entry of Materials)");
    number(*pl, "X Min", 0.0, "Rectangle: left edge (on a grid line)");
    number(*pl, "X Max", 1.0, "Rectangle: right edge (on a grid line)");
    number(*pl, "Y Min", 0.0, "Rectangle: bottom edge (on a grid line)");
    number(*pl, "Y Max", 1.0, "Rectangle: top edge (on a grid line)");
    number(*pl, "Z Min", 0.0, "Rectangle in 3D: back face (on a grid plane)");
    number(*pl, "Z Max", 1.0, "Rectangle in 3D: front face (on a grid plane)");
    number(*pl, "Center X", 0.5, "Ellipse: x of the centre");
    number(*pl, "Center Y", 0.5, "Ellipse: y of the centre");
    number(*pl, "Radius X", 0.25, "Ellipse: semi-axis along x");
    number(*pl, "Radius Y", 0.25, "Ellipse: semi-axis along y");
    pl->set("Vertices", "", "Polygon: 'x1, y1; x2, y2; x3, y3; ...' (either orientation, not self-crossing)");
    pl->set("File", "", "Particles File: CSV rows x, y, volume (m^3, i.e. area x Thickness); a relative path is "
                        "relative to the working directory");
    pl->set("Particles Per Cell X", 2, "particles per cell in x (lattice fill)");
    pl->set("Particles Per Cell Y", 2, "particles per cell in y (lattice fill)");
    pl->set("Particles Per Cell Z", 2, "particles per cell in z (lattice fill, 3D)");
    choice(*pl, "Particle Placement", "Uniform", {"Uniform", "Gauss"}, kParticlePlacementDoc);
    number(*pl, "Velocity X", 0.0, "initial velocity, x (m/s)");
    number(*pl, "Velocity Y", 0.0, "initial velocity, y (m/s)");
    number(*pl, "Velocity Z", 0.0, "initial velocity, z (m/s; 3D)");
  } else if (collection == "Constraints") {
    choice(*pl, "Where", "Face", {"Face", "Node", "Box"},
           "a face of a rectangular body, the grid node at (X, Y), or every grid node in the box X/Y Min/Max "
           "(edges included)");
    choice(*pl, "Face", "x-", {"x-", "x+", "y-", "y+", "z-", "z+"}, "face of the body (Where = Face; z-, z+ in 3D)");
    pl->set("Body", "", "the body whose face it is (Where = Face; empty: the first body)");
    number(*pl, "X", 0.0, "x of the node (Where = Node)");
    number(*pl, "Y", 0.0, "y of the node (Where = Node)");
    number(*pl, "Z", 0.0, "z of the node (Where = Node; 3D)");
    number(*pl, "X Min", 0.0, "box (Where = Box)");
    number(*pl, "X Max", 0.0, "box (Where = Box)");
    number(*pl, "Y Min", 0.0, "box (Where = Box)");
    number(*pl, "Y Max", 0.0, "box (Where = Box)");
    number(*pl, "Z Min", -1.0e300, "box (Where = Box; 3D; default: the whole grid in z)");
    number(*pl, "Z Max", 1.0e300, "box (Where = Box; 3D; default: the whole grid in z)");
    choice(*pl, "Components", "all", {"all", "x", "y", "z", "xy", "xz", "yz", "xyz"},
           "the components it prescribes (all: every component of the grid's dimension; z: 3D only)");
    choice(*pl, "Motion", "Fixed", {"Fixed", "Velocity", "Displacement"},
           "Fixed: the components stay at rest; Velocity: they move at Value X/Y/Z (m/s) times the time function; "
           "Displacement: they are displaced by Value X/Y/Z (m) times the time function from where they are at t = 0. "
           "The force the condition applies to the grid is in history.csv (<name>_reaction_<x|y|z>) and summary.yaml "
           "(Reactions)");
    number(*pl, "Value X", 0.0, "Motion = Velocity: velocity (m/s); Displacement: displacement (m); x");
    number(*pl, "Value Y", 0.0, "the same, y");
    number(*pl, "Value Z", 0.0, "the same, z (3D)");
    timeFunctionKeys(*pl, "Constant", "the factor of Value X/Y/Z over time");
  } else if (collection == "Loads") {
    choice(*pl, "Type", "Face Traction", {"Face Traction", "Node Force", "Particle Force", "Body Force", "Manufactured Body Force"},
           "uniform traction on a face of a rectangular body (consistent nodal forces), a force on the grid "
           "node at (X, Y), a force carried by the particle nearest (X, Y), a body force m_p g "
           "(Acceleration X/Y, e.g. gravity) on the particles of Body, or the body force m_p b(X_p, t) that makes "
           "the deck's manufactured solution exact (Exact Solution/Type = Axis-Aligned Manufactured Solution; no "
           "other key: the field is the exact solution's)");
    choice(*pl, "Face", "x+", {"x-", "x+", "y-", "y+", "z-", "z+"}, "face of the body (Face Traction; z-, z+ in 3D)");
    pl->set("Body", "", "Face Traction: the body whose face it is (empty: the first body); Body Force: the "
                        "body it acts on (empty: every body)");
    number(*pl, "Acceleration X", 0.0, "Body Force: acceleration, x (m/s^2)");
    number(*pl, "Acceleration Y", 0.0, "Body Force: acceleration, y (m/s^2)");
    number(*pl, "Acceleration Z", 0.0, "Body Force: acceleration, z (m/s^2; 3D)");
    number(*pl, "X", 0.0, "x of the point (Node Force, Particle Force)");
    number(*pl, "Y", 0.0, "y of the point (Node Force, Particle Force)");
    number(*pl, "Z", 0.0, "z of the point (Node Force, Particle Force; 3D)");
    number(*pl, "Force X", 0.0, "total force, x component (N)");
    number(*pl, "Force Y", 0.0, "total force, y component (N)");
    number(*pl, "Force Z", 0.0, "total force, z component (N; 3D)");
    timeFunctionKeys(*pl, "Step", "the factor of the force over time (the same factor scales a Body Force)");
  } else if (collection == "Monitors") {
    choice(*pl, "Quantity", "Displacement X",
           {"Displacement X", "Displacement Y", "Displacement Z", "Velocity X", "Velocity Y", "Velocity Z", "Stress XX",
            "Stress YY", "Stress XY", "Stress ZZ", "Stress YZ", "Stress XZ"},
           "particle quantity recorded in history.csv (Z and the YZ, XZ stresses in 3D; Stress ZZ in 2D is the "
           "out-of-plane stress, zero in plane stress)");
    number(*pl, "X", 0.0, "the particle nearest (X, Y[, Z]) at t = 0 is monitored");
    number(*pl, "Y", 0.0, "the particle nearest (X, Y[, Z]) at t = 0 is monitored");
    number(*pl, "Z", 0.0, "the particle nearest (X, Y, Z) at t = 0 is monitored (3D)");
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
    number(p, "Memory Limit GB", 0.0,
           "a deck whose estimated memory (grid and particles, over all ranks) exceeds this is rejected before "
           "anything is allocated; 0: the MemAvailable of the machine rank 0 runs on (/proc/meminfo)");
  }
  {
    ParameterList& p = valid->sublist("Grid", false, "structured background grid");
    p.set("Dimension", 2, "2 (plane strain or plane stress, with Thickness) or 3 (Origin Z, Cells Z, Cell Size Z; "
                          "no Plane Condition or Thickness)");
    number(p, "Origin X", 0.0, "x of the lower-left corner");
    number(p, "Origin Y", 0.0, "y of the lower-left corner");
    number(p, "Origin Z", 0.0, "z of the lower corner (3D)");
    p.set("Cells X", 10, "number of cells in x");
    p.set("Cells Y", 1, "number of cells in y");
    p.set("Cells Z", 1, "number of cells in z (3D)");
    number(p, "Cell Size X", 1.0, "cell size in x (m)");
    number(p, "Cell Size Y", 1.0, "cell size in y (m)");
    number(p, "Cell Size Z", 1.0, "cell size in z (m; 3D)");
    choice(p, "Plane Condition", "Plane Strain", {"Plane Strain", "Plane Stress"},
           "2D idealisation; a bar in plane stress has modulus E, in plane strain E/(1 - nu^2)");
    number(p, "Thickness", 1.0, "out-of-plane thickness b (m; 2D)");
  }
  valid->sublist("Materials", false, "named sublists, each a material (see --print-defaults)").disableRecursiveValidation();
  valid->sublist("Bodies", false,
                 "named sublists, each a body: a shape filled with particles of one material (see --print-defaults); "
                 "a later body replaces the particles of earlier ones inside its shape").disableRecursiveValidation();
  {
    ParameterList& p = valid->sublist("Method", false, "spatial discretisation");
    choice(p, "Shape Function", "MPM", shapeNames(),
           "MPM: linear tent at particle points; GIMP: uniform GIMP; cpGIMP: GIMP with the particle domain "
           "stretched by the diagonal of F (capped at half a cell), for large deformation; CPDI: CPDI1 (Sadeghirad et al. "
           "2011), the domain a parallelogram / parallelepiped carried by the full F, weights averaged over its corners "
           "(corners within 3 cells per direction); B-Spline Quadratic: C1 "
           "quadratic B-splines at particle points (3 nodes per direction, Steffen et al.'s boundary splines at the "
           "grid edge; at least 2 cells per direction); B-Spline Cubic: C2 cubic B-splines at particle points (4 nodes "
           "per direction, Steffen et al.'s modified edge splines; at least 3 cells per direction); FE Q4 / FE Q9: the finite-element "
           "reference on the same kernels, particles fixed at the Gauss points (Q4: bilinear, 2 x 2 per cell; "
           "Q9: biquadratic Lagrange elements of 2 x 2 cells, 3 x 3 points; Cells X and Y even), implicit "
           "only, Rectangle bodies only; Particles Per Cell is not used. In 3D FE Q4 is the trilinear Hex8 "
           "(2 x 2 x 2 points per cell) and FE Q9 the triquadratic Hex27 (3 x 3 x 3 per element of 2 x 2 x 2 cells)");
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
    number(e, "Mass Damping", 0.0,
           "mass-proportional damping c (1/s): each grid node's acceleration gets -c v_i (a force -c m_i v_i), for "
           "dynamic relaxation to a quasi-static state; a mode of angular frequency omega is critically damped at "
           "c = 2 omega, higher modes less (0: none, the scheme conserves energy)");
    e.set("Consistent Projection Iterations", 0,
          "Jacobi iterations towards the consistent-mass projection of particle momentum to grid velocity; "
          "0 = the classic lumped projection p/m, which smooths the velocity field by M_L^-1 M_C every step "
          "and about triples the lumped-mass wave dispersion; 1 removes that to O((kh)^4)");
    number(e, "Stability Factor", 1.0,
           "dt must not exceed this factor times 0.7 / (P-wave speed sqrt(1/hx^2 + 1/hy^2)): the critical step of "
           "lumped bilinear cells, times the smallest critical fraction measured over every transfer scheme "
           "(apps/stability_study.py) with a margin; above 1 a warning (the run may diverge)");
    ParameterList& im = p.sublist("Implicit", false, "implicit integrator options");
    im.set("Maximum Step Halvings", 4, "a step whose Newton iteration fails is retried with dt/2, dt/4, ... this many times");
    im.set("Consistent Projection Iterations", 0,
           "Jacobi iterations towards the consistent-mass projection of particle velocity and acceleration to "
           "the grid (0: lumped projection; see Integrator/Explicit); not used with Mass Matrix: Consistent, "
           "whose residual needs no projection");
    im.set("Preconditioner Refresh Interval", 1,
           "steps between numeric refactorisations of the Ifpack2 preconditioner (1: every step); its factors "
           "of a slightly older P remain a good preconditioner while the particles move little");
    im.set("Preconditioner Refresh GMRES Threshold", 0,
           "also rebuild the preconditioner at the step after one whose mean GMRES iterations per Newton "
           "iteration exceeded this (0: off)");
    im.set("Preconditioner At Every Newton Iteration", false,
           "Jacobian-Free with finite-strain materials: rebuild the preconditioner at every Newton iterate from the "
           "tangent at the trial state (material and geometric), instead of once per step");
    choice(im, "Mass Matrix", "Lumped", {"Lumped", "Consistent"},
           "Lumped: Guilkey & Weiss; Consistent: R uses M_C u and particles take their own Newmark update, "
           "which conserves the particles' energy (P then holds the consistent mass too, except with GIMP Stiffness = Integrated)");
    choice(im, "GIMP Stiffness", "Consistent", {"Integrated", "Consistent"},
           "GIMP's assembled stiffness (preconditioner, or Jacobian of Assembled Newton): Consistent = V_p B^T D B "
           "with the averaged gradients, the exact derivative of the GIMP internal force (Newton converges "
           "quadratically, GMRES in a few iterations); Integrated = the seed's D int_Omega_p B^T B, exact per "
           "particle-cell overlap but not the derivative of the GIMP force: once particles straddle cell lines "
           "GMRES stalls (198 iterations per Newton step, 27 times slower, on a padded cantilever). Worth it "
           "only to reproduce the seed");
    choice(im, "Grid Acceleration", "Equilibrium", {"Equilibrium", "Projected"},
           "Lumped mass only. Equilibrium: each step starts from a_i = (F_ext + F_int)_i / m_i and the particles "
           "take the grid's velocity increment dt/2 (a_i + a_i,new); Projected: a_i projected from the "
           "particles' accelerations, v_p += dt/2 (a_p + a_p,new) (Guilkey & Weiss 2003), whose acceleration "
           "error grows at omega dt >> 1 (11 times the static stress after 40 large steps of a step load)");
    im.set("Adaptive Time Step", false,
           "sub-step each deck step adaptively on the Newton iteration count (after Uintah's ImpMPM): a sub-step "
           "that took more than 12 Newton iterations shrinks the next by 0.6, one that took fewer than 4 doubles it "
           "(never beyond the deck's Time Step), and a failed one is retried at half its size, down to Minimum Time "
           "Step. history.csv and the VTU files stay on the deck's steps");
    number(im, "Minimum Time Step", 0.0,
           "Adaptive Time Step: the smallest sub-step before the run stops (0: the deck's Time Step / 2^Maximum Step Halvings)");
    im.set("Consistent Initial Acceleration", true,
           "start from a(0) = M^-1 (F_ext(0) + F_int(0)) instead of zero particle accelerations");
    number(im, "Newmark Beta", 0.25,
           "beta of the Newmark scheme on the grid, u = dt v + dt^2 ((1/2 - beta) a + beta a_new); with gamma "
           "unconditionally stable when 2 beta >= gamma >= 1/2. 1/4 with gamma = 1/2: average acceleration, no "
           "numerical damping; gamma > 1/2 with beta = (gamma + 1/2)^2 / 4 damps the highest frequencies most "
           "(per step by |gamma - 3/2| / (gamma + 1/2) at omega dt -> infinity)");
    number(im, "Newmark Gamma", 0.5, "gamma of the Newmark scheme, v_new = v + dt ((1 - gamma) a + gamma a_new)");
  }
  {
    ParameterList& p = valid->sublist("Initial Conditions", false, "initial particle state (default: at rest)");
    choice(p, "Type", "None", {"None", "Standing Wave", "Manufactured Solution"},
           "None: particles at rest; Standing Wave: zero displacement and v_x(X, 0) = Amplitude sin(Mode pi "
           "(X - X Min) / L), L = the body's length (one mode of a bar fixed at both ends); Manufactured Solution: "
           "zero displacement and the velocity of the deck's manufactured solution at t = 0 (Exact Solution/Type = "
           "Axis-Aligned Manufactured Solution)");
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
    choice(p, "Type", "None",
           {"None", "Bar Step Load", "Simply Supported Beam", "Bar Standing Wave", "Layered Bar Step Load", "Column Under Self-Weight",
            "Axis-Aligned Manufactured Solution", "Cantilever End Load"},
           "Bar Step Load: 1D rod fixed at X Min under the step load named by Load at X Max; "
           "Layered Bar Step Load: the same rod made of all the Rectangle bodies side by side along x, each of its "
           "own material, the load at the right end of the last: the wave fronts traced through every interface "
           "(transmitted 2 Z_b/(Z_a + Z_b), reflected (Z_b - Z_a)/(Z_a + Z_b)); displacement, velocity and stress XX; "
           "Simply Supported Beam: Euler-Bernoulli beam under the harmonic point load named by Load; "
           "Bar Standing Wave: 1D rod fixed in x at both ends (Constraints on faces x- and x+), no loads, "
           "started by Initial Conditions/Type = Standing Wave: u = (V/omega) sin(n pi X/L) sin(omega t), "
           "omega = c n pi / L (displacement, velocity and stress XX); "
           "Column Under Self-Weight: a plane-strain column on a fixed base with rollers on both sides under the "
           "Body Force named by Load (Acceleration Y < 0), quasi-static at the load's current factor: "
           "sigma_yy = -f rho0 g (l0 - Y) exactly, and the stretch and displacement of the linear or neo-Hookean "
           "law (physics/ColumnExact.hpp; displacement Y, stress YY and XX; modulus: the constrained lambda + 2 mu); "
           "Axis-Aligned Manufactured Solution: Wallstedt & Guilkey's (2008) field u_d = A sin(2 pi (X_d - o_d) / L) "
           "sin(omega t), omega = pi sqrt(E / rho0) / L, on a square (cube) neo-Hookean Body of side L with rollers "
           "on every face, driven by a Load of Type = Manufactured Body Force and started by Initial Conditions/Type "
           "= Manufactured Solution (physics/ManufacturedSolution.hpp); every displacement, velocity and stress, "
           "and the whole displacement field (summary.yaml: Displacement Field Error); "
           "Cantilever End Load: the elastica of the body clamped at X Min (a Face x- constraint, xy) under the "
           "dead end load that is the sum of the deck's loads (Particle Forces along y at X Max, one time function), "
           "quasi-static at k f(t), k = P L^2 / (Modulus I) (physics/ElasticaExact.hpp; displacement X and Y, the "
           "cross-section rotating rigidly with the centreline)");
    choice(p, "Modulus", "Plane Condition", {"Plane Condition", "Young Modulus"},
           "modulus of the exact solution: Plane Condition = E in plane stress, E/(1-nu^2) in plane strain");
    p.set("Load", "", "name of the load (in Loads) that the exact solution is driven by (not used by Bar Standing Wave)");
    p.set("Body", "", "the body the exact solution describes (empty: the first body; a Rectangle)");
    number(p, "Amplitude", 0.0, "Axis-Aligned Manufactured Solution: displacement amplitude A (m), 0 < A < L / (4 pi)");
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
    ParameterList& p = valid->sublist("Decomposition", false,
                                      "how MPI ranks split the grid: a Cartesian grid of ranks, each owning a box of cells");
    p.set("Ranks X", 0,
          "ranks along x (0: impm chooses every direction left 0, the factorisation of the rank count with the fewest "
          "nodes on rank boundaries); Ranks X x Ranks Y (x Ranks Z) must equal the rank count when all are given");
    p.set("Ranks Y", 0, "ranks along y (0: chosen by impm)");
    p.set("Ranks Z", 0, "ranks along z, 3D only (0: chosen by impm)");
    p.set("Migration Slack Cells", 1,
          "particles migrate lazily: a rank's ghost band is this many cells wider than its stencils need, and "
          "particles are exchanged with neighbouring ranks only once one of them is further than this from its "
          "rank's cells (0: after every step in which a particle changed rank)");
    p.set("Load Balance Interval", 0,
          "steps between load-balance checks (0: never; also at the start when positive): when the largest rank's "
          "particle count exceeds 'Load Balance Threshold' times the mean, the cuts between ranks move along each "
          "direction to equalise the particles per plane of ranks (tensor splits), and particles, grid maps and the "
          "integrator follow. The imbalance is in summary.yaml (Decomposition)");
    p.set("Load Balance Threshold", 1.1, "rebalance only above this max / mean particles per rank (>= 1)");
  }
  {
    ParameterList& p = valid->sublist("Output", false, "what is written");
    p.set("History Interval", 10, "steps between rows of history.csv");
    p.set("History Digits", 10, "significant digits of the values in history.csv (1 to 17; 17 writes every double exactly)");
    p.set("VTK Interval", 0, "steps between VTU particle files (0: first and last step only)");
    p.set("Plot", true, "write plot.png (computed against exact) with python3-matplotlib");
    p.set("Progress", true, "print a progress line with ETA on runs longer than a few seconds");
    p.set("Checkpoint Interval", 0,
          "steps between checkpoints (0: none): every particle field, the integrator's state and the history rows "
          "so far, in OUTPUT/checkpoint (a link to OUTPUT/checkpoint_<step>; only the latest is kept, written to a "
          "temporary directory and renamed when complete). `impm DECK --restart OUTPUT/checkpoint` continues from it: "
          "the deck must be the same except Output, Decomposition, Problem/Output Directory and Integrator/Number of "
          "Steps; "
          "history.csv is rewritten from the checkpoint's rows and continued, and equals the uninterrupted run's "
          "(bit for bit at the same rank and thread count, except assembled Newton with an iterative linear solver "
          "whose preconditioner is refreshed less often than every step: the restart builds a fresh one). "
          "Independent of History and VTK Interval (a checkpoint holds every history row written before it)");
    p.set("Energy And Momentum", false,
          "add kinetic, strain and total energy and linear momentum columns to history.csv, and their drift to "
          "summary.yaml (Energy, Momentum)");
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

namespace {
// The sections of the single-body form (still read; converted by convertSingleBodyForm).
RCP<const ParameterList> legacyTemplate(const std::string& section) {
  auto pl = rcp(new ParameterList(section));
  if (section == "Material") {
    pl->setParameters(*collectionTemplate("Materials"));
    choice(*pl, "Plane Condition", "Plane Strain", {"Plane Strain", "Plane Stress"}, "2D idealisation");
    number(*pl, "Thickness", 1.0, "out-of-plane thickness b (m)");
  } else if (section == "Body") {
    number(*pl, "X Min", 0.0, "left edge");
    number(*pl, "X Max", 1.0, "right edge");
    number(*pl, "Y Min", 0.0, "bottom edge");
    number(*pl, "Y Max", 1.0, "top edge");
    pl->set("Particles Per Cell X", 2, "particles per cell in x");
    pl->set("Particles Per Cell Y", 2, "particles per cell in y");
    choice(*pl, "Particle Placement", "Uniform", {"Uniform", "Gauss"}, kParticlePlacementDoc);
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
        throw DeckError(std::string("'") + old + "' is the single-body form and cannot be mixed with 'Bodies' (put it in "
                        "'Materials' / 'Bodies')");
    return;
  }
  if (deck.isSublist("Materials"))
    throw DeckError("'Materials' needs 'Bodies' (the single-body form uses 'Material' and 'Body')");
  if (!legacy)
    throw DeckError("the deck has no body: add 'Materials' and 'Bodies', or the single-body sections 'Material' and 'Body'");
  if (deck.isSublist("Grid"))
    for (const char* key : {"Plane Condition", "Thickness"})
      if (deck.sublist("Grid").isParameter(key))
        throw DeckError(std::string("'Grid/") + key + "' belongs to the 'Materials'/'Bodies' form; the single-body form "
                        "sets 'Material/" + key + "'");
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
  for (const char* key : {"Young Modulus", "Poisson Ratio", "Density", "Yield Stress", "Hardening Modulus"})
    m.set(key, material.get<double>(key));
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
      throw DeckError(std::string("'") + old + "' is the single-body form and cannot be mixed with 'Bodies' (put it in "
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
          throw DeckError(std::string("'Grid/") + key + "' is a 3D key: set 'Grid/Dimension' = 3, or remove it for a 2D deck");
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
        throw DeckError(std::string("'Grid/") + key + "' is a 2D idealisation; a deck with 'Grid/Dimension' = 3 has none (remove it)");
    if (deck.isSublist("Material") || deck.isSublist("Body"))
      throw DeckError("the single-body form ('Material', 'Body') is 2D; a deck with 'Grid/Dimension' = 3 uses 'Materials' and 'Bodies'");
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
