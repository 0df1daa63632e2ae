// The small vocabulary every deck section's schema is written in: a number (int or double in the
// deck, stored as double), a choice among names, and the readers that check a value with one
// message naming 'section/key'.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>

#include <string>
#include <vector>

#include "core/InputDeck.hpp"

namespace impm::schema {

// YAML decks write "1" for 1.0: ints and doubles are accepted, stored as double.
inline Teuchos::RCP<Teuchos::AnyNumberParameterEntryValidator> numberValidator() {
  Teuchos::AnyNumberParameterEntryValidator::AcceptedTypes accept(false);
  accept.allowInt(true).allowDouble(true).allowString(false);
  return Teuchos::rcp(
      new Teuchos::AnyNumberParameterEntryValidator(Teuchos::AnyNumberParameterEntryValidator::PREFER_DOUBLE, accept));
}

inline void number(Teuchos::ParameterList& pl, const std::string& key, double def, const std::string& doc) {
  pl.set(key, def, doc, numberValidator());
}

inline void choice(Teuchos::ParameterList& pl, const std::string& key, const std::string& def,
                   const std::vector<std::string>& values, const std::string& doc) {
  pl.set(key, def, doc,
         Teuchos::rcp(new Teuchos::StringValidator(Teuchos::Array<std::string>(values.begin(), values.end()))));
}

// A value that must be positive, or a DeckError naming 'section/key'.
inline double positive(const Teuchos::ParameterList& pl, const std::string& section, const std::string& key) {
  const double v = pl.get<double>(key);
  if (!(v > 0)) throw DeckError("'" + section + "/" + key + "' must be positive, got " + formatNumber(v));
  return v;
}

inline int positiveInt(const Teuchos::ParameterList& pl, const std::string& section, const std::string& key) {
  const int v = pl.get<int>(key);
  if (v <= 0) throw DeckError("'" + section + "/" + key + "' must be positive, got " + std::to_string(v));
  return v;
}

}  // namespace impm::schema
