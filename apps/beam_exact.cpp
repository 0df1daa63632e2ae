// impm_beam_exact: the verification budget of Problem 2 (benchmarks.md) for one beam deck.
//
// Reads a beam deck (e.g. apps/beam_implicit_mpm_plane_strain.yaml) and prints, as CSV on
// stdout, the mid-span (or --x) deflection w(x, t) at t = k dt, k = 0..steps (the deck's
// Integrator time step and number of steps) of
//   eb_E                 Euler-Bernoulli with the deck's E (the formula of benchmarks.md)
//   eb_Eprime            Euler-Bernoulli with E' = E/(1-nu^2) in plane strain (E in plane stress)
//   timo_Eprime          Timoshenko (shear + rotary inertia, kappa = 5/6) with E', G = E/(2(1+nu))
//   eb_Eprime_newmark    eb_Eprime's modal series advanced by Newmark average acceleration, dt
//   timo_Eprime_newmark  timo_Eprime's modal series advanced by Newmark average acceleration, dt
//   timo_E               Timoshenko with E
// so that consecutive differences measure the modulus choice, shear/rotary inertia and Newmark
// period elongation separately. A first comment line lists the first-mode frequencies.
//
//   build/apps/impm_beam_exact apps/beam_implicit_mpm_plane_strain.yaml [--x X] [--terms N]
//
// --x X      monitored x (default: the X of the load named by Exact Solution/Load)
// --terms N  modes per series (default: Exact Solution/Series Terms)
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "physics/BeamTheories.hpp"
#include "physics/ExactSolutions.hpp"

namespace {

void usage(std::ostream& os) { os << "usage: impm_beam_exact DECK.{yaml,xml} [--x X] [--terms N]\n"; }

bool parseDouble(const std::string& s, double& v) {
  try {
    size_t pos = 0;
    v = std::stod(s, &pos);
    return pos == s.size() && std::isfinite(v);
  } catch (const std::exception&) {
    return false;
  }
}

bool parseInt(const std::string& s, int& v) {
  try {
    size_t pos = 0;
    v = std::stoi(s, &pos);
    return pos == s.size();
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string deckPath;
  bool haveX = false;
  double xArg = 0;
  int termsArg = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage(std::cout);
      return 0;
    } else if (a == "--x" || a == "--terms") {
      if (i + 1 >= argc) {
        std::cerr << "impm_beam_exact: error: " << a << " needs a value\n";
        return 2;
      }
      const std::string v = argv[++i];
      if (a == "--x") {
        if (!parseDouble(v, xArg)) {
          std::cerr << "impm_beam_exact: error: --x needs a number, got '" << v << "'\n";
          return 2;
        }
        haveX = true;
      } else if (!parseInt(v, termsArg) || termsArg <= 0) {
        std::cerr << "impm_beam_exact: error: --terms needs a positive integer, got '" << v << "'\n";
        return 2;
      }
    } else if (a.rfind("--", 0) == 0) {
      std::cerr << "impm_beam_exact: error: unknown option '" << a << "'\n";
      usage(std::cerr);
      return 2;
    } else if (deckPath.empty()) {
      deckPath = a;
    } else {
      std::cerr << "impm_beam_exact: error: more than one deck given ('" << deckPath << "', '" << a << "')\n";
      return 2;
    }
  }
  if (deckPath.empty()) {
    usage(std::cerr);
    return 2;
  }

