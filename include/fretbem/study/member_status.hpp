// A study member's status file (MEMBER_DIR/sweep_member.txt, for sweeps and ensembles alike):
// written when the member starts (marked running) and when it ends (exit code, wall seconds,
// error line), always with the overrides it runs with. A re-run of the study reads it to skip
// the members that finished and to continue the ones that were stopped.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "fretbem/study/study_members.hpp"

namespace fretbem {

/// The error text of a member the study stopped (SIGTERM, SIGINT).
inline constexpr const char* kMemberInterrupted = "interrupted (study stopped)";
/// The error text while a member runs; it stays when the study is killed outright (SIGKILL,
/// a node failure) and cannot record the end. Both count as stopped: a re-run continues them.
inline constexpr const char* kMemberRunning = "running (or killed while running)";

struct MemberStatus {
  bool present = false;           ///< a status file exists
  int exit_code = -1;             ///< of `fretbem run`; 128 + signal when killed
  double seconds = 0;             ///< wall time of the member's last attempt
  std::string error;              ///< one line: the member's last message when it failed
  std::vector<std::string> sets;  ///< the overrides it ran with
};

MemberStatus read_member_status(const std::filesystem::path& member_dir);
/// Writes the status file whole or not at all (a failed write, e.g. a full disk, throws).
void write_member_status(const std::filesystem::path& member_dir, const MemberStatus& status);

/// Marked running: it runs now, or the study was killed outright while it ran.
bool member_running(const MemberStatus& status);
/// Interrupted by the study, or member_running.
bool member_stopped(const MemberStatus& status);
/// Stopped with the overrides the study now asks for and a checkpoint.h5 to continue from:
/// the next run of the study continues it with `fretbem run --resume` instead of restarting.
bool member_resumable(const StudyMembers& members, std::size_t k);
/// Finished with exit 0, with the overrides the study now asks for, outputs present.
bool member_complete(const StudyMembers& members, std::size_t k);
/// Indices of the members that are not complete (what a run or re-run has to do).
std::vector<std::size_t> pending_members(const StudyMembers& members);

/// What sweep.csv and members.csv say of a member: ok, failed, interrupted (stopped by a
/// signal), running (running now, or killed while running) or missing (not run yet).
std::string member_status_word(const MemberStatus& status, bool complete);

/// The lock the study process running member k holds for the member's life: beside the
/// member's folder, named after it (DIR/.member_0007.lock, DIR/H0.3/.seed_007.lock).
std::filesystem::path member_lock_file(const StudyMembers& members, std::size_t k);

}  // namespace fretbem
