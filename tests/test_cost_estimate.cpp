// `fretbem check`'s cost estimate against the runs it predicts, on small grids:
// FFT convolutions of stepped runs and simulated cycles of wear runs, which are counts and do
// not depend on the machine's load. The CPU-second figures and larger grids are measured by
// tools/bench/cost_estimate_accuracy.py (docs/reliability.md).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <string>
#include <vector>

#include "fretbem/history/cost_estimate.hpp"
#include "fretbem/history/model.hpp"
#include "fretbem/history/stepper.hpp"
#include "fretbem/wear/cost_estimate.hpp"
#include "fretbem/wear/integrator.hpp"
#include "support/hertz.hpp"

using namespace fretbem;
namespace fs = std::filesystem;

namespace {

Scenario scenario(const std::string& file, const std::vector<std::string>& sets) {
  return load_scenario(std::string(FRETBEM_SOURCE_DIR) + "/scenarios/" + file, sets);
}

// Every step of the path, as `fretbem run` does: its FFT convolutions.
double run_convolutions(const Scenario& sc) {
  auto model = build_model(sc);
  Stepper stepper(*model);
  double total = 0.0;
  for (std::size_t k = 0; k < stepper.steps(); ++k) total += stepper.advance(k).convolutions;
  return total;
}

struct Case {
  std::string file;
  std::vector<std::string> sets;
};

// `fretbem check`'s wear estimate of a case, then the run: its report and FFT convolutions.
struct WearEstimateAndRun {
  WearCostEstimate estimate;
  WearReport report;
  double convolutions = 0.0;
};

WearEstimateAndRun estimate_and_run(const Case& c) {
  const Scenario sc = scenario(c.file, c.sets);
  WearEstimateAndRun m;
  m.estimate = estimate_wear_cost(sc);
  auto model = build_model(sc);
  Stepper stepper(*model);
  WearCycles cycles(*model, stepper);
  Observer silent;
  const auto c0 = model->half_space->convolutions();
  m.report = integrate_wear(*model, cycles, silent);
  m.convolutions = double(model->half_space->convolutions() - c0);
  return m;
}

// The run's convolutions per simulated cycle within kWarmCostBand of the estimate's.
void expect_convolutions_per_cycle_in_band(const Case& c, const WearEstimateAndRun& m) {
  const double measured = m.convolutions / m.report.simulated_cycles;
  const double ratio = measured / m.estimate.convolutions_per_cycle;
  std::printf("%s %s: %.3g convolutions per simulated cycle against %.3g predicted: %.3g\n",
              c.file.c_str(), c.sets.back().c_str(), measured, m.estimate.convolutions_per_cycle,
              ratio);
  EXPECT_LE(ratio, kWarmCostBand) << c.file << " " << c.sets.back();
  EXPECT_GE(ratio, 1.0 / kWarmCostBand) << c.file << " " << c.sets.back();
}

}  // namespace

// The stated factor (docs/reliability.md): on force-controlled paths, cyclic or monotone, the
// measured convolutions are within a factor 1.5 of the prediction. Measured: 0.83-1.11 at
// n = 64-128 on the shipped scenarios, 0.74-1.04 on these cases at n = 32-48, 0.89 on the
// coupled one. The calibration
// sees the first steps only; later steps that cost differently from the model (first steps,
// then settled cycles at kSettledStepShare: the share measured 0.45-0.59) move the ratio.
TEST(CostEstimate, ConvolutionsOfForceControlledRunsWithinStatedFactor) {
  const std::vector<Case> cases = {
      {"mindlin_cycle.ini", {"grid.n=32"}},
      {"mindlin_cycle.ini", {"grid.n=48", "load.amplitude=0.3"}},
      {"mindlin_cycle.ini", {"grid.n=32", "load.amplitude=0.9", "load.steps_per_cycle=32"}},
      {"cattaneo.ini", {"grid.n=32"}},
      {"rough_fretting_cycle.ini", {"grid.n=32"}},
      {"rough_fretting_cycle.ini", {"grid.n=48", "load.cycles=4"}},
      // Coupled (rigid sphere on nu = 0.3): every step alternates 4-10 solves in every cycle;
      // 2.30 while its later steps counted as settled and predicted ones.
      {"mindlin_cycle.ini", {"grid.n=32", "load.steps_per_cycle=16", "solver.coupling=coupled"}},
  };
  for (const Case& c : cases) {
    const Scenario sc = scenario(c.file, c.sets);
    const double predicted = estimate_run_cost(sc).convolutions;
    const double measured = run_convolutions(sc);
    const double ratio = measured / predicted;
    std::printf("%s %s: measured %g, predicted %g, ratio %.3f\n", c.file.c_str(),
                c.sets.back().c_str(), measured, predicted, ratio);
    EXPECT_GT(ratio, 1.0 / 1.5) << c.file << " " << c.sets.back() << ": " << measured << " / "
                                << predicted;
    EXPECT_LT(ratio, 1.5) << c.file << " " << c.sets.back() << ": " << measured << " / "
                          << predicted;
  }
}

