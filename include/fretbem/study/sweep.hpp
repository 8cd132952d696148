// `fretbem sweep STUDY.ini`: run a study's members (serially in this process's job
// slots, or spread over MPI ranks), list their commands, run one, or aggregate what finished.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "fretbem/study/member_pool.hpp"

namespace fretbem {

struct SweepCommand {
  std::filesystem::path study;
  std::vector<std::string> sets;  ///< --set, after the study file's own fixed overrides
  std::filesystem::path out;      ///< --out, replaces study.out
  bool list = false;              ///< --list: print one member command per line
  long member = -1;               ///< --member K: run member K only
  bool aggregate = false;         ///< --aggregate: write sweep.csv from what finished
  PoolOptions options;
};

/// Exit status: 0 all members ok (or listed); 4 when a member is not ok after the run (failed,
/// or left to another process that still runs it) or, with --aggregate, when one failed; 143
/// (128 + SIGTERM) when a signal ended the study (sweep.csv is written all the same).
/// InputError on a bad study file or options.
int run_sweep_command(const SweepCommand& cmd);

}  // namespace fretbem
