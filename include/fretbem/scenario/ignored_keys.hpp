// Keys a scenario gives but the run never reads: every conditional key with the condition under
// which it is read (ignored_keys.cpp holds the table). `fretbem check` and `fretbem run` both
// warn about each such key, so a value that changes nothing is never accepted without a word.
#pragma once

#include <string>
#include <vector>

#include "fretbem/scenario/scenario.hpp"

namespace fretbem {

struct IgnoredKey {
  std::string key;  ///< "section.key"
  std::string why;  ///< when it is read, and what this scenario has instead
};

/// The given keys (Scenario::given_keys) that this scenario's choices leave unread, in key order.
std::vector<IgnoredKey> ignored_keys(const Scenario& sc);

/// "KEY is ignored: WHY" for each ignored key: the warning text check and run print.
std::vector<std::string> ignored_key_warnings(const Scenario& sc);

/// The keys the table covers: those read only under a condition. Every other key is read by
/// every run (the material, grid, normal load, solver settings, outputs and the laws' names).
std::vector<std::string> conditional_keys();

}  // namespace fretbem