namespace {

// The unit sphere under F_z = F0 (1 + 0.3 sin 2 pi t), F_x = 0.3 F0 cos 2 pi t, 16 rows a
// period over three periods (a quarter-period lead-in from F_x = 0), with `load_keys` in [load].
std::string sphere_table_ini(const fs::path& dir, const std::string& load_keys) {
  const double F0 = fretbem_test::unit_hertz_force();
  std::ofstream table(dir / "varying.csv");
  table << std::setprecision(17) << "time,Fz,Fx\n";
  for (int k = -4; k <= 48; ++k) {
    const double t = k / 16.0;
    table << t << "," << F0 * (1 + 0.3 * std::sin(2 * M_PI * t)) << ","
          << (k == -4 ? 0.0 : 0.3 * F0 * std::cos(2 * M_PI * t)) << "\n";
  }
  return fretbem_test::unit_sphere_ini(32, "path = table\ntable = varying.csv\n" + load_keys,
                                       "[solver]\nstiffness = false\n");
}

fs::path temporary_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

// A table whose normal load changes on every row moves the Coulomb bound within every step, so
// no later step starts at its answer: neither the settled share nor the cycle predictor's
// applies (kMovingBoundStepShare). Its rows whole and in 4 sub-steps, within the stated factor
// 1.5 (measured here 0.75 and 0.83; on the five cases of tools/bench/step_control_cost.py,
// n = 48-96, 32 rows a period: 1.04-1.29 whole, 1.00-1.13 in 4 sub-steps; 1.34-5.4 before the
// moving-bound share).
TEST(CostEstimate, ConvolutionsOfAVaryingNormalLoadTableWithinStatedFactor) {
  const fs::path dir = temporary_dir("fretbem_cost_");
  for (const char* substeps : {"1", "4"}) {
    const Scenario sc = parse_scenario(sphere_table_ini(dir, "substeps = " + std::string(substeps)),
                                       "varying", dir);
    const double predicted = estimate_run_cost(sc).convolutions;
    const double measured = run_convolutions(sc);
    std::printf("substeps %s: measured %g, predicted %g, ratio %.3f\n", substeps, measured,
                predicted, measured / predicted);
    EXPECT_GT(measured / predicted, 1.0 / 1.5) << substeps;
    EXPECT_LT(measured / predicted, 1.5) << substeps;
  }
  fs::remove_all(dir);
}

// The sinusoidal varying-load table of tools/bench/step_control_cost.py (F_z = P (1 + 0.3 sin
// 2 pi t), F_x = 0.5 mu P cos 2 pi t, 32 rows a period from t = -1/4 over three periods) on
// its rough case (rough_fretting_cycle.ini's surface, n = 64, P = 2 N) under load.tolerance.
std::string rough_bench_ini(const fs::path& dir, const std::string& tolerance) {
  std::ofstream table(dir / "rough.csv");
  table << std::setprecision(17) << "time,Fz,Fx\n";
  for (int j = 0; j <= 3 * 32 + 8; ++j) {
    const double t = -0.25 + j / 32.0;
    table << t << "," << 2.0 * (1 + 0.3 * std::sin(2 * M_PI * t)) << ","
          << 0.5 * 0.5 * 2.0 * std::cos(2 * M_PI * t) << "\n";
  }
  return "[material]\nE = 210e9\nnu = 0.3\nmu = 0.5\n[grid]\nn = 64\nlength = 1e-4\n"
         "[surface]\ntype = rough\nmethod = fourier\nhurst = 0.8\nrms_height = 1e-7\nseed = 1\n"
         "[load]\npath = table\ntable = rough.csv\ntolerance = " +
         tolerance + "\n[solver]\nstiffness = none\n";
}

}  // namespace

