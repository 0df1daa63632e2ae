// The input deck: one Teuchos::ParameterList per run, read from XML or YAML. Its schema and check
// (unknown keys, types, allowed values, defaults) are solvers/build/Deck.hpp's; every problem is
// reported as a DeckError naming the key.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <map>
#include <stdexcept>
#include <string>

namespace impm {

struct DeckError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A number as messages print it (6 significant digits).
std::string formatNumber(double value);

// Reads a deck (".xml" or ".yaml"/".yml"); throws DeckError if it cannot be read or parsed.
Teuchos::RCP<Teuchos::ParameterList> readDeck(const std::string& path);

}  // namespace impm
