#include "fretbem/study/sweep_runner.hpp"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "fretbem/core/file_lock.hpp"
#include "fretbem/core/format.hpp"
#include "fretbem/core/resources.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/core/text_file.hpp"
#include "fretbem/io/output_lock.hpp"
#include "fretbem/study/subprocess.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStatusFile = "sweep_member.txt";
// The error text of a member the study stopped, and of one that is running (or was, when the
// study was killed without a chance to record it): both count as interrupted.
constexpr const char* kInterrupted = "interrupted (study stopped)";
constexpr const char* kRunning = "running (or killed while running)";

// A status file is either whole or absent (a failed write, e.g. a full disk, throws).
void write_status(const fs::path& dir, const MemberStatus& s) {
  std::ostringstream out;
  out << "exit_code=" << s.exit_code << "\nseconds=" << format_number(s.seconds)
      << "\nerror=" << s.error << '\n';
  for (const auto& set : s.sets) out << "set=" << set << '\n';
  write_file_atomically(dir / kStatusFile, out.str());
}

struct Running {
  std::size_t index = 0;
  std::chrono::steady_clock::time_point start;
  std::optional<FileLock> lock;  // the member is this process's until it ends
};

// A member's own `fretbem run` holds its OutputLock (io/output_lock.hpp) while it runs; one
// orphaned by a study killed outright runs on after the study's member lock is gone.
bool run_still_active(const fs::path& member_dir) {
  std::error_code ec;
  const fs::path lock = member_dir / OutputLock::file_name;
  return fs::exists(lock, ec) && !FileLock::try_lock(lock);
}

class Runner {
 public:
  Runner(const SweepSpec& spec, const SweepOptions& opt) : spec_(spec), opt_(opt) {}

  // An interrupted member continues from its checkpoint; any other starts afresh. A member
  // another process runs right now (a second `fretbem sweep` of the same study, two MPI ranks
  // given the same --member) is left to it: before its lock, a second study emptied the
  // member's folder under the running member and overwrote its status and log (issue 14,
  // session 6).
  void start(std::size_t k) {
    auto lock = FileLock::try_lock(member_lock_file(spec_, k));
    if (!lock) {
      std::fprintf(stderr,
                   "%s: member %zu (%s) is being run by another fretbem process; not "
                   "started here\n",
                   opt_.label.c_str(), k, spec_.member_dir(k).c_str());
      return;
    }
    if (member_complete(spec_, k)) return;  // the other process finished it meanwhile
    const fs::path dir = spec_.out / spec_.member_dir(k);
    if (run_still_active(dir)) {
      std::fprintf(stderr,
                   "%s: member %zu (%s): a fretbem run is still writing into it (left "
                   "over from a study that was killed?); not started here\n",
                   opt_.label.c_str(), k, spec_.member_dir(k).c_str());
      return;
    }
    const bool resume = member_resumable(spec_, k);
    if (!resume) {
      fs::remove_all(dir);  // stale outputs of a failed attempt
      fs::create_directories(dir);
    }
    MemberStatus running;
    running.error = kRunning, running.sets = spec_.member_sets(k);
    write_status(dir, running);
    const auto cmd = resume ? std::vector<std::string>{opt_.binary.string(), "run", "--resume",
                                                       dir.string(), "--quiet"}
                            : member_run_command(spec_, k, opt_.binary);
    const pid_t pid = spawn_logged(cmd, dir / "log.txt");
    if (pid < 0) return finish(k, 127, 0, "could not start " + opt_.binary.string());
    running_[pid] = {k, std::chrono::steady_clock::now(), std::move(lock)};
  }

  // Collects the members that ended; true when any did.
  bool reap() {
    bool any = false;
    for (auto it = running_.begin(); it != running_.end();) {
      const auto code = poll_child(it->first);
      if (!code) {
        ++it;
        continue;
      }
      // The member lock goes with `done`, after its status is written: released before, another
      // study took the member as still running and resumed the finished run.
      const Running done = std::move(it->second);
      const std::size_t k = done.index;
      const double s = seconds_since(done.start);
      it = running_.erase(it);
      const fs::path log = spec_.out / spec_.member_dir(k) / "log.txt";
      // Ctrl-C reaches the members too: one that died of it while we stop was interrupted.
      const bool interrupted = *code > 128 && stop_requested();
      finish(k, *code, s, *code == 0 ? "" : interrupted ? kInterrupted : last_line(log));
      any = true;
    }
    return any;
  }

  // SIGTERM to every running member, then their exits, each recorded as interrupted unless
  // it had just finished (exit 0: recorded as finished, not "interrupted" beside exit 0).
  void stop_all() {
    for (const auto& [pid, r] : running_) kill(pid, SIGTERM);
    for (const auto& [pid, r] : running_) {
      const int code = wait_child(pid);
      finish(r.index, code, seconds_since(r.start), code == 0 ? "" : kInterrupted);
    }
    running_.clear();
  }

  // After a failure of the study itself (its status files cannot be written): the members are
  // ended without further records, so that none runs on unobserved.
  void abandon_all() noexcept {
    for (const auto& [pid, r] : running_) kill(pid, SIGTERM);
    for (const auto& [pid, r] : running_) wait_child(pid);
    running_.clear();
  }

