// Test helper: decks that impm must refuse. Each case edits a good deck; validating it and
// building the Simulation must throw one DeckError whose message names the key ('key...) and
// says why.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_UnitTestHelpers.hpp>
#include <Tpetra_Core.hpp>

#include <functional>
#include <string>
#include <vector>

#include "core/InputDeck.hpp"
#include "solvers/Simulation.hpp"
#include "solvers/build/Deck.hpp"

namespace impm_test {

struct DeckRefusal {
  std::string what, key, message;
  std::function<void(Teuchos::ParameterList&)> edit;
};

inline void checkRefusals(const Teuchos::ParameterList& good, const std::vector<DeckRefusal>& cases,
                          const std::string& outdir, Teuchos::FancyOStream& out, bool& success) {
  for (const DeckRefusal& c : cases) {
    Teuchos::ParameterList d = good;
    c.edit(d);
    std::string message;
    try {
      impm::validateDeck(d);
      impm::Simulation sim(d, Tpetra::getDefaultComm(), outdir);
    } catch (const impm::DeckError& e) {
      message = e.what();
    }
    out << c.what << ": " << message << "\n";
    TEST_ASSERT(message.find("'" + c.key) != std::string::npos);
    TEST_ASSERT(message.find(c.message) != std::string::npos);
  }
}

}  // namespace impm_test
