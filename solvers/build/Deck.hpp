// The deck's schema and its check: every valid parameter with its default and documentation
// (each section's own, from solvers/build/), a deck checked against it with one DeckError naming
// the key, and the schema printed for --help and --print-defaults.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <map>
#include <ostream>
#include <string>

#include "core/InputDeck.hpp"

namespace impm {

// Every valid parameter with its default and documentation. The collections "Materials",
// "Bodies", "Constraints", "Loads" and "Monitors" hold any number of named sublists, each of
// the form collectionTemplate(name). The single-body form (sections "Material" and "Body") is
// converted by validateDeck into one entry of Materials and Bodies.
Teuchos::RCP<const Teuchos::ParameterList> validParameters();
Teuchos::RCP<const Teuchos::ParameterList> collectionTemplate(const std::string& collection);

// Checks the deck against validParameters() and fills in defaults, in place.
void validateDeck(Teuchos::ParameterList& deck);

// Sublists validated by the package that reads them (e.g. "Implicit Solver"), for printing.
using SublistDefaults = std::map<std::string, Teuchos::RCP<const Teuchos::ParameterList>>;
// The valid parameters with defaults, as YAML, with one example entry per collection.
void printDefaults(std::ostream& os, const SublistDefaults& extra = {});
// The valid parameters with their documentation.
void printHelp(std::ostream& os, const SublistDefaults& extra = {});

}  // namespace impm
