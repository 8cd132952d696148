#include "fretbem/study/sweep_spec.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/scenario/scenario.hpp"
#include "fretbem/study/member_grid.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

// A comment starts at '#' or ';' at the line's start or after white space.
std::string strip_comment(const std::string& line) {
  for (std::size_t i = 0; i < line.size(); ++i)
    if ((line[i] == '#' || line[i] == ';') && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t'))
      return line.substr(0, i);
  return line;
}

// Every item between commas, empty ones included: "1, 2," is three items, the last one
// empty, so that a trailing comma is refused as an empty item inside is.
std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t comma; (comma = s.find(',', start)) != std::string::npos; start = comma + 1)
    out.push_back(trim(s.substr(start, comma - start)));
  out.push_back(trim(s.substr(start)));
  return out;
}

bool parse_double(const std::string& s, double& v) {
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(v);
}

// "linear(a, b, n)" / "log(a, b, n)": n values from a to b, both ends exact.
std::vector<std::string> range_values(const std::string& key, const std::string& text, bool log) {
  const auto open = text.find('('), close = text.rfind(')');
  const auto args = split_commas(text.substr(open + 1, close - open - 1));
  double a = 0, b = 0, n = 0;
  const std::string what = "[vary] " + key + " = " + text;
  if (close != text.size() - 1 || args.size() != 3 || !parse_double(args[0], a) ||
      !parse_double(args[1], b) || !parse_double(args[2], n) || n < 1 || n != std::floor(n) ||
      n > 1e6)
    throw InputError(what + ": expected " + (log ? "log" : "linear") +
                     "(first, last, count) with finite ends and a whole count 1 ... 1000000");
  if (log && !(a > 0 && b > 0)) throw InputError(what + ": log ranges need positive ends");
  const int count = int(n);
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i) {
    const double t = count == 1 ? 0.0 : double(i) / (count - 1);
    // Linear: the weighted mean of the ends, exact for whole numbers (a + t (b - a) gives
    // surface.seed = 7.000000000000001 in linear(1, 10000, 10000)).
    double v = log          ? std::exp(std::log(a) + t * (std::log(b) - std::log(a)))
               : count == 1 ? a
                            : (a * (count - 1 - i) + b * i) / (count - 1);
    if (i == 0) v = a;
    if (i == count - 1 && count > 1) v = b;
    out.push_back(format_number(v));
  }
  return out;
}

struct StudyFile {
  std::map<std::string, std::string> study;
  std::vector<std::string> sets;
  std::vector<std::pair<std::string, std::string>> vary;  // in file order
};

StudyFile read_study_file(const fs::path& file) {
  std::error_code ec;
  if (fs::exists(file, ec) && !fs::is_regular_file(file, ec))
    throw InputError(file.string() + ": not a study file (a folder or a device)");
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot read the study file");
  StudyFile f;
  std::string section;
  int line_no = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++line_no;
    if (line_no == 1) drop_utf8_bom(raw);
    const std::string line = trim(strip_comment(raw));
    const std::string where = file.string() + ":" + std::to_string(line_no);
    if (line.empty()) continue;
    if (line.front() == '[') {
      if (line.back() != ']') throw InputError(where + ": malformed section header '" + line + "'");
      section = trim(line.substr(1, line.size() - 2));
      if (section != "study" && section != "vary")
        throw InputError(where + ": unknown section [" + section + "] (study, vary)");
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string::npos || section.empty())
      throw InputError(where + ": expected key = value inside [study] or [vary]");
    const std::string key = trim(line.substr(0, eq)), value = trim(line.substr(eq + 1));
    if (section == "vary") {
      for (const auto& [k, v] : f.vary)
        if (k == key) throw InputError(where + ": [vary] " + key + " given twice");
      f.vary.emplace_back(key, value);
    } else if (key == "set") {
      f.sets.push_back(value);
    } else if (key == "scenario" || key == "out" || key == "combine" || key == "max_grid_n") {
      f.study[key] = value;
    } else {
      throw InputError(where + ": unknown key study." + key +
                       " (scenario, out, combine, set, max_grid_n)");
    }
  }
  return f;
}

