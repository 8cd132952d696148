// Runs the fretbem binary from a test and captures what it prints.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_dir.hpp"

namespace fretbem_test {

struct CliResult {
  int status = -1;  ///< exit code, -1 if the process did not exit normally
  std::string out, err;
};

/// One folder per test process and tag (ctest runs a file's cases in parallel processes).
inline std::filesystem::path process_dir(const std::string& tag) {
  const auto d = process_temp_dir() / tag;
  std::filesystem::create_directories(d);
  return d;
}

/// `fretbem ARGS` (FRETBEM_BINARY) with stdout and stderr captured in process_dir(tag).
inline CliResult run_fretbem(const std::string& args, const std::string& tag) {
  const auto tmp = process_dir(tag);
  const std::string cmd = std::string(FRETBEM_BINARY) + " " + args + " > " +
                          (tmp / "out").string() + " 2> " + (tmp / "err").string();
  CliResult r;
  const int s = std::system(cmd.c_str());
  r.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(tmp / "out");
  r.err = slurp(tmp / "err");
  return r;
}

}  // namespace fretbem_test
