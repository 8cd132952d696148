// How a study pool (study/member_pool.hpp) starts a member's `fretbem run` and collects its
// exit: as a process of its own (posix_spawn of the fretbem binary), or in one of `jobs`
// worker processes forked from the study, each running members one after another through
// the command line's own entry point. A worker keeps what the process start, the dynamic
// loader and the first touch of the heap cost a spawned member (about 0.2 s of CPU a member
// at n = 256, docs/performance.md); a member that crashes ends its worker only, and the next
// member gets a fresh one.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace fretbem {

/// Runs a fretbem command line (args[0] the program, args[1] the command) in this process and
/// returns its exit status, as `main` would.
using MemberEntry = std::function<int(const std::vector<std::string>& args)>;

class MemberLauncher {
 public:
  virtual ~MemberLauncher() = default;
  /// Starts `args` with stdout and stderr appended to `log`; a handle for the calls below, or
  /// nullopt when it could not be started.
  virtual std::optional<int> start(const std::vector<std::string>& args,
                                   const std::filesystem::path& log) = 0;
  /// Exit status of a started member once it has ended (128 + signal when killed).
  virtual std::optional<int> poll(int handle) = 0;
  /// Waits for the member's end; its exit status as poll.
  virtual int wait(int handle) = 0;
  /// Sends SIGTERM to the process running the member.
  virtual void terminate(int handle) = 0;
};

/// The exit status of a waitpid status: the exit code, or 128 + the signal that ended it.
int exit_code(int wait_status);

/// Each member a process of its own: args[0] is executed.
std::unique_ptr<MemberLauncher> make_spawn_launcher();
/// Members in forked worker processes that call `entry` (args[0] is not executed). To be
/// made while this process runs no other thread: the workers are forked from it.
std::unique_ptr<MemberLauncher> make_worker_launcher(MemberEntry entry);

}  // namespace fretbem
