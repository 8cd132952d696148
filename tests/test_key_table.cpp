// The declarative tables against the code and docs that use them. The scenario key table:
// every default is what the reader assumes and the writer writes, every choice and range the
// reader applies is the table's, and the README lists every key with its default. The output
// field table: output.fields, result.h5's units, the README and tools/plot_fields.py.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/output_fields.hpp"
#include "fretbem/io/result_metadata.hpp"
#include "fretbem/scenario/ignored_keys.hpp"
#include "fretbem/scenario/key_table.hpp"
#include "fretbem/scenario/scenario.hpp"

namespace fs = std::filesystem;
using fretbem::KeyType;
using fretbem::scenario_keys;
using fretbem::ScenarioKey;

namespace {

// The smallest scenario: every key it does not give takes its default.
const std::string kMinimal = R"([material]
E = 210e9
nu = 0.3
[grid]
n = 16
length = 1e-3
[surface]
radius = 0.01
[load]
normal_force = 10
)";

// Every key that a ramp, rough surface, wear run and friction law read is given, so that any
// one choice set by an override leaves a scenario the cross-key rules accept.
const std::string kFull = kMinimal + R"(amplitude = 0.5
displacement_amplitude = 1e-7
[surface]
rms_height = 1e-6
seed = 3
[wear]
coefficient = 1e-15
cycles = 100
[friction]
mu_kinetic = 0.25
mu_final = 0.2
scale = 1
)";

fretbem::Scenario parse(const std::string& text, const std::vector<std::string>& overrides) {
  return fretbem::parse_scenario(text, "test.ini", fs::temp_directory_path(), overrides);
}

/// The InputError message, or "" when the text parses.
std::string error_of(const std::string& text, const std::vector<std::string>& overrides) {
  try {
    parse(text, overrides);
  } catch (const fretbem::InputError& e) {
    return e.what();
  }
  return "";
}

/// "section.key" -> value of the resolved text's written lines.
std::map<std::string, std::string> written(const std::string& resolved) {
  std::map<std::string, std::string> out;
  std::istringstream in(resolved);
  std::string line, section;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (line[0] == '[') {
      section = line.substr(1, line.size() - 2);
      continue;
    }
    const auto eq = line.find(" = ");
    out[section + "." + line.substr(0, eq)] = line.substr(eq + 3);
  }
  return out;
}

std::string override_of(const ScenarioKey& k, const std::string& value) {
  return std::string(k.key) + "=" + value;
}

bool is_number(const std::string& s, double& v) {
  std::istringstream in(s);
  return (in >> v) && in.eof();
}

}  // namespace

// The resolved text (result.h5 /scenario, checkpoints) writes every key the table gives a
// default for with that default; the keys written as unset have none.
TEST(KeyTable, ResolvedTextWritesEachDefault) {
  // Written only away from their default: the coupling keys only when coupled, the predictor
  // only when not auto (resolved texts of default runs carry no keys they do not use).
  const std::set<std::string> conditional = {"solver.coupling_tolerance",
                                             "solver.coupling_iterations", "solver.predictor"};
  const auto values = written(parse(kMinimal, {}).resolved_text);
  const auto coupled = written(parse(kMinimal, {"solver.coupling=coupled"}).resolved_text);
  for (const ScenarioKey& k : scenario_keys()) {
    const std::string key(k.key);
    if (k.default_value.empty()) continue;
    if (conditional.count(key)) {
      if (coupled.count(key)) {
        EXPECT_EQ(coupled.at(key), k.default_value) << key;
      }
      continue;
    }
    ASSERT_TRUE(values.count(key)) << key << " is not written";
    EXPECT_EQ(values.at(key), k.default_value) << key;
  }
  for (const auto& [key, value] : coupled)
    EXPECT_NO_THROW(fretbem::scenario_key(key)) << "written key outside the table: " << key;
}

// A key given with its table default leaves the scenario as it was: the reader's assumption
// is the table's.
TEST(KeyTable, GivingTheDefaultChangesNothing) {
  const std::string base = parse(kMinimal, {}).resolved_text;
  for (const ScenarioKey& k : scenario_keys()) {
    if (k.default_value.empty()) continue;
    EXPECT_EQ(parse(kMinimal, {override_of(k, std::string(k.default_value))}).resolved_text, base)
        << k.key;
  }
}

// Every choice of the table is accepted and written back with its spelling; anything else is
// refused with the table's list.
TEST(KeyTable, EveryChoiceIsReadAndWrittenAsTheTableSpellsIt) {
  for (const ScenarioKey& k : scenario_keys()) {
    if (k.type != KeyType::choice) continue;
    std::string list;
    for (const auto& c : k.choices) {
      list += (list.empty() ? "" : "|") + c;
      const std::string msg = error_of(kFull, {override_of(k, c)});
      // surface.type = file and load.path = table need a file: the refusal names that key.
      if (!msg.empty()) {
        EXPECT_EQ(msg.find("is not one of"), std::string::npos) << msg;
        continue;
      }
      const auto values = written(parse(kFull, {override_of(k, c)}).resolved_text);
      if (values.count(std::string(k.key))) {
        EXPECT_EQ(values.at(std::string(k.key)), c);
      }
    }
    const std::string msg = error_of(kFull, {override_of(k, "bogus")});
    EXPECT_NE(msg.find("not one of " + list), std::string::npos) << k.key << ": " << msg;
  }
}

