#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <iostream>

#include "fretbem/core/input_warning.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/elastic/kernel_samples.hpp"
#include "fretbem/study/member_launcher.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

// The worker's ends of its two pipes, at fixed descriptors once every other inherited one is
// closed (the study's locks among them: a worker holding a member's lock file open would keep
// the lock after the study released it).
constexpr int kJobFd = 3;     // study -> worker: the member's command and log
constexpr int kResultFd = 4;  // worker -> study: the member's exit status

bool write_all(int fd, const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w, n -= std::size_t(w);
  }
  return true;
}

// False at the end of the pipe, and in a worker asked to stop while it waits for work.
bool read_all(int fd, void* data, std::size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = ::read(fd, p, n);
    if (r < 0 && errno == EINTR && !stop_requested()) continue;
    if (r <= 0) return false;
    p += r, n -= std::size_t(r);
  }
  return true;
}

bool write_string(int fd, const std::string& s) {
  const std::uint32_t n = std::uint32_t(s.size());
  return write_all(fd, &n, sizeof n) && write_all(fd, s.data(), n);
}

std::optional<std::string> read_string(int fd) {
  std::uint32_t n = 0;
  if (!read_all(fd, &n, sizeof n)) return std::nullopt;
  std::string s(n, '\0');
  if (!read_all(fd, s.data(), n)) return std::nullopt;
  return s;
}

// One job: the log file, then the command line, each string length-prefixed.
std::optional<std::vector<std::string>> read_job(fs::path& log) {
  const auto file = read_string(kJobFd);
  std::uint32_t count = 0;
  if (!file || !read_all(kJobFd, &count, sizeof count)) return std::nullopt;
  log = *file;
  std::vector<std::string> args;
  for (std::uint32_t i = 0; i < count; ++i) {
    auto a = read_string(kJobFd);
    if (!a) return std::nullopt;
    args.push_back(std::move(*a));
  }
  return args;
}

// The member's stdout and stderr appended to its log, as a spawned member's are; stdout fully
// buffered as in a process whose stdout is a file, so the log's lines come in the same order.
bool redirect_output(const fs::path& log) {
  std::fflush(nullptr);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const bool ok = ::dup2(fd, 1) == 1 && ::dup2(fd, 2) == 2;
  ::close(fd);
  std::setvbuf(stdout, nullptr, _IOFBF, BUFSIZ);
  return ok;
}

// A fresh process has no input-warning handler (a resumed run sets none and drops them); the
// previous member's must not print into this one's log.
int run_job(const MemberEntry& entry, const std::vector<std::string>& args, const fs::path& log) {
  if (!redirect_output(log)) return 127;
  set_input_warning_handler({});
  const int code = entry(args);
  std::cout.flush();
  std::fflush(nullptr);
  return code;
}

// The job to a worker. One that died while idle (a Ctrl-C reaches the whole process group)
// has closed its end: the write then fails with EPIPE instead of raising SIGPIPE, which would
// end the study before it records its members.
bool send_job(int fd, const std::vector<std::string>& args, const fs::path& log) {
  sigset_t pipe_signal, old;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &old);
  const std::uint32_t count = std::uint32_t(args.size());
  bool sent = write_string(fd, log.string()) && write_all(fd, &count, sizeof count);
  for (std::size_t i = 0; sent && i < args.size(); ++i) sent = write_string(fd, args[i]);
  if (!sent) {
    const timespec now{};
    sigtimedwait(&pipe_signal, nullptr, &now);  // the SIGPIPE the failed write left pending
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  return sent;
}

[[noreturn]] void worker_main(const MemberEntry& entry, int job_fd, int result_fd) {
  const int job = ::fcntl(job_fd, F_DUPFD, kResultFd + 1);
  const int result = ::fcntl(result_fd, F_DUPFD, kResultFd + 1);
  ::dup2(job, kJobFd), ::dup2(result, kResultFd);
  ::close_range(kResultFd + 1, ~0U, 0);
  keep_kernel_samples(true);  // members of one grid share them (a study's usual case)
  fs::path log;
  while (!stop_requested()) {
    const auto args = read_job(log);
    if (!args) break;
    const std::int32_t code = run_job(entry, *args, log);
    if (!write_all(kResultFd, &code, sizeof code)) break;
  }
  std::fflush(nullptr);
  ::_exit(0);
}

