// Scenario values: the merged key/value set of a scenario file and its --set overrides, and
// the conversions that check each value and name it in the one-line message when it is wrong.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/format.hpp"
#include "keys.hpp"

namespace fretbem::scenario_detail {

namespace fs = std::filesystem;

/// Bounds of every dimensional input (see Reader::magnitude).
inline constexpr double kMinMagnitude = 1e-100, kMaxMagnitude = 1e100;

std::string trim(std::string_view s);
/// Values are echoed in one-line messages: no control characters, bounded length.
std::string printable(std::string_view s);
std::string lower(std::string s);

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
  /// The keys given (file and overrides), sorted.
  std::vector<std::string> keys() const {
    std::vector<std::string> out;
    for (const auto& [k, e] : entries_) out.push_back(k);
    return out;
  }
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
      fail_value(key, std::string("must be ") + (lo_open ? "> " : ">= ") + format_number(lo));
    fail_value(key, "is out of range " + std::string(lo_open ? "(" : "[") + format_number(lo) +
                        ", " + format_number(hi) + (hi_open ? ")" : "]"));
  }
  double positive(const std::string& key) const { return real_in(key, 0.0, true); }

  /// A positive dimensional quantity (SI) whose size the arithmetic can carry: within
  /// [kMinMagnitude, kMaxMagnitude]. The solvers form products and quotients of up to three
  /// inputs (E* delta h, F / h^2, r^2 / R, squared norms of n^2 values); with every factor
  /// inside 1e+-100 each of them stays inside the double range (1e+-308) with margin, where
  /// 1e-300 or 1e300 overflow to inf/NaN residuals or underflow to silent zero results.
  double magnitude(const std::string& key) const {
    const double v = positive(key);
    if (v < kMinMagnitude || v > kMaxMagnitude)
      fail_value(key,
                 "is outside [1e-100, 1e100], the range the solver's arithmetic can carry "
                 "(check the unit: SI)");
    return v;
  }

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

  /// The value of a real, magnitude or wavelength key, checked against the key table's range.
  double number(const std::string& key) const;
  /// The value of an integer key, checked against the key table's range.
  long long count(const std::string& key) const;
  /// The index of a choice key's value among the key table's choices.
  std::size_t option(const std::string& key) const;

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
}  // namespace fretbem::scenario_detail