// Under load.tolerance the step control solves each row whose normal load changes in the
// sub-steps a rate learnt over the run's first period asks for; the estimate forecasts them
// from the path's curvature (kCurvatureRateFactor); counting rows whole leaves the rough bench
// 1.96 and 2.32 times above the estimate at 1e-3 and 1e-4. Within the stated
// factor 1.5 there and on the unit sphere's 16-row table, and the printed range of the rate
// (kCurvatureRateRange) holds the estimate.
TEST(CostEstimate, ConvolutionsUnderLoadToleranceWithinStatedFactor) {
  const fs::path dir = temporary_dir("fretbem_cost_tolerance_");
  auto check = [](const Scenario& sc, const std::string& name) {
    const RunCostEstimate e = estimate_run_cost(sc);
    const double measured = run_convolutions(sc);
    std::printf("%s: measured %g, predicted %g (%g to %g), ratio %.3f\n", name.c_str(), measured,
                e.convolutions, e.convolutions_low, e.convolutions_high, measured / e.convolutions);
    EXPECT_GT(measured / e.convolutions, 1.0 / 1.5) << name;
    EXPECT_LT(measured / e.convolutions, 1.5) << name;
    EXPECT_LE(e.convolutions_low, e.convolutions) << name;
    EXPECT_GE(e.convolutions_high, e.convolutions) << name;
  };
  for (const std::string tolerance : {"1e-3", "1e-4"}) {
    check(parse_scenario(rough_bench_ini(dir, tolerance), "rough", dir), "rough " + tolerance);
    check(parse_scenario(sphere_table_ini(dir, "tolerance = " + tolerance), "varying", dir),
          "unit sphere " + tolerance);
  }
  fs::remove_all(dir);
}

// A displacement-controlled ramp past full sliding: the steps in gross slip cost one
// convolution, which the first steps cannot foresee. The estimate stays an upper bound
// (measured 0.34x at n = 256).
TEST(CostEstimate, DisplacementRampIntoGrossSlipIsOverestimated) {
  const Scenario sc = scenario("rough_monotone.ini", {"grid.n=64"});
  const double predicted = estimate_run_cost(sc).convolutions;
  const double measured = run_convolutions(sc);
  EXPECT_LE(measured, predicted);
  EXPECT_GT(measured, 0.2 * predicted);
}

// Wear runs: the simulated cycles of the run fall in the predicted range, the range spans at
// most a decade (kExplicitRangeFactor for erk), and its middle, which the progress line's ETA
// counts on, is within 2x of the run's count. Implicit (dirk) runs of the sphere at Q = 0.3
// and 0.9 muP (k = 2e-11, N = 5e4: thousands of explicit caps) beside the shipped scenarios.
TEST(CostEstimate, WearSimulatedCyclesInPredictedRange) {
  const std::vector<Case> cases = {
      {"fretting_wear.ini", {"grid.n=32"}},
      {"fretting_wear.ini", {"grid.n=32", "wear.cycles=1000"}},
      {"gross_slip_wear.ini", {"grid.n=32"}},
      {"rough_fretting_wear.ini", {"grid.n=32"}},
      {"fretting_wear.ini", {"grid.n=32", "wear.cycles=6", "wear.integrator=cycle"}},
      {"fretting_wear.ini",
       {"grid.n=32", "load.amplitude=0.3", "wear.coefficient=2e-11", "wear.cycles=5e4"}},
      {"fretting_wear.ini",
       {"grid.n=32", "load.amplitude=0.9", "wear.coefficient=2e-11", "wear.cycles=5e4"}},
  };
  for (const Case& c : cases) {
    const WearEstimateAndRun m = estimate_and_run(c);
    const WearCostEstimate& e = m.estimate;
    const WearReport& rep = m.report;
    EXPECT_GE(rep.simulated_cycles, e.simulated_low - 1e-9) << c.file << " " << c.sets.back();
    EXPECT_LE(rep.simulated_cycles, e.simulated_high + 1e-9) << c.file << " " << c.sets.back();
    EXPECT_LE(e.simulated_high,
              (e.implicit ? 10.0 : kExplicitRangeFactor) * e.simulated_low * (1 + 1e-12));
    const double middle = SimulatedCycles{e.simulated_low, e.simulated_high}.middle();
    EXPECT_LE(rep.simulated_cycles, 2.0 * middle) << c.file << " " << c.sets.back();
    EXPECT_GE(rep.simulated_cycles, 0.5 * middle) << c.file << " " << c.sets.back();
    std::string sets;
    for (const auto& set : c.sets) sets += " " + set;
    std::printf("%s%s: simulated %g in [%g, %g]\n", c.file.c_str(), sets.c_str(),
                rep.simulated_cycles, e.simulated_low, e.simulated_high);
  }
}

