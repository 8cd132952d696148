#include "fretbem/study/member_pool.hpp"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <map>
#include <thread>

#include "fretbem/core/file_lock.hpp"
#include "fretbem/core/output_lock.hpp"
#include "fretbem/core/resources.hpp"
#include "fretbem/core/stop_signal.hpp"
#include "fretbem/io/replaced_results.hpp"
#include "fretbem/study/member_launcher.hpp"
#include "fretbem/study/member_status.hpp"
#include "fretbem/study/mpi_queue.hpp"
#include "fretbem/study/subprocess.hpp"

namespace fretbem {

namespace fs = std::filesystem;

namespace {

struct Running {
  std::size_t index = 0;
  std::chrono::steady_clock::time_point start;
  std::optional<FileLock> lock;  // the member is this process's until it ends
};

// A member's own `fretbem run` holds its OutputLock while it runs; one orphaned by a study
// killed outright runs on after the study's member lock is gone.
bool run_still_active(const fs::path& member_dir) {
  std::error_code ec;
  const fs::path lock = member_dir / OutputLock::file_name;
  return fs::exists(lock, ec) && !FileLock::try_lock(lock);
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// In worker processes when the caller gives the entry point, except under an MPI launcher: a
// worker forked from a rank would carry the launcher's environment into its members, which
// would take themselves for ranks of a distributed run (subprocess.cpp).
std::unique_ptr<MemberLauncher> launcher_for(const PoolOptions& opt) {
  if (opt.in_process && !mpi_launched()) return make_worker_launcher(opt.in_process);
  return make_spawn_launcher();
}

class Pool {
 public:
  Pool(const StudyMembers& members, const PoolOptions& opt)
      : members_(members), opt_(opt), launcher_(launcher_for(opt)) {}

  // A stopped member continues from its checkpoint; any other starts afresh. A member another
  // process runs right now is left to it: emptying its folder would pull the outputs from under
  // the running member, and its status and log would be overwritten.
  void start(std::size_t k) {
    const fs::path lock_file = member_lock_file(members_, k);
    fs::create_directories(lock_file.parent_path());
    auto lock = FileLock::try_lock(lock_file);
    if (!lock) return leave(k, " is being run by another fretbem process");
    if (!opt_.restart && member_complete(members_, k)) return;  // finished elsewhere meanwhile
    const fs::path dir = members_.path(k);
    if (run_still_active(dir))
      return leave(k,
                   ": a fretbem run is still writing into it (left over from a study that was "
                   "killed?)");
    const bool resume = !opt_.restart && member_resumable(members_, k);
    // A member run afresh keeps the results it replaces until it finishes, and puts them back
    // when it fails (io/replaced_results.hpp), as `run --overwrite` does: every member under
    // --overwrite, and one whose folder holds results a failed or killed replacement kept.
    // Any other folder holds the stale outputs of an earlier attempt only.
    const bool replace = opt_.restart || (!resume && holds_replaced_results(dir));
    if (!resume && !replace) fs::remove_all(dir);
    fs::create_directories(dir);
    MemberStatus running;
    running.error = kMemberRunning, running.sets = members_.sets(k);
    write_member_status(dir, running);
    auto cmd = resume ? std::vector<std::string>{opt_.binary.string(), "run", "--resume",
                                                 dir.string(), "--quiet"}
                      : member_run_command(members_, k, opt_.binary);
    if (replace) cmd.push_back("--overwrite");
    const auto handle = launcher_->start(cmd, dir / "log.txt");
    if (!handle) return finish(k, 127, 0, "could not start " + opt_.binary.string());
    running_[*handle] = {k, std::chrono::steady_clock::now(), std::move(lock)};
  }

  // Collects the members that ended; true when any did.
  bool reap() {
    bool any = false;
    for (auto it = running_.begin(); it != running_.end();) {
      const auto code = launcher_->poll(it->first);
      if (!code) {
        ++it;
        continue;
      }
      // The member lock goes with `done`, after its status is written: released before, another
      // study would take the member as still running and resume the finished run.
      const Running done = std::move(it->second);
      const std::size_t k = done.index;
      it = running_.erase(it);
      // Ctrl-C reaches the members too: one that died of it while we stop was interrupted.
      const bool interrupted = *code > 128 && stop_requested();
      finish(k, *code, seconds_since(done.start),
             *code == 0    ? ""
             : interrupted ? kMemberInterrupted
                           : last_line(members_.path(k) / "log.txt"));
      any = true;
    }
    return any;
  }

  // SIGTERM to every running member, then their exits, each recorded as interrupted unless
  // it had just finished (exit 0: recorded as finished, not "interrupted" beside exit 0).
  void stop_all() {
    for (const auto& [handle, r] : running_) launcher_->terminate(handle);
    for (const auto& [handle, r] : running_) {
      const int code = launcher_->wait(handle);
      finish(r.index, code, seconds_since(r.start), code == 0 ? "" : kMemberInterrupted);
    }
    running_.clear();
  }

  // After a failure of the study itself (its status files cannot be written): the members are
  // ended without further records, so that none runs on unobserved.
  void abandon_all() noexcept {
    for (const auto& [handle, r] : running_) launcher_->terminate(handle);
    for (const auto& [handle, r] : running_) launcher_->wait(handle);
    running_.clear();
  }

  std::size_t running() const { return running_.size(); }

 private:
  void leave(std::size_t k, const char* why) {
    std::fprintf(stderr, "%s: member %zu (%s)%s; not started here\n", opt_.label.c_str(), k,
                 members_.dir(k).string().c_str(), why);
  }

  void finish(std::size_t k, int code, double seconds, const std::string& error) {
    MemberStatus s;
    s.exit_code = code, s.seconds = seconds, s.error = error, s.sets = members_.sets(k);
    write_member_status(members_.path(k), s);
    const std::string name = members_.dir(k).string();
    if (code != 0 && error == kMemberInterrupted)
      std::fprintf(stderr, "%s: member %zu (%s) interrupted\n", opt_.label.c_str(), k,
                   name.c_str());
    else if (code != 0)
      std::fprintf(stderr, "%s: member %zu (%s) failed (exit %d): %s\n", opt_.label.c_str(), k,
                   name.c_str(), code, error.c_str());
    else if (!opt_.quiet)
      std::fprintf(stderr, "%s: member %zu (%s) ok, %.1f s\n", opt_.label.c_str(), k, name.c_str(),
                   seconds);
  }

  const StudyMembers& members_;
  const PoolOptions& opt_;
  std::unique_ptr<MemberLauncher> launcher_;
  std::map<int, Running> running_;  // by the launcher's handle
};

// Polls rather than blocks in waitpid: a signal must be seen while members run, and rank 0 of
// an MPI study answers the other ranks between polls.
bool poll_members(Pool& pool, MemberQueue& queue, int jobs) {
  bool exhausted = false, stopped = false;
  for (;;) {
    if (stop_requested() && !stopped) {
      stopped = true;
      pool.stop_all();
      if (!exhausted) queue.next(true), exhausted = true;  // tell rank 0 (MPI) we are done
    }
    while (!stopped && !exhausted && int(pool.running()) < jobs) {
      const auto k = queue.next(false);
      if (!k) {
        exhausted = true;
        break;
      }
      pool.start(*k);
    }
    const bool reaped = pool.reap();
    queue.service(stopped);
    if (pool.running() == 0 && (exhausted || stopped) && queue.drained()) break;
    // 2 ms: a free core waits ~1 ms on average for its next member (20 ms cost the paper
    // ensemble's 100 one-second members ~0.5 s of wall time); the poll itself is a waitpid
    // per running member.
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return !stopped;
}

}  // namespace

bool run_study_members(const StudyMembers& members, MemberQueue& queue, const PoolOptions& opt) {
  const int jobs = opt.jobs > 0 ? opt.jobs : usable_cpus();
  Pool pool(members, opt);
  try {
    return poll_members(pool, queue, jobs);
  } catch (...) {
    pool.abandon_all();
    throw;
  }
}

}  // namespace fretbem
