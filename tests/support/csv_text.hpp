// Output files as text, for byte-for-byte comparisons of runs (resumed against uninterrupted,
// with an option against without it). Header-only.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace fretbem_test
