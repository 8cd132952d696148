// The key names (from the key table, key_table.cpp) and the nearest-name suggestions.
#include "keys.hpp"

#include <algorithm>
#include <limits>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/output_fields.hpp"
#include "fretbem/scenario/key_table.hpp"
#include "value_reader.hpp"

namespace fretbem::scenario_detail {

const std::vector<std::string> kSections = scenario_sections();

const std::vector<std::string> kKeys = [] {
  std::vector<std::string> names;
  for (const ScenarioKey& k : scenario_keys()) names.emplace_back(k.key);
  return names;
}();

const std::vector<std::string> kFieldNames = selectable_field_names();

namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      const std::size_t sub = diag + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, sub});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string_view short_name(std::string_view key) {
  const auto dot = key.find('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

// Nearest valid name. The part after the section also counts (one step dearer), so that a
// right key in the wrong section ([grid] mu) still finds material.mu.
std::string suggestion(std::string_view key, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_score = std::numeric_limits<std::size_t>::max();
  // Case-blind: `NU` is one capital away from material.nu but two edits from material.E.
  const std::string k = lower(std::string(key));
  for (const auto& name : names) {
    const std::string n = lower(name);
    const std::size_t score =
        std::min(edit_distance(k, n), edit_distance(short_name(k), short_name(n)) + 1);
    if (score < best_score) best_score = score, best = name;
  }
  const std::size_t limit = std::max<std::size_t>(2, short_name(key).size() / 3);
  if (best_score > limit) return {};
  return " (did you mean '" + best + "'?)";
}

void reject_unknown(const std::string& key, const std::string& where) {
  if (std::find(kKeys.begin(), kKeys.end(), key) != kKeys.end()) return;
  const auto dot = key.find('.');
  if (dot == std::string::npos)
    throw InputError(where + ": key '" + printable(key) + "' is outside any section" +
                     suggestion(key, kKeys));
  const std::string section = key.substr(0, dot);
  if (std::find(kSections.begin(), kSections.end(), section) == kSections.end()) {
    std::string hint = suggestion(section, kSections);
    if (hint.empty())
      hint = " (sections: material, grid, surface, load, solver, output, wear, friction)";
    throw InputError(where + ": unknown section [" + printable(section) + "] in key '" +
                     printable(key) + "'" + hint);
  }
  throw InputError(where + ": unknown key '" + printable(key) + "'" + suggestion(key, kKeys));
}

std::string normalise_key(const std::string& key) {
  const auto dot = key.find('.');
  if (dot == std::string::npos) return trim(key);
  return trim(key.substr(0, dot)) + "." + trim(key.substr(dot + 1));
}

}  // namespace fretbem::scenario_detail
