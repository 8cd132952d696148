// Scenario reading and validation (DESIGN §4 "Scenario files").
//
// Boost.Program_options only tokenises the INI text (every key registered as a string, unknown
// ones kept); every value is then converted and checked here, so that all messages share one
// shape: `FILE: KEY = VALUE problem` for file values and `--set KEY=VALUE: problem` for overrides.
#include "fretbem/scenario/scenario.hpp"

#include <algorithm>
#include <boost/program_options.hpp>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "fretbem/core/errors.hpp"

namespace fretbem {

namespace {

namespace fs = std::filesystem;
namespace po = boost::program_options;

const std::vector<std::string> kSections = {"material", "grid",   "surface", "load",
                                            "solver",   "output", "wear"};

// Every key a scenario may hold, in the order resolved_text writes them.
const std::vector<std::string> kKeys = {
    "material.E",
    "material.nu",
    "material.E2",
    "material.nu2",
    "material.mu",
    "grid.n",
    "grid.nx",
    "grid.ny",
    "grid.length",
    "grid.periodic",
    "surface.type",
    "surface.radius",
    "surface.hurst",
    "surface.rms_height",
    "surface.rms_slope",
    "surface.method",
    "surface.seed",
    "surface.rolloff_wavelength",
    "surface.cutoff_wavelength",
    "surface.file",
    "surface.dataset",
    "load.normal_force",
    "load.indentation",
    "load.path",
    "load.control",
    "load.amplitude",
    "load.displacement_amplitude",
    "load.direction",
    "load.cycles",
    "load.steps_per_cycle",
    "load.steps",
    "load.table",
    "solver.tolerance",
    "solver.max_iterations",
    "solver.coupling",
    "solver.threads",
    "solver.algorithm",
    "solver.stiffness",
    "solver.fft_plan",
    "solver.fft_precision",
    "solver.precondition",
    "solver.monotone",
    "output.dir",
    "output.fields",
    "output.fields_every",
    "output.checkpoint_every",
    "wear.law",
    "wear.coefficient",
    "wear.cycles",
    "wear.integrator",
    "wear.rtol",
    "wear.atol",
    "wear.newton",
    "wear.indenter_share",
};

const std::vector<std::string> kFieldNames = {"pressure", "traction_x", "traction_y",  "state",
                                              "slip_x",   "slip_y",     "dissipation", "wear"};

// Grid limits keep nx*ny and the 2nx x 2ny padded FFT grid inside a 32-bit int index.
constexpr long long kMaxSide = 65536;
constexpr long long kMaxNodes = 1LL << 28;
constexpr std::size_t kMaxFileBytes = 1 << 20;

std::string trim(std::string_view s) {
  const auto* ws = " \t\r\n\f\v";
  const auto b = s.find_first_not_of(ws);
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(ws);
  return std::string(s.substr(b, e - b + 1));
}

// Values are echoed in one-line messages: no control characters, bounded length.
std::string printable(std::string_view s) {
  std::string out;
  for (const char c : s.substr(0, 80)) {
    const auto u = static_cast<unsigned char>(c);
    out += (u < 0x20 || u == 0x7f) ? '?' : c;
  }
  if (s.size() > 80) out += "...";
  return out;
}

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

std::string_view short_name(std::string_view key) {
  const auto dot = key.find('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

// Nearest valid name. The part after the section also counts (one step dearer), so that a
// right key in the wrong section ([grid] mu) still finds material.mu.
std::string suggestion(std::string_view key, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_score = std::numeric_limits<std::size_t>::max();
  for (const auto& name : names) {
    const std::size_t score =
        std::min(edit_distance(key, name), edit_distance(short_name(key), short_name(name)) + 1);
    if (score < best_score) best_score = score, best = name;
  }
  const std::size_t limit = std::max<std::size_t>(2, short_name(key).size() / 3);
  if (best_score > limit) return {};
  return " (did you mean '" + best + "'?)";
}

std::string format_double(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

struct Entry {
  std::string value;
  std::string origin;  ///< "--set KEY=VALUE" for overrides, empty for file values
};

/// The merged key/value set with the name used in messages; converts values and reports.
class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }
  void set(const std::string& key, Entry e) { entries_[key] = std::move(e); }
  bool has(const std::string& key) const { return entries_.count(key) != 0; }
  const std::string& raw(const std::string& key) const { return entries_.at(key).value; }

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(file_ + ": " + problem);
  }

  /// problem reads after the value: "is not an integer", "must be > 0".
  [[noreturn]] void fail_value(const std::string& key, const std::string& problem) const {
    const Entry& e = entries_.at(key);
    if (e.origin.empty())
      throw InputError(file_ + ": " + key + " = " + printable(e.value) + " " + problem);
    std::string p = problem.rfind("is ", 0) == 0 ? problem.substr(3) : problem;
    throw InputError(printable(e.origin) + ": " + p);
  }

  void require(const std::string& key, const std::string& why = "") const {
    if (!has(key)) fail("missing required key '" + key + "'" + why);
  }

  double real(const std::string& key) const {
    const std::string s = raw(key);
    const char* b = s.data() + (s.size() > 1 && s[0] == '+' ? 1 : 0);
    const char* e = s.data() + s.size();
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(b, e, v);
    if (ec == std::errc::result_out_of_range) fail_value(key, "is out of the range of a double");
    if (ec != std::errc() || ptr != e) fail_value(key, "is not a number");
    if (!std::isfinite(v)) fail_value(key, "is not a finite number");
    return v;
  }

  /// Real in the interval lo..hi; open ends exclude the bound. Infinite hi means no bound.
  double real_in(const std::string& key, double lo, bool lo_open,
                 double hi = std::numeric_limits<double>::infinity(), bool hi_open = true) const {
    const double v = real(key);
    const bool ok = (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    if (ok) return v;
    if (std::isinf(hi))
      fail_value(key, std::string("must be ") + (lo_open ? "> " : ">= ") + format_double(lo));
    fail_value(key, "is out of range " + std::string(lo_open ? "(" : "[") + format_double(lo) +
                        ", " + format_double(hi) + (hi_open ? ")" : "]"));
  }
  double positive(const std::string& key) const { return real_in(key, 0.0, true); }

  long long integer(const std::string& key, long long lo, long long hi) const {
    const std::string s = raw(key);
    const char* b = s.data() + (s.size() > 1 && s[0] == '+' ? 1 : 0);
    const char* e = s.data() + s.size();
    long long v = 0;
    const auto [ptr, ec] = std::from_chars(b, e, v);
    if (ec == std::errc::result_out_of_range) fail_value(key, "is out of range");
    if (ec != std::errc() || ptr != e) fail_value(key, "is not an integer");
    if (v < lo) fail_value(key, "must be >= " + std::to_string(lo));
    if (v > hi)
      fail_value(key, "is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }

  std::uint64_t unsigned64(const std::string& key) const {
    const std::string s = raw(key);
    std::uint64_t v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec == std::errc::result_out_of_range) fail_value(key, "is out of range [0, 2^64)");
    if (ec != std::errc() || ptr != s.data() + s.size())
      fail_value(key, "is not a non-negative integer");
    return v;
  }

  bool boolean(const std::string& key) const {
    const std::string s = lower(raw(key));
    if (s == "true" || s == "1" || s == "yes" || s == "on") return true;
    if (s == "false" || s == "0" || s == "no" || s == "off") return false;
    fail_value(key, "is not a boolean (true/false, yes/no, 1/0)");
  }

  /// Index of the value in choices.
  std::size_t choice(const std::string& key, const std::vector<std::string>& choices) const {
    const std::string& s = raw(key);
    for (std::size_t i = 0; i < choices.size(); ++i)
      if (s == choices[i]) return i;
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : "|") + c;
    fail_value(key, "is not one of " + list + suggestion(s, choices));
  }

  /// Path resolved against base; optionally required to be an existing regular file.
  fs::path path(const std::string& key, const fs::path& base, bool must_exist) const {
    const std::string& s = raw(key);
    if (s.empty()) fail_value(key, "is empty");
    fs::path p(s);
    if (p.is_relative()) p = base / p;
    std::error_code ec;
    p = fs::absolute(p, ec).lexically_normal();
    if (must_exist && !fs::is_regular_file(p, ec))
      fail_value(key, "is not a file (looked for " + printable(p.string()) + ")");
    return p;
  }

 private:
  std::string file_;
  std::map<std::string, Entry> entries_;
};

void reject_unknown(const std::string& key, const std::string& where) {
  if (std::find(kKeys.begin(), kKeys.end(), key) != kKeys.end()) return;
  const auto dot = key.find('.');
  if (dot == std::string::npos)
    throw InputError(where + ": key '" + printable(key) + "' is outside any section" +
                     suggestion(key, kKeys));
  const std::string section = key.substr(0, dot);
  if (std::find(kSections.begin(), kSections.end(), section) == kSections.end()) {
    std::string hint = suggestion(section, kSections);
    if (hint.empty()) hint = " (sections: material, grid, surface, load, solver, output, wear)";
    throw InputError(where + ": unknown section [" + printable(section) + "] in key '" +
                     printable(key) + "'" + hint);
  }
  throw InputError(where + ": unknown key '" + printable(key) + "'" + suggestion(key, kKeys));
}

// "[ grid ]" reaches us as " grid .n": normalise the section and the name separately.
std::string normalise_key(const std::string& key) {
  const auto dot = key.find('.');
  if (dot == std::string::npos) return trim(key);
  return trim(key.substr(0, dot)) + "." + trim(key.substr(dot + 1));
}

void read_file_entries(const std::string& text, Reader& r) {
  po::options_description desc;
  for (const auto& k : kKeys) desc.add_options()(k.c_str(), po::value<std::string>());
  std::istringstream in(text);
  po::parsed_options parsed(&desc);
  try {
    parsed = po::parse_config_file(in, desc, /*allow_unregistered=*/true);
  } catch (const std::exception& e) {
    r.fail(printable(e.what()));
  }
  std::set<std::string> seen;
  for (const auto& opt : parsed.options) {
    const std::string key = normalise_key(opt.string_key);
    const std::string value = opt.value.empty() ? std::string() : trim(opt.value.front());
    if (short_name(key).empty())
      r.fail("a line has no key before '=' (value '" + printable(value) + "')");
    reject_unknown(key, r.file());
    if (!seen.insert(key).second)
      r.fail("duplicated key '" + key + "' (" + printable(r.raw(key)) + " and " + printable(value) +
             ")");
    r.set(key, Entry{value, ""});
  }
}

void apply_override(const std::string& text, Reader& r) {
  const std::string where = "--set " + printable(text);
  const auto eq = text.find('=');
  if (eq == std::string::npos) throw InputError(where + ": expected section.key=value");
  const std::string key = normalise_key(text.substr(0, eq));
  if (short_name(key).empty()) throw InputError(where + ": expected section.key=value");
  reject_unknown(key, where);
  r.set(key, Entry{trim(text.substr(eq + 1)), where});
}

void read_material(const Reader& r, Material& m) {
  r.require("material.E");
  r.require("material.nu");
  m.body1 = Body{r.positive("material.E"), r.real_in("material.nu", 0.0, false, 0.5, true)};
  if (r.has("material.E2") != r.has("material.nu2"))
    r.fail("material.E2 and material.nu2 describe the second body: give both or neither");
  if (r.has("material.E2"))
    m.body2 = Body{r.positive("material.E2"), r.real_in("material.nu2", 0.0, false, 0.5, true)};
  if (r.has("material.mu")) m.mu = r.positive("material.mu");
}

void read_grid(const Reader& r, Grid& g) {
  const bool both = r.has("grid.nx") && r.has("grid.ny");
  if (!both) r.require("grid.n", " (or both grid.nx and grid.ny)");
  const long long n = r.has("grid.n") ? r.integer("grid.n", 2, kMaxSide) : 0;
  const long long nx = r.has("grid.nx") ? r.integer("grid.nx", 2, kMaxSide) : n;
  const long long ny = r.has("grid.ny") ? r.integer("grid.ny", 2, kMaxSide) : n;
  if (nx * ny > kMaxNodes)
    r.fail("grid of " + std::to_string(nx) + " x " + std::to_string(ny) +
           " nodes is too large (at most 2^28 nodes)");
  r.require("grid.length");
  const double length = r.positive("grid.length");
  g = Grid{static_cast<int>(nx), static_cast<int>(ny), length / static_cast<double>(nx),
           r.has("grid.periodic") && r.boolean("grid.periodic")};
}

void read_rough(const Reader& r, RoughSpec& s) {
  if (r.has("surface.hurst")) s.hurst = r.real_in("surface.hurst", 0.0, true, 1.0, false);
  if (r.has("surface.rms_height")) s.rms_height = r.positive("surface.rms_height");
  if (r.has("surface.rms_slope")) s.rms_slope = r.positive("surface.rms_slope");
  if (r.has("surface.method"))
    s.method = static_cast<RoughMethod>(r.choice("surface.method", {"midpoint", "fourier"}));
  if (r.has("surface.seed")) s.seed = r.unsigned64("surface.seed");
  if (r.has("surface.rolloff_wavelength"))
    s.rolloff_wavelength = r.real_in("surface.rolloff_wavelength", 0.0, false);
  if (r.has("surface.cutoff_wavelength"))
    s.cutoff_wavelength = r.real_in("surface.cutoff_wavelength", 0.0, false);
}

void check_rough(const Reader& r, const RoughSpec& s) {
  if (s.rms_height.has_value() == s.rms_slope.has_value())
    r.fail("surface.type = rough needs exactly one of surface.rms_height and surface.rms_slope");
  r.require("surface.seed",
            " for surface.type = rough (results are reproducible only with an "
            "explicit seed)");
  if (s.rolloff_wavelength > 0 && s.cutoff_wavelength > 0 &&
      s.cutoff_wavelength >= s.rolloff_wavelength)
    r.fail("surface.cutoff_wavelength = " + format_double(s.cutoff_wavelength) +
           " must be shorter than surface.rolloff_wavelength = " +
           format_double(s.rolloff_wavelength));
}

void read_surface(const Reader& r, const fs::path& base, SurfaceSpec& s) {
  if (r.has("surface.type"))
    s.type =
        static_cast<SurfaceType>(r.choice("surface.type", {"sphere", "flat", "rough", "file"}));
  if (r.has("surface.radius")) s.radius = r.positive("surface.radius");
  read_rough(r, s.rough);
  if (r.has("surface.dataset")) s.dataset = r.raw("surface.dataset");
  const bool is_file = s.type == SurfaceType::file;
  if (r.has("surface.file")) s.file = r.path("surface.file", base, is_file);
  if (s.type == SurfaceType::sphere) r.require("surface.radius", " for surface.type = sphere");
  if (s.type == SurfaceType::rough) check_rough(r, s.rough);
  if (is_file) r.require("surface.file", " for surface.type = file");
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(trim(cell));
  return out;
}

// The table's header decides what it can drive; catch a mismatch here rather than mid-run.
void check_table(const Reader& r, const LoadSpec& l) {
  std::ifstream in(l.table);
  std::string line;
  while (std::getline(in, line) && (trim(line).empty() || trim(line)[0] == '#')) {
  }
  const std::vector<std::string> known = {"time", "Fz", "delta", "Fx", "Fy", "Ux", "Uy"};
  std::set<std::string> cols;
  for (const auto& c : split_csv_line(line)) {
    if (std::find(known.begin(), known.end(), c) == known.end())
      r.fail_value("load.table", "has an unknown column '" + printable(c) + "'" +
                                     suggestion(c, known) +
                                     "; columns: time, Fz, delta, Fx, "
                                     "Fy, Ux, Uy");
    cols.insert(c);
  }
  if (!cols.count("time")) r.fail_value("load.table", "has no 'time' column in its header row");
  const bool normal_given = l.normal_force || l.indentation;
  if (!normal_given && !cols.count("Fz") && !cols.count("delta"))
    r.fail_value("load.table",
                 "has neither Fz nor delta, and neither load.normal_force nor "
                 "load.indentation is given");
  if (normal_given && (cols.count("Fz") || cols.count("delta")))
    r.fail_value("load.table",
                 "has an Fz or delta column as well as a constant normal load "
                 "key; give one");
  const bool force_cols = cols.count("Fx") || cols.count("Fy");
  const bool disp_cols = cols.count("Ux") || cols.count("Uy");
  if (l.control == Control::force && disp_cols)
    r.fail_value("load.table", "has Ux/Uy columns but load.control = force");
  if (l.control == Control::displacement && force_cols)
    r.fail_value("load.table", "has Fx/Fy columns but load.control = displacement");
}

void read_load_values(const Reader& r, const fs::path& base, LoadSpec& l) {
  if (r.has("load.normal_force")) l.normal_force = r.positive("load.normal_force");
  if (r.has("load.indentation")) l.indentation = r.positive("load.indentation");
  if (r.has("load.path"))
    l.path = static_cast<PathType>(r.choice("load.path", {"none", "ramp", "sine", "table"}));
  if (r.has("load.control"))
    l.control = static_cast<Control>(r.choice("load.control", {"force", "displacement"}));
  if (r.has("load.amplitude")) l.amplitude = r.real("load.amplitude");
  if (r.has("load.displacement_amplitude"))
    l.displacement_amplitude = r.real("load.displacement_amplitude");
  if (r.has("load.direction")) l.direction = r.real("load.direction");
  if (r.has("load.cycles")) l.cycles = static_cast<int>(r.integer("load.cycles", 1, 1 << 30));
  if (r.has("load.steps_per_cycle"))
    l.steps_per_cycle = static_cast<int>(r.integer("load.steps_per_cycle", 4, 1 << 30));
  if (r.has("load.steps")) l.steps = static_cast<int>(r.integer("load.steps", 1, 1 << 30));
  if (r.has("load.table")) l.table = r.path("load.table", base, l.path == PathType::table);
}

void check_amplitudes(const Reader& r, const LoadSpec& l) {
  if (l.path != PathType::ramp && l.path != PathType::sine) return;
  if (l.control == Control::force) {
    r.require("load.amplitude", " for a force-controlled ramp or sine");
    if (l.amplitude >= 1.0)
      r.fail_value("load.amplitude",
                   "is impossible: a tangential force >= mu Fz cannot be held by friction "
                   "(gross sliding); use a value < 1, or load.control = displacement");
    if (l.amplitude <= 0.0) r.fail_value("load.amplitude", "is out of range (0, 1)");
  } else {
    r.require("load.displacement_amplitude", " for a displacement-controlled ramp or sine");
    if (l.displacement_amplitude <= 0.0) r.fail_value("load.displacement_amplitude", "must be > 0");
  }
  if (l.path == PathType::sine &&
      static_cast<long long>(l.cycles) * l.steps_per_cycle > std::numeric_limits<int>::max())
    r.fail("load.cycles x load.steps_per_cycle is too many steps");
}

void read_load(const Reader& r, const fs::path& base, LoadSpec& l) {
  read_load_values(r, base, l);
  if (l.normal_force && l.indentation)
    r.fail("load.normal_force and load.indentation are both given; give exactly one");
  if (l.path == PathType::table) {
    r.require("load.table", " for load.path = table");
    check_table(r, l);
  } else if (!l.normal_force && !l.indentation) {
    r.fail("missing required key 'load.normal_force' or 'load.indentation'");
  }
  check_amplitudes(r, l);
}

void read_solver(const Reader& r, SolverSpec& s) {
  if (r.has("solver.tolerance"))
    s.tolerance = r.real_in("solver.tolerance", 0.0, true, 1e-2, false);
  if (r.has("solver.max_iterations"))
    s.max_iterations = static_cast<int>(r.integer("solver.max_iterations", 1, 1 << 30));
  if (r.has("solver.coupling"))
    s.coupling = static_cast<Coupling>(r.choice("solver.coupling", {"analogy", "cerruti"}));
  if (r.has("solver.threads")) s.threads = static_cast<int>(r.integer("solver.threads", 0, 4096));
  if (r.has("solver.algorithm"))
    s.algorithm =
        static_cast<TangentialAlgorithm>(r.choice("solver.algorithm", {"projected", "partition"}));
  if (r.has("solver.stiffness")) s.stiffness = r.boolean("solver.stiffness");
  if (r.has("solver.fft_plan"))
    s.fft_measure = r.choice("solver.fft_plan", {"estimate", "measure"}) == 1;
  if (r.has("solver.monotone"))
    s.shortcut = r.choice("solver.monotone", {"incremental", "shortcut"}) == 1;
  if (r.has("solver.precondition")) {
    static constexpr Precondition kinds[] = {Precondition::automatic, Precondition::on,
                                             Precondition::off};
    s.precondition = kinds[r.choice("solver.precondition", {"automatic", "on", "off"})];
  }
  if (r.has("solver.fft_precision"))
    s.fft_precision = r.choice("solver.fft_precision", {"double", "float"}) == 1
                          ? FftPrecision::float32
                          : FftPrecision::float64;
  // Float convolutions put a round-off floor under every residual. Without an explicit
  // tolerance the floor is the default (written to the resolved scenario); an explicit one
  // below it is refused here, so `fretbem check` catches it and no solve stagnates to
  // max_iterations first.
  if (s.fft_precision == FftPrecision::float32) {
    if (!r.has("solver.tolerance"))
      s.tolerance = kFloatFftMinTolerance;
    else if (s.tolerance < kFloatFftMinTolerance)
      r.fail_value("solver.tolerance", "is below " + format_double(kFloatFftMinTolerance) +
                                           ", the smallest tolerance float FFTs can reach "
                                           "(solver.fft_precision = float): raise it or use "
                                           "solver.fft_precision = double");
  }
}

std::vector<std::string> read_fields(const Reader& r) {
  std::vector<std::string> out;
  const std::string list = trim(r.raw("output.fields"));
  if (list.empty() || list == "none") return out;
  for (const auto& f : split_csv_line(list)) {
    if (std::find(kFieldNames.begin(), kFieldNames.end(), f) == kFieldNames.end())
      r.fail_value("output.fields", "names an unknown field '" + printable(f) + "'" +
                                        suggestion(f, kFieldNames) +
                                        "; fields: pressure, traction_x, traction_y, state, "
                                        "slip_x, slip_y, dissipation, wear");
    if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
  }
  return out;
}

void read_output(const Reader& r, OutputSpec& o) {
  if (r.has("output.dir")) {
    if (r.raw("output.dir").empty()) r.fail_value("output.dir", "is empty");
    o.dir = r.raw("output.dir");
  }
  if (r.has("output.fields")) o.fields = read_fields(r);
  if (r.has("output.fields_every"))
    o.fields_every = static_cast<int>(r.integer("output.fields_every", 0, 1 << 30));
  if (r.has("output.checkpoint_every"))
    o.checkpoint_every = static_cast<int>(r.integer("output.checkpoint_every", 0, 1 << 30));
}

void read_wear(const Reader& r, WearSpec& w) {
  if (r.has("wear.law"))
    w.law = static_cast<WearLaw>(r.choice("wear.law", {"none", "archard", "energy"}));
  if (r.has("wear.coefficient")) w.coefficient = r.positive("wear.coefficient");
  if (r.has("wear.cycles")) w.cycles = r.positive("wear.cycles");
  if (r.has("wear.integrator"))
    w.integrator = static_cast<WearIntegrator>(
        r.choice("wear.integrator", {"arkode", "cycle", "erk", "dirk"}));
  if (r.has("wear.rtol")) w.rtol = r.positive("wear.rtol");
  if (r.has("wear.atol")) w.atol = r.positive("wear.atol");
  if (r.has("wear.newton"))
    w.newton = static_cast<WearNewton>(r.choice("wear.newton", {"frozen", "krylov"}));
  if (r.has("wear.indenter_share"))
    w.indenter_share = r.real_in("wear.indenter_share", 0.0, false, 1.0, false);
  if (w.law == WearLaw::none) return;
  r.require("wear.coefficient", " when wear.law is not none");
  r.require("wear.cycles", " when wear.law is not none");
  if (w.integrator == WearIntegrator::cycle && w.cycles != std::floor(w.cycles))
    r.fail_value("wear.cycles", "is not a whole number (wear.integrator = cycle)");
}

// ---- resolved text: every key with its final value; unset optional keys as comments ----

class IniWriter {
 public:
  void section(const std::string& name) {
    out_ << (out_.tellp() > 0 ? "\n[" : "[") << name << "]\n";
  }
  void put(const std::string& key, const std::string& value) {
    out_ << key << " = " << value << "\n";
  }
  void put(const std::string& key, double v) { put(key, format_double(v)); }
  void put(const std::string& key, int v) { put(key, std::to_string(v)); }
  void put(const std::string& key, bool v) { put(key, std::string(v ? "true" : "false")); }
  void put(const std::string& key, const std::optional<double>& v) {
    if (v)
      put(key, *v);
    else
      out_ << "# " << key << " = (unset)\n";
  }
  void put(const std::string& key, const fs::path& p) {
    if (p.empty())
      out_ << "# " << key << " = (unset)\n";
    else
      put(key, p.string());
  }
  void raw(const std::string& line) { out_ << line << "\n"; }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

void write_material(IniWriter& w, const Material& m) {
  w.section("material");
  w.put("E", m.body1.E);
  w.put("nu", m.body1.nu);
  w.put("E2", m.body2 ? std::optional<double>(m.body2->E) : std::nullopt);
  w.put("nu2", m.body2 ? std::optional<double>(m.body2->nu) : std::nullopt);
  w.put("mu", m.mu);
}

void write_grid(IniWriter& w, const Grid& g) {
  w.section("grid");
  if (g.nx == g.ny) {
    w.put("n", g.nx);
  } else {
    w.put("nx", g.nx);
    w.put("ny", g.ny);
  }
  w.put("length", g.length_x());
  w.put("periodic", g.periodic);
}

void write_surface(IniWriter& w, const SurfaceSpec& s) {
  static const char* types[] = {"sphere", "flat", "rough", "file"};
  w.section("surface");
  w.put("type", std::string(types[static_cast<int>(s.type)]));
  w.put("radius", s.radius > 0 ? std::optional<double>(s.radius) : std::nullopt);
  w.put("hurst", s.rough.hurst);
  w.put("rms_height", s.rough.rms_height);
  w.put("rms_slope", s.rough.rms_slope);
  w.put("method", std::string(s.rough.method == RoughMethod::midpoint ? "midpoint" : "fourier"));
  w.put("seed", std::to_string(s.rough.seed));
  w.put("rolloff_wavelength", s.rough.rolloff_wavelength);
  w.put("cutoff_wavelength", s.rough.cutoff_wavelength);
  w.put("file", s.file);
  if (s.dataset.empty())
    w.raw("# dataset = (unset)");
  else
    w.put("dataset", s.dataset);
}

void write_load(IniWriter& w, const LoadSpec& l) {
  static const char* paths[] = {"none", "ramp", "sine", "table"};
  w.section("load");
  w.put("normal_force", l.normal_force);
  w.put("indentation", l.indentation);
  w.put("path", std::string(paths[static_cast<int>(l.path)]));
  w.put("control", std::string(l.control == Control::force ? "force" : "displacement"));
  w.put("amplitude", l.amplitude);
  w.put("displacement_amplitude", l.displacement_amplitude);
  w.put("direction", l.direction);
  w.put("cycles", l.cycles);
  w.put("steps_per_cycle", l.steps_per_cycle);
  w.put("steps", l.steps);
  w.put("table", l.table);
}

void write_solver(IniWriter& w, const SolverSpec& s) {
  w.section("solver");
  w.put("tolerance", s.tolerance);
  w.put("max_iterations", s.max_iterations);
  w.put("coupling", std::string(s.coupling == Coupling::analogy ? "analogy" : "cerruti"));
  w.put("threads", s.threads);
  w.put("algorithm",
        std::string(s.algorithm == TangentialAlgorithm::projected ? "projected" : "partition"));
  w.put("stiffness", s.stiffness);
  w.put("fft_plan", std::string(s.fft_measure ? "measure" : "estimate"));
  w.put("fft_precision",
        std::string(s.fft_precision == FftPrecision::float32 ? "float" : "double"));
  w.put("monotone", std::string(s.shortcut ? "shortcut" : "incremental"));
  w.put("precondition", std::string(s.precondition == Precondition::automatic ? "automatic"
                                    : s.precondition == Precondition::on      ? "on"
                                                                              : "off"));
}

void write_output(IniWriter& w, const OutputSpec& o) {
  w.section("output");
  w.put("dir", o.dir.string());
  std::string fields;
  for (const auto& f : o.fields) fields += (fields.empty() ? "" : ", ") + f;
  w.put("fields", fields.empty() ? std::string("none") : fields);
  w.put("fields_every", o.fields_every);
  w.put("checkpoint_every", o.checkpoint_every);
}

void write_wear(IniWriter& w, const WearSpec& s) {
  static const char* laws[] = {"none", "archard", "energy"};
  w.section("wear");
  w.put("law", std::string(laws[static_cast<int>(s.law)]));
  // 0 means "not given" (both must be > 0 when given).
  w.put("coefficient", s.coefficient > 0 ? std::optional<double>(s.coefficient) : std::nullopt);
  w.put("cycles", s.cycles > 0 ? std::optional<double>(s.cycles) : std::nullopt);
  static const char* integrators[] = {"arkode", "cycle", "erk", "dirk"};
  w.put("integrator", std::string(integrators[static_cast<int>(s.integrator)]));
  w.put("rtol", s.rtol);
  w.put("atol", s.atol);
  w.put("newton", std::string(s.newton == WearNewton::frozen ? "frozen" : "krylov"));
  w.put("indenter_share", s.indenter_share);
}

std::string resolved_text(const Scenario& s) {
  IniWriter w;
  w.raw("# fretbem " FRETBEM_VERSION " resolved scenario '" + s.name + "'");
  w.raw("# relative paths below were resolved against the scenario's folder");
  write_material(w, s.material);
  write_grid(w, s.grid);
  write_surface(w, s.surface);
  write_load(w, s.load);
  write_solver(w, s.solver);
  write_output(w, s.output);
  write_wear(w, s.wear);
  return w.str();
}

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& name,
                        const std::filesystem::path& base_dir,
                        const std::vector<std::string>& overrides) {
  Reader r(name);
  read_file_entries(text, r);
  for (const auto& o : overrides) apply_override(o, r);

  Scenario s;
  s.name = fs::path(name).stem().string();
  read_material(r, s.material);
  read_grid(r, s.grid);
  read_surface(r, base_dir, s.surface);
  read_load(r, base_dir, s.load);
  read_solver(r, s.solver);
  read_output(r, s.output);
  read_wear(r, s.wear);
  s.resolved_text = resolved_text(s);
  return s;
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