// Members of the product (first axis slowest, like nested loops) or of the zip.
std::vector<std::vector<std::string>> combine(const std::vector<SweepAxis>& axes, bool zip) {
  std::vector<std::vector<std::string>> out;
  if (zip) {
    for (std::size_t i = 0; i < axes.front().values.size(); ++i) {
      std::vector<std::string> m;
      for (const auto& a : axes) m.push_back(a.values[i]);
      out.push_back(m);
    }
    return out;
  }
  out.push_back({});
  for (const auto& a : axes) {
    std::vector<std::vector<std::string>> next;
    for (const auto& m : out)
      for (const auto& v : a.values) {
        next.push_back(m);
        next.back().push_back(v);
      }
    out.swap(next);
  }
  return out;
}

std::string describe(const SweepSpec& s, std::size_t k) {
  std::string d;
  for (std::size_t i = 0; i < s.axes.size(); ++i)
    d += (i ? ", " : "") + s.axes[i].key + "=" + s.members[k][i];
  return d;
}

void refuse_duplicates(const SweepSpec& s) {
  std::map<std::vector<std::string>, std::size_t> seen;
  for (std::size_t k = 0; k < s.members.size(); ++k) {
    const auto [it, fresh] = seen.emplace(s.members[k], k);
    if (!fresh)
      throw InputError(s.study_file.string() + ": members " + std::to_string(it->second) + " and " +
                       std::to_string(k) + " are the same (" + describe(s, k) +
                       "): each member must differ");
  }
}

// Counted before the product is built: two ranges of 10^6 values ask for 10^12 members, and
// building them takes past 400 MB in two minutes before anything runs (measured).
void refuse_too_many_members(const SweepSpec& s) {
  double count = s.zip ? double(s.axes.front().values.size()) : 1.0;
  std::string sizes;
  for (const auto& a : s.axes) {
    if (!s.zip) count *= double(a.values.size());
    sizes += (sizes.empty() ? "" : " x ") + std::to_string(a.values.size());
  }
  if (count > kMaxSweepMembers)
    throw InputError(s.study_file.string() + ": the study has " + sizes + " = " +
                     format_number(count) + " members, more than " +
                     format_number(kMaxSweepMembers) +
                     ": split it into several studies or use combine = zip");
}

// [study] max_grid_n: a whole number of cells per side, or absent (0: no refinement).
int read_max_grid_n(const fs::path& file, const std::map<std::string, std::string>& study) {
  if (!study.count("max_grid_n")) return 0;
  const std::string& text = study.at("max_grid_n");
  double v = 0;
  if (!parse_double(text, v) || v != std::floor(v) || v < 2 || v > 65536)
    throw InputError(file.string() + ": study.max_grid_n = " + text +
                     ": expected a whole number of cells per side, 2 ... 65536");
  return int(v);
}

}  // namespace

std::vector<std::string> parse_sweep_values(const std::string& key, const std::string& text) {
  if (text.rfind("linear(", 0) == 0) return range_values(key, text, false);
  if (text.rfind("log(", 0) == 0) return range_values(key, text, true);
  if (trim(text).empty()) throw InputError("[vary] " + key + ": no values");
  std::vector<std::string> out;
  for (const auto& v : split_commas(text)) {
    if (v.empty())
      throw InputError("[vary] " + key + " = " + text +
                       ": empty value in the list (a doubled or trailing comma)");
    double x = 0;
    out.push_back(parse_double(v, x) ? format_number(x) : v);
  }
  return out;
}

