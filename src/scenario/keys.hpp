// The scenario's vocabulary: every section and key, the output field names, and the
// nearest-name suggestion that every "unknown ..." message carries.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace fretbem::scenario_detail {

extern const std::vector<std::string> kSections;
/// Every key a scenario may hold, in the key table's order (the names of scenario_keys()).
extern const std::vector<std::string> kKeys;
extern const std::vector<std::string> kFieldNames;

/// The part after the section ("grid.n" -> "n").
std::string_view short_name(std::string_view key);
/// " (did you mean 'NAME'?)" for the nearest of names, or empty when none is near.
std::string suggestion(std::string_view key, const std::vector<std::string>& names);
/// Throws InputError (prefixed with where) unless key is a known key.
void reject_unknown(const std::string& key, const std::string& where);
/// "[ grid ]" reaches us as " grid .n": normalise the section and the name separately.
std::string normalise_key(const std::string& key);

}  // namespace fretbem::scenario_detail
