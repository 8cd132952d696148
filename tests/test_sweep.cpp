// fretbem sweep: study files, member lists, the serial runner, --list/--member/
// --aggregate, failed members, restart after SIGTERM, and the cluster-node defaults.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <thread>

#include "fretbem/core/errors.hpp"
#include "fretbem/core/resources.hpp"
#include "fretbem/study/sweep_spec.hpp"
#include "support/child_process.hpp"
#include "sweep_test_util.hpp"

using namespace fretbem;
using namespace sweep_test;

namespace {

fs::path write_study(const fs::path& dir, const std::string& vary, const std::string& extra = "") {
  const fs::path f = dir / "study.ini";
  std::ofstream(f) << "[study]\nscenario = " << FRETBEM_SOURCE_DIR
                   << "/scenarios/rough_fretting_cycle.ini\nout = " << (dir / "out").string()
                   << "\n"
                   << extra << "[vary]\n"
                   << vary;
  return f;
}

std::string bin() {
  return FRETBEM_BINARY;
}

// The example study made small for tests: n = 32, one cycle of 8 steps per member.
const std::string kSmall = " --set grid.n=32 --set load.cycles=1 --set load.steps_per_cycle=8";

}  // namespace

TEST(SweepValues, ListsAndRanges) {
  EXPECT_EQ(parse_sweep_values("k", "0.5, 0.50 ,fourier"),
            (std::vector<std::string>{"0.5", "0.5", "fourier"}));
  EXPECT_EQ(parse_sweep_values("k", "linear(1, 3, 3)"), (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(parse_sweep_values("k", "linear(0.2, 0.2, 1)"), (std::vector<std::string>{"0.2"}));
  // log: both ends exact; interior values a geometric sequence (ratio 10 here) to rounding.
  const auto v = parse_sweep_values("k", "log(0.01, 100, 5)");
  ASSERT_EQ(v.size(), 5u);
  EXPECT_EQ(v.front(), "0.01");
  EXPECT_EQ(v.back(), "100");
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(std::stod(v[i]), std::pow(10.0, i - 2), 1e-14 * std::pow(10.0, i - 2));
  // Whole-numbered ranges stay whole (a + t (b - a) gives seed 7.000000000000001).
  const auto seeds = parse_sweep_values("surface.seed", "linear(1, 10000, 10000)");
  for (int i = 0; i < 10000; ++i) ASSERT_EQ(seeds[i], std::to_string(i + 1));
  for (const char* bad : {"linear(1, 3)", "log(0, 1, 3)", "linear(1, 2, 2.5)", "linear(a, 2, 3)",
                          "1,,2", "log(1, 2, 0)", "log(-1, 1, 3)", "linear(0, 1, 0)",
                          "linear(0, 1, 1e7)", "linear(0, nan, 3)", ",", ""})
    EXPECT_THROW(parse_sweep_values("k", bad), InputError) << bad;
}

TEST(SweepSpec, ProductFirstKeySlowestAndZip) {
  const fs::path d = scratch("spec");
  auto s = load_sweep_spec(write_study(d, "load.amplitude = 0.3, 0.7\nsurface.seed = 1, 2, 3\n"));
  ASSERT_EQ(s.members.size(), 6u);
  EXPECT_EQ(s.members[1], (std::vector<std::string>{"0.3", "2"}));
  EXPECT_EQ(s.members[3], (std::vector<std::string>{"0.7", "1"}));
  EXPECT_EQ(s.member_sets(5).back(), "surface.seed=3");
  EXPECT_EQ(s.member_dir(5), "member_0005");
  s = load_sweep_spec(
      write_study(d, "load.amplitude = 0.3, 0.7\nsurface.seed = 1, 2\n", "combine = zip\n"));
  ASSERT_EQ(s.members.size(), 2u);
  EXPECT_EQ(s.members[1], (std::vector<std::string>{"0.7", "2"}));
}

TEST(SweepSpec, BadStudiesAreRefusedNamingTheProblem) {
  const fs::path d = scratch("bad");
  struct Case {
    std::string vary, extra, says;
  } cases[] = {
      {"load.amplitude = 0.5, 0.50\n", "", "are the same"},  // duplicate member
      {"surface.seed = 1, 1\n", "", "are the same"},
      {"load.amplitude = 0.3, 0.7\nsurface.seed = 1\n", "combine = zip\n", "equally many"},
      {"load.amplitude = 0.3\n", "combine = diagonal\n", "combine"},
      {"load.amplitude = 0.3\n", "frobnicate = 1\n", "study.frobnicate"},
      {"", "", "names no key"},
      {"load.amplitude = 0.3, 1.5\n", "", "member 1"},  // past full sliding: member named
      {"material.mue = 0.3\n", "", "material.mue"},     // unknown key
      {"load.amplitude = linear(0.1, 0.5)\n", "", "linear(first, last, count)"},
  };
  for (const auto& c : cases) {
    try {
      load_sweep_spec(write_study(d, c.vary, c.extra));
      ADD_FAILURE() << c.vary << c.extra << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    }
  }
  // A scenario name longer than the filesystem allows (found by fuzz_sweep: the status query
  // threw std::filesystem_error, exit 1) is refused like a missing one.
  {
    const fs::path f = d / "long.ini";
    std::ofstream(f) << "[study]\nscenario = " << std::string(300, 'a') << ".ini\n[vary]\n"
                     << "load.amplitude = 0.3\n";
    EXPECT_THROW(load_sweep_spec(f), InputError);
  }
  // From the command line: one line on stderr, exit 2.
  const Result r = shell(bin() + " sweep " + write_study(d, "surface.seed = 2, 2\n").string(), d);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// Serial run, and --list + --member + --aggregate, give the same sweep.csv digit for digit
// (wall times aside); every member's summary is the last row of its own cycles.csv.
TEST(SweepRun, SerialEqualsListMemberAggregate) {
  const fs::path d = scratch("serial");
  const fs::path a = d / "a", b = d / "b";
  const Result serial = shell(
      bin() + " sweep " + example_study() + " --quiet --jobs 2 --out " + a.string() + kSmall, d);
  ASSERT_EQ(serial.status, 0) << serial.err;
  const Result list =
      shell(bin() + " sweep " + example_study() + " --list --out " + b.string() + kSmall, d);
  ASSERT_EQ(list.status, 0) << list.err;
  std::stringstream lines(list.out);
  int n = 0;
  for (std::string cmd; std::getline(lines, cmd); ++n) {
    EXPECT_NE(cmd.find("--member " + std::to_string(n)), std::string::npos) << cmd;
    ASSERT_EQ(shell(cmd + " --quiet", d).status, 0) << cmd;
  }
  EXPECT_EQ(n, 6);
  ASSERT_EQ(
      shell(bin() + " sweep " + example_study() + " --aggregate --out " + b.string() + kSmall, d)
          .status,
      0);
  const auto ra = rows_without_time(a / "sweep.csv"), rb = rows_without_time(b / "sweep.csv");
  ASSERT_EQ(ra.size(), 7u);
  EXPECT_EQ(ra, rb);
  EXPECT_EQ(column(a / "sweep.csv", "status"), std::vector<std::string>(6, "ok"));
  // The summary is copied from the member's own cycles.csv (last row), not recomputed.
  const std::string cycles = slurp(a / "member_0004" / "cycles.csv");
  const std::string last = cycles.substr(cycles.rfind('\n', cycles.size() - 2) + 1);
  const auto energy = column(a / "sweep.csv", "dissipated_energy");
  EXPECT_NE(last.find("," + energy[4] + ","), std::string::npos) << last << " vs " << energy[4];
  EXPECT_EQ(column(a / "sweep.csv", "load.amplitude")[4], "0.7");
  EXPECT_EQ(column(a / "sweep.csv", "surface.seed")[4], "2");
}

// One member that cannot converge (one iteration allowed) fails with its error recorded; the
// others complete; the exit status says some failed; a re-run retries only that one.
TEST(SweepRun, BadMemberIsReportedAndTheOthersComplete) {
  const fs::path d = scratch("badmember");
  const fs::path study = write_study(
      d, "solver.max_iterations = 1000, 1, 999\nsurface.seed = 1, 2, 3\n",
      "combine = zip\nset = grid.n=32\nset = load.cycles=1\nset = load.steps_per_cycle=8\n");
  const Result r = shell(bin() + " sweep " + study.string() + " --quiet", d);
  EXPECT_EQ(r.status, 4) << r.err;
  EXPECT_NE(r.err.find("member 1 (member_0001) failed"), std::string::npos) << r.err;
  EXPECT_EQ(column(d / "out" / "sweep.csv", "status"),
            (std::vector<std::string>{"ok", "failed", "ok"}));
  EXPECT_EQ(column(d / "out" / "sweep.csv", "exit_code")[1], "3");  // solver failure
  const Result again = shell(bin() + " sweep " + study.string(), d);
  EXPECT_EQ(again.status, 4);
  EXPECT_EQ(again.err.find("member 0"), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("member 1"), std::string::npos) << again.err;
}

// SIGTERM ends the running member and still writes the aggregate of the finished ones; the
// re-run runs exactly the members that had not finished.
TEST(SweepRun, SigtermThenRerunRunsOnlyTheMissingMembers) {
  const fs::path d = scratch("sigterm");
  const fs::path out = d / "out";
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string log = (d / "first.err").string();
    freopen(log.c_str(), "w", stderr);
    execl(FRETBEM_BINARY, FRETBEM_BINARY, "sweep", example_study().c_str(), "--jobs", "1", "--out",
          out.c_str(), "--set", "grid.n=32", nullptr);
    _exit(127);
  }
  // Wait for two finished members (status written at the start says running), then stop.
  int status = 0;
  ASSERT_TRUE(fretbem_test::wait_until(
      pid,
      [&] {
        return slurp(out / "member_0001" / "sweep_member.txt").find("exit_code=0\n") !=
               std::string::npos;
      },
      &status))
      << slurp(d / "first.err");
  kill(pid, SIGTERM);
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 143) << slurp(d / "first.err");
  const auto st = column(out / "sweep.csv", "status");
  ASSERT_EQ(st.size(), 6u);
  const int ok = int(std::count(st.begin(), st.end(), "ok"));
  EXPECT_GE(ok, 2);
  EXPECT_LT(ok, 6);
  for (std::size_t k = ok; k < st.size(); ++k) EXPECT_NE(st[k], "ok") << k;
  const Result again = shell(
      bin() + " sweep " + example_study() + " --jobs 1 --out " + out.string() + " --set grid.n=32",
      d);
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(int(std::count(again.err.begin(), again.err.end(), '\n')), 6 - ok + 1) << again.err;
  for (int k = 0; k < ok; ++k)
    EXPECT_EQ(again.err.find("member " + std::to_string(k) + " "), std::string::npos) << again.err;
  EXPECT_EQ(column(out / "sweep.csv", "status"), std::vector<std::string>(6, "ok"));
}

TEST(SweepRun, MemberOutOfRangeIsBadInput) {
  const fs::path d = scratch("range");
  const Result r =
      shell(bin() + " sweep " + example_study() + " --member 6 --out " + d.string(), d);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("members 0..5"), std::string::npos) << r.err;
}

