// Value conversions of the scenario reader: whitespace, printable echoes, and the checks the
// key table (key_table.cpp) declares for each key.
#include "value_reader.hpp"

#include <cctype>

#include "fretbem/scenario/key_table.hpp"

namespace fretbem::scenario_detail {

std::string trim(std::string_view s) {
  const auto* ws = " \t\r\n\f\v";
  const auto b = s.find_first_not_of(ws);
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(ws);
  return std::string(s.substr(b, e - b + 1));
}

std::string printable(std::string_view s) {
  std::string out;
  for (const char c : s.substr(0, 80)) {
    const auto u = static_cast<unsigned char>(c);
    out += (u < 0x20 || u == 0x7f) ? '?' : c;
  }
  if (s.size() > 80) out += "...";
  return out;
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

double Reader::number(const std::string& key) const {
  const ScenarioKey& k = scenario_key(key);
  switch (k.type) {
    case KeyType::magnitude:
      return magnitude(key);
    case KeyType::wavelength:  // 0 means "none"; anything else is a dimensional value
      return real_in(key, 0.0, false) == 0.0 ? 0.0 : magnitude(key);
    case KeyType::real:
      if (std::isinf(k.lo) && std::isinf(k.hi)) return real(key);
      return real_in(key, k.lo, k.lo_open, k.hi, k.hi_open);
    default:
      throw std::logic_error(key + " is not a number key");
  }
}

long long Reader::count(const std::string& key) const {
  const ScenarioKey& k = scenario_key(key);
  if (k.type != KeyType::integer) throw std::logic_error(key + " is not an integer key");
  return integer(key, static_cast<long long>(k.lo), static_cast<long long>(k.hi));
}

std::size_t Reader::option(const std::string& key) const {
  const ScenarioKey& k = scenario_key(key);
  if (k.type != KeyType::choice) throw std::logic_error(key + " is not a choice key");
  return choice(key, k.choices);
}

}  // namespace fretbem::scenario_detail