// Each bound of a real or integer key is where the reader starts refusing: the bound itself
// passes (closed ends), the next representable value beyond it is refused naming the key.
TEST(KeyTable, RangesAreTheReadersBounds) {
  const std::string two_bodies = kMinimal + "[material]\nE2 = 1e11\nnu2 = 0.3\n";
  int checked = 0;
  for (const ScenarioKey& k : scenario_keys()) {
    if (k.type != KeyType::real && k.type != KeyType::integer) continue;
    const std::string prefix = "--set " + std::string(k.key) + "=";
    for (const bool upper : {false, true}) {
      const double bound = upper ? k.hi : k.lo;
      if (std::isinf(bound)) continue;
      const bool open = upper ? k.hi_open : k.lo_open;
      const double beyond = k.type == KeyType::integer
                                ? bound + (upper ? 1 : -1)
                                : std::nextafter(bound, upper ? 1e300 : -1e300);
      const auto text = [&](double v) {
        return k.type == KeyType::integer ? std::to_string(static_cast<long long>(v))
                                          : fretbem::format_number(v);
      };
      const std::string at = error_of(two_bodies, {override_of(k, text(bound))});
      EXPECT_EQ(at.rfind(prefix, 0) == 0, open) << k.key << " at " << bound << ": " << at;
      const std::string past = error_of(two_bodies, {override_of(k, text(beyond))});
      EXPECT_EQ(past.rfind(prefix, 0), 0u) << k.key << " beyond " << bound << ": " << past;
      ++checked;
    }
  }
  EXPECT_GE(checked, 30);
}

// Numbers carry a unit and every key a doc line; the conditional-key warnings name table keys.
TEST(KeyTable, EveryKeyIsDocumentedAndEveryRuleNamesAKey) {
  std::set<std::string> names;
  for (const ScenarioKey& k : scenario_keys()) {
    EXPECT_TRUE(names.insert(std::string(k.key)).second) << "twice: " << k.key;
    EXPECT_FALSE(k.doc.empty()) << k.key;
    const bool numeric = k.type == KeyType::real || k.type == KeyType::magnitude ||
                         k.type == KeyType::wavelength || k.type == KeyType::integer;
    if (numeric) {
      EXPECT_FALSE(k.unit.empty()) << k.key;
    }
    const std::string section(k.key.substr(0, k.key.find('.')));
    const auto& sections = fretbem::scenario_sections();
    EXPECT_NE(std::find(sections.begin(), sections.end(), section), sections.end()) << k.key;
  }
  for (const auto& key : fretbem::conditional_keys()) EXPECT_TRUE(names.count(key)) << key;
}

// README "Scenario files": each key is in the first cell of a row, whose last cell gives the
// defaults in the same order as the keys ("1, 64, 20"); every key the README names exists.
TEST(KeyTable, ReadmeListsEveryKeyWithItsDefault) {
  std::ifstream in(fs::path(FRETBEM_SOURCE_DIR) / "README.md");
  std::string line;
  bool inside = false;
  std::map<std::string, std::string> readme_default;  // key -> its token of the last cell
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) inside = line == "## Scenario files";
    if (!inside || line.rfind("| `", 0) != 0) continue;
    const std::string first = line.substr(2, line.find(" | ") - 2);
    const std::string last = line.substr(line.rfind(" | ") + 3);
    std::vector<std::string> keys, tokens;
    for (auto b = first.find('`'); b != std::string::npos; b = first.find('`', b + 1)) {
      const auto e = first.find('`', b + 1);
      keys.push_back(first.substr(b + 1, e - b - 1));
      b = e;
    }
    std::istringstream cells(last.substr(0, last.size() - 1));
    for (std::string t; std::getline(cells, t, ',');) tokens.push_back(t);
    for (std::size_t i = 0; i < keys.size(); ++i) {
      EXPECT_NO_THROW(fretbem::scenario_key(keys[i])) << "README names " << keys[i];
      std::string token = i < tokens.size() ? tokens[i] : "";
      token.erase(0, token.find_first_not_of(' '));
      readme_default[keys[i]] = token.substr(0, token.find(' '));
    }
  }
  for (const ScenarioKey& k : scenario_keys()) {
    const std::string key(k.key);
    ASSERT_TRUE(readme_default.count(key)) << key << " is missing from the README key table";
    if (k.default_value.empty()) continue;
    const std::string& doc = readme_default.at(key);
    double a = 0, b = 0;
    if (is_number(doc, a) && is_number(std::string(k.default_value), b)) {
      EXPECT_EQ(a, b) << key;
    } else {
      EXPECT_EQ(doc, k.default_value) << key;
    }
  }
}

