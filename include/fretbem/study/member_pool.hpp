// The subprocess pool of studies (`fretbem sweep`, `fretbem ensemble`): runs the members a
// queue hands out, up to `jobs` at a time (in worker processes or as subprocesses:
// study/member_launcher.hpp), each a `fretbem run` in its own folder with stdout
// and stderr in its log.txt and its status file (study/member_status.hpp) written when it starts
// and when it ends. A member that is complete is skipped, one that was stopped continues from
// its checkpoint, any other starts afresh in an emptied folder; a member another process holds
// (another study of the same folder, a run orphaned by a study killed outright) is left to it.
// SIGTERM or SIGINT (core/stop_signal.hpp, installed by the caller) ends the running members,
// each recorded as interrupted, and starts no more.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

#include "fretbem/study/member_launcher.hpp"
#include "fretbem/study/study_members.hpp"

namespace fretbem {

struct PoolOptions {
  int jobs = 0;  ///< members run at once by this process; 0: usable_cpus()
  bool quiet = false;
  std::filesystem::path binary;         ///< the fretbem executable members run (default: this one)
  std::string label = "fretbem sweep";  ///< prefix of its messages ("fretbem sweep[rank 1]")
  /// Start every member afresh, complete or stopped ones too (`ensemble --overwrite`).
  bool restart = false;
  /// The command line's entry point: members then run in `jobs` worker processes forked from
  /// this one (study/member_launcher.hpp), not each in a process of its own; `binary` is
  /// then only named in messages and member commands.
  MemberEntry in_process;
};

/// Hands out member indices to one process's pool: the whole list serially, or a share
/// negotiated with the other MPI ranks (study/mpi_queue.cpp).
class MemberQueue {
 public:
  virtual ~MemberQueue() = default;
  /// The next member to run here; nullopt when none is left for this process (or `stopping`).
  virtual std::optional<std::size_t> next(bool stopping) = 0;
  /// Called between polls: answer other processes (rank 0). `stopping`: hand out no more.
  virtual void service(bool /*stopping*/) {}
  /// Every other process has been told there is no more work.
  virtual bool drained() const { return true; }
};

/// Runs the members the queue hands out. Returns false when a signal ended the run early.
bool run_study_members(const StudyMembers& members, MemberQueue& queue, const PoolOptions& opt);

}  // namespace fretbem
