// Helpers shared by the sweep tests (serial and MPI): running the binary, reading sweep.csv.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/temp_dir.hpp"

namespace sweep_test {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A fresh directory per test process (ctest runs cases in parallel processes).
inline fs::path scratch(const std::string& name) {
  return fretbem_test::process_temp_dir().fresh(name);
}

// Runs a shell command line; captures stdout and stderr.
inline Result shell(const std::string& cmd, const fs::path& dir) {
  const std::string line =
      cmd + " > " + (dir / "stdout").string() + " 2> " + (dir / "stderr").string();
  const int s = std::system(line.c_str());
  return {WIFEXITED(s) ? WEXITSTATUS(s) : -1, slurp(dir / "stdout"), slurp(dir / "stderr")};
}

inline std::string example_study() {
  return (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / "sweep_example.ini").string();
}

// sweep.csv with the wall-time column blanked: everything else must agree digit for digit.
inline std::vector<std::string> rows_without_time(const fs::path& csv) {
  std::ifstream in(csv);
  std::vector<std::string> rows;
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  {
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) head.push_back(c);
  }
  rows.push_back(line);
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string out, c;
    for (std::size_t i = 0; std::getline(ss, c, ','); ++i) {
      if (i) out += ',';
      out += i < head.size() && head[i] == "seconds" ? std::string("-") : c;
    }
    rows.push_back(out);
  }
  return rows;
}

// Column `name` of every data row of sweep.csv.
inline std::vector<std::string> column(const fs::path& csv, const std::string& name) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  std::size_t idx = 0, i = 0;
  for (std::string c; std::getline(hs, c, ','); ++i)
    if (c == name) idx = i;
  std::vector<std::string> out;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string c;
    for (std::size_t j = 0; j <= idx && std::getline(ss, c, ','); ++j) {
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace sweep_test