  std::size_t running() const { return running_.size(); }

 private:
  static double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  }

  void finish(std::size_t k, int code, double seconds, const std::string& error) {
    MemberStatus s;
    s.exit_code = code, s.seconds = seconds, s.error = error, s.sets = spec_.member_sets(k);
    write_status(spec_.out / spec_.member_dir(k), s);
    const std::string name = spec_.member_dir(k).string();
    if (code != 0 && error == kInterrupted)
      std::fprintf(stderr, "%s: member %zu (%s) interrupted\n", opt_.label.c_str(), k,
                   name.c_str());
    else if (code != 0)
      std::fprintf(stderr, "%s: member %zu (%s) failed (exit %d): %s\n", opt_.label.c_str(), k,
                   name.c_str(), code, error.c_str());
    else if (!opt_.quiet)
      std::fprintf(stderr, "%s: member %zu (%s) ok, %.1f s\n", opt_.label.c_str(), k, name.c_str(),
                   seconds);
  }

  const SweepSpec& spec_;
  const SweepOptions& opt_;
  std::map<pid_t, Running> running_;
};

// The polling loop of run_sweep_members.
bool run_members(Runner& runner, MemberQueue& queue, int jobs) {
  bool exhausted = false, stopped = false;
  for (;;) {
    if (stop_requested() && !stopped) {
      stopped = true;
      runner.stop_all();
      if (!exhausted) queue.next(true), exhausted = true;  // tell rank 0 (MPI) we are done
    }
    while (!stopped && !exhausted && int(runner.running()) < jobs) {
      const auto k = queue.next(false);
      if (!k) {
        exhausted = true;
        break;
      }
      runner.start(*k);
    }
    const bool reaped = runner.reap();
    queue.service(stopped);
    if (runner.running() == 0 && (exhausted || stopped) && queue.drained()) break;
    // 2 ms, as the ensemble's poll (ensemble.cpp: 20 ms left cores idle between members).
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return !stopped;
}

}  // namespace

MemberStatus read_member_status(const fs::path& dir) {
  MemberStatus s;
  std::ifstream in(dir / kStatusFile);
  if (!in) return s;
  s.present = true;
  for (std::string line; std::getline(in, line);) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    if (key == "exit_code") s.exit_code = std::atoi(value.c_str());
    if (key == "seconds") s.seconds = std::strtod(value.c_str(), nullptr);
    if (key == "error") s.error = value;
    if (key == "set") s.sets.push_back(value);
  }
  return s;
}

bool member_stopped(const MemberStatus& s) {
  return s.present && (s.error == kInterrupted || member_running(s));
}

bool member_running(const MemberStatus& s) {
  return s.present && s.error == kRunning;
}

bool member_resumable(const SweepSpec& spec, std::size_t k) {
  const fs::path dir = spec.out / spec.member_dir(k);
  const MemberStatus s = read_member_status(dir);
  std::error_code ec;
  return member_stopped(s) && s.sets == spec.member_sets(k) &&
         fs::exists(dir / "checkpoint.h5", ec);
}

bool member_complete(const SweepSpec& spec, std::size_t k) {
  const fs::path dir = spec.out / spec.member_dir(k);
  const MemberStatus s = read_member_status(dir);
  std::error_code ec;
  return s.present && s.exit_code == 0 && s.sets == spec.member_sets(k) &&
         fs::exists(dir / "timeseries.csv", ec);
}

std::vector<std::size_t> pending_members(const SweepSpec& spec) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < spec.members.size(); ++k)
    if (!member_complete(spec, k)) out.push_back(k);
  return out;
}

// Single-threaded FFTs first, so that a study's own solver.threads still wins; members are the
// unit of parallelism.
std::vector<std::string> member_run_command(const SweepSpec& spec, std::size_t k,
                                            const fs::path& binary) {
  std::vector<std::string> a{binary.string(),
                             "run",
                             spec.scenario.string(),
                             "--quiet",
                             "--out",
                             (spec.out / spec.member_dir(k)).string(),
                             "--set",
                             "solver.threads=1"};
  for (const auto& s : spec.member_sets(k)) a.insert(a.end(), {"--set", s});
  return a;
}

// Polls rather than blocks in waitpid: rank 0 of an MPI study answers the other ranks
// between polls. 20 ms per poll is nothing against members that take seconds.
bool run_sweep_members(const SweepSpec& spec, MemberQueue& queue, const SweepOptions& opt) {
  const int jobs = opt.jobs > 0 ? opt.jobs : usable_cpus();
  Runner runner(spec, opt);
  try {
    return run_members(runner, queue, jobs);
  } catch (...) {
    runner.abandon_all();
    throw;
  }
}

fs::path member_lock_file(const SweepSpec& spec, std::size_t k) {
  std::string name = ".";  // appended, not "." + ...: GCC 12 -Wrestrict false positive
  name += spec.member_dir(k).string();
  name += ".lock";
  return spec.out / name;
}

}  // namespace fretbem
