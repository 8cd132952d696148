// One writer per output folder: an exclusive advisory lock (flock) on DIR/.fretbem.lock, held
// for the life of the object (the kernel releases it on any exit, SIGKILL included). Without
// it two runs started into one --out at the same moment both pass the "holds results" check and
// write into each other's files (the second truncates the first's timeseries.csv). Only core
// chores underneath: runs (cli) and ensembles (study) take it, and a study's member pool tests
// it to see whether a member's own run still lives.
#pragma once

#include <filesystem>
#include <optional>

#include "fretbem/core/file_lock.hpp"

namespace fretbem {

class OutputLock {
 public:
  /// Creates DIR if needed and locks it; InputError naming DIR when another process holds
  /// the lock ("another fretbem <holder> is writing into this folder") or the folder cannot
  /// be created. `holder`: what takes the folder, a run or an ensemble.
  explicit OutputLock(const std::filesystem::path& dir, const char* holder = "run");
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  static constexpr const char* file_name = ".fretbem.lock";

 private:
  std::optional<FileLock> lock_;
};

}  // namespace fretbem