// Wear runs: the FFT convolutions per simulated cycle of the run (every solve: normal,
// corrective, tangential and the implicit method's inner products) against the estimate from
// the calibration's warm evaluation, within kWarmCostBand (docs/reliability.md). Measured
// 0.94, 1.25 and 1.57 times the warm evaluation here (0.78, 1.04 and 1.31 times the estimate);
// the cold first evaluation counts 2-4 times more than the runs.
TEST(CostEstimate, WearConvolutionsPerCycleWithinStatedFactor) {
  const std::vector<Case> cases = {
      {"fretting_wear.ini", {"grid.n=64"}},
      {"rough_fretting_wear.ini", {"grid.n=64"}},
      {"rough_fretting_wear.ini", {"grid.n=64", "wear.cycles=1e5", "wear.rtol=1e-2"}},
  };
  for (const Case& c : cases) {
    const WearEstimateAndRun m = estimate_and_run(c);
    expect_convolutions_per_cycle_in_band(c, m);
  }
}

// The progress line's ETA counts the steps' cost shares: after each step the time left is
// elapsed x (1 - f) / f with f the share done. Against the run's own convolutions (what the
// time follows), that ETA is within 2x of the time left at every step from the tenth on, on a
// three-cycle Mindlin loop whose settled and predicted cycles cost 4x less than the first; the
// step count alone (f = steps done / steps) is not.
TEST(CostEstimate, StepSharesGiveAnEtaWithinTwiceTheTimeLeft) {
  const Scenario sc = scenario("mindlin_cycle.ini", {"grid.n=64"});
  auto model = build_model(sc);
  Stepper stepper(*model);
  std::vector<double> conv;
  for (std::size_t k = 0; k < stepper.steps(); ++k) conv.push_back(stepper.advance(k).convolutions);
  const std::vector<double> share = step_cost_shares(*model);
  ASSERT_EQ(share.size(), conv.size());
  auto left_over_done = [](const std::vector<double>& cost, std::size_t k) {
    double done = 0.0, all = 0.0;
    for (std::size_t i = 0; i < cost.size(); ++i) (i <= k ? done : all) += cost[i];
    return all / done;  // (1 - f) / f
  };
  const std::vector<double> per_step(conv.size(), 1.0);
  double worst = 1.0, worst_count = 1.0;
  for (std::size_t k = 9; k + 1 < conv.size(); ++k) {
    const double truth = left_over_done(conv, k);
    const double eta = left_over_done(share, k) / truth;
    const double by_count = left_over_done(per_step, k) / truth;
    worst = std::max({worst, eta, 1.0 / eta});
    worst_count = std::max({worst_count, by_count, 1.0 / by_count});
  }
  std::printf("ETA / time left, worst factor: cost shares %.2f, step count %.2f\n", worst,
              worst_count);
  EXPECT_LE(worst, 2.0);
  EXPECT_GT(worst_count, 2.0);
}

namespace {

// Peak RSS (bytes) of `fretbem run` on a shipped scenario with `sets`, from the child's own
// rusage (wait4: ru_maxrss of this child alone, in KiB on Linux).
double peak_rss_of_run(const std::string& file, const std::vector<std::string>& sets,
                       const fs::path& out) {
  std::vector<std::string> argv{FRETBEM_BINARY, "run",
                                std::string(FRETBEM_SOURCE_DIR) + "/scenarios/" + file};
  for (const auto& s : sets) argv.insert(argv.end(), {"--set", s});
  argv.insert(argv.end(), {"--out", out.string(), "--overwrite", "--quiet"});
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  struct rusage usage {};
  while (::wait4(pid, &status, 0, &usage) < 0) {
  }
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << file;
  return 1024.0 * double(usage.ru_maxrss);
}

}  // namespace

