// Bad decks end with one DeckError naming the offending key or value, before any output:
// unknown key, wrong type, bad choice, non-positive sizes or moduli, Poisson ratio outside
// (-1, 0.5), particles outside the grid, an explicit dt above the stable limit.
#include <Teuchos_UnitTestHarness.hpp>
#include <Tpetra_Core.hpp>

#include <Teuchos_XMLParameterListCoreHelpers.hpp>

#include <filesystem>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/Simulation.hpp"

namespace {

using impm::DeckError;
using Teuchos::ParameterList;

// A small valid bar deck, as a user would write it.
ParameterList goodDeck(const std::string& outdir) {
  ParameterList d("impm");
  d.sublist("Problem").set("Output Directory", outdir);
  auto& g = d.sublist("Grid");
  g.set("Cells X", 10);
  g.set("Cells Y", 1);
  g.set("Cell Size X", 1e-3);
  g.set("Cell Size Y", 1e-3);
  auto& b = d.sublist("Body");
  b.set("X Max", 0.01);
  b.set("Y Max", 1e-3);
  auto& m = d.sublist("Material");
  m.set("Thickness", 1e-3);
  d.sublist("Integrator").set("Time Step", 1e-8);
  auto& c = d.sublist("Constraints").sublist("left");
  c.set("Face", "x-");
  c.set("Components", "x");
  auto& l = d.sublist("Loads").sublist("pull");
  l.set("Force X", 1.0);
  return d;
}

// Runs validation and set-up; returns the DeckError message ("" if none).
std::string problemWith(ParameterList deck) {
  try {
    impm::validateDeck(deck);
    impm::Simulation sim(deck, Tpetra::getDefaultComm());
  } catch (const DeckError& e) {
    return e.what();
  }
  return "";
}

bool mentions(const std::string& msg, const std::string& what) { return msg.find(what) != std::string::npos; }

TEUCHOS_UNIT_TEST(InputDeck, GoodDeckPasses) {
  const std::string dir = "deck_test_good_output";
  TEST_EQUALITY_CONST(problemWith(goodDeck(dir)), "");
  // Set-up alone writes nothing.
  TEST_ASSERT(!std::filesystem::exists(dir));
}

// The same deck as YAML and as XML reads to the same validated list, and runs set-up.
TEUCHOS_UNIT_TEST(InputDeck, YamlAndXmlAgree) {
  auto yaml = impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/bar_explicit_gimp_plane_strain.yaml");
  Teuchos::writeParameterListToXmlFile(*yaml, "deck_test_bar.xml");
  auto xml = impm::readDeck("deck_test_bar.xml");
  impm::validateDeck(*yaml);
  impm::validateDeck(*xml);
  TEST_ASSERT(Teuchos::haveSameValues(*yaml, *xml));
  TEST_EQUALITY_CONST(xml->sublist("Method").get<std::string>("Shape Function"), "GIMP");
  TEST_EQUALITY_CONST(problemWith(*xml), "");
}

TEUCHOS_UNIT_TEST(InputDeck, DefaultsAreFilledIn) {
  ParameterList d = goodDeck("x");
  impm::validateDeck(d);
  TEST_EQUALITY_CONST(d.sublist("Integrator").sublist("Explicit").get<std::string>("Update Scheme"), "USL");
  TEST_EQUALITY_CONST(d.sublist("Loads").sublist("pull").get<std::string>("Time Function"), "Step");
  // The single-body form is read as the material "Material" and the rectangle "Body".
  TEST_FLOATING_EQUALITY(d.sublist("Materials").sublist("Material").get<double>("Poisson Ratio"), 0.3, 1e-15);
  TEST_EQUALITY_CONST(d.sublist("Bodies").sublist("Body").get<std::string>("Shape"), "Rectangle");
  TEST_FLOATING_EQUALITY(d.sublist("Grid").get<double>("Thickness"), 1e-3, 1e-15);
  TEST_ASSERT(!d.isSublist("Material") && !d.isSublist("Body"));
}

TEUCHOS_UNIT_TEST(InputDeck, UnknownKeyIsNamed) {
  ParameterList d = goodDeck("x");
  d.sublist("Material").set("Youngs Modulus", 1.0);
  const std::string msg = problemWith(d);
  out << msg << "\n";
  TEST_ASSERT(mentions(msg, "unknown key 'Material/Youngs Modulus'"));
  ParameterList d2 = goodDeck("x");
  d2.sublist("Loads").sublist("pull").set("Magnitude", 3.0);
  TEST_ASSERT(mentions(problemWith(d2), "Loads/pull/Magnitude"));
}

TEUCHOS_UNIT_TEST(InputDeck, WrongTypeIsNamed) {
  ParameterList d = goodDeck("x");
  d.sublist("Grid").set("Cells X", 2.5);
  const std::string msg = problemWith(d);
  out << msg << "\n";
  TEST_ASSERT(mentions(msg, "Grid/Cells X") && mentions(msg, "int"));
  ParameterList d2 = goodDeck("x");
  d2.sublist("Material").set("Density", std::string("heavy"));
  TEST_ASSERT(mentions(problemWith(d2), "Material/Density"));
}

TEUCHOS_UNIT_TEST(InputDeck, BadChoiceIsNamed) {
  ParameterList d = goodDeck("x");
  d.sublist("Method").set("Shape Function", "cubic");
  const std::string msg = problemWith(d);
  out << msg << "\n";
  TEST_ASSERT(mentions(msg, "'cubic'") && mentions(msg, "Method/Shape Function") && mentions(msg, "GIMP"));
}

TEUCHOS_UNIT_TEST(InputDeck, NonPositiveSizesAndModuli) {
  for (auto [section, key] : {std::make_pair("Grid", "Cell Size X"), std::make_pair("Material", "Young Modulus"),
                              std::make_pair("Material", "Density"), std::make_pair("Material", "Thickness"),
                              std::make_pair("Integrator", "Time Step")}) {
    ParameterList d = goodDeck("x");
    d.sublist(section).set(key, -1.0);
    const std::string msg = problemWith(d);
    out << msg << "\n";
    TEST_ASSERT(mentions(msg, std::string(section) + "/" + key) && mentions(msg, "positive"));
  }
  ParameterList d = goodDeck("x");
  d.sublist("Grid").set("Cells Y", 0);
  TEST_ASSERT(mentions(problemWith(d), "Grid/Cells Y"));
}

TEUCHOS_UNIT_TEST(InputDeck, PoissonRatioRange) {
  for (double nu : {0.5, 0.7, -1.0, -3.0}) {
    ParameterList d = goodDeck("x");
    d.sublist("Material").set("Poisson Ratio", nu);
    const std::string msg = problemWith(d);
    out << msg << "\n";
    TEST_ASSERT(mentions(msg, "Material/Poisson Ratio"));
  }
  ParameterList ok = goodDeck("x");
  ok.sublist("Material").set("Poisson Ratio", 0.49);
  TEST_EQUALITY_CONST(problemWith(ok), "");
}

TEUCHOS_UNIT_TEST(InputDeck, ParticlesOutsideTheGrid) {
  ParameterList d = goodDeck("x");
  d.sublist("Body").set("X Max", 0.02);
  const std::string msg = problemWith(d);
  out << msg << "\n";
  TEST_ASSERT(mentions(msg, "outside the grid") && mentions(msg, "Body/X Max"));
}

TEUCHOS_UNIT_TEST(InputDeck, ExplicitTimeStepAboveStableLimit) {
  ParameterList d = goodDeck("x");
  // P-wave speed in plane strain is about 5875 m/s; on the deck's 1 mm x 1 mm cells the limit
  // 0.7 / (c_p sqrt(1/hx^2 + 1/hy^2)) is 8.4e-8 s (the cells' own, 1.2e-7 s, is not reached
  // with particle transfers; h_min / c_p = 1.7e-7 s blows up at once).
  d.sublist("Integrator").set("Time Step", 9e-8);
  const std::string msg = problemWith(d);
  out << msg << "\n";
  TEST_ASSERT(mentions(msg, "Integrator/Time Step") && mentions(msg, "stable limit"));
  ParameterList ok = goodDeck("x");
  ok.sublist("Integrator").set("Time Step", 8e-8);
  TEST_EQUALITY_CONST(problemWith(ok), "");
}

TEUCHOS_UNIT_TEST(InputDeck, ExactSolutionMustNameALoad) {
  ParameterList d = goodDeck("x");
  d.sublist("Exact Solution").set("Type", "Bar Step Load");
  d.sublist("Exact Solution").set("Load", "missing");
  TEST_ASSERT(mentions(problemWith(d), "Exact Solution/Load"));
}

}  // namespace