TEST(Resources, CgroupLimitV2V1AndUnlimited) {
  const fs::path d = scratch("cgroup");
  EXPECT_FALSE(cgroup_memory_limit(d.string()));  // nothing there: no limit
  std::ofstream(d / "memory.max") << "max\n";
  EXPECT_FALSE(cgroup_memory_limit(d.string()));
  std::ofstream(d / "memory.max") << "2147483648\n";
  EXPECT_EQ(cgroup_memory_limit(d.string()).value_or(0), 2147483648.0);
  const fs::path v1 = scratch("cgroup_v1");
  fs::create_directories(v1 / "memory");
  std::ofstream(v1 / "memory" / "memory.limit_in_bytes") << "9223372036854771712\n";
  EXPECT_FALSE(cgroup_memory_limit(v1.string()));  // v1's "unlimited"
  std::ofstream(v1 / "memory" / "memory.limit_in_bytes") << "1073741824\n";
  EXPECT_EQ(cgroup_memory_limit(v1.string()).value_or(0), 1073741824.0);
  EXPECT_GT(usable_memory_bytes(), 0.0);
  // Slurm's cgroup v2 layout: the limit on the job, "max" in the step and task below it.
  const fs::path job = scratch("cgroup_slurm");
  fs::create_directories(job / "job_7" / "step_0" / "task_0");
  std::ofstream(job / "memory.max") << "max\n";
  std::ofstream(job / "job_7" / "memory.max") << "4294967296\n";
  std::ofstream(job / "job_7" / "step_0" / "memory.max") << "max\n";
  std::ofstream(job / "job_7" / "step_0" / "task_0" / "memory.max") << "max\n";
  EXPECT_EQ(cgroup_memory_limit(job.string(), "/job_7/step_0/task_0").value_or(0), 4294967296.0);
  std::ofstream(job / "job_7" / "step_0" / "memory.max") << "1073741824\n";  // the smaller wins
  EXPECT_EQ(cgroup_memory_limit(job.string(), "/job_7/step_0/task_0/").value_or(0), 1073741824.0);
}

