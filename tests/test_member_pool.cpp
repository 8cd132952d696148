// The study pool's worker processes (study/member_launcher.hpp): members run one after another
// in `jobs` processes forked from the study, each member's output in its own log, and a member
// that crashes ends its worker only. The members here are stand-ins for `fretbem run` (the
// entry point writes what a run would and returns its status); test_faults_studies runs the
// real ones through the CLI.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>

#include "fretbem/study/member_pool.hpp"
#include "fretbem/study/member_status.hpp"
#include "fretbem/study/mpi_queue.hpp"
#include "sweep_test_util.hpp"

using namespace fretbem;
using namespace sweep_test;

namespace {

constexpr std::size_t kMembers = 6;

StudyMembers stand_in_members(const fs::path& out) {
  StudyMembers m;
  m.scenario = "stand_in.ini", m.out = out, m.count = kMembers;
  m.dir = [](std::size_t k) { return fs::path("member_" + std::to_string(k)); };
  m.sets = [](std::size_t k) { return std::vector<std::string>{"k=" + std::to_string(k)}; };
  return m;
}

fs::path out_dir_of(const std::vector<std::string>& args) {
  for (std::size_t i = 0; i + 1 < args.size(); ++i)
    if (args[i] == "--out") return args[i + 1];
  return {};
}

// Member 2 crashes (SIGABRT, 128 + 6), member 4 fails as a run with bad input does (a line on
// stderr, status 2); every member records the process it ran in.
int stand_in_run(const std::vector<std::string>& args) {
  const fs::path dir = out_dir_of(args);
  std::ofstream(dir / "pid") << ::getpid();
  if (dir.filename() == "member_2") std::abort();
  if (dir.filename() == "member_4") return std::fprintf(stderr, "bad value of k\n"), 2;
  std::printf("ran %s\n", dir.filename().c_str());
  std::ofstream(dir / "timeseries.csv") << "step\n0\n";
  return 0;
}

long pid_of(const StudyMembers& m, std::size_t k) {
  return std::stol(slurp(m.path(k) / "pid"));
}

}  // namespace

TEST(MemberPool, WorkersRunMembersInTurnAndACrashEndsOnlyItsWorker) {
  const StudyMembers m = stand_in_members(scratch("pool_workers"));
  PoolOptions opt;
  opt.jobs = 1, opt.quiet = true, opt.binary = "fretbem", opt.in_process = stand_in_run;
  auto queue = make_local_queue(pending_members(m));
  ASSERT_TRUE(run_study_members(m, *queue, opt));

  for (std::size_t k : {0, 1, 3, 5}) {
    EXPECT_TRUE(member_complete(m, k)) << k;
    EXPECT_EQ(slurp(m.path(k) / "log.txt"), "ran member_" + std::to_string(k) + "\n") << k;
  }
  const MemberStatus crashed = read_member_status(m.path(2)), bad = read_member_status(m.path(4));
  EXPECT_EQ(crashed.exit_code, 128 + SIGABRT);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.error, "bad value of k");
  // One worker at a time: members 0-2 in the first, 3-5 in the one that replaced it.
  std::set<long> pids;
  for (std::size_t k = 0; k < kMembers; ++k) pids.insert(pid_of(m, k));
  EXPECT_EQ(pids.size(), 2u);
  EXPECT_EQ(pids.count(::getpid()), 0u) << "a member ran in the study's own process";
  EXPECT_EQ(pid_of(m, 0), pid_of(m, 2));
  EXPECT_EQ(pid_of(m, 3), pid_of(m, 5));
}

TEST(MemberPool, TwoJobsTwoWorkers) {
  const StudyMembers m = stand_in_members(scratch("pool_two_jobs"));
  PoolOptions opt;
  opt.jobs = 2, opt.quiet = true, opt.binary = "fretbem";
  opt.in_process = [](const std::vector<std::string>& args) {
    std::ofstream(out_dir_of(args) / "pid") << ::getpid();
    std::ofstream(out_dir_of(args) / "timeseries.csv") << "step\n0\n";
    return 0;
  };
  auto queue = make_local_queue(pending_members(m));
  ASSERT_TRUE(run_study_members(m, *queue, opt));
  std::set<long> pids;
  for (std::size_t k = 0; k < kMembers; ++k) {
    EXPECT_TRUE(member_complete(m, k)) << k;
    pids.insert(pid_of(m, k));
  }
  EXPECT_LE(pids.size(), 2u);
}

// A worker that ends while idle (as on a Ctrl-C, which reaches every process of the group):
// the next member's job meets a closed pipe, and the study neither dies of SIGPIPE nor fails
// the member, which runs in a fresh worker.
TEST(MemberPool, AWorkerGoneWhileIdleIsReplaced) {
  const StudyMembers m = stand_in_members(scratch("pool_gone_idle"));
  PoolOptions opt;
  opt.jobs = 1, opt.quiet = true, opt.binary = "fretbem";
  opt.in_process = [](const std::vector<std::string>& args) {
    const fs::path dir = out_dir_of(args);
    std::ofstream(dir / "pid") << ::getpid();
    std::ofstream(dir / "timeseries.csv") << "step\n0\n";
    if (dir.filename() == "member_0") ::close(3);  // the worker's job pipe: it ends once idle
    return 0;
  };
  auto queue = make_local_queue(pending_members(m));
  ASSERT_TRUE(run_study_members(m, *queue, opt));
  for (std::size_t k = 0; k < kMembers; ++k) EXPECT_TRUE(member_complete(m, k)) << k;
  EXPECT_NE(pid_of(m, 0), pid_of(m, 1));
  EXPECT_EQ(pid_of(m, 1), pid_of(m, 5));
}