// The memory guard's estimate bounds the measured peak RSS of runs that hold the cycle
// predictor's and the Masing image's tables (2 Mindlin cycles, a rough cycle), of the Masing
// image alone (1 cycle) and of wear runs. The program's fixed RSS (libraries, ~24 MiB) is
// independent of the grid and would hide a per-cell term at a test's grid, so the grid's part
// is compared too: peak at n = 128 minus the peak of the same run at n = 16 against the
// estimate's difference. That part of a 2-cycle run measured 19.7 MiB, against 9.2 MiB from
// an estimate without the cycle predictor's and the Masing image's shares (MemoryCosts).
TEST(CostEstimate, MemoryEstimateBoundsPeakRss) {
  const fs::path dir = fs::temp_directory_path() / ("fretbem_memory_" + std::to_string(::getpid()));
  const std::vector<Case> cases = {
      {"mindlin_cycle.ini", {"load.cycles=2"}},
      {"mindlin_cycle.ini", {"load.cycles=1"}},
      {"rough_fretting_cycle.ini", {}},
      {"fretting_wear.ini", {"wear.integrator=cycle", "wear.cycles=10"}},
      // The implicit integrator over a long run: its grid part, 13.2 MiB at n = 128, was above
      // an estimate without the wear share (11.5 MiB).
      {"rough_fretting_wear.ini", {"wear.cycles=1e5", "wear.rtol=1e-2"}},
  };
  for (const Case& c : cases) {
    double peak[2], estimate[2];
    for (const int i : {0, 1}) {
      std::vector<std::string> sets = c.sets;
      sets.push_back(i == 0 ? "grid.n=16" : "grid.n=128");
      auto model = prepare_model(scenario(c.file, sets));
      estimate[i] = estimate_memory(model->scenario, model->cycle_predictor).total();
      peak[i] = peak_rss_of_run(c.file, sets, dir / std::to_string(i));
    }
    std::printf("%s %s: peak %.1f MiB (n = 16: %.1f), estimate %.1f MiB (%.1f)\n", c.file.c_str(),
                c.sets.empty() ? "" : c.sets[0].c_str(), peak[1] / (1 << 20), peak[0] / (1 << 20),
                estimate[1] / (1 << 20), estimate[0] / (1 << 20));
    EXPECT_GE(estimate[1], peak[1]) << c.file;
    EXPECT_GE(estimate[0], peak[0]) << c.file;
    EXPECT_GE(estimate[1] - estimate[0], peak[1] - peak[0]) << c.file;
  }
  fs::remove_all(dir);
}

// Cycle mode (wear.integrator = cycle) simulates carried cycles, each from the last one's end,
// and never asks the loop to repeat: `check` calibrates on the third carried cycle. A friction
// law whose mu drifts cycle by cycle (evolving) has no repeating loop, which a steady cycle
// would have needed; under `coupled` each step starts from the same step one cycle earlier
// (0.24 of the convolutions of a step from the last step's end, sweep case 48/18), which a
// steady loop does not. Held to the band of the ODE integrators' estimate (kWarmCostBand),
// and the simulated cycles to the run's N + 1.
TEST(CostEstimate, CycleModeEstimatesTheCarriedCycles) {
  const std::vector<std::string> cycle_mode = {"grid.n=32", "wear.integrator=cycle",
                                               "wear.cycles=6"};
  auto with = [&](std::vector<std::string> sets) {
    sets.insert(sets.begin(), cycle_mode.begin(), cycle_mode.end());
    return Case{"fretting_wear.ini", sets};
  };
  const std::vector<Case> cases = {
      with({"friction.law=evolving", "friction.mu_final=0.35", "friction.evolution=slip_path",
            "friction.scale=1e-6"}),
      with({"solver.coupling=coupled"}),
  };
  for (const Case& c : cases) {
    const WearEstimateAndRun m = estimate_and_run(c);
    EXPECT_EQ(m.estimate.simulated_low, m.report.simulated_cycles) << c.sets.back();
    EXPECT_EQ(m.estimate.simulated_high, m.report.simulated_cycles) << c.sets.back();
    expect_convolutions_per_cycle_in_band(c, m);
  }
}
