// The scenario key table: every key a scenario may hold, with its value type, unit, accepted
// range or choices, default and one line of documentation. The INI reader's per-value checks
// (type, range, choices), the resolved-text writer's choice names, the unknown-key suggestions
// and the README key table (checked by test_scenario) all come from this one table. Rules that
// tie keys together (give exactly one of two keys, a key required by another's value) stay in
// the section readers (src/scenario/sections.cpp).
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace fretbem {

/// How a key's value is read (scenario_detail::Reader names each check's message).
enum class KeyType {
  real,        ///< any finite double within [lo, hi] (open ends as flagged)
  magnitude,   ///< a positive SI quantity within [1e-100, 1e100]
  wavelength,  ///< 0 (none) or a magnitude
  integer,     ///< a whole number within [lo, hi]
  seed,        ///< an unsigned 64-bit integer
  boolean,     ///< true/false, yes/no, on/off, 1/0
  choice,      ///< one of choices; the index is the value
  path,        ///< a file path, resolved against the scenario's folder
  text,        ///< free text
  fields,      ///< a comma-separated list of output field names, or none
};

struct ScenarioKey {
  std::string_view key;  ///< "section.name"
  KeyType type;
  std::string_view unit;  ///< SI unit of the value ("1" for dimensionless, "" for non-numbers)
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  std::vector<std::string> choices;  ///< choice keys: the accepted spellings, in enum order
  /// The value written by the resolved text when the key is not given; "" when the key is
  /// written as unset (or, for required keys, must be given).
  std::string_view default_value;
  std::string_view doc;  ///< one line: what the key sets
};

/// Every key, in the order the resolved text writes them.
const std::vector<ScenarioKey>& scenario_keys();
/// The key's entry; throws std::out_of_range for a name outside the table.
const ScenarioKey& scenario_key(std::string_view key);
/// The spelling of choice index i of a choice key.
const std::string& choice_name(std::string_view key, std::size_t i);
/// The section names, in the order the resolved text writes them.
const std::vector<std::string>& scenario_sections();

}  // namespace fretbem
