// Child processes in tests that stop or kill a run: waiting on what the child has done, never
// on the clock, so that a loaded machine only makes a test slower.
#pragma once

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

namespace fretbem_test {

/// Starts `argv` (argv[0] the program) with stdout and stderr to files and `sig` already
/// pending: blocked and raised in the child before exec. The program receives it when it
/// unblocks the signal (install_stop_signal_handlers): a stop requested before the run began.
inline pid_t spawn_with_pending_signal(int sig, const std::vector<std::string>& argv,
                                       const std::filesystem::path& out,
                                       const std::filesystem::path& err) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, sig);
  sigprocmask(SIG_BLOCK, &set, nullptr);
  ::kill(::getpid(), sig);
  const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (o < 0 || e < 0 || ::dup2(o, 1) < 0 || ::dup2(e, 2) < 0) ::_exit(126);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  ::execv(args[0], args.data());
  ::_exit(127);
}

/// Polls `ready` until it holds (true) or the child `pid` has exited (false; the child is
/// then reaped and its wait status stored in *status).
inline bool wait_until(pid_t pid, const std::function<bool()>& ready, int* status) {
  for (;;) {
    if (ready()) return true;
    if (::waitpid(pid, status, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));  // a polling interval only
  }
}

/// The exit code of a child, or 128 + the signal that ended it.
inline int wait_exit(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace fretbem_test
