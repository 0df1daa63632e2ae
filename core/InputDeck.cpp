#include "core/InputDeck.hpp"

#include <Teuchos_XMLParameterListCoreHelpers.hpp>
#include <Teuchos_YamlParameterListCoreHelpers.hpp>

#include <fstream>
#include <iomanip>
#include <sstream>

namespace impm {

using Teuchos::ParameterList;
using Teuchos::RCP;

std::string formatNumber(double value) {
  std::ostringstream os;
  os << std::setprecision(6) << value;
  return os.str();
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

}  // namespace impm
