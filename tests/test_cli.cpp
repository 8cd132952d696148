// The command line contract (README "Command line"): exit codes, one-line errors, outputs and
// columns.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/cli.hpp"
#include "support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using Result = fretbem_test::CliResult;

// Runs the fretbem binary with arguments; captures stdout and stderr.
Result fretbem(const std::string& args) {
  return fretbem_test::run_fretbem(args, "fretbem_cli_test");
}

std::string scenario(const std::string& name) {
  return (fs::path(FRETBEM_SOURCE_DIR) / "scenarios" / name).string();
}

int lines(const std::string& s) {
  return int(std::count(s.begin(), s.end(), '\n'));
}

}  // namespace

TEST(Cli, HelpAndVersion) {
  EXPECT_EQ(fretbem("--help").status, 0);
  EXPECT_NE(fretbem("--help").out.find("fretbem run"), std::string::npos);
  const Result v = fretbem("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_NE(v.out.find("fretbem "), std::string::npos);
}

TEST(Cli, BadInputIsOneClearLineAndNonZeroExit) {
  const std::string cases[] = {
      "",                                                          // no command
      "frobnicate",                                                // unknown command
      "run no_such_file.ini",                                      // missing file
      "run " + scenario("hertz.ini") + " --set material.mue=0.3",  // unknown key
      "run " + scenario("hertz.ini") + " --set grid.n=abc",        // not an integer
      "run " + scenario("hertz.ini") + " --set material.nu=0.7",   // out of range
      "run " + scenario("hertz.ini") + " --set material.E=nan",    // not finite
      "check " + scenario("hertz.ini") + " --set load.path=spiral",
      "run " + scenario("cattaneo.ini") + " --set load.amplitude=1.2",  // past full sliding
      "run --resume no_such_dir",
      "surface",  // no --out
  };
  for (const auto& c : cases) {
    const Result r = fretbem(c);
    EXPECT_NE(r.status, 0) << c;
    EXPECT_EQ(lines(r.err), 1) << c << "\n" << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << c;
  }
  // The message names the offending key.
  EXPECT_NE(
      fretbem("run " + scenario("hertz.ini") + " --set material.mue=0.3").err.find("material.mu"),
      std::string::npos);
}

TEST(Cli, CheckValidatesWithoutRunning) {
  const Result r = fretbem("check " + scenario("mindlin_cycle.ini"));
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("ok"), std::string::npos);
}

// Cycle counts print as integers (core/format format_count): wear.cycles = 10000 is "10000",
// not "1e+04" (what shortest round-trip or %.4g would print).
TEST(Cli, CheckPrintsWearCyclesAsIntegers) {
  for (const std::string n : {"10000", "1000000", "4000"}) {
    const Result r = fretbem("check " + scenario("fretting_wear.ini") +
                             " --set grid.n=16 --set wear.cycles=" + n);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("wear run of " + n + " cycles"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("wear: " + n + " load cycles"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("(wear.cycles = " + n + " = "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("cycles = 1e+"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("e+0 cycles"), std::string::npos) << r.out;
  }
}

TEST(Cli, RunWritesTheContractColumns) {
  const fretbem_test::TempDir tmp("cli_run");
  const fs::path dir = tmp / "run";
  const Result r =
      fretbem("run " + scenario("cattaneo.ini") + " --quiet --set grid.n=32 --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(dir / "timeseries.csv");
  std::string header;
  std::getline(in, header);
  const std::string contract =
      "step,time,cycle,Fz,delta,Fx,Fy,Ux,Uy,contact_area,stick_area,slip_area,Fx_stick,kx,"
      "dissipation,wear_volume,normal_iterations,tangential_iterations";
  EXPECT_EQ(header.rfind(contract, 0), 0u) << header;
  int rows = 0;
  for (std::string line; std::getline(in, line); ++rows)
    EXPECT_EQ(line.find("nan"), std::string::npos) << line;
  EXPECT_EQ(rows, 20);  // row 0 plus load.steps = 19
  EXPECT_TRUE(fs::exists(dir / "result.h5"));
  EXPECT_TRUE(fs::exists(dir / "cycles.csv"));
}

TEST(Cli, SurfaceWritesAHeightMapAndStatistics) {
  const fretbem_test::TempDir tmp("cli_surface");
  const fs::path out = tmp / "surface.npy";
  const Result r = fretbem("surface --set surface.hurst=0.6 --set grid.n=64 --out " + out.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_NE(r.out.find("rms height"), std::string::npos);
  EXPECT_NE(r.out.find("Hurst"), std::string::npos);
}

// One octave of fit range (n = 64) scattered fits of H = 0.8 from 0.66 to 1.55 over five seeds;
// two octaves (n = 128, also as the short side of a rectangle) kept them within 0.16.
TEST(Cli, SurfaceWarnsWhenTheHurstFitRestsOnTooFewWavelengths) {
  const fretbem_test::TempDir tmp("cli_hurst");
  const fs::path out = tmp / "surface.npy";
  for (const auto& [grid, warns] :
       {std::pair{"--set grid.n=64", true}, std::pair{"--set grid.n=32", true},
        std::pair{"--set grid.nx=256 --set grid.ny=64", true},
        std::pair{"--set grid.n=128", false}}) {
    const Result r = fretbem(std::string("surface ") + grid + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << grid << ": " << r.err;
    EXPECT_EQ(r.err.find("warning: the Hurst fit rests on") != std::string::npos, warns)
        << grid << ": " << r.err;
  }
}

// --quiet silences the progress report, not the results; steps are counted as
// `check` counts them, row 0 (the normal loading) included.
TEST(Cli, QuietKeepsTheSummaryAndStopsCountRows) {
  const fretbem_test::TempDir tmp("cli_quiet");
  const fs::path& dir = tmp.path();
  const std::string base = "run " + scenario("mindlin_cycle.ini") +
                           " --quiet --set grid.n=16 --set load.steps_per_cycle=8 --out ";
  const Result full = fretbem(base + (dir / "full").string());
  ASSERT_EQ(full.status, 0) << full.err;
  EXPECT_NE(full.out.find("steps done"), std::string::npos);
  EXPECT_NE(full.out.find("energy per cycle: "), std::string::npos);
  // No progress line; the only stderr line is the resolution warning (n = 16: the slip ring
  // spans under one cell).
  EXPECT_EQ(full.err.find("step "), std::string::npos) << full.err;
  EXPECT_LE(std::count(full.err.begin(), full.err.end(), '\n'), 1) << full.err;
  const Result part = fretbem(base + (dir / "part").string() + " --stop-after 2");
  ASSERT_EQ(part.status, 0) << part.err;
  const Result check = fretbem("check " + scenario("mindlin_cycle.ini") +
                               " --set grid.n=16 --set load.steps_per_cycle=8");
  // The same total in both messages.
  const auto total = full.out.substr(9, full.out.find(" steps done") - 9);
  EXPECT_NE(part.out.find("stopped after 2 of " + total + " steps"), std::string::npos) << part.out;
  EXPECT_NE(check.out.find(total), std::string::npos) << check.out;
}

// A surface needs no scenario file, whichever scale the user sets.
TEST(Cli, SurfaceWithoutScenarioTakesEitherScale) {
  const fretbem_test::TempDir tmp("cli_slope");
  const fs::path out = tmp / "surface.npy";
  const Result r =
      fretbem("surface --set grid.n=32 --set surface.rms_slope=0.1 --out " + out.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("rms slope  0.1"), std::string::npos) << r.out;
}
