// FFT threads on small grids: below n = 512 a run uses one FFT thread whatever solver.threads
// asks, so a second thread costs no CPU there (a transform of a 32 x 32 padded grid takes
// microseconds, less than handing work between threads; docs/performance.md, "FFT threads").
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "fretbem/core/resources.hpp"
#include "fretbem/elastic/half_space.hpp"
#include "fretbem/history/model.hpp"

using namespace fretbem;

namespace {

Scenario scenario_at(int n, int threads) {
  return parse_scenario("[material]\nE = 1\nnu = 0.3\nmu = 0.5\n[grid]\nn = " + std::to_string(n) +
                            "\nlength = 1\n[surface]\ntype = sphere\nradius = 1\n[load]\n"
                            "normal_force = 0.0229\npath = sine\namplitude = 0.6\n[solver]\n"
                            "threads = " +
                            std::to_string(threads) + "\n",
                        "t", ".");
}

double seconds(const timeval& t) {
  return double(t.tv_sec) + 1e-6 * double(t.tv_usec);
}

// User + system CPU seconds of one `fretbem run` child (its own rusage from wait4).
double run_cpu(int threads, const std::string& out) {
  const std::vector<std::string> args = {
      FRETBEM_BINARY,  "run",       FRETBEM_SOURCE_DIR "/scenarios/mindlin_cycle.ini",
      "--set",         "grid.n=16", "--set",
      "load.cycles=1", "--set",     "solver.threads=" + std::to_string(threads),
      "--out",         out,         "--overwrite",
      "--quiet"};
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  rusage ru{};
  wait4(pid, &status, 0, &ru);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "threads " << threads;
  return seconds(ru.ru_utime) + seconds(ru.ru_stime);
}

}  // namespace

TEST(FftThreads, SmallGridsUseOneThread) {
  EXPECT_EQ(fft_options(scenario_at(16, 2)).threads, 1);
  EXPECT_EQ(fft_options(scenario_at(256, 2)).threads, 1);
  EXPECT_EQ(fft_options(scenario_at(256, 0)).threads, 1);
  EXPECT_EQ(fft_options(scenario_at(512, 2)).threads, 2);
  EXPECT_EQ(fft_options(scenario_at(512, 0)).threads, usable_cpus());
}

// CPU time, not wall time: it does not grow with the machine's load. The factor and the
// slack cover the run-to-run spread of a 0.1 s run; spinning OpenMP workers at n = 16 cost
// 16-21 times the CPU of one thread on a busy machine, about the same on an idle one
// (docs/performance.md, "FFT threads"), so only a busy machine tells them apart.
TEST(FftThreads, SecondThreadCostsNoCpuOnASmallGrid) {
  const std::string dir = ::testing::TempDir() + "fft_threads_" + std::to_string(getpid());
  const double one = run_cpu(1, dir + "_1"), two = run_cpu(2, dir + "_2");
  EXPECT_LE(two, 3.0 * one + 0.25) << "threads=1: " << one << " s, threads=2: " << two << " s";
  std::filesystem::remove_all(dir + "_1");
  std::filesystem::remove_all(dir + "_2");
}

// Runs below n = 512 use one FFT thread whatever solver.threads asks, so the operator is checked
// directly: ESTIMATE plans give the same bits with one and two threads (README, solver.fft_plan).
TEST(FftThreads, TwoThreadsGiveTheSameBits) {
  const Grid grid = Grid::square(32, 1.0);
  Material mat;
  mat.body1 = {1.0, 0.3};
  FftOptions two;
  two.threads = 2;
  HalfSpace one_thread(grid, mat, Coupling::cerruti),
      two_threads(grid, mat, Coupling::cerruti, two);
  Field p(32, 32), t(32, 32);
  for (Eigen::Index k = 0; k < p.size(); ++k)
    p(k) = std::sin(0.37 * double(k)) + 1.5, t(k) = std::cos(0.11 * double(k));
  Field u1, u2, ux1, uy1, ux2, uy2;
  one_thread.normal(p, u1);
  two_threads.normal(p, u2);
  one_thread.tangential(t, p, ux1, uy1);
  two_threads.tangential(t, p, ux2, uy2);
  EXPECT_TRUE((u1.array() == u2.array()).all());
  EXPECT_TRUE((ux1.array() == ux2.array()).all());
  EXPECT_TRUE((uy1.array() == uy2.array()).all());
}