  try {
    auto deck = impm::readDeck(deckPath);
    impm::validateDeck(*deck);
    using Teuchos::ParameterList;
    // The beam is the first body, of its own material (the single-body form reads as these).
    const ParameterList& bodies = deck->sublist("Bodies");
    if (bodies.numParams() == 0) throw impm::DeckError("'Bodies' is empty");
    const ParameterList& body = bodies.sublist(bodies.name(bodies.begin()));
    const ParameterList& materials = deck->sublist("Materials");
    if (!materials.isSublist(body.get<std::string>("Material")))
      throw impm::DeckError("'Bodies/" + bodies.name(bodies.begin()) + "/Material' names no entry of Materials");
    const ParameterList& mat = materials.sublist(body.get<std::string>("Material"));
    const ParameterList& grid = deck->sublist("Grid");
    const ParameterList& integ = deck->sublist("Integrator");
    const ParameterList& ex = deck->sublist("Exact Solution");

    const double E = mat.get<double>("Young Modulus"), nu = mat.get<double>("Poisson Ratio");
    const double rho = mat.get<double>("Density"), thickness = grid.get<double>("Thickness");
    const bool planeStrain = grid.get<std::string>("Plane Condition") == "Plane Strain";
    const double xMin = body.get<double>("X Min"), L = body.get<double>("X Max") - xMin;
    const double depth = body.get<double>("Y Max") - body.get<double>("Y Min");
    const double dt = integ.get<double>("Time Step");
    const int steps = integ.get<int>("Number of Steps");
    if (!(E > 0) || !(rho > 0) || !(thickness > 0))
      throw impm::DeckError("Material: Young Modulus, Density and Thickness must be positive");
    if (!(nu > -1 && nu < 0.5)) throw impm::DeckError("'Material/Poisson Ratio' must be in (-1, 0.5)");
    if (!(L > 0) || !(depth > 0)) throw impm::DeckError("Body: X Max > X Min and Y Max > Y Min needed");
    if (!(dt > 0)) throw impm::DeckError("'Integrator/Time Step' must be positive");
    if (steps <= 0) throw impm::DeckError("'Integrator/Number of Steps' must be positive");

    const std::string loadName = ex.get<std::string>("Load");
    const ParameterList& loads = deck->sublist("Loads");
    if (loadName.empty() || !loads.isSublist(loadName))
      throw impm::DeckError("'Exact Solution/Load' = '" + loadName + "' names no entry of Loads");
    const ParameterList& load = loads.sublist(loadName);
    if (load.get<std::string>("Time Function") != "Sine")
      throw impm::DeckError("load '" + loadName + "' must have 'Time Function: Sine' for the beam solutions");
    const double F0 = load.get<double>("Force Y"), omega = load.get<double>("Angular Frequency");
    const double a = load.get<double>("X") - xMin;
    if (!(a > 0 && a < L)) throw impm::DeckError("load '" + loadName + "': X must lie strictly between the supports");
    const double x = (haveX ? xArg : load.get<double>("X")) - xMin;
    if (!(x >= 0 && x <= L)) {
      std::cerr << "impm_beam_exact: error: --x must lie within the body\n";
      return 2;
    }
    const int terms = termsArg > 0 ? termsArg : ex.get<int>("Series Terms");
    if (terms <= 0) throw impm::DeckError("'Exact Solution/Series Terms' must be positive");

    const double Ep = planeStrain ? E / (1 - nu * nu) : E, G = E / (2 * (1 + nu));
    const double A = depth * thickness, I = thickness * depth * depth * depth / 12.0;
    const impm::BeamHarmonicExact ebE{L, a, E, I, rho * A, F0, omega};
    const impm::BeamHarmonicExact ebEp{L, a, Ep, I, rho * A, F0, omega};
    const impm::TimoshenkoBeamHarmonic timoEp{L, a, Ep, G, 5.0 / 6.0, A, I, rho, F0, omega};
    const impm::TimoshenkoBeamHarmonic timoE{L, a, E, G, 5.0 / 6.0, A, I, rho, F0, omega};

    const auto wEbE = impm::deflectionHistory(ebE, x, dt, steps, terms);
    const auto wEbEp = impm::deflectionHistory(ebEp, x, dt, steps, terms);
    const auto wTimoEp = timoEp.deflectionHistory(x, dt, steps, terms);
    const auto wEbEpN = impm::deflectionHistoryNewmark(ebEp, x, dt, steps, terms);
    const auto wTimoEpN = timoEp.deflectionHistoryNewmark(x, dt, steps, terms);
    const auto wTimoE = timoE.deflectionHistory(x, dt, steps, terms);

    const double w1T = timoEp.omega(1, 0);
    std::printf(
        "# omega_1 (rad/s): eb_E %.6f, eb_Eprime %.6f, timo_Eprime %.6f, newmark (2/dt)atan(omega dt/2) "
        "of eb_Eprime %.6f, of timo_Eprime %.6f; timo_E %.6f; %s, x = %g, dt = %g, %d terms\n",
        ebE.omega1(), ebEp.omega1(), w1T, impm::newmarkFrequency(ebEp.omega1(), dt), impm::newmarkFrequency(w1T, dt),
        timoE.omega(1, 0), planeStrain ? "plane strain" : "plane stress", x + xMin, dt, terms);
    std::printf("t,eb_E,eb_Eprime,timo_Eprime,eb_Eprime_newmark,timo_Eprime_newmark,timo_E\n");
    for (int k = 0; k <= steps; ++k)
      std::printf("%.10g,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e\n", k * dt, wEbE[k], wEbEp[k], wTimoEp[k], wEbEpN[k],
                  wTimoEpN[k], wTimoE[k]);
  } catch (const impm::DeckError& e) {
    std::cerr << "impm_beam_exact: error in deck '" << deckPath << "': " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "impm_beam_exact: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
