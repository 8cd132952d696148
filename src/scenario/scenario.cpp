// Scenario reading and validation (README "Scenario files").
//
// Boost.Program_options only tokenises the INI text (every key registered as a string, unknown
// ones kept); every value is then converted and checked here, so that all messages share one
// shape: `FILE: KEY = VALUE problem` for file values and `--set KEY=VALUE: problem` for overrides.
#include "fretbem/scenario/scenario.hpp"

#include <fstream>
#include <sstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/text_file.hpp"
#include "sections.hpp"

namespace fretbem {

namespace fs = std::filesystem;
using namespace scenario_detail;

namespace {

constexpr std::size_t kMaxFileBytes = 1 << 20;

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& name,
                        const std::filesystem::path& base_dir,
                        const std::vector<std::string>& overrides) {
  Reader r(name);
  read_file_entries(std::string(without_utf8_bom(text)), r);
  for (const auto& o : overrides) apply_override(o, r);

  Scenario s;
  s.name = fs::path(name).stem().string();
  read_material(r, s.material);
  read_grid(r, s.grid);
  if (r.has("grid.allow_edge_contact")) s.allow_edge_contact = r.boolean("grid.allow_edge_contact");
  read_surface(r, base_dir, s.surface);
  read_load(r, base_dir, s.load);
  read_solver(r, s.solver);
  read_output(r, s.output);
  read_wear(r, s.wear);
  s.given_keys = r.keys();
  read_friction(r, s.load, s.material.mu, s.friction);
  check_wear_friction(r, s.wear, s.friction);
  resolve_load_substeps(r, s.wear, s.solver, s.load);
  s.resolved_text = resolved_text(s);
  return s;
}

void set_output_dir(Scenario& s, const fs::path& dir) {
  s.output.dir = dir;
  s.resolved_text = resolved_text(s);
}

Scenario load_scenario(const std::filesystem::path& file,
                       const std::vector<std::string>& overrides) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw InputError(file.string() + ": scenario file not found");
  if (!fs::is_regular_file(file, ec))
    throw InputError(file.string() + ": scenario is not a regular file");
  const auto size = fs::file_size(file, ec);
  if (ec || size > kMaxFileBytes)
    throw InputError(file.string() + ": scenario file is too large (over 1 MiB) or unreadable");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open the scenario file");
  std::ostringstream text;
  text << in.rdbuf();
  fs::path base = file.parent_path();
  if (base.empty()) base = ".";
  return parse_scenario(text.str(), file.filename().string(), base, overrides);
}

}  // namespace fretbem
