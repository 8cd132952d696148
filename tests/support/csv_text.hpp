// Output files as text, for byte-for-byte comparisons of runs (resumed against uninterrupted,
// with an option against without it), and as columns of numbers. Header-only.
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fretbem_test {

/// The whole file as text (empty when it cannot be read).
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The CSV text of `p` with column `name` blanked in every row.
inline std::string without_column(const std::filesystem::path& p, const std::string& name) {
  std::istringstream in(read_text(p));
  std::string line, out;
  long skip = -1;
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::string cell;
    for (long c = 0; std::getline(cells, cell, ','); ++c) {
      if (skip < 0 && cell == name) skip = c;
      out += (c == skip ? std::string() : cell) + ',';
    }
    out += '\n';
  }
  return out;
}

/// The first of timeseries.csv and cycles.csv that is empty in run folder `a` or differs
/// between `a` and `b` with column `name` blanked ("" when both agree).
inline std::string differing_tables(const std::filesystem::path& a, const std::filesystem::path& b,
                                    const std::string& name) {
  for (const char* f : {"timeseries.csv", "cycles.csv"}) {
    const std::string x = without_column(a / f, name);
    if (x.empty() || x != without_column(b / f, name)) return f;
  }
  return "";
}

/// A CSV file as columns of numbers by header name (NaN for an empty or non-numeric cell).
inline std::map<std::string, std::vector<double>> csv_columns(const std::filesystem::path& csv) {
  std::istringstream in(read_text(csv));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) head.push_back(c);
  std::map<std::string, std::vector<double>> out;
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::string c;
    for (std::size_t i = 0; i < head.size(); ++i) {
      if (!std::getline(cells, c, ',')) c.clear();
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      out[head[i]].push_back(end != c.c_str() ? v : NAN);
    }
  }
  return out;
}

}  // namespace fretbem_test
