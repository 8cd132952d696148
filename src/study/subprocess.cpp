#include "fretbem/study/subprocess.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>

#include "fretbem/study/member_launcher.hpp"

extern char** environ;

namespace fretbem {

namespace {

// The environment of a member: this process's, less what the MPI launcher set for its ranks
// (OMPI_*, PMIX_*, PMI_*). A member is a serial `fretbem run`, not a rank: with
// the launcher's OMPI_COMM_WORLD_SIZE = 2 it would take itself for a run under
// `mpirun -n 2` and refuse (tests SweepMpi.*).
std::vector<char*> member_environment() {
  std::vector<char*> env;
  for (char** e = environ; *e != nullptr; ++e) {
    const bool launcher = std::strncmp(*e, "OMPI_", 5) == 0 || std::strncmp(*e, "PMIX_", 5) == 0 ||
                          std::strncmp(*e, "PMI_", 4) == 0;
    if (!launcher) env.push_back(*e);
  }
  env.push_back(nullptr);
  return env;
}

}  // namespace

pid_t spawn_logged(const std::vector<std::string>& args, const std::filesystem::path& log) {
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  for (auto& s : copy) argv.push_back(s.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  std::vector<char*> env = member_environment();
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), env.data());
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

int exit_code(int wait_status) {
  return WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : 128 + WTERMSIG(wait_status);
}

std::optional<int> poll_child(pid_t pid) {
  int status = 0;
  const pid_t r = waitpid(pid, &status, WNOHANG);
  if (r == pid) return exit_code(status);
  if (r < 0 && errno != EINTR) return 127;  // not our child (any more): count it as failed
  return std::nullopt;
}

int wait_child(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return 127;
  return exit_code(status);
}

std::string last_line(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \r\t") != std::string::npos) last = line;
  // The progress line ends in '\r' redraws: keep what follows the last one.
  if (const auto cr = last.find_last_of('\r'); cr != std::string::npos && cr + 1 < last.size())
    last = last.substr(cr + 1);
  return last.empty() ? "(no output)" : last;
}

namespace {

// A member's handle is its pid.
class SpawnLauncher final : public MemberLauncher {
 public:
  std::optional<int> start(const std::vector<std::string>& args,
                           const std::filesystem::path& log) override {
    const pid_t pid = spawn_logged(args, log);
    return pid < 0 ? std::nullopt : std::optional<int>(pid);
  }
  std::optional<int> poll(int pid) override { return poll_child(pid); }
  int wait(int pid) override { return wait_child(pid); }
  void terminate(int pid) override { kill(pid, SIGTERM); }
};

}  // namespace

std::unique_ptr<MemberLauncher> make_spawn_launcher() {
  return std::make_unique<SpawnLauncher>();
}

}  // namespace fretbem