std::vector<std::string> SweepSpec::member_sets(std::size_t k) const {
  std::vector<std::string> s = sets;
  for (std::size_t i = 0; i < axes.size(); ++i) s.push_back(axes[i].key + "=" + members[k][i]);
  // Both sides: a scenario that gives grid.nx and grid.ny ignores grid.n.
  if (k < grids.size() && grids[k].n != grids[k].base_n)
    for (const char* side : {"grid.nx=", "grid.ny="})
      s.push_back(side + std::to_string(grids[k].n));
  return s;
}

fs::path SweepSpec::member_dir(std::size_t k) const {
  const int width = std::max(4, int(std::to_string(members.size() - 1).size()));
  char name[32];
  std::snprintf(name, sizeof name, "member_%0*zu", width, k);
  return name;
}

StudyMembers SweepSpec::study_members() const {
  StudyMembers m;
  m.scenario = scenario, m.out = out, m.defaults = {"solver.threads=1"}, m.count = members.size();
  m.dir = [this](std::size_t k) { return member_dir(k); };
  m.sets = [this](std::size_t k) { return member_sets(k); };
  return m;
}

SweepSpec load_sweep_spec(const fs::path& file, const std::vector<std::string>& extra_sets,
                          const fs::path& out) {
  const StudyFile f = read_study_file(file);
  SweepSpec s;
  s.study_file = file;
  if (!f.study.count("scenario")) throw InputError(file.string() + ": no study.scenario given");
  s.scenario = fs::absolute(file.parent_path() / f.study.at("scenario")).lexically_normal();
  std::error_code ec;  // a name too long for the filesystem is bad input too, not a crash
  if (!fs::is_regular_file(s.scenario, ec)) {
    std::error_code ec2;
    const bool exists = !ec && fs::exists(s.scenario, ec2);
    throw InputError(file.string() + ": study.scenario " + s.scenario.string() +
                     (exists ? " is not a file" : " not found") +
                     (ec ? " (" + ec.message() + ")" : ""));
  }
  const std::string mode = f.study.count("combine") ? f.study.at("combine") : "product";
  if (mode != "product" && mode != "zip")
    throw InputError(file.string() + ": study.combine = " + mode + " (product or zip)");
  s.zip = mode == "zip";
  s.out = !out.empty()           ? out
          : f.study.count("out") ? fs::path(f.study.at("out"))
                                 : fs::path("out") / ("sweep_" + file.stem().string());
  s.out = fs::absolute(s.out).lexically_normal();
  s.sets = f.sets;
  s.sets.insert(s.sets.end(), extra_sets.begin(), extra_sets.end());
  if (f.vary.empty()) throw InputError(file.string() + ": [vary] names no key to vary");
  for (const auto& [key, text] : f.vary) try {
      s.axes.push_back({key, parse_sweep_values(key, text)});
    } catch (const InputError& e) {
      throw InputError(file.string() + ": " + e.what());
    }
  for (const auto& a : s.axes)
    if (s.zip && a.values.size() != s.axes.front().values.size())
      throw InputError(file.string() + ": combine = zip needs equally many values, but " +
                       s.axes.front().key + " has " + std::to_string(s.axes.front().values.size()) +
                       " and " + a.key + " has " + std::to_string(a.values.size()));
  s.max_grid_n = read_max_grid_n(file, f.study);
  refuse_too_many_members(s);
  s.members = combine(s.axes, s.zip);
  refuse_duplicates(s);
  // Each member's scenario is read twice when the study refines its grid: the second time
  // checks the refined grid (its size limits, the memory it needs) as the run will see it.
  for (std::size_t k = 0; k < s.members.size(); ++k) try {
      s.grids.push_back(
          choose_member_grid(load_scenario(s.scenario, s.member_sets(k)), s.max_grid_n));
      if (s.grids.back().n != s.grids.back().base_n) load_scenario(s.scenario, s.member_sets(k));
    } catch (const InputError& e) {
      throw InputError("member " + std::to_string(k) + " (" + describe(s, k) + "): " + e.what());
    }
  return s;
}

}  // namespace fretbem
