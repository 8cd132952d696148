// Running the members of a sweep (issue 15): each member is a `fretbem run` subprocess of the
// base scenario with the member's overrides, in its own directory below the study's output,
// stdout and stderr in its log.txt, and a status file written when it starts and when it ends.
// A re-run skips the members whose status says they finished and continues interrupted ones
// from their checkpoint; SIGTERM or SIGINT ends the running members (each is recorded as
// interrupted) and the study still writes its aggregate.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fretbem/study/sweep_spec.hpp"

namespace fretbem {

struct SweepOptions {
  int jobs = 0;  ///< members run at once by this process; 0: usable_cpus()
  bool quiet = false;
  std::filesystem::path binary;         ///< the fretbem executable members run (default: this one)
  std::string label = "fretbem sweep";  ///< prefix of its messages ("fretbem sweep[rank 1]")
};

/// What a member's status file (DIR/member_K/sweep_member.txt) records.
struct MemberStatus {
  bool present = false;           ///< a status file exists
  int exit_code = -1;             ///< of `fretbem run`; 128 + signal when killed
  double seconds = 0;             ///< wall time of the member
  std::string error;              ///< one line: the member's last message when it failed
  std::vector<std::string> sets;  ///< the overrides it ran with
};

MemberStatus read_member_status(const std::filesystem::path& member_dir);
/// Marked running: it runs now, or the study was killed outright while it ran.
bool member_running(const MemberStatus& status);
/// Interrupted by the study, or member_running.
bool member_stopped(const MemberStatus& status);
/// Stopped with the overrides the study now asks for and a checkpoint.h5 to continue from:
/// the next run of the study continues it with `fretbem run --resume` instead of restarting.
bool member_resumable(const SweepSpec& spec, std::size_t k);
/// Finished with exit 0, with the overrides the study now asks for, outputs present.
bool member_complete(const SweepSpec& spec, std::size_t k);
/// DIR/.member_K.lock: held by the study process that runs member K, for the member's life.
std::filesystem::path member_lock_file(const SweepSpec& spec, std::size_t k);

/// The `fretbem run` command line of member k (what a user types to rerun it alone).
std::vector<std::string> member_run_command(const SweepSpec& spec, std::size_t k,
                                            const std::filesystem::path& binary);

/// Hands out member indices to one process's runner: the whole list serially, or a share
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

/// Runs the members the queue hands out, up to `jobs` at a time, writing each one's status
/// file. Returns false when a signal ended the run early (core/stop_signal.hpp, installed by
/// the caller).
bool run_sweep_members(const SweepSpec& spec, MemberQueue& queue, const SweepOptions& opt);

/// Indices of the members that are not complete (what a run or re-run has to do).
std::vector<std::size_t> pending_members(const SweepSpec& spec);

}  // namespace fretbem
