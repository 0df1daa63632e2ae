// The input deck: one Teuchos::ParameterList per run, read from XML or YAML, checked against
// the full list of valid parameters (unknown keys, types, allowed values) and completed with
// defaults. Every problem is reported as a DeckError naming the key.
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

// Every valid parameter with its default and documentation. The collections "Materials",
// "Bodies", "Constraints", "Loads" and "Monitors" hold any number of named sublists, each of
// the form collectionTemplate(name). The single-body form (sections "Material" and "Body") is
// converted by validateDeck into one entry of Materials and Bodies.
Teuchos::RCP<const Teuchos::ParameterList> validParameters();
Teuchos::RCP<const Teuchos::ParameterList> collectionTemplate(const std::string& collection);

// Reads a deck (".xml" or ".yaml"/".yml"); throws DeckError if it cannot be read or parsed.
Teuchos::RCP<Teuchos::ParameterList> readDeck(const std::string& path);

// Checks the deck against validParameters() and fills in defaults, in place.
void validateDeck(Teuchos::ParameterList& deck);

// Sublists validated by the package that reads them (e.g. "Implicit Solver"), for printing.
using SublistDefaults = std::map<std::string, Teuchos::RCP<const Teuchos::ParameterList>>;
// The valid parameters with defaults, as YAML, with one example entry per collection.
void printDefaults(std::ostream& os, const SublistDefaults& extra = {});
// The valid parameters with their documentation.
void printHelp(std::ostream& os, const SublistDefaults& extra = {});

}  // namespace impm