TEST(Resources, SlurmCpusPerTaskCapsTheAffinityCount) {
  unsetenv("SLURM_CPUS_PER_TASK");
  const int affinity = usable_cpus();
  EXPECT_GE(affinity, 1);
  setenv("SLURM_CPUS_PER_TASK", "1", 1);
  EXPECT_EQ(usable_cpus(), 1);
  setenv("SLURM_CPUS_PER_TASK", "100000", 1);
  EXPECT_EQ(usable_cpus(), affinity);  // never more than the mask allows
  setenv("SLURM_CPUS_PER_TASK", "two", 1);
  EXPECT_FALSE(slurm_cpus_per_task());
  EXPECT_EQ(usable_cpus(), affinity);
  unsetenv("SLURM_CPUS_PER_TASK");
}

// A member whose study was killed outright (its status still says running) continues from its
// checkpoint on the next run instead of starting afresh: its directory is kept, and the result
// is the uninterrupted one (here the checkpoint is the final one, so to the last digit).
TEST(SweepRun, KilledMemberContinuesFromItsCheckpoint) {
  const fs::path d = scratch("resume");
  const std::string member0 = bin() + " sweep " + example_study() + " --member 0 --quiet --out " +
                              (d / "out").string() + kSmall;
  ASSERT_EQ(shell(member0, d).status, 0);
  const fs::path dir = d / "out" / "member_0000";
  const std::string cycles = slurp(dir / "cycles.csv");
  std::string status = slurp(dir / "sweep_member.txt");
  status.replace(status.find("exit_code=0"), 11, "exit_code=-1");
  status.replace(status.find("error=\n"), 7, "error=running (or killed while running)\n");
  std::ofstream(dir / "sweep_member.txt") << status;
  std::ofstream(dir / "marker") << "kept";
  ASSERT_EQ(shell(bin() + " sweep " + example_study() + " --aggregate --out " +
                      (d / "out").string() + kSmall,
                  d)
                .status,
            0);
  EXPECT_EQ(column(d / "out" / "sweep.csv", "status")[0], "running");
  ASSERT_EQ(shell(member0, d).status, 0);
  EXPECT_TRUE(fs::exists(dir / "marker"));  // resumed in place, not restarted
  EXPECT_EQ(slurp(dir / "cycles.csv"), cycles);
  EXPECT_NE(slurp(dir / "sweep_member.txt").find("exit_code=0\n"), std::string::npos);
}