struct Worker {
  pid_t pid = -1;
  int job_fd = -1, result_fd = -1;  // the study's ends
  bool busy = false;
};

class WorkerLauncher final : public MemberLauncher {
 public:
  explicit WorkerLauncher(MemberEntry entry) : entry_(std::move(entry)) {}
  ~WorkerLauncher() override {
    for (Worker& w : workers_) retire(w);
  }

  // An idle worker that is gone is replaced once by a fresh one.
  std::optional<int> start(const std::vector<std::string>& args, const fs::path& log) override {
    for (int attempt = 0; attempt < 2; ++attempt) {
      const int h = idle_worker();
      if (h < 0) return std::nullopt;
      Worker& w = workers_[std::size_t(h)];
      if (send_job(w.job_fd, args, log)) return w.busy = true, h;
      retire(w);
    }
    return std::nullopt;
  }

  std::optional<int> poll(int h) override { return collect(h, 0); }
  int wait(int h) override { return *collect(h, -1); }
  void terminate(int h) override {
    const Worker& w = workers_[std::size_t(h)];
    if (w.pid > 0) ::kill(w.pid, SIGTERM);
  }

 private:
  // The first idle worker, forked when none is idle; -1 when fork fails.
  int idle_worker() {
    for (std::size_t i = 0; i < workers_.size(); ++i)
      if (workers_[i].pid > 0 && !workers_[i].busy) return int(i);
    int job[2], result[2];
    if (::pipe2(job, O_CLOEXEC) != 0) return -1;
    if (::pipe2(result, O_CLOEXEC) != 0) return ::close(job[0]), ::close(job[1]), -1;
    std::fflush(nullptr);  // else the worker would print what the study has buffered again
    const pid_t pid = ::fork();
    if (pid == 0) worker_main(entry_, job[0], result[1]);
    ::close(job[0]), ::close(result[1]);
    if (pid < 0) return ::close(job[1]), ::close(result[0]), -1;
    ::fcntl(result[0], F_SETFL, O_NONBLOCK);
    const Worker w{pid, job[1], result[0], false};
    for (std::size_t i = 0; i < workers_.size(); ++i)
      if (workers_[i].pid < 0) return workers_[i] = w, int(i);
    workers_.push_back(w);
    return int(workers_.size() - 1);
  }

  // The member's status once the worker reports it (timeout_ms as poll(2)); a worker that
  // died instead (a crash, a kill, a member that called exit) is reaped and its status is
  // the member's.
  std::optional<int> collect(int h, int timeout_ms) {
    Worker& w = workers_[std::size_t(h)];
    pollfd p{w.result_fd, POLLIN, 0};
    int ready = 0;
    while ((ready = ::poll(&p, 1, timeout_ms)) < 0 && errno == EINTR) {
    }
    if (ready == 0) return std::nullopt;
    std::int32_t code = 0;
    ssize_t r = 0;
    while ((r = ::read(w.result_fd, &code, sizeof code)) < 0 && errno == EINTR) {
    }
    w.busy = false;
    if (r == ssize_t(sizeof code)) return code;
    return retire(w);
  }

  // Ends a worker: its job pipe closed (an idle worker exits at its end), then reaped. The
  // worker's exit status.
  int retire(Worker& w) {
    if (w.pid < 0) return 127;
    ::close(w.job_fd), ::close(w.result_fd);
    int status = 0;
    while (::waitpid(w.pid, &status, 0) < 0)
      if (errno != EINTR) return w = Worker{}, 127;
    w = Worker{};
    return exit_code(status);
  }

  MemberEntry entry_;
  std::vector<Worker> workers_;
};

}  // namespace

std::unique_ptr<MemberLauncher> make_worker_launcher(MemberEntry entry) {
  return std::make_unique<WorkerLauncher>(std::move(entry));
}

}  // namespace fretbem