// output.fields accepts exactly the table's selectable fields, in any order, and result.h5
// describes every field with the table's unit and long name.
TEST(OutputFieldTable, ScenarioAndResultMetadataUseIt) {
  std::string all;
  for (const auto& name : fretbem::selectable_field_names())
    all += (all.empty() ? "" : ", ") + name;
  EXPECT_EQ(parse(kMinimal, {"output.fields=" + all}).output.fields,
            fretbem::selectable_field_names());
  for (const fretbem::OutputField& f : fretbem::output_field_table()) {
    const fretbem::io::FieldInfo info = fretbem::io::field_info(f.name);
    EXPECT_EQ(info.units, f.units) << f.name;
    EXPECT_EQ(info.long_name, f.long_name) << f.name;
    EXPECT_EQ(info.flag, f.flag) << f.name;
    if (!f.selectable) {
      EXPECT_NE(error_of(kMinimal, {"output.fields=" + f.name}).find("unknown field"),
                std::string::npos)
          << f.name;
    }
  }
  EXPECT_EQ(fretbem::io::field_info("no_such_field").units, "");
}

namespace {

/// The table's unit in the README's and the plots' spelling.
std::string udunits_of(const std::string& shown) {
  static const std::map<std::string, std::string> known = {
      {"Pa", "Pa"}, {"MPa", "Pa"}, {"m", "m"}, {"nm", "m"}, {"J/m²", "J m-2"}, {"–", "1"}};
  return known.count(shown) ? known.at(shown) : "?" + shown;
}

}  // namespace

// README "Outputs": each selectable field is in a row of the field table with its unit.
TEST(OutputFieldTable, ReadmeListsEveryFieldWithItsUnit) {
  std::ifstream in(fs::path(FRETBEM_SOURCE_DIR) / "README.md");
  std::map<std::string, std::string> unit_of;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line == "| field | meaning | unit |") inside = true;
    if (!inside) continue;
    if (line.empty()) break;
    if (line.rfind("| `", 0) != 0) continue;
    const std::string first = line.substr(2, line.find(" | ") - 2);
    const std::string unit =
        line.substr(line.rfind(" | ") + 3, line.size() - line.rfind(" | ") - 5);
    for (auto b = first.find('`'); b != std::string::npos; b = first.find('`', b + 1)) {
      const auto e = first.find('`', b + 1);
      unit_of[first.substr(b + 1, e - b - 1)] = unit;
      b = e;
    }
  }
  for (const fretbem::OutputField& f : fretbem::output_field_table()) {
    if (!f.selectable) continue;
    ASSERT_TRUE(unit_of.count(f.name)) << f.name << " is missing from the README field table";
    EXPECT_EQ(udunits_of(unit_of.at(f.name)), f.units) << f.name;
  }
}

// tools/plot_fields.py's UNITS: one entry per selectable field but state (drawn with its own
// legend), each label's unit the table's unit scaled by the entry's factor.
TEST(OutputFieldTable, PlotFieldsToolAgreesWithIt) {
  std::ifstream in(fs::path(FRETBEM_SOURCE_DIR) / "tools" / "plot_fields.py");
  static const std::map<std::string, double> factor_of = {
      {"MPa", 1e-6}, {"nm", 1e9}, {"J/m²", 1.0}, {"Pa", 1.0}, {"m", 1.0}};
  std::set<std::string> plotted;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("UNITS = {", 0) == 0) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    if (line == "}") break;
    // '    "pressure": ("pressure (MPa)", 1e-6),'
    const auto q1 = line.find('"'), q2 = line.find('"', q1 + 1);
    const std::string name = line.substr(q1 + 1, q2 - q1 - 1);
    const auto open = line.rfind('('), close = line.find(')', open);
    const std::string shown = line.substr(open + 1, close - open - 1);
    const double factor = std::stod(line.substr(line.rfind(',', line.size() - 2) + 1));
    plotted.insert(name);
    const auto it =
        std::find_if(fretbem::output_field_table().begin(), fretbem::output_field_table().end(),
                     [&](const fretbem::OutputField& f) { return f.name == name && f.selectable; });
    ASSERT_NE(it, fretbem::output_field_table().end()) << "plot_fields.py plots " << name;
    EXPECT_EQ(udunits_of(shown), it->units) << name;
    ASSERT_TRUE(factor_of.count(shown)) << name << ": " << shown;
    EXPECT_DOUBLE_EQ(factor, factor_of.at(shown)) << name;
  }
  for (const auto& name : fretbem::selectable_field_names())
    if (name != "state") {
      EXPECT_TRUE(plotted.count(name)) << name << " is not in UNITS";
    }
}
