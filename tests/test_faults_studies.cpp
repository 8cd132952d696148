// Hostile-user faults of studies and ensembles (tools/bench/hostile_hunt.py found most of
// these): summaries on a full disk, two studies into one folder, a member still run by another
// process, studies and ensembles killed outright and run again, study files and options a
// careless user types, ensembles of what cannot be aggregated. Members are n = 16 or 32, a few
// to a few hundred steps (well under a second each on an idle core).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <thread>

#include "fretbem/core/file_lock.hpp"
#include "fretbem/core/text_file.hpp"
#include "sweep_test_util.hpp"

using namespace fretbem;
using namespace sweep_test;

namespace {

const std::string kBin = FRETBEM_BINARY;
const std::string kRough = std::string(FRETBEM_SOURCE_DIR) + "/scenarios/rough_monotone.ini";
const std::string kMindlin = std::string(FRETBEM_SOURCE_DIR) + "/scenarios/mindlin_cycle.ini";

// A four-member study of the Mindlin sphere, small.
fs::path small_study(const fs::path& dir, const std::string& head = "") {
  const fs::path f = dir / "study.ini";
  std::ofstream(f) << head << "[study]\nscenario = " << kMindlin
                   << "\nset = grid.n=32\nset = load.cycles=1\nset = load.steps_per_cycle=8\n"
                      "[vary]\nload.amplitude = 0.3, 0.5, 0.7, 0.8\n";
  return f;
}

int lines(const std::string& s) {
  return int(std::count(s.begin(), s.end(), '\n'));
}

int count_of(const std::string& s, const std::string& what) {
  int n = 0;
  for (std::size_t p = 0; (p = s.find(what, p)) != std::string::npos; ++p) ++n;
  return n;
}

// Polls `done` every 20 ms until it holds or `limit` has passed (a bound for a broken build,
// far beyond what a loaded machine needs); whether it held.
bool wait_until(const std::function<bool()>& done,
                std::chrono::seconds limit = std::chrono::seconds(120)) {
  const auto t0 = std::chrono::steady_clock::now();
  while (!done()) {
    if (std::chrono::steady_clock::now() - t0 > limit) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

// Starts `fretbem ARGS...` as the leader of a new process group (the members it spawns join
// it), stderr into `err`: the group can then be killed outright, as a node failure would.
pid_t start_group(const std::vector<std::string>& args, const fs::path& err) {
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    if (!freopen(err.c_str(), "w", stderr)) _exit(127);
    std::vector<char*> argv{const_cast<char*>(kBin.c_str())};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(kBin.c_str(), argv.data());
    _exit(127);
  }
  setpgid(pid, pid);  // also here: the group exists before the parent signals it
  return pid;
}

// A member's time series has a data row: its run is under way (and holds its folder's lock).
bool has_rows(const fs::path& csv, int rows = 1) {
  return lines(slurp(csv)) >= rows + 1;
}

// The member's own run has ended: nobody holds its folder's lock any more.
bool run_ended(const fs::path& member_dir) {
  return FileLock::try_lock(member_dir / ".fretbem.lock").has_value();
}

// The physical columns of a time series: all but `kx`, which a resumed run repeats only to its
// solver tolerance (README, "resume"), and `convolutions`, the work a step cost (a resumed step
// that rebuilds its solver state costs more; seen: 16 against 7).
std::vector<std::string> physical_rows(const fs::path& csv) {
  std::vector<std::string> rows;
  std::stringstream in(slurp(csv));
  std::vector<bool> skip;
  for (std::string line; std::getline(in, line);) {
    std::stringstream cells(line);
    std::string row, c;
    for (std::size_t i = 0; std::getline(cells, c, ','); ++i) {
      if (rows.empty()) skip.push_back(c == "kx" || c == "convolutions");
      if (i >= skip.size() || !skip[i]) row += c + ",";
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

// Each ran to exit 0 before: identical members of a sphere (a zero-width interval), k_x columns
// all nan, an aggregate of empty bins; --seeds 2147483647 looped forever.
TEST(StudyFaults, EnsembleRefusesWhatItCannotAggregate) {
  const fs::path d = scratch("ensemble_refusals");
  const std::string base = kBin + " ensemble " + kRough + " --hurst 0.5 --seeds 2 --quiet --out " +
                           (d / "e").string() + " --set grid.n=16 --set load.steps=3";
  std::ofstream(d / "file") << "x";
  const struct {
    std::string args, says;
  } cases[] = {
      {" --set surface.type=sphere --set surface.radius=0.01", "surface.type must be rough"},
      {" --set solver.stiffness=none", "solver.stiffness must be every"},
      {" --set solver.stiffness=turning", "solver.stiffness must be every"},
      {" --set load.path=none", "load.path = none"},
      {" --seeds 2147483647", "--seeds"},
  };
  for (const auto& c : cases) {
    const Result r = shell(base + c.args, d);
    EXPECT_EQ(r.status, 2) << c.args << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(d / "e" / "H0.5")) << c.args;
  }
  // --out naming a file: the run's message and exit code (it was exit 1, "cannot create
  // directories").
  const Result r = shell(kBin + " ensemble " + kRough + " --hurst 0.5 --out " +
                             (d / "file").string() + " --set grid.n=16",
                         d);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("cannot create the output folder"), std::string::npos) << r.err;
}

// Two studies of the same file into one folder at once (a Slurm requeue beside the old job, a
// second terminal): every member runs exactly once, the other study leaves it alone, and the
// results equal one study's. Before, the second emptied a member's folder under the running
// member, and members failed on each other's locks ("failed (exit 2)" with another member's log
// line as the error).
TEST(StudyFaults, TwoSweepsIntoOneFolderShareTheMembers) {
  const fs::path d = scratch("two_sweeps");
  const fs::path study = small_study(d), out = d / "out";
  const std::string cmd = kBin + " sweep " + study.string() + " --jobs 1 --out " + out.string();
  const Result r = shell("(" + cmd + " 2> " + (d / "a.err").string() + " & " + cmd + "; wait)", d);
  const std::string both = r.err + slurp(d / "a.err");
  EXPECT_EQ(count_of(both, ") ok,"), 4) << both;  // every member ran once
  EXPECT_EQ(count_of(both, "failed ("), 0) << both;
  EXPECT_EQ(
      shell(kBin + " sweep " + study.string() + " --aggregate --out " + out.string(), d).status, 0);
  EXPECT_EQ(column(out / "sweep.csv", "status"), std::vector<std::string>(4, "ok"));
}

// A member another process holds is left to it: the study's member lock (another study), or the
// member's own run lock (a `fretbem run` orphaned by a study killed with SIGKILL: emptying its
// folder would delete its outputs under it); the study then has no result for them and exits 4.
// The rerun after the locks are gone runs just those members.
TEST(StudyFaults, SweepLeavesMembersOthersRun) {
  const fs::path d = scratch("held_members");
  const fs::path study = small_study(d), out = d / "out";
  fs::create_directories(out / "member_0001");
  {
    auto study_lock = FileLock::try_lock(out / ".member_0000.lock");
    auto run_lock = FileLock::try_lock(out / "member_0001" / ".fretbem.lock");
    ASSERT_TRUE(study_lock && run_lock);
    std::ofstream(out / "member_0001" / "timeseries.csv") << "step\n0\n";  // the orphan's
    const Result r =
        shell(kBin + " sweep " + study.string() + " --jobs 1 --out " + out.string(), d);
    EXPECT_EQ(r.status, 4) << r.err;  // two members have no result yet
    EXPECT_NE(r.err.find("2 ok, 0 failed"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("member 0 (member_0000) is being run by another fretbem process"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("member 1 (member_0001): a fretbem run is still writing into it"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(slurp(out / "member_0001" / "timeseries.csv"), "step\n0\n");  // left alone
    EXPECT_EQ(column(out / "sweep.csv", "status"),
              (std::vector<std::string>{"missing", "missing", "ok", "ok"}));
  }
  const Result again =
      shell(kBin + " sweep " + study.string() + " --jobs 1 --out " + out.string(), d);
  EXPECT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(count_of(again.err, ") ok,"), 2) << again.err;
  EXPECT_EQ(column(out / "sweep.csv", "status"), std::vector<std::string>(4, "ok"));
}

// Study files and options a careless user types: a byte-order mark and CRLF (refused as "line
// 1: expected key = value"), 10^6 x 10^6 members (grew past 400 MB before anything ran), a
// folder as the study file ("no study.scenario given"), options of another command (ignored).
TEST(StudyFaults, HostileStudyFilesAndOptions) {
  const fs::path d = scratch("study_files");
  const fs::path bom = d / "bom.ini";
  std::ofstream(bom) << "\xEF\xBB\xBF[study]\r\nscenario = " << kMindlin
                     << "\r\nset = grid.n=16\r\n[vary]\r\nload.amplitude = 0.3, 0.5\r\n";
  EXPECT_EQ(
      shell(kBin + " sweep " + bom.string() + " --list --out " + (d / "o").string(), d).status, 0);
  const fs::path huge = d / "huge.ini";
  std::ofstream(huge) << "[study]\nscenario = " << kMindlin
                      << "\n[vary]\nsurface.seed = linear(1, 1000000, 1000000)\n"
                         "load.amplitude = linear(0.1, 0.5, 1000000)\n";
  const struct {
    std::string args, says;
  } cases[] = {
      {"sweep " + huge.string() + " --list", "1e+12 members"},
      {"sweep " + d.string() + " --list", "not a study file"},
      {"check " + kMindlin + " --hurst 0.5", "--hurst is not an option of `fretbem check`"},
      {"run " + kMindlin + " --jobs 2", "--jobs is not an option of `fretbem run`"},
      {"sweep " + bom.string() + " --seeds 5", "--seeds is not an option of `fretbem sweep`"},
  };
  for (const auto& c : cases) {
    const Result r = shell(kBin + " " + c.args, d);
    EXPECT_EQ(r.status, 2) << c.args << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
  }
}

// A failed write never replaces the file: PATH.tmp that cannot be created (here a folder of
// that name) leaves PATH as it was, and the error names PATH.
TEST(StudyFaults, AtomicWriteKeepsThePreviousFile) {
  const fs::path d = scratch("atomic");
  const fs::path f = d / "sweep.csv";
  write_file_atomically(f, "good\n");
  EXPECT_EQ(slurp(f), "good\n");
  fs::create_directories(d / "sweep.csv.tmp");
  try {
    write_file_atomically(f, "new\n");
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(f.string() + ": cannot write"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(slurp(f), "good\n");
  EXPECT_THROW(write_file_atomically(d / "no" / "such" / "x.csv", "x"), std::runtime_error);
}

// A full disk (tmpfs, root only) while sweep.csv and aggregate.csv are written: exit 1, one line
// naming the file, and the last good sweep.csv kept (never an empty sweep.csv or an aggregate.csv
// cut short with exit 0).
TEST(StudyFaults, SummariesOnAFullDiskKeepTheLastGoodVersion) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a tmpfs";
  const fs::path d = scratch("full_disk"), mnt = d / "tmpfs";
  fs::create_directories(mnt);
  // Room for the four members' results (1.2 MB at n = 32, fields at step 0 and the turning
  // points); the ensemble below gets 1 MB, less than its 10001-row aggregate.
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=3m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here";
  const fs::path study = small_study(d), out = mnt / "sw";
  Result r =
      shell(kBin + " sweep " + study.string() + " --quiet --jobs 2 --out " + out.string(), d);
  EXPECT_EQ(r.status, 0) << r.err;
  const std::string good = slurp(out / "sweep.csv");
  {  // fill the disk
    std::ofstream fill(mnt / "fill", std::ios::binary);
    const std::string block(4096, 'x');
    while (fill.write(block.data(), std::streamsize(block.size()))) {
    }
  }
  r = shell(kBin + " sweep " + study.string() + " --aggregate --out " + out.string(), d);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("sweep.csv: cannot write: No space left on device"), std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(out / "sweep.csv"), good);
  EXPECT_FALSE(fs::exists(out / "sweep.csv.tmp"));
  fs::remove(mnt / "fill");
  fs::remove_all(out);
  ASSERT_EQ(::mount("tmpfs", mnt.c_str(), "tmpfs", MS_REMOUNT, "size=1m"), 0);
  r = shell(kBin + " ensemble " + kRough + " --hurst 0.5 --seeds 2 --bins 10000 --quiet --out " +
                (mnt / "e").string() + " --set grid.n=16 --set load.steps=3",
            d);
  const bool written = fs::exists(mnt / "e" / "aggregate.csv");
  ::umount(mnt.c_str());
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("aggregate.csv: cannot write"), std::string::npos) << r.err;
  EXPECT_FALSE(written);
}

// A sweep killed outright (SIGKILL to the study alone) leaves its running member's `fretbem
// run` behind. Re-running the study while that run still writes leaves the member to it, and
// must not report success: exit 4, the member `running` in sweep.csv, the count on stderr.
TEST(StudyFaults, RerunBesideAKilledSweepsRunningMemberIsNotSuccess) {
  const fs::path d = scratch("killed_sweep");
  const fs::path study = d / "study.ini", out = d / "out";
  // Member 0 runs for minutes (until killed below), member 1 in a fraction of a second.
  std::ofstream(study) << "[study]\nscenario = " << kMindlin
                       << "\nset = grid.n=32\nset = load.steps_per_cycle=8\n"
                          "[vary]\nload.cycles = 20000, 1\n";
  const pid_t sweep = start_group(
      {"sweep", study.string(), "--jobs", "1", "--quiet", "--out", out.string()}, d / "first.err");
  const fs::path member0 = out / "member_0000";
  ASSERT_TRUE(wait_until([&] { return has_rows(member0 / "timeseries.csv"); }))
      << slurp(d / "first.err");
  kill(sweep, SIGKILL);
  waitpid(sweep, nullptr, 0);
  ASSERT_FALSE(run_ended(member0)) << "the orphaned member run should still be running";
  const Result r =
      shell(kBin + " sweep " + study.string() + " --jobs 1 --quiet --out " + out.string(), d);
  kill(-sweep, SIGKILL);  // the orphan
  EXPECT_EQ(r.status, 4) << r.err;
  EXPECT_NE(r.err.find("member 0 (member_0000): a fretbem run is still writing into it"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("1 ok, 0 failed, 1 running"), std::string::npos) << r.err;
  EXPECT_EQ(column(out / "sweep.csv", "status"), (std::vector<std::string>{"running", "ok"}));
  EXPECT_TRUE(wait_until([&] { return run_ended(member0); }));
}

// An ensemble killed outright (SIGKILL to it and its members: a node failure, the OOM killer)
// is continued by running the same command again: the finished member is kept as it is, the
// killed one continues from its checkpoint in place, and its rows are those of the member run
// alone without interruption (a re-run that started the members afresh into their folders
// would fail each of them on the results there: "pass --overwrite").
namespace {

// An ensemble of `seeds` rough members at n = 32, 1000 steps each, checkpointed every 50.
std::vector<std::string> long_ensemble(const fs::path& out, int seeds, int jobs) {
  return {"ensemble",
          kRough,
          "--hurst",
          "0.5",
          "--seeds",
          std::to_string(seeds),
          "--jobs",
          std::to_string(jobs),
          "--quiet",
          "--out",
          out.string(),
          "--set",
          "grid.n=32",
          "--set",
          "load.steps=1000",
          "--set",
          "output.checkpoint_every=50"};
}

std::string command_line(const std::vector<std::string>& args) {
  std::string cmd = kBin;
  for (const auto& a : args) cmd += " " + a;
  return cmd;
}

// Member `seed` of long_ensemble run alone, without interruption, in d/alone_SEED.
std::vector<std::string> uninterrupted_member(const fs::path& d, int seed) {
  const std::string alone = (d / ("alone_" + std::to_string(seed))).string();
  const Result r =
      shell(kBin + " run " + kRough + " --quiet --out " + alone +
                " --set solver.threads=1 --set solver.fft_plan=auto --set solver.monotone=shortcut "
                "--set grid.n=32 --set load.steps=1000 --set output.checkpoint_every=50 "
                "--set surface.hurst=0.5 --set surface.seed=" +
                std::to_string(seed),
            d);
  EXPECT_EQ(r.status, 0) << r.err;
  return physical_rows(fs::path(alone) / "timeseries.csv");
}

void expect_same_rows(const std::vector<std::string>& continued,
                      const std::vector<std::string>& uninterrupted) {
  ASSERT_EQ(continued.size(), 1002u);
  ASSERT_EQ(uninterrupted.size(), 1002u);
  for (std::size_t i = 0; i < continued.size(); ++i)
    if (continued[i] != uninterrupted[i]) {
      EXPECT_EQ(continued[i], uninterrupted[i]) << "first differing row " << i;
      break;
    }
}

}  // namespace

TEST(StudyFaults, EnsembleKilledOutrightContinuesOnRerun) {
  const fs::path d = scratch("killed_ensemble"), out = d / "e";
  // This test's own wisdom file: a concurrent test measuring another size could extend a shared
  // one between the runs compared below (FFTW may then re-choose plans: round-off changes).
  setenv("FRETBEM_FFTW_WISDOM", (d / "wisdom").c_str(), 1);
  const std::vector<std::string> args = long_ensemble(out, 2, 1);
  const pid_t ensemble = start_group(args, d / "first.err");
  const fs::path seed1 = out / "H0.5" / "seed_001", seed2 = out / "H0.5" / "seed_002";
  // Members run one at a time: seed 2 has a checkpoint once seed 1 has ended.
  ASSERT_TRUE(wait_until([&] { return fs::exists(seed2 / "checkpoint.h5"); }))
      << slurp(d / "first.err");
  kill(-ensemble, SIGKILL);
  waitpid(ensemble, nullptr, 0);
  ASSERT_TRUE(wait_until([&] { return run_ended(seed2); }));
  std::ofstream(seed1 / "marker") << "kept";
  std::ofstream(seed2 / "marker") << "kept";
  const Result r = shell(command_line(args), d);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(seed1 / "marker")) << "the finished member ran again";
  EXPECT_TRUE(fs::exists(seed2 / "marker")) << "the killed member started afresh";
  const auto members = slurp(out / "members.csv");
  EXPECT_EQ(count_of(members, ",0,"), 2) << members;
  EXPECT_EQ(count_of(members, ",ok\n"), 2) << members;
  expect_same_rows(physical_rows(seed2 / "timeseries.csv"), uninterrupted_member(d, 2));
  unsetenv("FRETBEM_FFTW_WISDOM");
}

// SIGTERM to the ensemble alone (as `kill PID` or a batch system's stop of the main process):
// the study stops the members its worker processes run, each checkpointed and recorded as
// interrupted, and exits 143; run again, it keeps the finished member and continues the
// stopped ones, whose rows are the uninterrupted run's.
TEST(StudyFaults, EnsembleStoppedBySigtermContinuesOnRerun) {
  const fs::path d = scratch("stopped_ensemble"), out = d / "e";
  setenv("FRETBEM_FFTW_WISDOM", (d / "wisdom").c_str(), 1);  // as the test above
  const std::vector<std::string> args = long_ensemble(out, 3, 2);
  const pid_t ensemble = start_group(args, d / "first.err");
  const fs::path seed1 = out / "H0.5" / "seed_001", seed3 = out / "H0.5" / "seed_003";
  // Two workers: seed 3 starts once seed 1 or 2 has ended.
  ASSERT_TRUE(wait_until([&] { return has_rows(seed3 / "timeseries.csv"); }))
      << slurp(d / "first.err");
  kill(ensemble, SIGTERM);
  int status = 0;
  waitpid(ensemble, &status, 0);
  ASSERT_TRUE(WIFEXITED(status)) << slurp(d / "first.err");
  EXPECT_EQ(WEXITSTATUS(status), 143) << slurp(d / "first.err");
  std::vector<int> finished;
  for (int s = 1; s <= 3; ++s) {
    const fs::path dir = out / "H0.5" / ("seed_00" + std::to_string(s));
    ASSERT_TRUE(run_ended(dir)) << "a worker outlived the ensemble";
    const std::string st = slurp(dir / "sweep_member.txt");
    if (st.find("exit_code=0\n") != std::string::npos)
      finished.push_back(s);
    else
      EXPECT_NE(st.find("interrupted"), std::string::npos) << st;
    std::ofstream(dir / "marker") << "kept";
  }
  ASSERT_GE(finished.size(), 1u);
  ASSERT_LE(finished.size(), 2u) << "SIGTERM came after the last member ended";
  const Result r = shell(command_line(args), d);
  EXPECT_EQ(r.status, 0) << r.err;
  const auto members = slurp(out / "members.csv");
  EXPECT_EQ(count_of(members, ",ok\n"), 3) << members;
  for (int s = 1; s <= 3; ++s) {
    const fs::path dir = out / "H0.5" / ("seed_00" + std::to_string(s));
    EXPECT_TRUE(fs::exists(dir / "marker")) << "seed " << s << " ran again from the start";
  }
  expect_same_rows(physical_rows(seed3 / "timeseries.csv"), uninterrupted_member(d, 3));
  unsetenv("FRETBEM_FFTW_WISDOM");
}

// aggregate.csv leaves a cell empty where there is no value (no NaN): the means of a bin no
// member reaches, the 95 % interval of a bin one member covers (the interval needs two).
TEST(StudyFaults, EnsembleAggregateLeavesMissingValuesEmpty) {
  const fs::path d = scratch("aggregate_cells"), out = d / "e";
  // One member, a displacement ramp that stops far below full sliding: f covers [0, ~0.25].
  const Result r = shell(kBin + " ensemble " + kRough +
                             " --hurst 0.5 --seeds 1 --bins 20 --quiet --out " + out.string() +
                             " --set grid.n=16 --set load.steps=3 --set "
                             "load.displacement_amplitude=5e-7",
                         d);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string agg = slurp(out / "aggregate.csv");
  EXPECT_EQ(agg.find("nan"), std::string::npos) << agg;
  int covered = 0, empty = 0;
  std::stringstream in(agg);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream cells(line + ",");  // the trailing comma keeps a last empty cell
    for (std::string v; std::getline(cells, v, ',');) c.push_back(v);
    ASSERT_EQ(c.size(), 13u) << line;
    for (int i = 0; i < 5; ++i) EXPECT_FALSE(c[i].empty()) << line;  // the bin itself
    const bool one = c[5] == "1";
    covered += one, empty += c[5] == "0";
    for (int i : {7, 9, 11}) EXPECT_EQ(c[i].empty(), !one) << line;  // means
    for (int i : {8, 10, 12}) EXPECT_TRUE(c[i].empty()) << line;     // intervals
  }
  EXPECT_GT(covered, 0);
  EXPECT_GT(empty, 0);
}
