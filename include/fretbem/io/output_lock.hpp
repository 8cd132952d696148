// One run at a time per output folder: an exclusive advisory lock (flock) on DIR/.fretbem.lock,
// held for the life of the process (the kernel releases it on any exit, SIGKILL included).
// Two runs started into one --out at the same moment both passed the "holds results" check
// and wrote into each other's files (issue 14 session 4: the second truncated the first's
// timeseries.csv and removed its checkpoint with --overwrite).
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
